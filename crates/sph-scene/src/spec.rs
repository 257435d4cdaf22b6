//! The scene file's contents as Rust types (deserialised from TOML with `serde`; every table
//! refuses unknown keys). See the crate documentation for the format.

use serde::Deserialize;
use toml::Spanned;

/// A whole scene.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Name (results file `<name>-<method>.h5`; default: the file's stem).
    pub name: Option<String>,
    /// 2 (plane strain) or 3.
    pub dimension: Spanned<u32>,
    /// `tl`, `tl-hf`, `tl-gm`, `ul-og`, `ul-oas`, `ul-enog` or `mps`.
    pub method: Spanned<String>,
    /// Simulated end time (s).
    pub end_time: Spanned<f64>,
    /// The material of every body (`[material]`), or named materials the bodies choose from
    /// (`[[material]]`).
    pub material: Spanned<MaterialsSpec>,
    /// Method parameters (keys of the method family; see the crate documentation).
    pub numerics: Option<Spanned<toml::Table>>,
    /// Output schedule.
    #[serde(default)]
    pub output: OutputSpec,
    /// The bodies (at least one).
    #[serde(rename = "body")]
    pub bodies: Vec<Spanned<BodySpec>>,
    /// Constraints on regions of the bodies.
    #[serde(default, rename = "constraint")]
    pub constraints: Vec<Spanned<ConstraintSpec>>,
    /// Body accelerations and point forces.
    #[serde(default, rename = "load")]
    pub loads: Vec<Spanned<LoadSpec>>,
    /// Probes (material points whose position and velocity are recorded).
    #[serde(default, rename = "probe")]
    pub probes: Vec<Spanned<ProbeSpec>>,
    /// Rigid tools in kinematic contact, frictionless or with Coulomb friction (every method).
    #[serde(default, rename = "tool")]
    pub tools: Vec<Spanned<ToolSpec>>,
    /// Contact pairs of bodies (`[[contact]]`): one name is that body's self-contact (TL
    /// methods); deformable bodies touch each other by default.
    #[serde(default, rename = "contact")]
    pub contacts: Vec<Spanned<ContactSpec>>,
    /// Quasi-static relaxation (TL methods).
    pub relaxation: Option<Spanned<RelaxationSpec>>,
    /// Named values that `${…}` in the other values uses (resolved before the rest is read).
    pub parameters: Option<toml::Table>,
}

/// The scene's materials: one `[material]` table, or a list of `[[material]]` tables each with
/// a `name` that a body's `material` key chooses.
// Parsed once per scene: the unboxed table is simpler to match and its size is irrelevant.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum MaterialsSpec {
    /// `[material]`: the material of every body (and of the bodies without a `material` key).
    One(MaterialSpec),
    /// `[[material]]`: named materials.
    List(Vec<Spanned<MaterialSpec>>),
}

impl<'de> Deserialize<'de> for MaterialsSpec {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        struct Either;
        impl<'de> serde::de::Visitor<'de> for Either {
            type Value = MaterialsSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a [material] table or a list of [[material]] tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                MaterialSpec::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(MaterialsSpec::One)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Self::Value, A::Error> {
                Vec::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(MaterialsSpec::List)
            }
        }
        d.deserialize_any(Either)
    }
}

/// The material: a law and its constants (Young's modulus and Poisson's ratio, or bulk and
/// shear moduli).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// The name a body's `material` key gives (required in a `[[material]]` list).
    pub name: Option<String>,
    /// `neo-hookean`, `linear-elastic`, `saint-venant-kirchhoff`, `kirchhoff-vol-dev`,
    /// `mooney-rivlin` (the updated-Lagrangian methods use only the constants), or the plastic
    /// `j2`, `johnson-cook` (`ul-og`, `ul-oas`).
    #[serde(default = "default_law")]
    pub law: String,
    /// Density ρ0 (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio ν.
    pub nu: Option<f64>,
    /// Bulk modulus K (Pa), with `shear_modulus` instead of E and ν.
    pub bulk_modulus: Option<f64>,
    /// Shear modulus G (Pa).
    pub shear_modulus: Option<f64>,
    /// `mooney-rivlin`: `c₂/(c₁ + c₂)` (default the MPS paper's ≈ 0.0741), with E and ν or K
    /// and G.
    pub c2_fraction: Option<f64>,
    /// `mooney-rivlin`: `c₁` (Pa) of MPS eq. 12, with `c2` and `lambda` instead of the elastic
    /// constants (small-strain G = c₁ + c₂, K = 2λ).
    pub c1: Option<f64>,
    /// `mooney-rivlin`: `c₂` (Pa).
    pub c2: Option<f64>,
    /// `mooney-rivlin`: `λ` (Pa).
    pub lambda: Option<f64>,
    /// `kirchhoff-vol-dev`: the dimension of the isochoric split, `spatial` (d = the scene's
    /// dimension, the TL paper's; default) or `embedded-3d` (d = 3, true plane strain in 2D).
    pub deviator: Option<String>,
    // The constants of the plastic laws `j2` and `johnson-cook` (see
    // `sph_materials::plasticity`); keys of another law are an error.
    /// `j2`: initial yield stress σ_0 (Pa).
    pub yield_stress: Option<f64>,
    /// `j2`: linear hardening modulus H (Pa), default 0 (perfectly plastic).
    pub hardening_modulus: Option<f64>,
    /// `j2`: saturation stress σ_∞ (Pa) of Voce hardening, with `saturation_exponent`.
    pub saturation_stress: Option<f64>,
    /// `j2`: saturation exponent δ of Voce hardening.
    pub saturation_exponent: Option<f64>,
    /// `johnson-cook`: A (Pa).
    #[serde(rename = "A")]
    pub jc_a: Option<f64>,
    /// `johnson-cook`: B (Pa).
    #[serde(rename = "B")]
    pub jc_b: Option<f64>,
    /// `johnson-cook`: n.
    #[serde(rename = "n")]
    pub jc_n: Option<f64>,
    /// `johnson-cook`: C (default 0: rate-independent).
    #[serde(rename = "C")]
    pub jc_c: Option<f64>,
    /// `johnson-cook`: m of the thermal softening (with the temperatures).
    #[serde(rename = "m")]
    pub jc_m: Option<f64>,
    /// `johnson-cook`: reference strain rate ε̇0 (1/s), default 1.
    pub reference_strain_rate: Option<f64>,
    /// `johnson-cook`: room temperature (K).
    pub room_temperature: Option<f64>,
    /// `johnson-cook`: melting temperature (K).
    pub melting_temperature: Option<f64>,
    /// `johnson-cook`: initial temperature (K), default the room temperature.
    pub temperature: Option<f64>,
    /// `johnson-cook`: Taylor–Quinney fraction β of plastic work into heat, default 0.9.
    pub taylor_quinney: Option<f64>,
    /// `johnson-cook`: specific heat c_p (J/(kg K)), required with thermal softening.
    pub specific_heat: Option<f64>,
}

fn default_law() -> String {
    "neo-hookean".into()
}

/// When the run writes and samples.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Simulated time between snapshots (default `end_time/50`; 0: first and last only).
    pub snapshot_interval: Option<f64>,
    /// Time between disorder/energy samples (default `end_time/200`).
    pub monitor_interval: Option<f64>,
    /// Time between probe samples (default 0: every step).
    pub probe_interval: Option<f64>,
    /// Most steps the run may take (default 0: no limit); reaching it before `end_time` stops
    /// the run with a diagnostic, results kept.
    pub max_steps: Option<u64>,
    /// Fields written with every snapshot (default: velocity, displacement, von_mises,
    /// jacobian, density, disorder where the method offers them).
    pub fields: Option<Vec<String>>,
}

/// A region of space. In TOML a one-key table: `{ box = { min = [..], max = [..] } }`.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Axis-aligned box (rectangle in 2D).
    Box {
        /// Lower corner.
        min: Vec<f64>,
        /// Upper corner.
        max: Vec<f64>,
    },
    /// Disc (2D) or ball (3D).
    Ball {
        /// Centre.
        centre: Vec<f64>,
        /// Radius.
        radius: f64,
    },
    /// Annulus (2D) or spherical shell (3D): `inner ≤ |x − centre| ≤ outer`.
    Shell {
        /// Centre.
        centre: Vec<f64>,
        /// Inner radius.
        inner: f64,
        /// Outer radius.
        outer: f64,
    },
    /// Cylinder or tube (3D): from `base` along `axis` over `length`, `inner ≤ r ≤ radius`.
    Cylinder {
        /// Centre of the base disc.
        base: Vec<f64>,
        /// Direction of the axis.
        axis: Vec<f64>,
        /// Outer radius.
        radius: f64,
        /// Length along the axis.
        length: f64,
        /// Inner radius (0: solid).
        #[serde(default)]
        inner: f64,
    },
    /// Points in any of the parts.
    Union(Vec<ShapeSpec>),
    /// Points in every part.
    Intersection(Vec<ShapeSpec>),
    /// Points of `base` not in `cut`.
    Difference {
        /// The shape.
        base: Box<ShapeSpec>,
        /// What is removed.
        cut: Box<ShapeSpec>,
    },
    /// A closed triangle mesh (3D): an STL (ASCII or binary) or Wavefront OBJ file, placed by
    /// `x' = R (scale · x) + translate`.
    Mesh {
        /// The file, relative to the scene file.
        file: String,
        /// Scale factor (default 1; `1e-3` for a part drawn in millimetres).
        scale: Option<f64>,
        /// Rotation about an axis through the origin, after scaling (default none).
        rotate: Option<RotateSpec>,
        /// Translation, applied last (default none).
        translate: Option<Vec<f64>>,
    },
    /// A closed outline (2D): a vertex list (`.csv`, `.txt`, `.xy`, `.dat`) or the polygons of
    /// an SVG drawing, placed as a mesh is (rotation about z only).
    Outline {
        /// The file, relative to the scene file.
        file: String,
        /// Scale factor (default 1).
        scale: Option<f64>,
        /// Rotation about z, after scaling (default none).
        rotate: Option<RotateSpec>,
        /// Translation, applied last (default none).
        translate: Option<Vec<f64>>,
    },
}

/// A geometry file and where it goes (the fields of [`ShapeSpec::Mesh`] and
/// [`ShapeSpec::Outline`]).
#[derive(Clone, Copy, Debug)]
pub struct GeometryFileSpec<'a> {
    /// The file, relative to the scene file.
    pub file: &'a str,
    /// Scale factor.
    pub scale: Option<f64>,
    /// Rotation.
    pub rotate: Option<&'a RotateSpec>,
    /// Translation.
    pub translate: Option<&'a [f64]>,
}

impl ShapeSpec {
    /// A mesh's or outline's file and placement (`None` for the other shapes).
    pub fn geometry_file(&self) -> Option<GeometryFileSpec<'_>> {
        match self {
            ShapeSpec::Mesh {
                file,
                scale,
                rotate,
                translate,
            }
            | ShapeSpec::Outline {
                file,
                scale,
                rotate,
                translate,
            } => Some(GeometryFileSpec {
                file,
                scale: *scale,
                rotate: rotate.as_ref(),
                translate: translate.as_deref(),
            }),
            _ => None,
        }
    }
}

/// A rotation by `degrees` about `axis` (right-handed).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateSpec {
    /// The axis (default `[0, 0, 1]`, the only one a 2D outline may turn about).
    pub axis: Option<Vec<f64>>,
    /// The angle, degrees.
    pub degrees: f64,
}

/// One body: its particles (a shape filled at spacing `dp`, or a particle file) and initial
/// velocity.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name (constraints and loads refer to it).
    pub name: String,
    /// Particle spacing.
    pub dp: f64,
    /// The shape to fill (or `particles`).
    pub shape: Option<ShapeSpec>,
    /// `lattice` (a Cartesian lattice whose cell faces pass through the shape's lower bound;
    /// the default for every shape but a mesh or outline), `polar` (concentric layers: a 2D ball
    /// or shell, a 3D cylinder) or `fitted` (the lattice relaxed onto the surface of a mesh or
    /// outline; their default).
    pub layout: Option<String>,
    /// Relaxation steps of the `fitted` layout (default 200; 0: the lattice fill).
    pub relax_steps: Option<usize>,
    /// A CSV particle file (`x,y[,z],volume` per line, `#` comments), relative to the scene
    /// file, instead of `shape`.
    pub particles: Option<String>,
    /// Uniform initial velocity.
    pub velocity: Option<Vec<f64>>,
    /// The name of its material (default: the `[material]` table, or the only `[[material]]`).
    pub material: Option<String>,
}

/// A constraint on the particles of a region.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintSpec {
    /// `fixed`, `velocity` (prescribed) or `components` (only the components set in
    /// `components` prescribed; a roller grip).
    #[serde(rename = "type")]
    pub kind: String,
    /// Where (a shape; particles inside it).
    pub region: ShapeSpec,
    /// The body it applies to (default: every body).
    pub body: Option<String>,
    /// A name: the run records the reaction force the constraint receives as a series.
    pub name: Option<String>,
    /// Prescribed velocity (`velocity`, `components`).
    pub velocity: Option<Vec<f64>>,
    /// Prescribed components (`components`).
    pub components: Option<Vec<bool>>,
    /// The amplitude curve that scales `velocity` (default: constant).
    pub amplitude: Option<AmplitudeSpec>,
}

/// A load.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// `gravity` (a body acceleration), `point` (a force on the particle nearest `at`) or
    /// `pressure` (a follower pressure on the surface particles of `region`).
    #[serde(rename = "type")]
    pub kind: String,
    /// Acceleration (`gravity`).
    pub acceleration: Option<Vec<f64>>,
    /// Force in newtons (per unit depth in 2D) (`point`).
    pub force: Option<Vec<f64>>,
    /// Where the point force acts (`point`).
    pub at: Option<Vec<f64>>,
    /// Where gravity acts (default: everywhere); the surface the pressure loads.
    pub region: Option<ShapeSpec>,
    /// The body the pressure loads (default: every body).
    pub body: Option<String>,
    /// Pressure (Pa; positive pushes into the body) (`pressure`).
    pub pressure: Option<f64>,
    /// The loaded area (m²; m per unit depth in 2D) the particles share equally (default: each
    /// particle its volume over `dp`) (`pressure`).
    pub area: Option<f64>,
    /// One outward normal for every loaded particle (default: each particle's own, estimated
    /// from its neighbours) (`pressure`).
    pub normal: Option<Vec<f64>>,
    /// The amplitude curve that scales the acceleration, force or pressure (default:
    /// constant).
    pub amplitude: Option<AmplitudeSpec>,
}

/// An amplitude curve `a(t)` (dimensionless) that scales a prescribed value. In TOML a one-key
/// table: `{ smooth-step = { duration = 1e-3 } }`, `{ table = [[0.0, 0.0], [1e-3, 1.0]] }`.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum AmplitudeSpec {
    /// Linear from 0 at `start` to 1 at `start + duration`, then 1.
    Ramp {
        /// When it begins (s, default 0).
        #[serde(default)]
        start: f64,
        /// How long it takes (s).
        duration: f64,
    },
    /// From 0 to 1 along `ξ³(10 − 15ξ + 6ξ²)`: no jump in value, slope or curvature.
    SmoothStep {
        /// When it begins (s, default 0).
        #[serde(default)]
        start: f64,
        /// How long it takes (s).
        duration: f64,
    },
    /// Piecewise linear through `[time, value]` points, held beyond the ends.
    Table(Vec<Vec<f64>>),
    /// `offset + amplitude · sin(2π frequency · t + phase)`.
    Sine {
        /// Hz.
        frequency: f64,
        /// Default 1.
        #[serde(default = "one")]
        amplitude: f64,
        /// rad, default 0.
        #[serde(default)]
        phase: f64,
        /// Default 0.
        #[serde(default)]
        offset: f64,
    },
}

/// A probe on a material point.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Name (`/probes/<name>`).
    pub name: String,
    /// Reference position.
    pub at: Vec<f64>,
    /// Output fields sampled at the probe at every monitor sample (`/probes/<name>/fields`).
    pub fields: Option<Vec<String>>,
}

/// A rigid tool.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolSpec {
    /// Name (`/series/<name>` records its travel and reaction).
    pub name: String,
    /// `box`, `ball`, `half-space = { point = [..], normal = [..] }`, or a `mesh` (3D) or
    /// `outline` (2D) file.
    pub shape: ToolShapeSpec,
    /// Direction of travel (default: no motion).
    pub direction: Option<Vec<f64>>,
    /// Speed (m/s, default 0).
    #[serde(default)]
    pub speed: f64,
    /// Smooth start (s, default 0).
    #[serde(default)]
    pub ramp_time: f64,
    /// Travel after which it stops (m, default: never).
    pub travel: Option<f64>,
    /// A piecewise-linear path instead: `[time, ux, uy(, uz)]` waypoints of the displacement.
    pub path: Option<Vec<Vec<f64>>>,
    /// A velocity curve instead: this velocity (m/s) times `amplitude`.
    pub velocity: Option<Vec<f64>>,
    /// The amplitude curve of `velocity` (default: constant).
    pub amplitude: Option<AmplitudeSpec>,
    /// A rotation about an axis through a centre that moves with the tool.
    pub rotation: Option<RotationSpec>,
    /// Static Coulomb coefficient μ_s against the body (default: `friction_kinetic`, else 0).
    pub friction_static: Option<f64>,
    /// Kinetic Coulomb coefficient μ_k ≤ μ_s (default: `friction_static`, else 0).
    pub friction_kinetic: Option<f64>,
}

/// A tool's rotation: angle `angular_velocity · ∫ amplitude`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationSpec {
    /// A point of the axis, in the tool's initial position.
    pub centre: Vec<f64>,
    /// The axis (3D; right-handed; in 2D the z axis, which may be given as `[0, 0, ±1]`).
    pub axis: Option<Vec<f64>>,
    /// Angular velocity (rad/s).
    pub angular_velocity: f64,
    /// Its amplitude curve (default: constant).
    pub amplitude: Option<AmplitudeSpec>,
}

/// A tool's shape.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum ToolShapeSpec {
    /// Axis-aligned box.
    Box {
        /// Lower corner.
        min: Vec<f64>,
        /// Upper corner.
        max: Vec<f64>,
    },
    /// Disc or ball.
    Ball {
        /// Centre.
        centre: Vec<f64>,
        /// Radius.
        radius: f64,
    },
    /// Half-space whose surface passes through `point` and faces along `normal`.
    HalfSpace {
        /// A point of the surface.
        point: Vec<f64>,
        /// Outward normal.
        normal: Vec<f64>,
    },
    /// A closed triangle mesh (3D), read and placed as a body's `mesh` shape
    /// ([`ShapeSpec::Mesh`]); its surface is the tool's.
    Mesh {
        /// The file, relative to the scene file.
        file: String,
        /// Scale factor (default 1).
        scale: Option<f64>,
        /// Rotation about an axis through the origin, after scaling (default none).
        rotate: Option<RotateSpec>,
        /// Translation, applied last (default none).
        translate: Option<Vec<f64>>,
    },
    /// A closed outline (2D), read and placed as a body's `outline` shape
    /// ([`ShapeSpec::Outline`]).
    Outline {
        /// The file, relative to the scene file.
        file: String,
        /// Scale factor (default 1).
        scale: Option<f64>,
        /// Rotation about z, after scaling (default none).
        rotate: Option<RotateSpec>,
        /// Translation, applied last (default none).
        translate: Option<Vec<f64>>,
    },
}

impl ToolShapeSpec {
    /// A mesh's or outline's file and placement (`None` for the primitives).
    pub fn geometry_file(&self) -> Option<GeometryFileSpec<'_>> {
        match self {
            ToolShapeSpec::Mesh {
                file,
                scale,
                rotate,
                translate,
            }
            | ToolShapeSpec::Outline {
                file,
                scale,
                rotate,
                translate,
            } => Some(GeometryFileSpec {
                file,
                scale: *scale,
                rotate: rotate.as_ref(),
                translate: translate.as_deref(),
            }),
            _ => None,
        }
    }
}

/// A contact between bodies: two names (their contact, on by default between deformable
/// bodies) or one (that body's self-contact, TL methods).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// One or two body names.
    pub bodies: Vec<String>,
    /// Not built yet (refused in one line).
    pub friction_static: Option<f64>,
    /// Not built yet (refused in one line).
    pub friction_kinetic: Option<f64>,
}

/// Quasi-static relaxation: the pairwise damping with `η = (β/4)√(ρ0 E) L`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RelaxationSpec {
    /// β (default 1).
    #[serde(default = "one")]
    pub beta: f64,
    /// The body size L along the load (m).
    pub length: f64,
}

fn one() -> f64 {
    1.0
}
