//! The parts of a scene file a run is built from: the material, the bodies (shapes, particle
//! files), regions, constraints, loads, tools and the output schedule.

use super::*;

/// Longest line of a particle file, bytes: a line holds four numbers.
pub(super) const MAX_PARTICLE_LINE: usize = 4096;

impl Scene {
    /// The material's constants and law.
    pub(super) fn material(
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
    pub(super) fn body<D: SceneDim>(
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
            return Err(self.error_in(
                &at("dp"),
                &key("dp"),
                format!("{}: allowed: > 0", Num(s.dp)),
            ));
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
    /// Read as a stream, line by line (at most [`MAX_PARTICLE_LINE`] bytes each), the particles
    /// counted against the memory budget as they come, so a file far larger than memory is
    /// refused before it is held (a FIFO or device is refused at once).
    pub(super) fn particle_file<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        file: &str,
    ) -> Result<ParticleSet<D>, SceneError> {
        use std::io::{BufRead, Read};
        let path = self.dir.join(file);
        let fail = |m: String| self.error_in(at, key, format!("{}: {m}", path.display()));
        let (handle, _) = sph_output::input::open_input(&path, u64::MAX)
            .map_err(|e| self.error_in(at, key, e.to_string()))?;
        let mut reader = std::io::BufReader::new(handle);
        let (mut x, mut v) = (Vec::new(), Vec::new());
        let mut line = Vec::new();
        let mut allowed = sph_core::budget::remaining::<D>();
        for no in 1.. {
            line.clear();
            let n = (&mut reader)
                .take(MAX_PARTICLE_LINE as u64 + 1)
                .read_until(b'\n', &mut line)
                .map_err(|e| fail(format!("cannot read it: {e}")))?;
            if n == 0 {
                break;
            }
            if n > MAX_PARTICLE_LINE {
                return Err(fail(format!(
                    "line {no} is longer than {MAX_PARTICLE_LINE} bytes"
                )));
            }
            let text = std::str::from_utf8(&line)
                .map_err(|_| fail(format!("line {no} is not UTF-8 text")))?
                .trim();
            if text.is_empty() || text.starts_with('#') {
                continue;
            }
            let cols: Result<Vec<f64>, _> =
                text.split(',').map(|c| c.trim().parse::<f64>()).collect();
            match cols {
                Ok(c) if c.len() == D::D + 1 => {
                    x.push(D::vector([c[0], c[1], if D::D == 3 { c[2] } else { 0.0 }]));
                    v.push(c[D::D]);
                }
                _ => {
                    return Err(fail(format!(
                        "{no}: expected {} numbers (coordinates, volume)",
                        D::D + 1
                    )))
                }
            }
            if x.len() as u64 > allowed {
                allowed = sph_core::budget::remaining::<D>();
                if x.len() as u64 > allowed {
                    let what = format!("the particle file {}", path.display());
                    let e = sph_core::budget::exceeded::<D>(x.len() as f64, &what);
                    return Err(self.error_in(
                        at,
                        key,
                        format!("{e} (and it goes on: stopped reading at line {no})"),
                    ));
                }
            }
        }
        sph_core::budget::book::<D>(x.len() as u64);
        ParticleSet::from_parts(x, v).map_err(|e| fail(e.to_string()))
    }

    /// A shape as a region of space.
    pub(super) fn shape<D: Dim>(
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
                Err(bad(format!("{what} = {}: allowed >= 0", Num(r))))
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
                    return Err(bad(format!(
                        "inner = {} must be below outer = {}",
                        Num(a),
                        Num(b)
                    )));
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
    pub(super) fn vector<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        v: &[f64],
    ) -> Result<D::Vector, SceneError> {
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
    pub(super) fn region<D: Dim>(
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

    pub(super) fn constraints<D: Dim>(
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

    pub(super) fn loads<D: Dim>(
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

    pub(super) fn tools<D: Dim>(&self) -> Result<Vec<RigidTool<D>>, SceneError> {
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

    pub(super) fn schedule(&self, end_time: f64) -> Result<Schedule, SceneError> {
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
                        message: format!("{}: allowed >= 0", Num(v)),
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
}
