//! The scene-file key reference: every key a scene file can hold, with its type, default, unit,
//! the methods that honour it and what it means. [`reference_markdown`] renders it for
//! docs/user-guide.md; a test checks that it lists exactly the keys the scene's types
//! ([`crate::spec`]) and [`crate::numerics_keys`] accept, and that the guide holds the current
//! rendering (regenerate with `SPH_UPDATE_DOCS=1 cargo test -p sph-scene --test reference`).

use sph_core::conventions;

/// One key of the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyDoc {
    /// The key's path: `material.nu`, `body[].dp`, `tool[].rotation.axis`; shapes under
    /// `shape.`, tool shapes under `tool-shape.`, amplitude curves under `amplitude.`.
    pub key: String,
    /// What it holds (`number`, `string`, `[x, y(, z)]`, a shape, …).
    pub kind: String,
    /// Its default (`required` if it has none; `—` where the key is optional without one).
    pub default: String,
    /// Which methods honour it (`all`, `TL`, `UL`, `MPS`, or method names).
    pub methods: String,
    /// What it means, with its unit and allowed values.
    pub meaning: String,
}

fn k(key: &str, kind: &str, default: &str, methods: &str, meaning: &str) -> KeyDoc {
    KeyDoc {
        key: key.into(),
        kind: kind.into(),
        default: default.into(),
        methods: methods.into(),
        meaning: meaning.into(),
    }
}

/// A number as the reference prints it.
fn num(x: f64) -> String {
    format!("{x:?}")
}

const VEC: &str = "[x, y(, z)]";

/// Every key, in the order the reference lists them.
pub fn keys() -> Vec<KeyDoc> {
    let tl = sph_tl::TlParams::default();
    let ul = sph_ul::UlParams::default();
    let mps = sph_mps::MpsParams::default();
    vec![
        // Top level.
        k("name", "string", "the file's stem", "all", "the scene's name: results are `<name>-<method>.h5`; a name, not a path (no `/`, `..`, control characters)"),
        k("dimension", "2 or 3", "required", "all", "2: plane strain (x, y; per unit depth in z); 3: x, y, z"),
        k("method", "string", "required", "all", "tl, tl-hf, tl-gm (total-Lagrangian SPH), ul-og, ul-oas, ul-enog, ul-gnog (updated-Lagrangian SPH), mps (Hamiltonian particles); `--method` overrides it"),
        k("end_time", "number", "required", "all", "simulated time to run to (s), > 0"),
        // Parameters.
        k("parameters.NAME", "number, string, boolean or array", "—", "all", "a named value that `${…}` in any other value uses (`dp = \"${H / 20}\"`); a name is a letter or `_` then letters, digits, `_`, not a scene key or a function name; `--set NAME=VALUE` overrides it"),
        // Material.
        k("material.name", "string", "— (required in a [[material]] list)", "all", "the name a body's `material` key chooses; `--set material.NAME.KEY=VALUE` sets a key of a named material"),
        k("material.law", "string", "neo-hookean", "all", "elastic: neo-hookean, linear-elastic (= saint-venant-kirchhoff), saint-venant-kirchhoff, kirchhoff-vol-dev, mooney-rivlin (TL, MPS; UL uses the elastic constants only); plastic (ul-og, ul-oas, ul-gnog, tl, tl-gm; the other methods refuse it): j2, johnson-cook, with the elastic constants for the elastic part (hypoelastic in UL, Hencky in TL)"),
        k("material.density", "number", "required", "all", "reference density ρ0 (kg/m³)"),
        k("material.youngs_modulus", "number", "— (or K and G)", "all", "Young's modulus E (Pa), with `nu`"),
        k("material.nu", "number", "— (or K and G)", "all", "Poisson's ratio ν, −1 < ν < 0.5"),
        k("material.bulk_modulus", "number", "— (or E and ν)", "all", "bulk modulus K (Pa), with `shear_modulus`"),
        k("material.shear_modulus", "number", "— (or E and ν)", "all", "shear modulus G (Pa), with `bulk_modulus`"),
        k("material.c2_fraction", "number", &num(sph_materials::MooneyRivlinLike::MPS_PAPER_C2_FRACTION), "TL, MPS", "mooney-rivlin: c₂/(c₁ + c₂) in [0, 1), with E and ν or K and G (the default is the MPS paper's ratio)"),
        k("material.c1", "number", "—", "TL, MPS", "mooney-rivlin by its own constants (MPS eq. 12): c₁ (Pa), with `c2` and `lambda` instead of the elastic constants (small-strain G = c₁ + c₂, K = 2λ)"),
        k("material.c2", "number", "—", "TL, MPS", "mooney-rivlin: c₂ (Pa), ≥ 0"),
        k("material.lambda", "number", "—", "TL, MPS", "mooney-rivlin: λ (Pa)"),
        k("material.deviator", "string", "spatial", "TL, MPS", "kirchhoff-vol-dev: `spatial` (isochoric split in the scene's dimension, the TL paper's) or `embedded-3d` (d = 3: true plane strain in 2D)"),
        k("material.yield_stress", "number", "required by j2", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "j2: initial yield stress σ_0 (Pa), > 0"),
        k("material.hardening_modulus", "number", "0", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "j2: linear isotropic hardening modulus H (Pa), ≥ 0: σ_y = σ_0 + H ε̄p"),
        k("material.saturation_stress", "number", "—", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "j2: Voce saturation stress σ_∞ (Pa), ≥ σ_0, with `saturation_exponent`: σ_y = σ_0 + H ε̄p + (σ_∞ − σ_0)(1 − exp(−δ ε̄p))"),
        k("material.saturation_exponent", "number", "—", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "j2: Voce saturation exponent δ, > 0"),
        k("material.A", "number", "required by johnson-cook", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: A (Pa), > 0, of σ_y = (A + B ε̄p^n)(1 + C ln max(ε̇̄p/ε̇0, 1))(1 − T*^m)"),
        k("material.B", "number", "required by johnson-cook", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: B (Pa), ≥ 0"),
        k("material.n", "number", "required by johnson-cook", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: strain-hardening exponent n, > 0"),
        k("material.C", "number", "0", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: strain-rate coefficient C, ≥ 0"),
        k("material.reference_strain_rate", "number", "1.0", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: reference plastic strain rate ε̇0 (1/s), > 0"),
        k("material.m", "number", "— (no thermal softening)", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: thermal-softening exponent m, > 0, with `room_temperature`, `melting_temperature`, `specific_heat`; T* = (T − T_room)/(T_melt − T_room) clamped to [0, 1]"),
        k("material.room_temperature", "number", "—", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: room temperature T_room (K), > 0"),
        k("material.melting_temperature", "number", "—", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: melting temperature T_melt (K), > T_room"),
        k("material.temperature", "number", "room_temperature", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: initial temperature (K), > 0"),
        k("material.taylor_quinney", "number", "0.9", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: fraction β of the plastic work turned into heat, in [0, 1] (adiabatic: ΔT = β σ_y Δε̄p/(ρ0 c_p))"),
        k("material.specific_heat", "number", "—", "ul-og, ul-oas, ul-gnog, tl, tl-gm", "johnson-cook: specific heat c_p (J/(kg K)), > 0"),
        // Numerics.
        k("numerics.h_over_dp", "number", &format!("{} (TL), {} (UL)", num(tl.h_over_dp), num(ul.h_over_dp)), "TL, UL", "smoothing length over particle spacing (cut-off 2h)"),
        k("numerics.cfl", "number", &num(tl.cfl), "TL", "CFL number of the time step"),
        k("numerics.damping", "boolean (TL), number (MPS)", &format!("{} (TL), {} (MPS)", tl.damping, num(mps.damping)), "TL, MPS", "TL: Kelvin–Voigt damping on or off; MPS: the velocity damping coefficient (1/s)"),
        k("numerics.dt_stretch", "boolean", &tl.stretch_limited_dt.to_string(), "TL", "scale the time step by the smallest principal stretch (strong compression)"),
        k("numerics.pair_data", "string", tl.pair_storage.name(), "TL", "`stored` reference kernel data, or `recomputed` at every force pass (less memory, about 2.5× the time)"),
        k("numerics.zeta", "number", &format!("{} (tl-hf), 0.7 d + 2.1 (ul-enog, d the dimension)", num(sph_tl::hourglass_free::DEFAULT_ZETA)), "tl-hf, ul-enog", "ζ of the non-nested shear (Laplacian of position / of velocity)"),
        k("numerics.laplacian", "string", tl.hf_laplacian.name(), "tl-hf", "`paper`: the paper's one ζ for the Laplacian of position; `normalised`: each particle's own ζ = d / tr of its reference neighbourhood's second moment (1.033 in a full 2D lattice neighbourhood, about 1.6 at a flat face, where 1.07 is too stiff and too soft); `zeta` then stays at its default"),
        k("numerics.alpha", "number", &num(sph_tl::ganzenmuller::DEFAULT_ALPHA), "tl-gm", "Ganzenmüller's hourglass-control strength α"),
        k("numerics.cfl_acoustic", "number", &num(ul.cfl_acoustic), "UL", "CFL number of the acoustic step"),
        k("numerics.cfl_advection", "number", &num(ul.cfl_advection), "UL", "CFL number of the advection step"),
        k("numerics.stepping", "string", "dual", "UL", "`dual` (acoustic sub-steps within each advection step) or `single`"),
        k("numerics.riemann", "string", "sphinxsys-tests", "UL", "the Riemann solver's form: sphinxsys-tests, paper, limited-no-jump"),
        k("numerics.corrected_gradient", "boolean", &ul.corrected_velocity_gradient.to_string(), "UL", "correct the velocity gradient with B in OG and OAS"),
        k("numerics.refresh_kernel_data", "boolean", &ul.refresh_kernel_data.to_string(), "UL", "recompute the pair kernel data in every acoustic sub-step"),
        k("numerics.allow_fracture", "boolean", &ul.allow_isolated.to_string(), "UL", "let particles that lose every neighbour fly on instead of stopping the run"),
        k("numerics.energy_budget", "boolean", &ul.energy_budget.to_string(), "UL", "keep the energy budget (its residual in the summary)"),
        k("numerics.contact_scale", "number", &format!("{} (TL), {} (UL)", num(sph_tl::DEFAULT_CONTACT_SCALE), num(ul.contact_scale)), "TL, UL", "scale κ of the body–body (and TL self-) contact pressure p = κ c0² ρ_c; TL's time step follows with √κ c0"),
        k("numerics.epsilon", "number", &num(sph_ul::artificial_stress::DEFAULT_EPSILON), "ul-oas", "artificial stress strength ε"),
        k("numerics.n", "integer", &sph_ul::artificial_stress::DEFAULT_EXPONENT.to_string(), "ul-oas", "artificial stress exponent n"),
        k("numerics.xi", "number", &num(sph_ul::generalized::DEFAULT_XI), "ul-gnog", "penalty factor ξ of the generalized non-hourglass formulation (arXiv 2409.11474), > 0"),
        k("numerics.re_over_l0", "number", &num(mps.re_over_l0), "MPS", "influence radius over particle spacing"),
        k("numerics.courant", "number", &num(mps.courant), "MPS", "Courant number of the time step"),
        k("numerics.integrator", "string", "velocity-verlet", "MPS", "`velocity-verlet` or `symplectic-euler`"),
        k("numerics.stabilisation", "number", &num(mps.stabilisation), "MPS", "α of the Hamiltonian stabilisation (0: off; 3 recommended, docs/validation.md)"),
        k("numerics.fit", "string", "linear", "MPS", "the weighted-least-squares fit: `linear` (the paper's) or `quadratic`"),
        // Output.
        k("output.snapshot_interval", "number", "end_time/50", "all", "simulated time between snapshots (s); 0: the first and the last only"),
        k("output.monitor_interval", "number", "end_time/200", "all", "time between samples of the disorder indicator, the energies and the probe fields (s)"),
        k("output.probe_interval", "number", "0", "all", "time between probe samples (s); 0: every step"),
        k("output.max_steps", "integer", "0", "all", "most steps the run may take (0: no limit); reaching it stops the run with a diagnostic, results kept"),
        k("output.fields", "array of strings", "velocity, displacement, von_mises, jacobian, density, disorder, plastic_strain (those the method offers); with several bodies also body, material", "all", "the fields written with every snapshot"),
        // Bodies.
        k("body[].name", "string", "required", "all", "the body's name (constraints, loads and overrides `body.NAME.KEY` refer to it)"),
        k("body[].dp", "number", "required", "all", "particle spacing (m)"),
        k("body[].shape", "a shape", "— (or particles)", "all", "the region the lattice (or polar or fitted layout) fills"),
        k("body[].layout", "string", "fitted for a mesh or outline, else lattice", "all", "`lattice` (Cartesian, cell faces through the shape's lower bound), `polar` (concentric layers: a 2D ball or shell, a 3D cylinder) or `fitted` (a mesh or outline: the lattice fill with its count brought to round(enclosed volume / dp^d) by removing outer-layer particles spread over the surface (or adding some inside it), then relaxed so that the outer layer lies dp/2 inside the surface and the volumes are even; each particle keeps the volume dp^d, and the preview reports the total against the enclosed volume)"),
        k("body[].relax_steps", "integer", "200", "all", "fitted layout: relaxation steps (0: the count-matched lattice fill as it is)"),
        k("body[].particles", "string", "— (or shape)", "all", "a CSV particle file, `x,y[,z],volume` per line (`#` comments), relative to the scene file"),
        k("body[].velocity", VEC, "at rest", "all", "uniform initial velocity (m/s)"),
        k("body[].material", "string", "the [material], or the only [[material]]", "all", "the name of the body's material; several materials in one run: UL and MPS (a TL method runs several bodies with one material)"),
        // Constraints.
        k("constraint[].type", "string", "required", "all", "`fixed` (held), `velocity` (moved at `velocity`), `components` (only the `components` marked true are prescribed: a roller grip)"),
        k("constraint[].region", "a shape", "required", "all", "the particles inside it"),
        k("constraint[].body", "string", "every body", "all", "the body it applies to"),
        k("constraint[].name", "string", "—", "all", "named: its reaction force is recorded as `/series/<name>` (TL)"),
        k("constraint[].velocity", VEC, "required by velocity, components", "all", "the prescribed velocity (m/s), scaled by `amplitude`"),
        k("constraint[].components", "[bool, bool(, bool)]", "required by components", "all", "which components are prescribed"),
        k("constraint[].amplitude", "an amplitude", "constant", "all", "the curve that scales `velocity` (a grip that starts smoothly)"),
        // Loads.
        k("load[].type", "string", "required", "all (pressure: TL, MPS)", "`gravity` (a body acceleration), `point` (a force on the particle nearest `at`), `pressure` (a follower pressure on the surface particles of `region`; needs a deformation gradient: TL, MPS)"),
        k("load[].acceleration", VEC, "required by gravity", "all", "the acceleration (m/s²), scaled by `amplitude`"),
        k("load[].force", VEC, "required by point", "all", "the force (N; N/m in 2D), scaled by `amplitude`"),
        k("load[].at", VEC, "required by point", "all", "where the point force acts (the nearest particle)"),
        k("load[].region", "a shape", "everywhere (gravity); required by pressure", "all", "gravity: the particles it accelerates; pressure: the particles whose surface ones it loads"),
        k("load[].body", "string", "every body", "TL, MPS", "pressure: the body it loads"),
        k("load[].pressure", "number", "required by pressure", "TL, MPS", "the pressure (Pa; > 0 pushes into the body), scaled by `amplitude`"),
        k("load[].area", "number", "each particle its volume over dp", "TL, MPS", "pressure: the loaded area (m²; m in 2D), shared equally by the surface particles (give it for a curved surface: the particles' centres lie dp/2 inside it)"),
        k("load[].normal", VEC, "each particle's own", "TL, MPS", "pressure: one outward normal for every loaded particle (a flat face); by default each surface particle's normal is estimated from its neighbours"),
        k("load[].amplitude", "an amplitude", "constant", "all", "the curve that scales the acceleration, force or pressure"),
        // Probes.
        k("probe[].name", "string", "required", "all", "`/probes/<name>` of the results"),
        k("probe[].at", VEC, "required", "all", "the material point's reference position (interpolated from the particles within 2.6 dp)"),
        k("probe[].fields", "array of strings", "none", "all", "output fields sampled there at every monitor sample (`/probes/<name>/fields`): any field the method offers (von_mises, jacobian, displacement, deformation_gradient, disorder, …)"),
        // Tools.
        k("tool[].name", "string", "required", "all", "`/series/<name>`: its travel and the force on it"),
        k("tool[].shape", "a tool shape", "required", "all", "its geometry in its initial position"),
        k("tool[].direction", VEC, "at rest", "all", "straight-line motion: the direction of travel"),
        k("tool[].speed", "number", "0", "all", "straight-line motion: the speed after the ramp (m/s), below the body's sound speed"),
        k("tool[].ramp_time", "number", "0", "all", "straight-line motion: the smooth start, (1 − cos)/2 (s)"),
        k("tool[].travel", "number", "never stops", "all", "straight-line motion: the travel after which it stops (m)"),
        k("tool[].path", "[[t, ux, uy(, uz)], …]", "—", "all", "instead of a line: piecewise-linear displacement through waypoints (times strictly increasing; held before the first and after the last)"),
        k("tool[].velocity", VEC, "—", "all", "instead of a line: the velocity (m/s), scaled by `amplitude`"),
        k("tool[].amplitude", "an amplitude", "constant", "all", "the curve that scales `velocity`"),
        k("tool[].rotation.centre", VEC, "required by rotation", "all", "a point of the axis in the tool's initial position (it moves with the tool)"),
        k("tool[].rotation.axis", "[x, y, z]", "[0, 0, 1] in 2D; required in 3D", "all", "the axis (right-handed); in 2D only ±z"),
        k("tool[].rotation.angular_velocity", "number", "required by rotation", "all", "angular velocity (rad/s), scaled by the rotation's `amplitude`"),
        k("tool[].rotation.amplitude", "an amplitude", "constant", "all", "the curve that scales the angular velocity"),
        k("tool[].friction_static", "number", "`friction_kinetic`, else 0", "all", "static Coulomb coefficient μ_s ≥ 0 against the bodies: a touching particle sticks while the impulse that stops its slip is within μ_s times the normal impulse"),
        k("tool[].friction_kinetic", "number", "`friction_static`, else 0", "all", "kinetic Coulomb coefficient 0 ≤ μ_k ≤ μ_s: a sliding particle is slowed by μ_k times the normal impulse; the series gains `friction_x`, `friction_y` (, `friction_z`) and `sticking`, the summary `tool_contact_work`, `friction_work`, `friction_dissipated`"),
        // Relaxation.
        k("contact[].bodies", "[string]", "required", "all", "two body names: their contact (on anyway between deformable bodies); one name: that body's self-contact (TL methods: particles farther apart than the kernel support in the reference touch when closer than dp)"),
        k("contact[].friction_static", "number", "`friction_kinetic`, else 0", "TL, UL", "static Coulomb coefficient μ_s ≥ 0 between the named bodies (one name: within the body's self-contact, TL): a contact pair sticks while the impulse that stops its tangential slip (its reduced mass over the larger count of frictional pairs of its two particles) is within μ_s times its normal impulse (contact force × Δt)"),
        k("contact[].friction_kinetic", "number", "`friction_static`, else 0", "TL, UL", "kinetic Coulomb coefficient 0 ≤ μ_k ≤ μ_s: a sliding pair receives μ_k times its normal impulse against its slip; the series gain `contact_friction_<b>` per body (`x`, `y` (, `z`) the mean friction force on body b, `sticking`), the summary `contact_friction_work`, UL's energy budget the term `contact_friction`"),
        k("relaxation.beta", "number", "1", "TL", "β of the pairwise damping η = (β/4)√(ρ0 E) L"),
        k("relaxation.length", "number", "required", "TL", "L, the body's size along the load (m)"),
        // Shapes.
        k("shape.box.min", VEC, "required", "all", "lower corner of an axis-aligned box (a rectangle in 2D)"),
        k("shape.box.max", VEC, "required", "all", "upper corner"),
        k("shape.ball.centre", VEC, "required", "all", "centre of a ball (a disc in 2D)"),
        k("shape.ball.radius", "number", "required", "all", "radius (m)"),
        k("shape.shell.centre", VEC, "required", "all", "centre of a spherical shell (an annulus in 2D): inner ≤ |x − centre| ≤ outer"),
        k("shape.shell.inner", "number", "required", "all", "inner radius (m)"),
        k("shape.shell.outer", "number", "required", "all", "outer radius (m), > inner"),
        k("shape.cylinder.base", "[x, y, z]", "required", "all", "3D: centre of the base disc of a cylinder or tube"),
        k("shape.cylinder.axis", "[x, y, z]", "required", "all", "direction of the axis"),
        k("shape.cylinder.radius", "number", "required", "all", "outer radius (m)"),
        k("shape.cylinder.length", "number", "required", "all", "length along the axis (m)"),
        k("shape.cylinder.inner", "number", "0", "all", "inner radius (m; 0: solid)"),
        k("shape.union", "[shape, …]", "—", "all", "points in any of the shapes"),
        k("shape.intersection", "[shape, …]", "—", "all", "points in every shape"),
        k("shape.difference.base", "a shape", "required", "all", "the shape …"),
        k("shape.difference.cut", "a shape", "required", "all", "… without the points of this one"),
        k("shape.mesh.file", "string", "required", "all", "3D: a closed triangle mesh, STL (ASCII or binary) or Wavefront OBJ, relative to the scene file; inside by the generalized winding number (small holes, duplicated and flipped triangles tolerated)"),
        k("shape.mesh.scale", "number", "1", "all", "scale factor applied first (1e-3: a part drawn in millimetres)"),
        k("shape.mesh.rotate.axis", "[x, y, z]", "[0, 0, 1]", "all", "rotation axis through the origin (right-handed), after scaling"),
        k("shape.mesh.rotate.degrees", "number", "required by rotate", "all", "rotation angle (degrees)"),
        k("shape.mesh.translate", VEC, "none", "all", "translation, applied last (m)"),
        k("shape.outline.file", "string", "required", "all", "2D: closed polylines, `x, y` per line (`.csv`, `.txt`, `.xy`, `.dat`; a blank line between loops, holes by the even-odd rule) or the `<polygon>`/`<polyline>` elements of an SVG file (y turned up); relative to the scene file; an outline that crosses itself is refused"),
        k("shape.outline.scale", "number", "1", "all", "as for mesh"),
        k("shape.outline.rotate.axis", "[x, y, z]", "[0, 0, 1]", "all", "only ±z"),
        k("shape.outline.rotate.degrees", "number", "required by rotate", "all", "rotation angle (degrees, counter-clockwise)"),
        k("shape.outline.translate", VEC, "none", "all", "translation, applied last (m)"),
        k("tool-shape.box.min", VEC, "required", "all", "lower corner of a box tool"),
        k("tool-shape.box.max", VEC, "required", "all", "upper corner"),
        k("tool-shape.ball.centre", VEC, "required", "all", "centre of a ball tool"),
        k("tool-shape.ball.radius", "number", "required", "all", "radius (m)"),
        k("tool-shape.half-space.point", VEC, "required", "all", "a point of a wall's surface"),
        k("tool-shape.half-space.normal", VEC, "required", "all", "the outward normal of the wall's surface: the solid lies on the other side, the body on this one"),
        k("tool-shape.mesh.file", "string", "required", "all", "3D: a rigid tool shaped by a closed triangle mesh (STL or OBJ, relative to the scene file; read, repaired and refused as a body's `shape.mesh`); the contact uses its signed distance (closest point by a BVH, side by the generalized winding number) and moves it with the tool"),
        k("tool-shape.mesh.scale", "number", "1", "all", "as for `shape.mesh`"),
        k("tool-shape.mesh.rotate.axis", "[x, y, z]", "[0, 0, 1]", "all", "as for `shape.mesh` (the placement; the tool's own `rotation` turns it in time)"),
        k("tool-shape.mesh.rotate.degrees", "number", "required by rotate", "all", "rotation angle (degrees)"),
        k("tool-shape.mesh.translate", VEC, "none", "all", "translation, applied last (m)"),
        k("tool-shape.outline.file", "string", "required", "all", "2D: a rigid tool shaped by a closed outline (as a body's `shape.outline`)"),
        k("tool-shape.outline.scale", "number", "1", "all", "as for `shape.outline`"),
        k("tool-shape.outline.rotate.axis", "[x, y, z]", "[0, 0, 1]", "all", "only ±z"),
        k("tool-shape.outline.rotate.degrees", "number", "required by rotate", "all", "rotation angle (degrees, counter-clockwise)"),
        k("tool-shape.outline.translate", VEC, "none", "all", "translation, applied last (m)"),
        // Amplitudes.
        k("amplitude.ramp.start", "number", "0", "all", "linear from 0 at `start` (s) …"),
        k("amplitude.ramp.duration", "number", "required", "all", "… to 1 at `start + duration` (s), then 1"),
        k("amplitude.smooth-step.start", "number", "0", "all", "0 until `start` (s), then ξ³(10 − 15ξ + 6ξ²), ξ = (t − start)/duration …"),
        k("amplitude.smooth-step.duration", "number", "required", "all", "… to 1 at `start + duration`, then 1: no jump in value, slope or curvature"),
        k("amplitude.table", "[[t, a], …]", "—", "all", "piecewise linear through the points (times strictly increasing), held beyond the ends"),
        k("amplitude.sine.frequency", "number", "required", "all", "offset + amplitude · sin(2π frequency · t + phase): frequency (Hz)"),
        k("amplitude.sine.amplitude", "number", "1", "all", "the oscillation's amplitude"),
        k("amplitude.sine.phase", "number", "0", "all", "phase at t = 0 (rad)"),
        k("amplitude.sine.offset", "number", "0", "all", "the mean value"),
    ]
}

/// The sections of the reference: (title, key prefix, what the section says first).
const SECTIONS: [(&str, &str, &str); 14] = [
    ("Top level", "", ""),
    ("`[parameters]`", "parameters.", "Parameters are resolved before anything else is read: a string that is one `${…}` becomes the value (a parameter's value of any type, or a number from arithmetic: `+ - * / ^`, parentheses, `pi`, `sqrt abs exp ln log10 sin cos tan asin acos atan floor ceil round min max`, all in floating point), a longer string gets each `${…}` replaced by its text (`name = \"plate-${dp}\"`). Parameters may use each other in any order."),
    ("`[material]` or `[[material]]`", "material.", "One `[material]` for every body, or a list of named `[[material]]` tables that each `[[body]]` chooses from with `material = \"NAME\"` (every material must be some body's; UL and MPS run bodies of different materials, the time step from the stiffest). Each holds E and ν, or K and G, and the law's own constants."),
    ("`[numerics]`", "numerics.", "The keys of the method's family; another method's key is an error. Defaults are the library's (`TlParams::default()`, `UlParams::default()`, `MpsParams::default()`)."),
    ("`[output]`", "output.", ""),
    ("`[[body]]`", "body[].", "One or more bodies; a TL method runs one (rigid parts are tools), UL and MPS bodies meet through the method's body–body contact."),
    ("`[[constraint]]`", "constraint[].", ""),
    ("`[[load]]`", "load[].", ""),
    ("`[[probe]]`", "probe[].", ""),
    ("`[[tool]]`", "tool[].", "Rigid tools, frictionless or with Coulomb friction, for every method (TL, UL, MPS). A tool moves along a straight line (`direction`, `speed`, `ramp_time`, `travel`), a `path` or a `velocity` curve, and may turn (`rotation`)."),
    ("`[relaxation]`", "relaxation.", "Quasi-static relaxation by pairwise damping (TL methods)."),
    ("Shapes", "shape.", "A shape is a one-key table: `{ box = { min = [0.0, 0.0], max = [0.1, 0.01] } }`; `union` and `intersection` take a list of shapes, `difference` two."),
    ("Tool shapes", "tool-shape.", "`{ box = … }`, `{ ball = … }`, `{ half-space = { point = [..], normal = [..] } }`, or a file placed as a body's: `{ mesh = { file = \"punch.stl\", scale = 1e-3 } }` (3D) or `{ outline = { file = \"die.csv\" } }` (2D)."),
    ("Amplitude curves", "amplitude.", "A dimensionless a(t) that scales a prescribed value, a one-key table: `{ ramp = { duration = 1e-3 } }`, `{ smooth-step = { start = 0.0, duration = 2e-3 } }`, `{ table = [[0.0, 0.0], [1e-3, 1.0]] }`, `{ sine = { frequency = 50.0 } }`."),
];

/// The section of a key: the longest prefix that matches (the top level otherwise).
fn section_of(key: &str) -> usize {
    SECTIONS
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.1.is_empty() && key.starts_with(s.1))
        .max_by_key(|(_, s)| s.1.len())
        .map_or(0, |(i, _)| i)
}

/// The reference as Markdown: one table per section, then what the results mean.
pub fn reference_markdown() -> String {
    let keys = keys();
    let mut out = String::from(
        "Every key a scene file can hold (generated from the scene's specification by \
         `SPH_UPDATE_DOCS=1 cargo test -p sph-scene --test reference`; do not edit by hand). \
         Any key can be set from the command line by its dotted path: `--set end_time=0.1`, \
         `--set material.nu=0.3`, `--set body.block.dp=1e-3` (an entry of a list by its name, \
         or `body[0].dp` by its index), `--set numerics.cfl=0.5` (added when the file lacks \
         it), `--set H=0.02` (a parameter), and `--method ul-enog`. A value a method cannot \
         honour is an error, and every error names the file, the line and the key (or the \
         `--set` that gave the value).\n",
    );
    for (s, (title, prefix, intro)) in SECTIONS.iter().enumerate() {
        let rows: Vec<&KeyDoc> = keys.iter().filter(|k| section_of(&k.key) == s).collect();
        out.push_str(&format!("\n#### {title}\n\n"));
        if !intro.is_empty() {
            out.push_str(intro);
            out.push_str("\n\n");
        }
        out.push_str("| key | type | default | methods | meaning |\n|---|---|---|---|---|\n");
        for r in rows {
            let key = r.key.strip_prefix(prefix).unwrap_or(&r.key);
            out.push_str(&format!(
                "| `{key}` | {} | {} | {} | {} |\n",
                cell(&r.kind),
                cell(&r.default),
                cell(&r.methods),
                cell(&r.meaning)
            ));
        }
    }
    out
}

/// Text for a Markdown table cell (`|` escaped).
fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

/// What the numbers of a results file mean: the sentences of [`sph_core::conventions`], which
/// the file's `/meta` and `/series/<name>@description` carry too.
pub fn conventions_markdown() -> String {
    let rows = [
        ("Units (`/meta@units`)", conventions::UNITS),
        ("2D (`/meta@per_unit_depth`)", conventions::PLANE_STRAIN),
        (
            "Reaction forces (`/meta@reaction_forces`)",
            conventions::REACTIONS,
        ),
        ("Probes (`/meta@probes`)", conventions::PROBES),
        (
            "`/series/<tool>` (its `description`)",
            conventions::TOOL_SERIES,
        ),
        (
            "`/series/<tool>` with friction (its `description`, after the above)",
            conventions::TOOL_FRICTION_SERIES,
        ),
        (
            "`/series/<grip>` (its `description`)",
            conventions::GRIP_SERIES,
        ),
        (
            "`/series/contact_force_<b>` (its `description`)",
            conventions::CONTACT_SERIES,
        ),
    ];
    let mut out = String::from(
        "Generated from `sph_core::conventions` (the same sentences are in every results \
         file).\n\n| what | meaning |\n|---|---|\n",
    );
    for (what, text) in rows {
        out.push_str(&format!("| {what} | {} |\n", cell(text)));
    }
    out
}
