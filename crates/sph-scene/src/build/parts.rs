//! The parts of a scene file a run is built from: the material, the bodies (shapes, particle
//! files), regions, constraints, loads, tools and the output schedule.

use super::*;

/// The scene's materials ([`Scene::materials`]).
pub(super) struct Materials {
    /// Constants and law of each material, in the file's order.
    pub built: Vec<(ElasticConstants, MaterialModel)>,
    /// Each body's material (an index into `built`).
    pub of_body: Vec<usize>,
    /// Each material's table (its span and keys), in the order of `built`.
    pub specs: Vec<(Range<usize>, MaterialSpec)>,
}

/// One body's particles, uniform initial velocity and, for the fitted layout, the fit's report.
pub(super) type BodyParts<D> = (ParticleSet<D>, <D as Dim>::Vector, Option<FitReport>);

/// A body's particles with the solid they fill (`None` for a particle file), for the overlap
/// check of [`Scene::check_overlaps`].
pub(super) type BodySolid<D> = Option<Box<dyn Shape<D>>>;

/// Longest line of a particle file, bytes: a line holds four numbers.
pub(super) const MAX_PARTICLE_LINE: usize = 4096;

impl Scene {
    /// A material's constants and law, with the law's own options (`c2_fraction`, or `c1`,
    /// `c2`, `lambda`, for `mooney-rivlin`; `deviator` for `kirchhoff-vol-dev`); `span` is its
    /// table's, `prefix` the path errors name (`material`, `material.NAME`).
    pub(super) fn material(
        &self,
        span: Range<usize>,
        s: &MaterialSpec,
        prefix: &str,
    ) -> Result<(ElasticConstants, MaterialModel), SceneError> {
        let at = |key| At {
            span: span.clone(),
            key,
        };
        // A plastic law's elastic part is the constants (hypoelastic in UL, Hencky in TL: the
        // methods that carry it use only them); the others refuse it (`Scene::run_in`).
        let kind: MaterialKind = if super::plasticity::is_plastic(&s.law) {
            MaterialKind::LinearElastic
        } else {
            s.law.parse().map_err(|e: sph_core::Error| {
                self.error_in(
                    &at("law"),
                    &format!("{prefix}.law"),
                    format!(
                        "{e}, or the plastic {}",
                        sph_materials::PLASTIC_LAW_NAMES.join(", ")
                    ),
                )
            })?
        };
        // Options of another law: an error, never ignored.
        let mooney = matches!(kind, MaterialKind::MooneyRivlin { .. });
        for (key, given, owner) in [
            ("c2_fraction", s.c2_fraction.is_some(), mooney),
            ("c1", s.c1.is_some(), mooney),
            ("c2", s.c2.is_some(), mooney),
            ("lambda", s.lambda.is_some(), mooney),
            (
                "deviator",
                s.deviator.is_some(),
                matches!(kind, MaterialKind::KirchhoffVolDev { .. }),
            ),
        ] {
            if given && !owner {
                let law = if key == "deviator" {
                    "kirchhoff-vol-dev"
                } else {
                    "mooney-rivlin"
                };
                return Err(self.error_in(
                    &at(key),
                    &format!("{prefix}.{key}"),
                    format!("a key of law = \"{law}\", not of law = \"{}\"", s.law),
                ));
            }
        }
        let law_error = |e: sph_core::Error| {
            let key = match &e {
                sph_core::Error::InvalidParameter { field, .. } => field.clone(),
                _ => "law".into(),
            };
            let at = At {
                span: span.clone(),
                key: &key,
            };
            self.error_in(&at, &format!("{prefix}.{key}"), e.to_string())
        };
        if let (Some(c1), Some(c2), Some(lambda)) = (s.c1, s.c2, s.lambda) {
            let elastic = [
                ("youngs_modulus", s.youngs_modulus.is_some()),
                ("nu", s.nu.is_some()),
                ("bulk_modulus", s.bulk_modulus.is_some()),
                ("shear_modulus", s.shear_modulus.is_some()),
                ("c2_fraction", s.c2_fraction.is_some()),
            ];
            if let Some((key, _)) = elastic.iter().find(|k| k.1) {
                return Err(self.error_in(
                    &at(key),
                    &format!("{prefix}.{key}"),
                    "give c1, c2 and lambda, or the elastic constants (with c2_fraction), not both",
                ));
            }
            let law = MooneyRivlinLike::new(c1, c2, lambda, s.density).map_err(law_error)?;
            return Ok((
                *Material::<sph_core::D2>::constants(&law),
                MaterialModel::MooneyRivlin(law),
            ));
        }
        if s.c1.is_some() || s.c2.is_some() || s.lambda.is_some() {
            return Err(self.error_in(
                &at("c1"),
                prefix,
                "mooney-rivlin by its own constants needs all of c1, c2 and lambda",
            ));
        }
        let constants = match (s.youngs_modulus, s.nu, s.bulk_modulus, s.shear_modulus) {
            (Some(e), Some(nu), None, None) => ElasticConstants::from_youngs(e, nu, s.density),
            (None, None, Some(k), Some(g)) => ElasticConstants::from_bulk_shear(k, g, s.density),
            _ => {
                return Err(self.error_in(
                    &at("youngs_modulus"),
                    prefix,
                    "give youngs_modulus and nu, or bulk_modulus and shear_modulus",
                ))
            }
        }
        .map_err(|e| {
            let key = match &e {
                sph_core::Error::InvalidParameter { field, .. } => field.clone(),
                _ => prefix.into(),
            };
            let key = if key == "poisson_ratio" {
                "nu".to_string()
            } else {
                key
            };
            let at = At {
                span: span.clone(),
                key: &key,
            };
            self.error_in(&at, &format!("{prefix}.{key}"), e.to_string())
        })?;
        let kind = match kind {
            MaterialKind::MooneyRivlin { c2_fraction } => MaterialKind::MooneyRivlin {
                c2_fraction: s.c2_fraction.unwrap_or(c2_fraction),
            },
            MaterialKind::KirchhoffVolDev { deviator } => MaterialKind::KirchhoffVolDev {
                deviator: match s.deviator.as_deref() {
                    None => deviator,
                    Some("spatial") => DeviatorDimension::Spatial,
                    Some("embedded-3d") => DeviatorDimension::Embedded3d,
                    Some(other) => {
                        return Err(self.error_in(
                            &at("deviator"),
                            &format!("{prefix}.deviator"),
                            format!("`{other}`: allowed values are spatial, embedded-3d"),
                        ))
                    }
                },
            },
            k => k,
        };
        let law = kind.build(constants).map_err(law_error)?;
        Ok((constants, law))
    }

    /// The scene's materials (constants and law, in the file's order) and each body's (an
    /// index into them). `[material]` is every body's; a body may name it if it has a `name`.
    /// With `[[material]]`, every entry needs a distinct name, a body names its material (or
    /// takes the only one), and every material must be some body's.
    pub(super) fn materials(&self) -> Result<Materials, SceneError> {
        let spec = &self.spec;
        let span = spec.material.span();
        // (span, spec, path prefix, name) of every material.
        let entries: Vec<(Range<usize>, &MaterialSpec, String, Option<&str>)> =
            match spec.material.get_ref() {
                MaterialsSpec::One(m) => {
                    vec![(span.clone(), m, "material".into(), m.name.as_deref())]
                }
                MaterialsSpec::List(list) => {
                    let mut out = Vec::with_capacity(list.len());
                    for m in list {
                        // Present and unique: checked at parse time (check_names).
                        let name = m.get_ref().name.as_deref().unwrap_or_default();
                        out.push((
                            m.span(),
                            m.get_ref(),
                            format!("material.{name}"),
                            Some(name),
                        ));
                    }
                    out
                }
            };
        let names = || {
            let named: Vec<String> = entries
                .iter()
                .filter_map(|e| e.3.map(|n| format!("`{n}`")))
                .collect();
            if named.is_empty() {
                "none has a name".to_string()
            } else {
                format!("the materials: {}", named.join(", "))
            }
        };
        let mut of_body = Vec::with_capacity(spec.bodies.len());
        for (k, b) in spec.bodies.iter().enumerate() {
            let at = At {
                span: b.span(),
                key: "material",
            };
            let index = match b.get_ref().material.as_deref() {
                Some(name) => entries
                    .iter()
                    .position(|e| e.3 == Some(name))
                    .ok_or_else(|| {
                        self.error_in(
                            &at,
                            &format!("body[{k}].material"),
                            format!("`{name}`: no material of that name ({})", names()),
                        )
                    })?,
                None if entries.len() == 1 => 0,
                None => {
                    return Err(self.error(
                        b.span(),
                        &format!("body[{k}].material"),
                        format!("required: the scene has several [[material]] ({})", names()),
                    ))
                }
            };
            of_body.push(index);
        }
        if let Some((k, e)) = entries
            .iter()
            .enumerate()
            .find(|(k, _)| !of_body.contains(k))
        {
            return Err(self.error(
                e.0.clone(),
                &e.2,
                format!(
                    "no body uses material[{k}] (give a [[body]] material = \"{}\", or remove it)",
                    e.3.unwrap_or_default()
                ),
            ));
        }
        let mut built = Vec::with_capacity(entries.len());
        for (span, m, prefix, _) in &entries {
            built.push(self.material(span.clone(), m, prefix)?);
        }
        let specs = entries
            .iter()
            .map(|(span, m, _, _)| (span.clone(), (*m).clone()))
            .collect();
        Ok(Materials {
            built,
            of_body,
            specs,
        })
    }

    /// One body's particles and uniform initial velocity, and the report of a fitted layout.
    pub(super) fn body<D: SceneDim>(
        &self,
        k: usize,
        b: &Spanned<BodySpec>,
    ) -> Result<BodyParts<D>, SceneError> {
        self.body_and_solid::<D>(k, b).map(|(parts, _)| parts)
    }

    /// [`Scene::body`] and the solid its particles fill.
    pub(super) fn body_and_solid<D: SceneDim>(
        &self,
        k: usize,
        b: &Spanned<BodySpec>,
    ) -> Result<(BodyParts<D>, BodySolid<D>), SceneError> {
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
        let mut report = None;
        let mut body_solid = None;
        let file_shape = s
            .shape
            .as_ref()
            .is_some_and(|s| s.geometry_file().is_some());
        let layout = s
            .layout
            .as_deref()
            .unwrap_or(if file_shape { "fitted" } else { "lattice" });
        if s.relax_steps.is_some() && layout != "fitted" {
            return Err(self.error_in(
                &at("relax_steps"),
                &key("relax_steps"),
                format!("belongs to the fitted layout (this body's layout is {layout})"),
            ));
        }
        let set = match (&s.shape, &s.particles) {
            (Some(shape), None) => match layout {
                "fitted" => {
                    let solid = match shape.geometry_file() {
                        Some(g) => self.file_solid::<D>(
                            &at("shape"),
                            &key("shape"),
                            matches!(shape, ShapeSpec::Mesh { .. }),
                            g,
                        )?,
                        None => {
                            return Err(self.error_in(
                                &at("layout"),
                                &key("layout"),
                                "the fitted layout fills a mesh (3D) or an outline (2D) shape",
                            ))
                        }
                    };
                    let options = FitOptions {
                        relax_steps: s.relax_steps.unwrap_or(DEFAULT_RELAX_STEPS),
                        ..FitOptions::default()
                    };
                    let (set, r) = fit::<D>(&solid, s.dp, &options)
                        .map_err(|e| self.error_in(&at("shape"), &key("shape"), e.to_string()))?;
                    report = Some(r);
                    body_solid = Some(Box::new(solid) as Box<dyn Shape<D>>);
                    set
                }
                "lattice" => {
                    let sh = self.shape::<D>(&at("shape"), &key("shape"), shape)?;
                    let origin = sh.bounds().0;
                    let lattice = Lattice::new(s.dp, origin)
                        .map_err(|e| self.error_in(&at("dp"), &key("dp"), e.to_string()))?;
                    let set = ParticleSet::fill(&lattice, &sh)
                        .map_err(|e| self.error_in(&at("shape"), &key("shape"), e.to_string()))?;
                    body_solid = Some(sh);
                    set
                }
                "polar" => {
                    let set = D::polar(shape, s.dp)
                        .map_err(|m| self.error_in(&at("layout"), &key("layout"), m))?;
                    body_solid = Some(self.shape::<D>(&at("shape"), &key("shape"), shape)?);
                    set
                }
                other => {
                    return Err(self.error_in(
                        &at("layout"),
                        &key("layout"),
                        format!("`{other}`: allowed values are lattice, polar, fitted"),
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
        Ok(((set, v, report), body_solid))
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
            ShapeSpec::Mesh { .. } | ShapeSpec::Outline { .. } => match s.geometry_file() {
                Some(g) => Box::new(self.file_solid::<D>(
                    at,
                    key,
                    matches!(s, ShapeSpec::Mesh { .. }),
                    g,
                )?),
                None => unreachable!("a mesh or outline has a file"),
            },
        })
    }

    /// A mesh (`mesh`) or outline shape: the file (relative to the scene file) read and placed.
    pub(super) fn file_solid<D: Dim>(
        &self,
        at: &At<'_>,
        key: &str,
        mesh: bool,
        g: GeometryFileSpec<'_>,
    ) -> Result<FileSolid<D>, SceneError> {
        let kind = if mesh { "mesh" } else { "outline" };
        let bad = |field: &str, m: String| self.error_in(at, &format!("{key}.{kind}.{field}"), m);
        if mesh && D::D != 3 {
            return Err(bad(
                "file",
                "a mesh is a 3D shape (in 2D use outline)".into(),
            ));
        }
        if !mesh && D::D != 2 {
            return Err(bad(
                "file",
                "an outline is a 2D shape (in 3D use mesh)".into(),
            ));
        }
        let scale = g.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(bad(
                "scale",
                format!("{}: allowed: > 0 and finite", Num(scale)),
            ));
        }
        let translate = match g.translate {
            Some(t) => D::to_vec3(self.vector::<D>(at, &format!("{key}.{kind}.translate"), t)?),
            None => DVec3::ZERO,
        };
        let (axis, degrees) = match g.rotate {
            Some(r) => {
                let axis = match &r.axis {
                    Some(a) if a.len() == 3 && a.iter().all(|c| c.is_finite()) => {
                        DVec3::new(a[0], a[1], a[2])
                    }
                    Some(a) => {
                        return Err(bad(
                            "rotate.axis",
                            format!("{a:?}: expected 3 finite numbers"),
                        ))
                    }
                    None => DVec3::Z,
                };
                if axis.length() == 0.0 {
                    return Err(bad("rotate.axis", "[0, 0, 0]: allowed: non-zero".into()));
                }
                if !mesh && (axis.x != 0.0 || axis.y != 0.0) {
                    return Err(bad(
                        "rotate.axis",
                        format!("{:?}: a 2D outline turns about z, [0, 0, 1]", r.axis),
                    ));
                }
                if !r.degrees.is_finite() {
                    return Err(bad(
                        "rotate.degrees",
                        format!("{}: allowed: finite", Num(r.degrees)),
                    ));
                }
                (axis, r.degrees)
            }
            None => (DVec3::Z, 0.0),
        };
        let placement = Placement {
            scale,
            axis,
            degrees,
            translate,
        };
        let path = self.dir.join(g.file);
        let solid = if mesh {
            FileSolid::<D>::mesh(&path, &placement)
        } else {
            FileSolid::<D>::outline(&path, &placement)
        };
        solid.map_err(|e| bad("file", e.to_string()))
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

    /// An amplitude curve, checked.
    pub(super) fn amplitude(
        &self,
        at: &At<'_>,
        key: &str,
        spec: Option<&AmplitudeSpec>,
    ) -> Result<Option<Amplitude>, SceneError> {
        let Some(spec) = spec else {
            return Ok(None);
        };
        let bad = |e: sph_core::Error| self.error_in(at, key, e.to_string());
        let a = match spec {
            AmplitudeSpec::Ramp { start, duration } => Amplitude::ramp(*start, *duration),
            AmplitudeSpec::SmoothStep { start, duration } => {
                Amplitude::smooth_step(*start, *duration)
            }
            AmplitudeSpec::Table(points) => {
                let mut pairs = Vec::with_capacity(points.len());
                for (k, p) in points.iter().enumerate() {
                    match p.as_slice() {
                        [t, a] => pairs.push((*t, *a)),
                        _ => {
                            return Err(self.error_in(
                                at,
                                key,
                                format!("table point {k} = {p:?}: expected [time, value]"),
                            ))
                        }
                    }
                }
                Amplitude::table(pairs)
            }
            AmplitudeSpec::Sine {
                frequency,
                amplitude,
                phase,
                offset,
            } => Amplitude::sine(*frequency, *amplitude, *phase, *offset),
        }
        .map_err(bad)?;
        Ok(Some(a))
    }

    /// `v`, or `v · a(t)` with an amplitude.
    fn scaled<D: Dim>(v: D::Vector, amplitude: Option<Amplitude>) -> TimeFunction<D> {
        match amplitude {
            None => TimeFunction::constant(v),
            Some(a) => TimeFunction::scaled(v, a),
        }
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
                let v = self.vector::<D>(&at("velocity"), &key("velocity"), v)?;
                let a =
                    self.amplitude(&at("amplitude"), &key("amplitude"), s.amplitude.as_ref())?;
                Ok(Self::scaled(v, a))
            };
            if s.kind == "fixed" {
                for (name, given) in [
                    ("velocity", s.velocity.is_some()),
                    ("components", s.components.is_some()),
                    ("amplitude", s.amplitude.is_some()),
                ] {
                    if given {
                        return Err(self.error_in(
                            &at(name),
                            &key(name),
                            "a fixed constraint takes no velocity, components or amplitude",
                        ));
                    }
                }
            }
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

    /// The body accelerations and point forces, and the surface pressures (which only a
    /// method with a deformation gradient applies).
    pub(super) fn loads<D: Dim>(
        &self,
        set: &ParticleSet<D>,
        ranges: &[(String, Range<usize>)],
        dps: &[f64],
    ) -> Result<(Loads<D>, Vec<SurfacePressure<D>>), SceneError> {
        let mut out = Loads::new();
        let mut pressures = Vec::new();
        for (k, l) in self.spec.loads.iter().enumerate() {
            let s: &LoadSpec = l.get_ref();
            let key = |name: &str| format!("load[{k}].{name}");
            let at = |name| At {
                span: l.span(),
                key: name,
            };
            // The keys of each type; any other given is an error.
            let keys: &[&str] = match s.kind.as_str() {
                "gravity" => &["acceleration", "region", "amplitude"],
                "point" => &["force", "at", "amplitude"],
                "pressure" => &["pressure", "region", "body", "area", "normal", "amplitude"],
                other => {
                    return Err(self.error_in(
                        &at("type"),
                        &key("type"),
                        format!("`{other}`: allowed values are gravity, point, pressure"),
                    ))
                }
            };
            for (name, given) in [
                ("acceleration", s.acceleration.is_some()),
                ("force", s.force.is_some()),
                ("at", s.at.is_some()),
                ("region", s.region.is_some()),
                ("body", s.body.is_some()),
                ("pressure", s.pressure.is_some()),
                ("area", s.area.is_some()),
                ("normal", s.normal.is_some()),
                ("amplitude", s.amplitude.is_some()),
            ] {
                if given && !keys.contains(&name) {
                    return Err(self.error_in(
                        &at(name),
                        &key(name),
                        format!(
                            "not a key of a {} load; its keys: {}",
                            s.kind,
                            keys.join(", ")
                        ),
                    ));
                }
            }
            let amplitude =
                self.amplitude(&at("amplitude"), &key("amplitude"), s.amplitude.as_ref())?;
            let needs = |name: &str| {
                self.error_in(
                    &at("type"),
                    &key(name),
                    format!("a {} load needs {name}", s.kind),
                )
            };
            match s.kind.as_str() {
                "gravity" => {
                    let g = s
                        .acceleration
                        .as_ref()
                        .ok_or_else(|| needs("acceleration"))?;
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
                    out.add_body_acceleration(region, Self::scaled(g, amplitude));
                }
                "point" => {
                    let f = s.force.as_ref().ok_or_else(|| needs("force"))?;
                    let x = s.at.as_ref().ok_or_else(|| needs("at"))?;
                    let f = self.vector::<D>(&at("force"), &key("force"), f)?;
                    let x = self.vector::<D>(&at("at"), &key("at"), x)?;
                    let i = set.nearest(x).expect("a scene has particles") as u32;
                    out.add_point_force(i, Self::scaled(f, amplitude));
                }
                _ => {
                    let p = s.pressure.ok_or_else(|| needs("pressure"))?;
                    if !p.is_finite() {
                        return Err(self.error_in(
                            &at("pressure"),
                            &key("pressure"),
                            format!("{p}: allowed: finite (Pa)"),
                        ));
                    }
                    let region = s.region.as_ref().ok_or_else(|| needs("region"))?;
                    let candidates = self.region(
                        &at("region"),
                        &key("region"),
                        set,
                        ranges,
                        region,
                        s.body.as_ref(),
                    )?;
                    let mut surface = Vec::new();
                    for (b, (_, r)) in ranges.iter().enumerate() {
                        let mine: Vec<u32> = candidates
                            .iter()
                            .copied()
                            .filter(|&i| r.contains(&(i as usize)))
                            .collect();
                        if !mine.is_empty() {
                            surface.extend(
                                surface_of::<D>(set.positions(), dps[b], &mine)
                                    .map_err(|e| {
                                        self.error_in(&at("region"), &key("region"), e.to_string())
                                    })?
                                    .into_iter()
                                    .map(|p| (p, dps[b])),
                            );
                        }
                    }
                    if surface.is_empty() {
                        return Err(self.error_in(
                            &at("region"),
                            &key("region"),
                            "the region holds particles but none on the body's surface",
                        ));
                    }
                    let normals: Vec<D::Vector> = match &s.normal {
                        Some(n) => {
                            let n = self.vector::<D>(&at("normal"), &key("normal"), n)?;
                            let len = D::norm(n);
                            if len == 0.0 {
                                return Err(self.error_in(
                                    &at("normal"),
                                    &key("normal"),
                                    "must not be zero",
                                ));
                            }
                            vec![n / len; surface.len()]
                        }
                        None => surface.iter().map(|(p, _)| p.normal).collect(),
                    };
                    let areas: Vec<f64> = match s.area {
                        Some(a) if a.is_finite() && a > 0.0 => {
                            vec![a / surface.len() as f64; surface.len()]
                        }
                        Some(a) => {
                            return Err(self.error_in(
                                &at("area"),
                                &key("area"),
                                format!(
                                    "{a}: allowed: > 0 and finite (m², m per unit depth in 2D)"
                                ),
                            ))
                        }
                        None => surface
                            .iter()
                            .map(|(p, dp)| set.volumes()[p.index as usize] / dp)
                            .collect(),
                    };
                    pressures.push(SurfacePressure {
                        particles: surface.iter().map(|(p, _)| p.index).collect(),
                        normals: Some(normals),
                        areas: Some(areas),
                        pressure: match amplitude {
                            None => PressureFunction::constant(p),
                            Some(a) => PressureFunction::scaled(p, a),
                        },
                    });
                }
            }
        }
        Ok((out, pressures))
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
                ToolShapeSpec::Mesh { .. } | ToolShapeSpec::Outline { .. } => {
                    match s.shape.geometry_file() {
                        Some(g) => self
                            .file_solid::<D>(
                                &at("shape"),
                                &key("shape"),
                                matches!(s.shape, ToolShapeSpec::Mesh { .. }),
                                g,
                            )?
                            .into_tool_shape(),
                        None => unreachable!("a mesh or outline has a file"),
                    }
                }
            }
            .map_err(|e| self.error_in(&at("shape"), &key("shape"), e.to_string()))?;
            let motion = self.tool_motion::<D>(&at, &key, s)?;
            // One coefficient given: the other is the same (no static excess).
            let mu_s = s.friction_static.or(s.friction_kinetic).unwrap_or(0.0);
            let mu_k = s.friction_kinetic.or(s.friction_static).unwrap_or(0.0);
            let friction = Friction::new(mu_s, mu_k).map_err(|e| {
                let field = match &e {
                    sph_core::Error::InvalidParameter { field, .. } => field.clone(),
                    _ => "friction_static".into(),
                };
                let name = if field == "friction_kinetic" {
                    "friction_kinetic"
                } else {
                    "friction_static"
                };
                self.error_in(&at(name), &key(name), e.to_string())
            })?;
            out.push(RigidTool::new(&s.name, shape, motion).with_friction(friction));
        }
        Ok(out)
    }

    /// A tool's motion: a straight line (`direction`, `speed`, `ramp_time`, `travel`), a
    /// `path`, or a `velocity` curve; and a `rotation`.
    fn tool_motion<'k, D: Dim>(
        &self,
        at: &dyn Fn(&'k str) -> At<'k>,
        key: &dyn Fn(&str) -> String,
        s: &ToolSpec,
    ) -> Result<ToolMotion<D>, SceneError> {
        let line = s.direction.is_some() || s.speed != 0.0 || s.ramp_time != 0.0;
        let line = line || s.travel.is_some();
        let given: Vec<&str> = [
            ("direction", line),
            ("path", s.path.is_some()),
            ("velocity", s.velocity.is_some()),
        ]
        .iter()
        .filter(|g| g.1)
        .map(|g| g.0)
        .collect();
        if given.len() > 1 {
            return Err(self.error_in(
                &at(given[1]),
                &key(given[1]),
                format!(
                    "a tool moves along a line (direction, speed, ramp_time, travel), a path or a \
                     velocity curve: {} and {} were both given",
                    given[0], given[1]
                ),
            ));
        }
        if s.amplitude.is_some() && s.velocity.is_none() {
            return Err(self.error_in(
                &at("amplitude"),
                &key("amplitude"),
                "a tool's amplitude scales its velocity: give velocity too",
            ));
        }
        let bad = |name: &'k str| {
            move |e: sph_core::Error| self.error_in(&at(name), &key(name), e.to_string())
        };
        let motion = if let Some(path) = &s.path {
            let mut points = Vec::with_capacity(path.len());
            for (n, p) in path.iter().enumerate() {
                if p.len() != D::D + 1 {
                    return Err(self.error_in(
                        &at("path"),
                        &key("path"),
                        format!(
                            "waypoint {n} = {p:?}: expected [time, {}]",
                            ["ux", "uy", "uz"][..D::D].join(", ")
                        ),
                    ));
                }
                points.push((p[0], self.vector::<D>(&at("path"), &key("path"), &p[1..])?));
            }
            ToolMotion::path(points).map_err(bad("path"))?
        } else if let Some(v) = &s.velocity {
            let v = self.vector::<D>(&at("velocity"), &key("velocity"), v)?;
            let a = self.amplitude(&at("amplitude"), &key("amplitude"), s.amplitude.as_ref())?;
            ToolMotion::translating(v, a).map_err(bad("velocity"))?
        } else {
            match &s.direction {
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
            .map_err(|e| self.error_in(&at("speed"), &key("motion"), e.to_string()))?
        };
        let Some(r) = &s.rotation else {
            return Ok(motion);
        };
        let centre = self.vector::<D>(&at("rotation"), &key("rotation.centre"), &r.centre)?;
        let axis = match (&r.axis, D::D) {
            (Some(a), _) if a.len() == 3 && a.iter().all(|x| x.is_finite()) => {
                DVec3::new(a[0], a[1], a[2])
            }
            (None, 2) => DVec3::Z,
            (Some(a), _) => {
                return Err(self.error_in(
                    &at("rotation"),
                    &key("rotation.axis"),
                    format!("{a:?}: expected 3 finite numbers"),
                ))
            }
            (None, _) => {
                return Err(self.error_in(
                    &at("rotation"),
                    &key("rotation.axis"),
                    "a 3D rotation needs its axis",
                ))
            }
        };
        let a = self.amplitude(
            &at("rotation"),
            &key("rotation.amplitude"),
            r.amplitude.as_ref(),
        )?;
        motion
            .rotating(centre, axis, r.angular_velocity, a)
            .map_err(|e| self.error_in(&at("rotation"), &key("rotation"), e.to_string()))
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
                    return Err(self.error_at_key(
                        k,
                        &format!("output.{k}"),
                        format!("{}: allowed >= 0", Num(v)),
                    ));
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
