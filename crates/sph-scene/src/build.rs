//! From a parsed scene to a running solver: shapes to particle sets, the material, the method,
//! regions to constraints/loads/probes, tools, and the run through `sph-driver`.

use crate::resolve::{resolve, Override, Resolved};
use crate::spec::{
    AmplitudeSpec, BodySpec, ConstraintSpec, GeometryFileSpec, LoadSpec, MaterialSpec,
    MaterialsSpec, SceneSpec, ShapeSpec, ToolShapeSpec, ToolSpec,
};
use glam::{DVec2, DVec3};
use serde_json::{json, Map, Value as Json};
use sph_core::contact_friction::FrictionTable;
use sph_core::error::Num;
use sph_core::friction::Friction;
use sph_core::pressure::{PressureFunction, SurfacePressure};
use sph_core::relaxation::PairwiseDamping;
use sph_core::surface::surface_of;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{
    Amplitude, Constraint, Constraints, Dim, Loads, Probe, Solver, TimeFunction, D2, D3,
};
use sph_driver::{drive, DriverError, RunOptions, RunRecord, Schedule};
use sph_geometry::fit::{fit, FitOptions, FitReport, DEFAULT_RELAX_STEPS};
use sph_geometry::generate::{
    annulus_polar, tube_polar, Aabb, Difference, FnShape, Intersection, Lattice, ParticleSet,
    Shape, Union,
};
use sph_geometry::mesh::Placement;
use sph_geometry::FileSolid;
use sph_materials::{
    DeviatorDimension, ElasticConstants, Material, MaterialKind, MaterialModel, MooneyRivlinLike,
};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

mod checks;
mod parts;
mod plasticity;
mod preview;

pub use preview::{BodyPreview, Preview};

/// A scene error: the file, the line (when known), the key and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The scene file (or the origin given to [`Scene::parse`]).
    pub file: String,
    /// 1-based line of the key, when known.
    pub line: Option<usize>,
    /// The key, as a path (`body[2].dp`).
    pub key: String,
    /// What is wrong and what is allowed.
    pub message: String,
    /// The override that gave the value, when one did (`--set material.nu=0.7`).
    pub set_by: Option<String>,
}

impl SceneError {
    pub(crate) fn new(
        file: &str,
        line: Option<usize>,
        key: &str,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.into(),
            line,
            key: key.into(),
            message: message.into(),
            set_by: None,
        }
    }
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let by = self
            .set_by
            .as_ref()
            .map(|o| format!(" (from {o})"))
            .unwrap_or_default();
        // A file name with a newline or other control character is shown escaped: an error
        // stays one line.
        let file = if self.file.chars().any(char::is_control) {
            format!("{:?}", self.file)
        } else {
            self.file.clone()
        };
        match self.line {
            Some(l) => write!(f, "{file}:{l}: {}{by}: {}", self.key, self.message),
            None => write!(f, "{file}: {}{by}: {}", self.key, self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// A body's size as built ([`Scene::body_thicknesses`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyThickness {
    /// The body's name.
    pub name: String,
    /// Its particle spacing.
    pub dp: f64,
    /// Its particles.
    pub particles: usize,
    /// The diameter of the largest ball (disc in 2D) inside it (m).
    pub thickness: f64,
}

/// A parsed scene, ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    spec: SceneSpec,
    /// The file's text, the text after overrides and parameters, and where each part of the
    /// latter came from.
    source: Resolved,
    file: String,
    dir: PathBuf,
    name: String,
    default_name: String,
}

/// Where a key sits: the span of its table and the key name inside it.
struct At<'a> {
    span: Range<usize>,
    key: &'a str,
}

impl Scene {
    /// Reads and parses a scene file.
    ///
    /// # Errors
    /// The file cannot be read, or it is not a valid scene (unknown keys, wrong types).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, SceneError> {
        Self::from_file_with(path, &[])
    }

    /// [`Scene::from_file`] with overrides (see [`Scene::parse_with`]).
    ///
    /// # Errors
    /// As [`Scene::from_file`] and [`Scene::parse_with`].
    pub fn from_file_with(
        path: impl AsRef<Path>,
        overrides: &[Override],
    ) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = sph_output::input::read_text_input(path)
            .map_err(|e| SceneError::new(&file, None, "file", e.reason))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        Self::parse_with(&text, &file, &dir, &stem, overrides)
    }

    /// Parses a scene from `text`; `file` names it in errors, `dir` resolves particle files,
    /// `default_name` is the name when the scene gives none. The `[parameters]` are resolved
    /// into the values that use them (`${…}`).
    ///
    /// # Errors
    /// Malformed TOML, unknown keys or wrong types, a bad parameter or `${…}`, with the line.
    pub fn parse(
        text: &str,
        file: &str,
        dir: &Path,
        default_name: &str,
    ) -> Result<Self, SceneError> {
        Self::parse_with(text, file, dir, default_name, &[])
    }

    /// [`Scene::parse`] with `overrides` applied first (`--set KEY=VALUE` of the command:
    /// a dotted path into the file, `body.NAME.KEY` or `body[INDEX].KEY` for one entry of a
    /// list, or the name of a parameter).
    ///
    /// # Errors
    /// As [`Scene::parse`], and an override that names nothing the file can hold.
    pub fn parse_with(
        text: &str,
        file: &str,
        dir: &Path,
        default_name: &str,
        overrides: &[Override],
    ) -> Result<Self, SceneError> {
        let source = resolve(text, file, overrides)?;
        let spec: SceneSpec = toml::from_str(&source.text).map_err(|e| {
            let offset = e.span().map(|s| s.start);
            located(&source, file, offset, "scene", e.message().trim())
        })?;
        let name = spec
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string());
        let scene = Self {
            spec,
            source,
            file: file.into(),
            dir: dir.into(),
            name,
            default_name: default_name.into(),
        };
        scene.check_names()?;
        Ok(scene)
    }

    /// The scene with one more override, `key = value` (see [`Scene::parse_with`]): what
    /// `sph run scene.toml --set key=value` does.
    ///
    /// ```
    /// # use sph_scene::Scene;
    /// # let text = "dimension = 2\nmethod = \"tl-hf\"\nend_time = 1e-3\n[parameters]\nH = 0.01\n\
    /// # [material]\ndensity = 1e3\nyoungs_modulus = 1e6\nnu = 0.3\n[[body]]\nname = \"b\"\n\
    /// # dp = \"${H / 10}\"\nshape = { box = { min = [0.0, 0.0], max = [0.1, \"${H}\"] } }\n";
    /// let scene = Scene::parse(text, "plate.toml", ".".as_ref(), "plate")?
    ///     .set("H", "0.02")?                // a parameter: dp and the box follow it
    ///     .set("material.nu", "0.45")?
    ///     .set("body.b.velocity", "[0.0, 1.0]")?
    ///     .set("method", "ul-enog")?;
    /// assert_eq!(scene.method(), "ul-enog");
    /// # Ok::<(), sph_scene::SceneError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Scene::parse_with`].
    pub fn set(self, key: &str, value: &str) -> Result<Self, SceneError> {
        let mut overrides = self.source.overrides.clone();
        overrides.push(Override {
            key: key.into(),
            value: value.into(),
        });
        Self::parse_with(
            &self.source.original,
            &self.file,
            &self.dir,
            &self.default_name,
            &overrides,
        )
    }

    /// The overrides applied ([`Scene::set`], `--set`).
    pub fn overrides(&self) -> &[Override] {
        &self.source.overrides
    }

    /// The parameters with their values (overrides applied), in the file's order.
    pub fn parameters(&self) -> &[(String, toml::Value)] {
        &self.source.parameters
    }

    /// The text the scene is built from: the file's, with the overrides and the parameters'
    /// values in place.
    pub fn resolved_text(&self) -> &str {
        &self.source.text
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The method (`tl-hf`, `ul-enog`, …).
    pub fn method(&self) -> &str {
        self.spec.method.get_ref()
    }

    /// The scene as parsed (overrides and parameters applied): its bodies, loads, tools, …
    pub fn spec(&self) -> &SceneSpec {
        &self.spec
    }

    /// Each body's spacing, particle count and thickness (the diameter of the largest ball or
    /// disc inside it, [`sph_core::surface::thickness`]: a plate's height, a ring's wall), from
    /// its particles as the scene builds them, without running: what sets the resolution a
    /// body needs (`sph advise`).
    ///
    /// # Errors
    /// What building the bodies finds wrong (as [`Scene::run`] would, before it runs).
    pub fn body_thicknesses(&self) -> Result<Vec<BodyThickness>, SceneError> {
        match *self.spec.dimension.get_ref() {
            2 => self.body_thicknesses_in::<D2>(),
            3 => self.body_thicknesses_in::<D3>(),
            d => Err(self.error(
                self.spec.dimension.span(),
                "dimension",
                format!("{d}: allowed values are 2 (plane strain) and 3"),
            )),
        }
    }

    fn body_thicknesses_in<D: SceneDim>(&self) -> Result<Vec<BodyThickness>, SceneError> {
        self.spec
            .bodies
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let (part, _, _) = self.body::<D>(k, b)?;
                self.check_body_size(k, b, &part)?;
                let dp = b.get_ref().dp;
                let thickness = sph_core::surface::thickness::<D>(part.positions(), dp)
                    .map_err(|e| self.core(b.span(), &format!("body[{k}]"), e))?;
                Ok(BodyThickness {
                    name: b.get_ref().name.clone(),
                    dp,
                    particles: part.len(),
                    thickness,
                })
            })
            .collect()
    }

    /// Builds the scene and runs it through [`drive`] with `options`.
    ///
    /// # Errors
    /// Everything the scene gets wrong, naming the file, line and key; or what the run driver
    /// refuses (an absurd schedule). A failure mid-run is in `record.failure`.
    pub fn run(&self, options: &RunOptions) -> Result<(RunRecord, Map<String, Json>), SceneError> {
        match *self.spec.dimension.get_ref() {
            2 => self.run_in::<D2>(options),
            3 => self.run_in::<D3>(options),
            d => Err(self.error(
                self.spec.dimension.span(),
                "dimension",
                format!("{d}: allowed values are 2 (plane strain) and 3"),
            )),
        }
    }

    fn error(&self, span: Range<usize>, key: &str, message: impl Into<String>) -> SceneError {
        located(&self.source, &self.file, Some(span.start), key, message)
    }

    /// An error at `key` inside the table spanning `at.span` (the key's own line when found).
    fn error_in(&self, at: &At<'_>, path: &str, message: impl Into<String>) -> SceneError {
        let offset = key_line(&self.source.text, &at.span, at.key).unwrap_or(at.span.start);
        located(&self.source, &self.file, Some(offset), path, message)
    }

    /// An error at the first line anywhere that sets `key` (its last part), if any.
    fn error_at_key(&self, key: &str, path: &str, message: impl Into<String>) -> SceneError {
        let last = key.rsplit('.').next().unwrap_or(key);
        let offset = find_key_line(&self.source.text, last);
        located(&self.source, &self.file, offset, path, message)
    }

    fn run_in<D: SceneDim>(
        &self,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), SceneError>
    where
        MaterialModel: Material<D>,
    {
        let spec = &self.spec;
        let end_time = *spec.end_time.get_ref();
        if !(end_time.is_finite() && end_time > 0.0) {
            return Err(self.error(spec.end_time.span(), "end_time", "allowed: > 0 and finite"));
        }
        let method = spec.method.get_ref().as_str();
        let family = family_of(method).ok_or_else(|| {
            self.error(
                spec.method.span(),
                "method",
                format!(
                    "`{method}`: allowed values are tl, tl-hf, tl-gm, ul-og, ul-oas, ul-enog, ul-gnog, mps"
                ),
            )
        })?;
        let materials = self.materials()?;
        // The first body's material (TL's one body; every body's with one material).
        let (constants, law) = materials.built[materials.of_body[0]];
        let several_materials = materials.built.len() > 1;
        let (mspan, mspec) = &materials.specs[materials.of_body[0]];
        if several_materials {
            if let Some((span, s)) = materials
                .specs
                .iter()
                .find(|(_, s)| plasticity::is_plastic(&s.law))
            {
                return Err(self.error_in(
                    &At {
                        span: span.clone(),
                        key: "law",
                    },
                    "material.law",
                    format!(
                        "`{}`: a plastic law is carried when the scene has one material; this one has {}",
                        s.law.trim(),
                        materials.specs.len()
                    ),
                ));
            }
        }
        let plastic = self.plastic_law(mspan.clone(), mspec)?;
        if plastic.is_some() && !plasticity::PLASTIC_METHODS.contains(&method) {
            return Err(self.error_in(
                &At {
                    span: mspan.clone(),
                    key: "law",
                },
                "material.law",
                format!(
                    "`{}` is carried by {}; {method} takes an elastic law{}",
                    mspec.law,
                    plasticity::PLASTIC_METHODS.join(", "),
                    match method {
                        "ul-enog" => " (its Laplacian shear force has no stress tensor to return)",
                        "tl-hf" => {
                            " (its Laplacian shear force hard-wires an elastic deviator, which a \
                             yield surface cannot cap)"
                        }
                        _ => "",
                    }
                ),
            ));
        }
        // Bodies: one particle set, each body a range of it.
        if spec.bodies.is_empty() {
            return Err(SceneError::new(
                &self.file,
                None,
                "body",
                "a scene needs at least one [[body]]",
            ));
        }
        let mut set = ParticleSet::<D>::new();
        let mut ranges: Vec<(String, Range<usize>)> = Vec::new();
        let mut velocities = Vec::new();
        let mut dp = f64::INFINITY;
        let mut dps = Vec::new();
        let mut solids = Vec::new();
        for (k, b) in spec.bodies.iter().enumerate() {
            let ((part, v, _), solid) = self.body_and_solid::<D>(k, b)?;
            self.check_body_size(k, b, &part)?;
            let r = set
                .extend(&part)
                .map_err(|e| self.core(b.span(), &format!("body[{k}]"), e))?;
            velocities.extend(std::iter::repeat_n(v, r.len()));
            ranges.push((b.get_ref().name.clone(), r));
            solids.push(solid);
            dp = dp.min(b.get_ref().dp);
            dps.push(b.get_ref().dp);
        }
        self.check_overlaps(&set, &ranges, &solids)?;
        let n = set.len();
        let body_of: Vec<u32> = (0..n)
            .map(|i| ranges.iter().position(|(_, r)| r.contains(&i)).unwrap_or(0) as u32)
            .collect();
        let material_of: Vec<u32> = body_of
            .iter()
            .map(|&b| materials.of_body[b as usize] as u32)
            .collect();
        let constraints = self.constraints::<D>(&set, &ranges)?;
        let (loads, pressures) = self.loads::<D>(&set, &ranges, &dps)?;
        let mut body = set.into_body(dp).with_velocities(velocities);
        if body.velocities.iter().all(|&v| v == D::zero()) {
            body.velocities.clear();
        }
        let mut probes = Vec::new();
        for (k, p) in spec.probes.iter().enumerate() {
            let at = |key| At {
                span: p.span(),
                key,
            };
            let x = self.vector::<D>(&at("at"), &format!("probe[{k}].at"), &p.get_ref().at)?;
            let probe = Probe::at(&p.get_ref().name, x, &body)
                .map_err(|e| self.error_in(&at("at"), &format!("probe[{k}].at"), e.to_string()))?;
            let fields: Vec<&str> = p
                .get_ref()
                .fields
                .iter()
                .flatten()
                .map(String::as_str)
                .collect();
            probes.push(probe.with_fields(&fields));
        }
        let probe_interval = spec.output.probe_interval.unwrap_or(0.0);
        let empty = toml::Table::new();
        let (numerics_span, numerics_table) = match &spec.numerics {
            Some(t) => (t.span(), t.get_ref()),
            None => (0..0, &empty),
        };
        let nat = At {
            span: numerics_span.clone(),
            key: "",
        };
        let keys = Keys::new(numerics_table);
        let multi = ranges.len() > 1;
        let (self_contacts, contact_friction) = self.contacts(&ranges, method)?;
        let schedule = self.schedule(end_time)?;
        let mut meta = Map::new();
        meta.insert("case".into(), json!(self.name));
        meta.insert("method".into(), json!(method));
        meta.insert("particles".into(), json!(n));
        meta.insert("scene".into(), json!(self.source.original));
        if !self.source.overrides.is_empty() {
            let set: Vec<String> = self
                .source
                .overrides
                .iter()
                .map(|o| format!("{}={}", o.key, o.value))
                .collect();
            meta.insert("overrides".into(), json!(set));
        }
        if !self.source.parameters.is_empty() {
            let p: Map<String, Json> = self
                .source
                .parameters
                .iter()
                .map(|(k, v)| (k.clone(), serde_json::to_value(v).unwrap_or(Json::Null)))
                .collect();
            meta.insert("parameters".into(), Json::Object(p));
        }
        meta.insert("crate_version".into(), json!(env!("CARGO_PKG_VERSION")));
        let fields = spec.output.fields.clone();
        let run =
            |solver: &mut dyn Solver<D>| -> Result<(RunRecord, Map<String, Json>), SceneError> {
                let offered = solver.field_names();
                // The driver checks the list (offered, none twice) before the run.
                // Several bodies: each particle's body and material id too.
                let ids: &[&str] = if multi { &["body", "material"] } else { &[] };
                let names: Vec<String> = match &fields {
                    Some(f) => f.clone(),
                    None => sph_driver::run::DEFAULT_FIELDS
                        .iter()
                        .chain(ids)
                        .filter(|f| offered.contains(f))
                        .map(|f| f.to_string())
                        .collect(),
                };
                for (k, p) in spec.probes.iter().enumerate() {
                    let fields = p.get_ref().fields.iter().flatten();
                    if let Some(bad) = fields.clone().find(|f| !offered.contains(&f.as_str())) {
                        return Err(self.error_in(
                            &At {
                                span: p.span(),
                                key: "fields",
                            },
                            &format!("probe[{k}].fields"),
                            format!("`{bad}`: {method} offers {}", offered.join(", ")),
                        ));
                    }
                    let list: Vec<&String> = fields.collect();
                    if let Some(twice) = list
                        .iter()
                        .enumerate()
                        .find(|(i, f)| list[..*i].contains(f))
                    {
                        return Err(self.error_in(
                            &At {
                                span: p.span(),
                                key: "fields",
                            },
                            &format!("probe[{k}].fields"),
                            format!("`{}` is listed twice", twice.1),
                        ));
                    }
                }
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                // Friction between bodies: its work (only then: other summaries unchanged).
                drive(solver, meta.clone(), schedule, &names, options, |s, _| {
                    s.figures()
                        .into_iter()
                        .filter(|(name, _)| *name == "contact_friction_work")
                        .map(|(name, w)| (name.to_string(), json!(w)))
                        .collect()
                })
                .map_err(|e| self.driver(e))
            };
        let no_relaxation = |what: &str| -> Result<(), SceneError> {
            if let Some(r) = &spec.relaxation {
                return Err(self.error(
                    r.span(),
                    "relaxation",
                    format!("the pairwise relaxation is for the TL methods, not {what}"),
                ));
            }
            Ok(())
        };
        match family {
            Family::Tl => {
                if several_materials {
                    return Err(self.error(
                        spec.bodies[1].span(),
                        "body[1]",
                        "a TL method runs its bodies with one material; give every body the same material (or make rigid parts [[tool]]s)",
                    ));
                }
                let shear = match method {
                    "tl" => sph_tl::Shear::Original,
                    "tl-hf" => sph_tl::Shear::HourglassFree {
                        zeta: keys.f64("zeta", sph_tl::hourglass_free::DEFAULT_ZETA),
                    },
                    _ => sph_tl::Shear::Ganzenmuller {
                        alpha: keys.f64("alpha", sph_tl::ganzenmuller::DEFAULT_ALPHA),
                    },
                };
                let d = sph_tl::TlParams::default();
                let pair_data = keys.text("pair_data", d.pair_storage.name());
                let Some(pair_storage) = sph_tl::PairStorage::from_name(&pair_data) else {
                    return Err(self.error_in(
                        &At {
                            span: numerics_span.clone(),
                            key: "pair_data",
                        },
                        "numerics.pair_data",
                        format!("`{pair_data}`: allowed values are stored, recomputed"),
                    ));
                };
                let laplacian = keys.text("laplacian", d.hf_laplacian.name());
                let Some(hf_laplacian) = sph_tl::HfLaplacian::from_name(&laplacian) else {
                    return Err(self.error_in(
                        &At {
                            span: numerics_span.clone(),
                            key: "laplacian",
                        },
                        "numerics.laplacian",
                        format!("`{laplacian}`: allowed values are paper, normalised"),
                    ));
                };
                let params = sph_tl::TlParams {
                    h_over_dp: keys.f64("h_over_dp", d.h_over_dp),
                    cfl: keys.f64("cfl", d.cfl),
                    damping: keys.bool("damping", d.damping),
                    stretch_limited_dt: keys.bool("dt_stretch", d.stretch_limited_dt),
                    pair_storage,
                    hf_laplacian,
                    ..d
                };
                let keys_contact_scale = keys.f64("contact_scale", sph_tl::DEFAULT_CONTACT_SCALE);
                let known = numerics_keys(method).expect("a method");
                keys.finish(method, &known)
                    .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let tools = self.tools::<D>()?;
                let distributed = options.ranks.as_ref().is_some_and(|c| c.size() > 1);
                // On ranks, each builds the neighbour data of its own share only.
                let built = if distributed {
                    sph_tl::TlSolver::for_ranks(body, law, shear, params)
                } else {
                    sph_tl::TlSolver::new(body, law, shear, params)
                };
                let mut s = built.map_err(|e| self.solver_error(e, &numerics_span, &known))?;
                let contact_scale = keys_contact_scale;
                if multi {
                    s = s
                        .with_bodies(body_of.clone())
                        .map_err(|e| self.core(spec.bodies[1].span(), "body", e))?;
                }
                for (b, span) in &self_contacts {
                    s = s
                        .with_self_contact(*b)
                        .map_err(|e| self.core(span.clone(), "contact", e))?;
                }
                if multi || !self_contacts.is_empty() {
                    s = s.with_contact_scale(contact_scale).map_err(|e| {
                        self.core(numerics_span.clone(), "numerics.contact_scale", e)
                    })?;
                }
                if let Some(table) = contact_friction.clone() {
                    s = s
                        .with_contact_friction(table)
                        .map_err(|e| self.core(spec.contacts[0].span(), "contact", e))?;
                }
                if let Some(law) = plastic {
                    s = s
                        .with_plasticity(law)
                        .map_err(|e| self.core(mspan.clone(), "material", e))?;
                }
                for sp in pressures {
                    s = s
                        .with_surface_pressure(sp)
                        .map_err(|e| self.error_at_key("pressure", "load", e.to_string()))?;
                }
                let mut s = s
                    .with_constraints(constraints)
                    .with_loads(loads)
                    .with_tools(tools)
                    .map_err(|e| self.tool_error(e))?
                    .with_probes(probes, probe_interval)
                    .map_err(|e| self.core(numerics_span.clone(), "output.probe_interval", e))?;
                if let Some(r) = &spec.relaxation {
                    let (beta, length) = (r.get_ref().beta, r.get_ref().length);
                    let eta = PairwiseDamping::viscosity_for(
                        beta,
                        constants.density,
                        constants.youngs_modulus,
                        length,
                    );
                    let damping = PairwiseDamping::new(eta)
                        .map_err(|e| self.core(r.span(), "relaxation", e))?;
                    s = s
                        .with_relaxation(damping)
                        .map_err(|e| self.core(r.span(), "relaxation", e))?;
                }
                if let Some(comm) = options.ranks.as_ref().filter(|c| c.size() > 1) {
                    let mut d = sph_tl::distribute(s, comm.clone())
                        .map_err(|e| self.core(numerics_span.clone(), "ranks", e))?;
                    return run(&mut d);
                }
                run(&mut s)
            }
            Family::Ul => {
                no_relaxation(method)?;
                if !pressures.is_empty() {
                    let k = spec
                        .loads
                        .iter()
                        .position(|l| l.get_ref().kind == "pressure")
                        .unwrap_or(0);
                    return Err(self.error_in(
                        &At {
                            span: spec.loads[k].span(),
                            key: "type",
                        },
                        &format!("load[{k}].type"),
                        format!(
                            "a pressure load follows the surface through the deformation \
                             gradient, which {method} does not carry; tl, tl-hf, tl-gm and mps \
                             apply it"
                        ),
                    ));
                }
                let shear = match method {
                    "ul-og" => sph_ul::Shear::Original,
                    "ul-gnog" => sph_ul::Shear::Generalized {
                        xi: keys.opt_f64("xi"),
                    },
                    "ul-oas" => sph_ul::Shear::ArtificialStress {
                        epsilon: keys.f64("epsilon", sph_ul::artificial_stress::DEFAULT_EPSILON),
                        n: keys.count("n", sph_ul::artificial_stress::DEFAULT_EXPONENT),
                    },
                    _ => sph_ul::Shear::NonNested {
                        zeta: keys.opt_f64("zeta"),
                        form: sph_ul::LaplacianForm::Conservative,
                    },
                };
                let d = sph_ul::UlParams::default();
                let stepping = match keys.text("stepping", "dual").as_str() {
                    "dual" => sph_ul::Stepping::Dual,
                    "single" => sph_ul::Stepping::Single,
                    other => {
                        return Err(self.error_in(
                            &At {
                                span: numerics_span.clone(),
                                key: "stepping",
                            },
                            "numerics.stepping",
                            format!("`{other}`: allowed values are dual, single"),
                        ))
                    }
                };
                let riemann = match keys.text("riemann", "sphinxsys-tests").as_str() {
                    "sphinxsys-tests" => sph_ul::RiemannScheme::SphinxsysTests,
                    "paper" => sph_ul::RiemannScheme::Paper,
                    "limited-no-jump" => sph_ul::RiemannScheme::LimitedNoJump,
                    other => {
                        return Err(self.error_in(
                            &At {
                                span: numerics_span.clone(),
                                key: "riemann",
                            },
                            "numerics.riemann",
                            format!(
                            "`{other}`: allowed values are sphinxsys-tests, paper, limited-no-jump"
                        ),
                        ))
                    }
                };
                let params = sph_ul::UlParams {
                    h_over_dp: keys.f64("h_over_dp", d.h_over_dp),
                    cfl_acoustic: keys.f64("cfl_acoustic", d.cfl_acoustic),
                    cfl_advection: keys.f64("cfl_advection", d.cfl_advection),
                    stepping,
                    riemann,
                    corrected_velocity_gradient: keys
                        .bool("corrected_gradient", d.corrected_velocity_gradient),
                    refresh_kernel_data: keys.bool("refresh_kernel_data", d.refresh_kernel_data),
                    allow_isolated: keys.bool("allow_fracture", d.allow_isolated),
                    energy_budget: keys.bool("energy_budget", d.energy_budget),
                    contact_scale: keys.f64("contact_scale", d.contact_scale),
                    // As in the cases: ENOG's τ (output only) is integrated when written.
                    track_shear_stress: options.output.is_some(),
                    ..d
                };
                let known = numerics_keys(method).expect("a method");
                keys.finish(method, &known)
                    .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let tools = self.tools::<D>()?;
                let mut s = if several_materials {
                    let table = materials.built.iter().map(|m| m.0).collect();
                    sph_ul::UlSolver::with_materials(body, table, material_of, shear, params)
                } else {
                    sph_ul::UlSolver::new(body, constants, shear, params)
                }
                .map_err(|e| self.solver_error(e, &numerics_span, &known))?;
                if let Some(law) = plastic {
                    s = s
                        .with_plasticity(law)
                        .map_err(|e| self.core(mspan.clone(), "material", e))?;
                }
                let mut s = s.with_constraints(constraints).with_loads(loads);
                if multi {
                    s = s
                        .with_contact(body_of)
                        .map_err(|e| self.core(spec.bodies[1].span(), "body", e))?;
                }
                if let Some(table) = contact_friction.clone() {
                    s = s
                        .with_contact_friction(table)
                        .map_err(|e| self.core(spec.contacts[0].span(), "contact", e))?;
                }
                let mut s = s
                    .with_tools(tools)
                    .map_err(|e| self.tool_error(e))?
                    .with_probes(probes, probe_interval)
                    .map_err(|e| self.core(numerics_span.clone(), "output.probe_interval", e))?;
                run(&mut s)
            }
            Family::Mps => {
                no_relaxation(method)?;
                let d = sph_mps::MpsParams::default();
                let integrator = match keys.text("integrator", "velocity-verlet").as_str() {
                    "velocity-verlet" => sph_mps::Integrator::VelocityVerlet,
                    "symplectic-euler" => sph_mps::Integrator::SymplecticEuler,
                    other => {
                        return Err(self.error_in(
                            &At {
                                span: numerics_span.clone(),
                                key: "integrator",
                            },
                            "numerics.integrator",
                            format!(
                                "`{other}`: allowed values are velocity-verlet, symplectic-euler"
                            ),
                        ))
                    }
                };
                let fit = match keys.text("fit", "linear").as_str() {
                    "linear" => sph_mps::wls::Fit::Linear,
                    "quadratic" => sph_mps::wls::Fit::Quadratic,
                    other => {
                        return Err(self.error_in(
                            &At {
                                span: numerics_span.clone(),
                                key: "fit",
                            },
                            "numerics.fit",
                            format!("`{other}`: allowed values are linear, quadratic"),
                        ))
                    }
                };
                let params = sph_mps::MpsParams {
                    re_over_l0: keys.f64("re_over_l0", d.re_over_l0),
                    courant: keys.f64("courant", d.courant),
                    damping: keys.f64("damping", d.damping),
                    stabilisation: keys.f64("stabilisation", d.stabilisation),
                    integrator,
                    fit,
                    ..d
                };
                let known = numerics_keys(method).expect("a method");
                keys.finish(method, &known)
                    .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let tools = self.tools::<D>()?;
                let mut s = if several_materials {
                    let table = materials.built.into_iter().map(|m| m.1).collect();
                    sph_mps::MpsSolver::with_materials(body, table, material_of, params)
                } else {
                    sph_mps::MpsSolver::new(body, law, params)
                }
                .map_err(|e| self.solver_error(e, &numerics_span, &known))?;
                for sp in pressures {
                    s = s
                        .with_surface_pressure(sp)
                        .map_err(|e| self.error_at_key("pressure", "load", e.to_string()))?;
                }
                let mut s = s.with_constraints(constraints).with_loads(loads);
                if multi {
                    s = s
                        .with_contact(sph_mps::Contact::between(body_of))
                        .map_err(|e| self.core(spec.bodies[1].span(), "body", e))?;
                }
                let mut s = s
                    .with_tools(tools)
                    .map_err(|e| self.tool_error(e))?
                    .with_probes(probes, probe_interval)
                    .map_err(|e| self.core(numerics_span.clone(), "output.probe_interval", e))?;
                if let Some(comm) = options.ranks.as_ref().filter(|c| c.size() > 1) {
                    let mut d = sph_mps::distribute(s, comm.clone())
                        .map_err(|e| self.core(numerics_span.clone(), "ranks", e))?;
                    return run(&mut d);
                }
                run(&mut s)
            }
        }
    }

    /// The `[[contact]]` tables: the self-contacts (body index and span) they ask for, and the
    /// Coulomb friction table when any table has `friction_static`/`friction_kinetic` (TL and
    /// UL methods; one coefficient given: the other is the same, as on a tool). Two names are
    /// the body–body contact every multi-body run has anyway; one name is a self-contact (TL
    /// methods).
    #[allow(clippy::type_complexity)]
    fn contacts(
        &self,
        ranges: &[(String, Range<usize>)],
        method: &str,
    ) -> Result<(Vec<(u32, Range<usize>)>, Option<FrictionTable>), SceneError> {
        let mut out = Vec::new();
        let mut table: Option<FrictionTable> = None;
        for (k, c) in self.spec.contacts.iter().enumerate() {
            let (span, spec) = (c.span(), c.get_ref());
            let at = |key| format!("contact[{k}].{key}");
            let friction = if spec.friction_static.is_some() || spec.friction_kinetic.is_some() {
                let key = if spec.friction_static.is_some() {
                    "friction_static"
                } else {
                    "friction_kinetic"
                };
                if !matches!(family_of(method), Some(Family::Tl | Family::Ul)) {
                    return Err(self.error(
                        span,
                        &at(key),
                        format!(
                            "friction between bodies is built for the TL and UL methods, not {method}"
                        ),
                    ));
                }
                let mu_s = spec
                    .friction_static
                    .or(spec.friction_kinetic)
                    .unwrap_or(0.0);
                let mu_k = spec
                    .friction_kinetic
                    .or(spec.friction_static)
                    .unwrap_or(0.0);
                Some(Friction::new(mu_s, mu_k).map_err(|e| {
                    let name = match &e {
                        sph_core::Error::InvalidParameter { field, .. }
                            if field == "friction_kinetic" =>
                        {
                            "friction_kinetic"
                        }
                        _ => "friction_static",
                    };
                    self.error(span.clone(), &at(name), e.to_string())
                })?)
            } else {
                None
            };
            if spec.bodies.is_empty() || spec.bodies.len() > 2 {
                return Err(self.error(
                    span,
                    &at("bodies"),
                    format!(
                        "{} names: give one body (its self-contact) or two (their contact)",
                        spec.bodies.len()
                    ),
                ));
            }
            let mut ids = Vec::new();
            for name in &spec.bodies {
                let Some(b) = ranges.iter().position(|(n, _)| n == name) else {
                    return Err(self.error(
                        span,
                        &at("bodies"),
                        format!("`{name}`: no body of that name"),
                    ));
                };
                ids.push(b as u32);
            }
            if let Some(f) = friction {
                let (a, b) = (ids[0], *ids.last().expect("one or two names"));
                table
                    .get_or_insert_with(|| FrictionTable::new(ranges.len()))
                    .set(a, b, f)
                    .map_err(|e| self.error(span.clone(), &at("bodies"), e.to_string()))?;
            }
            if ids.len() == 1 || ids[0] == ids[1] {
                if family_of(method) != Some(Family::Tl) {
                    return Err(self.error(
                        span,
                        &at("bodies"),
                        format!(
                            "self-contact (one body) is built for the TL methods, not {method}"
                        ),
                    ));
                }
                out.push((ids[0], span));
            }
        }
        Ok((out, table))
    }

    fn core(&self, span: Range<usize>, key: &str, e: sph_core::Error) -> SceneError {
        self.error(span, key, e.to_string())
    }

    /// A driver refusal, pointing at the output key or the end time it names.
    fn driver(&self, e: DriverError) -> SceneError {
        match &e {
            DriverError::InvalidValue { key, .. } => {
                let prefix = if key == "end_time" { "" } else { "output." };
                self.error_at_key(key, &format!("{prefix}{key}"), e.to_string())
            }
            _ => SceneError::new(&self.file, None, "run", e.to_string()),
        }
    }
}

/// The method families.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    Tl,
    Ul,
    Mps,
}

/// The `[numerics]` keys of `method` (`None` for an unknown method): what a scene file may set
/// for it (docs/user-guide.md's reference lists them with their defaults).
pub fn numerics_keys(method: &str) -> Option<Vec<&'static str>> {
    let mut keys = match family_of(method)? {
        Family::Tl => vec![
            "h_over_dp",
            "cfl",
            "damping",
            "dt_stretch",
            "pair_data",
            "contact_scale",
        ],
        Family::Ul => vec![
            "h_over_dp",
            "cfl_acoustic",
            "cfl_advection",
            "stepping",
            "riemann",
            "corrected_gradient",
            "refresh_kernel_data",
            "allow_fracture",
            "energy_budget",
            "contact_scale",
        ],
        Family::Mps => vec![
            "re_over_l0",
            "courant",
            "damping",
            "integrator",
            "stabilisation",
            "fit",
        ],
    };
    keys.extend_from_slice(match method {
        "tl-hf" => &["zeta", "laplacian"][..],
        "ul-enog" => &["zeta"][..],
        "tl-gm" => &["alpha"][..],
        "ul-oas" => &["epsilon", "n"][..],
        "ul-gnog" => &["xi"][..],
        _ => &[][..],
    });
    Some(keys)
}

/// Every method a scene file can name (`method`, `--method`).
pub const METHODS: &[&str] = &[
    "tl", "tl-hf", "tl-gm", "ul-og", "ul-oas", "ul-enog", "ul-gnog", "mps",
];

fn family_of(method: &str) -> Option<Family> {
    match method {
        "tl" | "tl-hf" | "tl-gm" => Some(Family::Tl),
        "ul-og" | "ul-oas" | "ul-enog" | "ul-gnog" => Some(Family::Ul),
        "mps" => Some(Family::Mps),
        _ => None,
    }
}

/// The `[numerics]` table, read key by key; `finish` names any key left unread.
struct Keys<'a> {
    table: &'a toml::Table,
    read: std::cell::RefCell<Vec<String>>,
    wrong: std::cell::RefCell<Option<String>>,
}

impl<'a> Keys<'a> {
    fn new(table: &'a toml::Table) -> Self {
        Self {
            table,
            read: Default::default(),
            wrong: Default::default(),
        }
    }

    fn get(&self, key: &str) -> Option<&toml::Value> {
        self.read.borrow_mut().push(key.into());
        self.table.get(key)
    }

    fn fail(&self, key: &str, want: &str) {
        self.wrong
            .borrow_mut()
            .get_or_insert_with(|| format!("`{key}` must be {want}"));
    }

    fn opt_f64(&self, key: &str) -> Option<f64> {
        match self.get(key)? {
            toml::Value::Float(x) => Some(*x),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => {
                self.fail(key, "a number");
                None
            }
        }
    }

    fn f64(&self, key: &str, default: f64) -> f64 {
        self.opt_f64(key).unwrap_or(default)
    }

    /// A whole number (1 to 2³²−1); the default when absent.
    fn count(&self, key: &str, default: u32) -> u32 {
        match self.get(key) {
            None => default,
            Some(toml::Value::Integer(i)) if (1..=i64::from(u32::MAX)).contains(i) => *i as u32,
            Some(_) => {
                self.fail(key, "a whole number >= 1");
                default
            }
        }
    }

    fn bool(&self, key: &str, default: bool) -> bool {
        match self.get(key) {
            None => default,
            Some(toml::Value::Boolean(b)) => *b,
            Some(_) => {
                self.fail(key, "true or false");
                default
            }
        }
    }

    fn text(&self, key: &str, default: &str) -> String {
        match self.get(key) {
            None => default.into(),
            Some(toml::Value::String(s)) => s.clone(),
            Some(_) => {
                self.fail(key, "a string");
                default.into()
            }
        }
    }

    /// The first wrong type, or the first key `method` does not know (a key of another method
    /// is refused, not ignored).
    fn finish(&self, method: &str, known: &[&str]) -> Result<(), String> {
        if let Some(m) = self.wrong.borrow().clone() {
            return Err(m);
        }
        match self.table.keys().find(|k| !known.contains(&k.as_str())) {
            Some(k) => Err(format!(
                "`{k}` is not a key of method {method}; its keys: {}",
                known.join(", ")
            )),
            None => Ok(()),
        }
    }
}

/// The dimension-specific parts of a scene: body-fitted (polar) layouts.
pub trait SceneDim: Dim {
    /// The polar layout of `shape` at spacing `dp`, or why there is none.
    fn polar(shape: &ShapeSpec, dp: f64) -> Result<ParticleSet<Self>, String>;
}

impl SceneDim for D2 {
    fn polar(shape: &ShapeSpec, dp: f64) -> Result<ParticleSet<D2>, String> {
        let (c, a, b) = match shape {
            ShapeSpec::Ball { centre, radius } => (centre, 0.0, *radius),
            ShapeSpec::Shell {
                centre,
                inner,
                outer,
            } => (centre, *inner, *outer),
            _ => return Err("the polar layout fills a 2D ball or shell".into()),
        };
        if c.len() != 2 {
            return Err(format!("centre {c:?}: expected 2 numbers"));
        }
        annulus_polar(DVec2::new(c[0], c[1]), a, b, dp).map_err(|e| e.to_string())
    }
}

impl SceneDim for D3 {
    fn polar(shape: &ShapeSpec, dp: f64) -> Result<ParticleSet<D3>, String> {
        match shape {
            ShapeSpec::Cylinder {
                base,
                axis,
                radius,
                length,
                inner,
            } if base.len() == 3 && axis.len() == 3 => tube_polar(
                DVec3::new(base[0], base[1], base[2]),
                DVec3::new(axis[0], axis[1], axis[2]),
                *inner,
                *radius,
                *length,
                dp,
            )
            .map_err(|e| e.to_string()),
            _ => Err("the polar layout fills a 3D cylinder".into()),
        }
    }
}

fn sphere_bounds<D: Dim>(c: D::Vector, r: f64) -> (D::Vector, D::Vector) {
    let mut d = D::zero();
    for k in 0..D::D {
        D::set_component(&mut d, k, r);
    }
    (c - d, c + d)
}

/// The start of the first line anywhere in the text that sets `key`.
fn find_key_line(text: &str, key: &str) -> Option<usize> {
    let mut offset = 0;
    for l in text.split_inclusive('\n') {
        if l.trim_start()
            .strip_prefix(key)
            .is_some_and(|r| r.trim_start().starts_with('='))
        {
            return Some(offset);
        }
        offset += l.len();
    }
    None
}

/// A scene error at byte `offset` of the resolved text: the file's line there, and the
/// override that wrote it, if one did.
fn located(
    source: &Resolved,
    file: &str,
    offset: Option<usize>,
    key: &str,
    message: impl Into<String>,
) -> SceneError {
    let (line, by) = match offset {
        Some(o) => source.origin(o),
        None => (None, None),
    };
    SceneError {
        set_by: by.map(|o| o.to_string()),
        ..SceneError::new(file, line, key, message)
    }
}

/// The start of the line of `key = …` in the table starting at `span` (up to the next table
/// header; a span of an array-of-tables entry may cover only its header), if written there.
fn key_line(text: &str, span: &Range<usize>, key: &str) -> Option<usize> {
    if key.is_empty() {
        return None;
    }
    let start = span.start.min(text.len());
    let mut offset = start;
    for (k, line) in text[start..].split_inclusive('\n').enumerate() {
        let t = line.trim_start();
        if k > 0 && t.starts_with('[') {
            break;
        }
        if let Some(rest) = t.strip_prefix(key) {
            if rest.trim_start().starts_with('=') {
                return Some(offset);
            }
        }
        // Inline tables: `shape = { box = … }` on one line.
        if line.contains(&format!(" {key} =")) || line.contains(&format!("{{{key} =")) {
            return Some(offset);
        }
        offset += line.len();
    }
    None
}
