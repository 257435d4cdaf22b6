//! From a parsed scene to a running solver: shapes to particle sets, the material, the method,
//! regions to constraints/loads/probes, tools, and the run through `sph-driver`.

use crate::spec::{
    BodySpec, ConstraintSpec, LoadSpec, MaterialSpec, SceneSpec, ShapeSpec, ToolShapeSpec,
};
use glam::{DVec2, DVec3};
use serde_json::{json, Map, Value as Json};
use sph_core::generate::{
    annulus_polar, tube_polar, Aabb, Difference, FnShape, Intersection, Lattice, ParticleSet,
    Shape, Union,
};
use sph_core::relaxation::PairwiseDamping;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{
    Body, Constraint, Constraints, Dim, Loads, Probe, Solver, TimeFunction, WendlandC2, D2, D3,
};
use sph_driver::{drive, DriverError, RunOptions, RunRecord, Schedule};
use sph_materials::{ElasticConstants, Material, MaterialKind, MaterialModel};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

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
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}: {}", self.file, self.key, self.message),
            None => write!(f, "{}: {}: {}", self.file, self.key, self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// A parsed scene, ready to run.
#[derive(Clone, Debug)]
pub struct Scene {
    spec: SceneSpec,
    text: String,
    file: String,
    dir: PathBuf,
    name: String,
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
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: file.clone(),
            line: None,
            key: "file".into(),
            message: e.to_string(),
        })?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        Self::parse(&text, &file, &dir, &stem)
    }

    /// Parses a scene from `text`; `file` names it in errors, `dir` resolves particle files,
    /// `default_name` is the name when the scene gives none.
    ///
    /// # Errors
    /// Malformed TOML, unknown keys or wrong types, with the line.
    pub fn parse(
        text: &str,
        file: &str,
        dir: &Path,
        default_name: &str,
    ) -> Result<Self, SceneError> {
        let spec: SceneSpec = toml::from_str(text).map_err(|e| SceneError {
            file: file.into(),
            line: e.span().map(|s| line_of(text, s.start)),
            key: "scene".into(),
            message: e.message().trim().to_string(),
        })?;
        let name = spec
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string());
        Ok(Self {
            spec,
            text: text.into(),
            file: file.into(),
            dir: dir.into(),
            name,
        })
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The method (`tl-hf`, `ul-enog`, …).
    pub fn method(&self) -> &str {
        self.spec.method.get_ref()
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
        SceneError {
            file: self.file.clone(),
            line: Some(line_of(&self.text, span.start)),
            key: key.into(),
            message: message.into(),
        }
    }

    /// An error at `key` inside the table spanning `at.span` (the key's own line when found).
    fn error_in(&self, at: &At<'_>, path: &str, message: impl Into<String>) -> SceneError {
        let line = key_line(&self.text, &at.span, at.key)
            .unwrap_or_else(|| line_of(&self.text, at.span.start));
        SceneError {
            file: self.file.clone(),
            line: Some(line),
            key: path.into(),
            message: message.into(),
        }
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
                    "`{method}`: allowed values are tl, tl-hf, tl-gm, ul-og, ul-oas, ul-enog, mps"
                ),
            )
        })?;
        let (constants, law) = self.material(&spec.material)?;
        // Bodies: one particle set, each body a range of it.
        if spec.bodies.is_empty() {
            return Err(SceneError {
                file: self.file.clone(),
                line: None,
                key: "body".into(),
                message: "a scene needs at least one [[body]]".into(),
            });
        }
        let mut set = ParticleSet::<D>::new();
        let mut ranges: Vec<(String, Range<usize>)> = Vec::new();
        let mut velocities = Vec::new();
        let mut dp = f64::INFINITY;
        for (k, b) in spec.bodies.iter().enumerate() {
            let (part, v) = self.body::<D>(k, b)?;
            let r = set
                .extend(&part)
                .map_err(|e| self.core(b.span(), &format!("body[{k}]"), e))?;
            velocities.extend(std::iter::repeat_n(v, r.len()));
            if ranges.iter().any(|(n, _)| *n == b.get_ref().name) {
                let at = At {
                    span: b.span(),
                    key: "name",
                };
                return Err(self.error_in(&at, &format!("body[{k}].name"), "names must be unique"));
            }
            ranges.push((b.get_ref().name.clone(), r));
            dp = dp.min(b.get_ref().dp);
        }
        let n = set.len();
        let body_of: Vec<u32> = (0..n)
            .map(|i| ranges.iter().position(|(_, r)| r.contains(&i)).unwrap_or(0) as u32)
            .collect();
        let constraints = self.constraints::<D>(&set, &ranges)?;
        let loads = self.loads::<D>(&set, &ranges)?;
        let probe_kernel = WendlandC2::<D>::from_spacing(dp, 1.3)
            .map_err(|e| self.core(spec.bodies[0].span(), "body[0].dp", e))?;
        let mut probes = Vec::new();
        for (k, p) in spec.probes.iter().enumerate() {
            let at = At {
                span: p.span(),
                key: "at",
            };
            let x = self.vector::<D>(&at, &format!("probe[{k}].at"), &p.get_ref().at)?;
            let probe = Probe::point(
                &p.get_ref().name,
                x,
                set.positions(),
                set.volumes(),
                &probe_kernel,
            )
            .map_err(|e| self.error_in(&at, &format!("probe[{k}].at"), e.to_string()))?;
            probes.push(probe);
        }
        let probe_interval = spec.output.probe_interval.unwrap_or(0.0);
        let mut body = Body::from_set(set, dp).with_velocities(velocities);
        if body.velocities.iter().all(|&v| v == D::zero()) {
            body.velocities.clear();
        }
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
        let schedule = self.schedule(end_time)?;
        let mut meta = Map::new();
        meta.insert("case".into(), json!(self.name));
        meta.insert("method".into(), json!(method));
        meta.insert("particles".into(), json!(n));
        meta.insert("scene".into(), json!(self.text));
        meta.insert("crate_version".into(), json!(env!("CARGO_PKG_VERSION")));
        let fields = spec.output.fields.clone();
        let run =
            |solver: &mut dyn Solver<D>| -> Result<(RunRecord, Map<String, Json>), SceneError> {
                let offered = solver.field_names();
                let names: Vec<String> = match &fields {
                    Some(f) => {
                        if let Some(bad) = f.iter().find(|f| !offered.contains(&f.as_str())) {
                            return Err(SceneError {
                                file: self.file.clone(),
                                line: None,
                                key: "output.fields".into(),
                                message: format!("`{bad}`: {method} offers {}", offered.join(", ")),
                            });
                        }
                        f.clone()
                    }
                    None => sph_driver::run::DEFAULT_FIELDS
                        .iter()
                        .filter(|f| offered.contains(f))
                        .map(|f| f.to_string())
                        .collect(),
                };
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                drive(solver, meta.clone(), schedule, &names, options, |_, _| {
                    Map::new()
                })
                .map_err(|e| self.driver(e))
            };
        let no_tools = |what: &str| -> Result<(), SceneError> {
            if let Some(t) = spec.tools.first() {
                return Err(self.error(
                    t.span(),
                    "tool",
                    format!("rigid tools need a TL method (tl, tl-hf, tl-gm); {what} bodies meet through body–body contact"),
                ));
            }
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
                if multi {
                    return Err(self.error(
                        spec.bodies[1].span(),
                        "body[1]",
                        "a TL method runs one body; make rigid parts [[tool]]s",
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
                let params = sph_tl::TlParams {
                    h_over_dp: keys.f64("h_over_dp", d.h_over_dp),
                    cfl: keys.f64("cfl", d.cfl),
                    damping: keys.bool("damping", d.damping),
                    stretch_limited_dt: keys.bool("dt_stretch", d.stretch_limited_dt),
                    pair_storage,
                    ..d
                };
                keys.finish(&[
                    "h_over_dp",
                    "cfl",
                    "zeta",
                    "alpha",
                    "damping",
                    "dt_stretch",
                    "pair_data",
                ])
                .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let tools = self.tools::<D>()?;
                let distributed = options.ranks.as_ref().is_some_and(|c| c.size() > 1);
                // On ranks, each builds the neighbour data of its own share only.
                let built = if distributed {
                    sph_tl::TlSolver::for_ranks(body, law, shear, params)
                } else {
                    sph_tl::TlSolver::new(body, law, shear, params)
                };
                let mut s = built
                    .map_err(|e| self.core(numerics_span.clone(), "numerics", e))?
                    .with_constraints(constraints)
                    .with_loads(loads)
                    .with_tools(tools)
                    .map_err(|e| self.core(spec.tools[0].span(), "tool", e))?
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
                no_tools(method)?;
                let shear = match method {
                    "ul-og" => sph_ul::Shear::Original,
                    "ul-oas" => sph_ul::Shear::ArtificialStress {
                        epsilon: keys.f64("epsilon", sph_ul::artificial_stress::DEFAULT_EPSILON),
                        n: keys.f64("n", sph_ul::artificial_stress::DEFAULT_EXPONENT as f64) as u32,
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
                    // As in the cases: ENOG's τ (output only) is integrated when written.
                    track_shear_stress: options.output.is_some(),
                    ..d
                };
                keys.finish(&[
                    "h_over_dp",
                    "cfl_acoustic",
                    "cfl_advection",
                    "stepping",
                    "riemann",
                    "zeta",
                    "epsilon",
                    "n",
                    "corrected_gradient",
                    "refresh_kernel_data",
                    "allow_fracture",
                ])
                .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let mut s = sph_ul::UlSolver::new(body, constants, shear, params)
                    .map_err(|e| self.core(numerics_span.clone(), "numerics", e))?
                    .with_constraints(constraints)
                    .with_loads(loads);
                if multi {
                    s = s
                        .with_contact(body_of)
                        .map_err(|e| self.core(spec.bodies[1].span(), "body", e))?;
                }
                let mut s = s
                    .with_probes(probes, probe_interval)
                    .map_err(|e| self.core(numerics_span.clone(), "output.probe_interval", e))?;
                run(&mut s)
            }
            Family::Mps => {
                no_tools(method)?;
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
                let params = sph_mps::MpsParams {
                    re_over_l0: keys.f64("re_over_l0", d.re_over_l0),
                    courant: keys.f64("courant", d.courant),
                    damping: keys.f64("damping", d.damping),
                    integrator,
                    ..d
                };
                keys.finish(&["re_over_l0", "courant", "damping", "integrator"])
                    .map_err(|m| self.error_in(&nat, "numerics", m))?;
                let mut s = sph_mps::MpsSolver::new(body, law, params)
                    .map_err(|e| self.core(numerics_span.clone(), "numerics", e))?
                    .with_constraints(constraints)
                    .with_loads(loads);
                if multi {
                    s = s
                        .with_contact(sph_mps::Contact::between(body_of))
                        .map_err(|e| self.core(spec.bodies[1].span(), "body", e))?;
                }
                let mut s = s
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

    /// The material's constants and law.
    fn material(
        &self,
        m: &Spanned<MaterialSpec>,
    ) -> Result<(ElasticConstants, MaterialModel), SceneError> {
        let at = |key| At {
            span: m.span(),
            key,
        };
        let s = m.get_ref();
        let constants = match (s.youngs_modulus, s.nu, s.bulk_modulus, s.shear_modulus) {
            (Some(e), Some(nu), None, None) => ElasticConstants::from_youngs(e, nu, s.density),
            (None, None, Some(k), Some(g)) => ElasticConstants::from_bulk_shear(k, g, s.density),
            _ => {
                return Err(self.error_in(
                    &at("youngs_modulus"),
                    "material",
                    "give youngs_modulus and nu, or bulk_modulus and shear_modulus",
                ))
            }
        }
        .map_err(|e| {
            let key = match &e {
                sph_core::Error::InvalidParameter { field, .. } => field.clone(),
                _ => "material".into(),
            };
            let key = if key == "poisson_ratio" {
                "nu".to_string()
            } else {
                key
            };
            let at = At {
                span: m.span(),
                key: &key,
            };
            self.error_in(&at, &format!("material.{key}"), e.to_string())
        })?;
        let kind: MaterialKind = s.law.parse().map_err(|e: sph_core::Error| {
            self.error_in(&at("law"), "material.law", e.to_string())
        })?;
        let law = kind
            .build(constants)
            .map_err(|e| self.error_in(&at("law"), "material.law", e.to_string()))?;
        Ok((constants, law))
    }

    /// One body's particles and uniform initial velocity.
    fn body<D: SceneDim>(
        &self,
        k: usize,
        b: &Spanned<BodySpec>,
    ) -> Result<(ParticleSet<D>, D::Vector), SceneError> {
        let s = b.get_ref();
        let key = |name: &str| format!("body[{k}].{name}");
        let at = |name| At {
            span: b.span(),
            key: name,
        };
        if !(s.dp.is_finite() && s.dp > 0.0) {
            return Err(self.error_in(&at("dp"), &key("dp"), format!("{}: allowed: > 0", s.dp)));
        }
        let set = match (&s.shape, &s.particles) {
            (Some(shape), None) => match s.layout.as_str() {
                "lattice" => {
                    let sh = self.shape::<D>(&at("shape"), &key("shape"), shape)?;
                    let origin = sh.bounds().0;
                    let lattice = Lattice::new(s.dp, origin)
                        .map_err(|e| self.error_in(&at("dp"), &key("dp"), e.to_string()))?;
                    ParticleSet::fill(&lattice, &sh)
                        .map_err(|e| self.error_in(&at("shape"), &key("shape"), e.to_string()))?
                }
                "polar" => D::polar(shape, s.dp)
                    .map_err(|m| self.error_in(&at("layout"), &key("layout"), m))?,
                other => {
                    return Err(self.error_in(
                        &at("layout"),
                        &key("layout"),
                        format!("`{other}`: allowed values are lattice, polar"),
                    ))
                }
            },
            (None, Some(file)) => {
                self.particle_file::<D>(&at("particles"), &key("particles"), file)?
            }
            _ => {
                return Err(self.error_in(
                    &at("shape"),
                    &key("shape"),
                    "give exactly one of shape and particles",
                ))
            }
        };
        let v = match &s.velocity {
            Some(v) => self.vector::<D>(&at("velocity"), &key("velocity"), v)?,
            None => D::zero(),
        };
        Ok((set, v))
    }

    /// A CSV particle file: `x,y[,z],volume` per line, blank lines and `#` comments skipped.
    fn particle_file<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        file: &str,
    ) -> Result<ParticleSet<D>, SceneError> {
        let path = self.dir.join(file);
        let text = std::fs::read_to_string(&path)
            .map_err(|e| self.error_in(at, key, format!("{}: {e}", path.display())))?;
        let (mut x, mut v) = (Vec::new(), Vec::new());
        for (no, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let cols: Result<Vec<f64>, _> =
                line.split(',').map(|c| c.trim().parse::<f64>()).collect();
            match cols {
                Ok(c) if c.len() == D::D + 1 => {
                    x.push(D::vector([c[0], c[1], if D::D == 3 { c[2] } else { 0.0 }]));
                    v.push(c[D::D]);
                }
                _ => {
                    return Err(self.error_in(
                        at,
                        key,
                        format!(
                            "{}:{}: expected {} numbers (coordinates, volume)",
                            path.display(),
                            no + 1,
                            D::D + 1
                        ),
                    ))
                }
            }
        }
        ParticleSet::from_parts(x, v)
            .map_err(|e| self.error_in(at, key, format!("{}: {e}", path.display())))
    }

    /// A shape as a region of space.
    fn shape<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        s: &ShapeSpec,
    ) -> Result<Box<dyn Shape<D>>, SceneError> {
        let bad = |m: String| self.error_in(at, key, m);
        let radius = |r: f64, what: &str| -> Result<f64, SceneError> {
            if r.is_finite() && r >= 0.0 {
                Ok(r)
            } else {
                Err(bad(format!("{what} = {r}: allowed >= 0")))
            }
        };
        Ok(match s {
            ShapeSpec::Box { min, max } => {
                let (a, b) = (
                    self.vector::<D>(at, key, min)?,
                    self.vector::<D>(at, key, max)?,
                );
                Box::new(Aabb::<D>::new(a, b).map_err(|e| bad(e.to_string()))?)
            }
            ShapeSpec::Ball { centre, radius: r } => {
                let (c, r) = (self.vector::<D>(at, key, centre)?, radius(*r, "radius")?);
                Box::new(FnShape::new(sphere_bounds::<D>(c, r), move |x| {
                    D::norm(x - c) <= r
                }))
            }
            ShapeSpec::Shell {
                centre,
                inner,
                outer,
            } => {
                let c = self.vector::<D>(at, key, centre)?;
                let (a, b) = (radius(*inner, "inner")?, radius(*outer, "outer")?);
                if a >= b {
                    return Err(bad(format!("inner = {a} must be below outer = {b}")));
                }
                Box::new(FnShape::new(sphere_bounds::<D>(c, b), move |x| {
                    let r = D::norm(x - c);
                    r >= a && r <= b
                }))
            }
            ShapeSpec::Cylinder {
                base,
                axis,
                radius: r,
                length,
                inner,
            } => {
                if D::D != 3 {
                    return Err(bad("cylinder is a 3D shape (in 2D use box)".into()));
                }
                let (b, a) = (
                    self.vector::<D>(at, key, base)?,
                    self.vector::<D>(at, key, axis)?,
                );
                let len = D::norm(a);
                if !(len > 0.0 && length.is_finite() && *length > 0.0) {
                    return Err(bad("axis must be non-zero and length > 0".into()));
                }
                let (e, r, l, ri) = (
                    a / len,
                    radius(*r, "radius")?,
                    *length,
                    radius(*inner, "inner")?,
                );
                let top = b + e * l;
                let mut lo = D::zero();
                let mut hi = D::zero();
                for k in 0..D::D {
                    let (p, q) = (D::component(b, k), D::component(top, k));
                    D::set_component(&mut lo, k, p.min(q) - r);
                    D::set_component(&mut hi, k, p.max(q) + r);
                }
                Box::new(FnShape::new((lo, hi), move |x| {
                    let d = x - b;
                    let s = D::dot(d, e);
                    let radial = D::norm(d - e * s);
                    (0.0..=l).contains(&s) && radial <= r && radial >= ri
                }))
            }
            ShapeSpec::Union(parts) => Box::new(Union::new(
                parts
                    .iter()
                    .map(|p| self.shape::<D>(at, key, p))
                    .collect::<Result<_, _>>()?,
            )),
            ShapeSpec::Intersection(parts) => Box::new(Intersection::new(
                parts
                    .iter()
                    .map(|p| self.shape::<D>(at, key, p))
                    .collect::<Result<_, _>>()?,
            )),
            ShapeSpec::Difference { base, cut } => Box::new(Difference::new(
                self.shape::<D>(at, key, base)?,
                self.shape::<D>(at, key, cut)?,
            )),
        })
    }

    /// A coordinate list as a vector of the scene's dimension.
    fn vector<D: Dim>(&self, at: &At<'_>, key: &str, v: &[f64]) -> Result<D::Vector, SceneError> {
        if v.len() != D::D || v.iter().any(|x| !x.is_finite()) {
            return Err(self.error_in(
                at,
                key,
                format!(
                    "{v:?}: expected {} finite numbers (the scene's dimension)",
                    D::D
                ),
            ));
        }
        Ok(D::vector([v[0], v[1], if D::D == 3 { v[2] } else { 0.0 }]))
    }

    /// The particles of `region` in `body` (every body when `None`).
    fn region<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        set: &ParticleSet<D>,
        ranges: &[(String, Range<usize>)],
        region: &ShapeSpec,
        body: Option<&String>,
    ) -> Result<Vec<u32>, SceneError> {
        let shape = self.shape::<D>(at, key, region)?;
        let range = match body {
            Some(name) => ranges
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, r)| r.clone())
                .ok_or_else(|| {
                    self.error_in(
                        at,
                        key,
                        format!(
                            "no body named `{name}`; the bodies: {}",
                            ranges
                                .iter()
                                .map(|r| r.0.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    )
                })?,
            None => 0..set.len(),
        };
        let p: Vec<u32> = set
            .inside(&shape)
            .into_iter()
            .filter(|&i| range.contains(&(i as usize)))
            .collect();
        if p.is_empty() {
            return Err(self.error_in(at, key, "the region holds no particle"));
        }
        Ok(p)
    }

    fn constraints<D: Dim>(
        &self,
        set: &ParticleSet<D>,
        ranges: &[(String, Range<usize>)],
    ) -> Result<Constraints<D>, SceneError> {
        let mut out = Constraints::new();
        for (k, c) in self.spec.constraints.iter().enumerate() {
            let s: &ConstraintSpec = c.get_ref();
            let key = |name: &str| format!("constraint[{k}].{name}");
            let at = |name| At {
                span: c.span(),
                key: name,
            };
            let particles = self.region(
                &at("region"),
                &key("region"),
                set,
                ranges,
                &s.region,
                s.body.as_ref(),
            )?;
            let velocity = |s: &ConstraintSpec| -> Result<TimeFunction<D>, SceneError> {
                let v = s.velocity.as_ref().ok_or_else(|| {
                    self.error_in(&at("type"), &key("velocity"), "this type needs a velocity")
                })?;
                Ok(TimeFunction::constant(self.vector::<D>(
                    &at("velocity"),
                    &key("velocity"),
                    v,
                )?))
            };
            let constraint = match s.kind.as_str() {
                "fixed" => Constraint::Fixed { particles },
                "velocity" => Constraint::PrescribedVelocity {
                    particles,
                    velocity: velocity(s)?,
                },
                "components" => {
                    let comp = s
                        .components
                        .as_ref()
                        .filter(|c| c.len() == D::D)
                        .ok_or_else(|| {
                            self.error_in(
                                &at("components"),
                                &key("components"),
                                format!("expected {} booleans", D::D),
                            )
                        })?;
                    let mut mask = [false; 3];
                    mask[..D::D].copy_from_slice(comp);
                    Constraint::PrescribedComponents {
                        particles,
                        velocity: velocity(s)?,
                        components: mask,
                    }
                }
                other => {
                    return Err(self.error_in(
                        &at("type"),
                        &key("type"),
                        format!("`{other}`: allowed values are fixed, velocity, components"),
                    ))
                }
            };
            let n = set.len();
            match &s.name {
                Some(name) => out.push_named(name, constraint, n),
                None => out.push(constraint, n),
            }
            .map_err(|e| self.error_in(&at("name"), &key("name"), e.to_string()))?;
        }
        Ok(out)
    }

    fn loads<D: Dim>(
        &self,
        set: &ParticleSet<D>,
        ranges: &[(String, Range<usize>)],
    ) -> Result<Loads<D>, SceneError> {
        let mut out = Loads::new();
        for (k, l) in self.spec.loads.iter().enumerate() {
            let s: &LoadSpec = l.get_ref();
            let key = |name: &str| format!("load[{k}].{name}");
            let at = |name| At {
                span: l.span(),
                key: name,
            };
            match s.kind.as_str() {
                "gravity" => {
                    let g = s.acceleration.as_ref().ok_or_else(|| {
                        self.error_in(
                            &at("type"),
                            &key("acceleration"),
                            "gravity needs an acceleration",
                        )
                    })?;
                    let g = self.vector::<D>(&at("acceleration"), &key("acceleration"), g)?;
                    let region = match &s.region {
                        Some(r) => Some(self.region(
                            &at("region"),
                            &key("region"),
                            set,
                            ranges,
                            r,
                            None,
                        )?),
                        None => None,
                    };
                    out.add_body_acceleration(region, TimeFunction::constant(g));
                }
                "point" => {
                    let (f, x) = match (&s.force, &s.at) {
                        (Some(f), Some(x)) => (f, x),
                        _ => {
                            return Err(self.error_in(
                                &at("type"),
                                &key("force"),
                                "a point load needs force and at",
                            ))
                        }
                    };
                    let f = self.vector::<D>(&at("force"), &key("force"), f)?;
                    let x = self.vector::<D>(&at("at"), &key("at"), x)?;
                    let i = set.nearest(x).expect("a scene has particles") as u32;
                    out.add_point_force(i, TimeFunction::constant(f));
                }
                other => {
                    return Err(self.error_in(
                        &at("type"),
                        &key("type"),
                        format!("`{other}`: allowed values are gravity, point"),
                    ))
                }
            }
        }
        Ok(out)
    }

    fn tools<D: Dim>(&self) -> Result<Vec<RigidTool<D>>, SceneError> {
        let mut out = Vec::new();
        for (k, t) in self.spec.tools.iter().enumerate() {
            let s = t.get_ref();
            let key = |name: &str| format!("tool[{k}].{name}");
            let at = |name| At {
                span: t.span(),
                key: name,
            };
            let shape = match &s.shape {
                ToolShapeSpec::Box { min, max } => ToolShape::cuboid(
                    self.vector::<D>(&at("shape"), &key("shape"), min)?,
                    self.vector::<D>(&at("shape"), &key("shape"), max)?,
                ),
                ToolShapeSpec::Ball { centre, radius } => ToolShape::ball(
                    self.vector::<D>(&at("shape"), &key("shape"), centre)?,
                    *radius,
                ),
                ToolShapeSpec::HalfSpace { point, normal } => ToolShape::half_space(
                    self.vector::<D>(&at("shape"), &key("shape"), point)?,
                    self.vector::<D>(&at("shape"), &key("shape"), normal)?,
                ),
            }
            .map_err(|e| self.error_in(&at("shape"), &key("shape"), e.to_string()))?;
            let motion = match &s.direction {
                Some(d) => ToolMotion::new(
                    self.vector::<D>(&at("direction"), &key("direction"), d)?,
                    s.speed,
                    s.ramp_time,
                    s.travel.unwrap_or(f64::INFINITY),
                ),
                None if s.speed == 0.0 => Ok(ToolMotion::fixed()),
                None => Err(sph_core::Error::invalid(
                    "tool direction",
                    "none",
                    "a direction when speed > 0",
                )),
            }
            .map_err(|e| self.error_in(&at("speed"), &key("motion"), e.to_string()))?;
            out.push(RigidTool::new(&s.name, shape, motion));
        }
        Ok(out)
    }

    fn schedule(&self, end_time: f64) -> Result<Schedule, SceneError> {
        let o = &self.spec.output;
        for (k, v) in [
            ("snapshot_interval", o.snapshot_interval),
            ("monitor_interval", o.monitor_interval),
            ("probe_interval", o.probe_interval),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(SceneError {
                        file: self.file.clone(),
                        line: find_key_line(&self.text, k),
                        key: format!("output.{k}"),
                        message: format!("{v}: allowed >= 0"),
                    });
                }
            }
        }
        Ok(Schedule {
            end_time,
            snapshot_interval: o
                .snapshot_interval
                .unwrap_or(end_time / f64::from(sph_driver::DEFAULT_SNAPSHOTS)),
            monitor_interval: o
                .monitor_interval
                .filter(|&m| m > 0.0)
                .unwrap_or(end_time / 200.0),
            probe_interval: o.probe_interval.unwrap_or(0.0),
            max_steps: o.max_steps.unwrap_or(0),
        })
    }

    fn core(&self, span: Range<usize>, key: &str, e: sph_core::Error) -> SceneError {
        self.error(span, key, e.to_string())
    }

    /// A driver refusal, pointing at the output key or the end time it names.
    fn driver(&self, e: DriverError) -> SceneError {
        let (key, line) = match &e {
            DriverError::InvalidValue { key, .. } => {
                let line = find_key_line(&self.text, key);
                let prefix = if key == "end_time" { "" } else { "output." };
                (format!("{prefix}{key}"), line)
            }
            _ => ("run".into(), None),
        };
        SceneError {
            file: self.file.clone(),
            line,
            key,
            message: e.to_string(),
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

fn family_of(method: &str) -> Option<Family> {
    match method {
        "tl" | "tl-hf" | "tl-gm" => Some(Family::Tl),
        "ul-og" | "ul-oas" | "ul-enog" => Some(Family::Ul),
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

    /// The first wrong type, or the first key the method does not know.
    fn finish(&self, known: &[&str]) -> Result<(), String> {
        if let Some(m) = self.wrong.borrow().clone() {
            return Err(m);
        }
        match self.table.keys().find(|k| !known.contains(&k.as_str())) {
            Some(k) => Err(format!(
                "`{k}` is not a key of this method; its keys: {}",
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

/// The first line anywhere in the file that sets `key`.
fn find_key_line(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            l.trim_start()
                .strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map(|k| k + 1)
}

/// 1-based line of byte `offset`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// The line of `key = …` in the table starting at `span` (up to the next table header; a span
/// of an array-of-tables entry may cover only its header), if written there.
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
                return Some(line_of(text, offset));
            }
        }
        // Inline tables: `shape = { box = … }` on one line.
        if line.contains(&format!(" {key} =")) || line.contains(&format!("{{{key} =")) {
            return Some(line_of(text, offset));
        }
        offset += line.len();
    }
    None
}
