//! What a scene is checked for before any work, and where the solvers' refusals point: names
//! that are names (never paths), keys of the scene's method only, bodies that are more than a
//! handful of particles, and a solver's error sent back to the table that caused it.

use super::parts::BodySolid;
use super::*;
use sph_core::error::check_name;
use sph_core::scene::MAX_PROBES;

/// Fewest particles a body needs along each axis: a kernel support fits inside it. A body of
/// one or two particles across (a `dp` as large as the body) has no interior the methods can
/// resolve.
pub(super) const MIN_PARTICLES_ACROSS: f64 = 3.0;

impl Scene {
    /// Every name of the scene (the scene's own, bodies, constraints, tools, probes) is a name
    /// ([`check_name`]) and unique in its kind; at most [`MAX_PROBES`] probes. Run at parse
    /// time: the scene's name becomes the results file's name.
    pub(super) fn check_names(&self) -> Result<(), SceneError> {
        let spec = &self.spec;
        if let Err(e) = check_name("name", &self.name) {
            return Err(if spec.name.is_some() {
                self.error_at_key("name", "name", e.to_string())
            } else {
                // Named after its file.
                SceneError::new(&self.file, None, "name (from the file name)", e.to_string())
            });
        }
        let named = |kind: &str, items: Vec<(Range<usize>, Option<&str>)>| {
            let mut seen: Vec<&str> = Vec::new();
            for (k, (span, name)) in items.into_iter().enumerate() {
                let Some(name) = name else { continue };
                let at = At { span, key: "name" };
                let key = format!("{kind}[{k}].name");
                check_name(&format!("{kind} name"), name)
                    .map_err(|e| self.error_in(&at, &key, e.to_string()))?;
                if seen.contains(&name) {
                    return Err(self.error_in(
                        &at,
                        &key,
                        format!("`{name}` is the name of another {kind}; names must be unique"),
                    ));
                }
                seen.push(name);
            }
            Ok(())
        };
        named(
            "body",
            spec.bodies
                .iter()
                .map(|b| (b.span(), Some(b.get_ref().name.as_str())))
                .collect(),
        )?;
        if let MaterialsSpec::List(list) = spec.material.get_ref() {
            if let Some((k, m)) = list
                .iter()
                .enumerate()
                .find(|(_, m)| m.get_ref().name.is_none())
            {
                return Err(self.error(
                    m.span(),
                    &format!("material[{k}].name"),
                    "a [[material]] needs a name (a [[body]] chooses it by material = \"NAME\")",
                ));
            }
            named(
                "material",
                list.iter()
                    .map(|m| (m.span(), m.get_ref().name.as_deref()))
                    .collect(),
            )?;
        }
        named(
            "constraint",
            spec.constraints
                .iter()
                .map(|c| (c.span(), c.get_ref().name.as_deref()))
                .collect(),
        )?;
        named(
            "tool",
            spec.tools
                .iter()
                .map(|t| (t.span(), Some(t.get_ref().name.as_str())))
                .collect(),
        )?;
        // A tool and a named constraint both record a series `/series/<name>`.
        for (k, t) in spec.tools.iter().enumerate() {
            let name = &t.get_ref().name;
            if spec
                .constraints
                .iter()
                .any(|c| c.get_ref().name.as_ref() == Some(name))
            {
                let at = At {
                    span: t.span(),
                    key: "name",
                };
                return Err(self.error_in(
                    &at,
                    &format!("tool[{k}].name"),
                    format!("`{name}` is also a constraint's name; each series needs its own"),
                ));
            }
        }
        if spec.probes.len() > MAX_PROBES {
            return Err(self.error(
                spec.probes[MAX_PROBES].span(),
                "probe",
                format!(
                    "{} probes: at most {MAX_PROBES} (record a field instead)",
                    spec.probes.len()
                ),
            ));
        }
        named(
            "probe",
            spec.probes
                .iter()
                .map(|p| (p.span(), Some(p.get_ref().name.as_str())))
                .collect(),
        )
    }

    /// A body of fewer than [`MIN_PARTICLES_ACROSS`] particles along an axis is refused: its
    /// spacing is as large as the body.
    pub(super) fn check_body_size<D: Dim>(
        &self,
        k: usize,
        b: &Spanned<BodySpec>,
        set: &ParticleSet<D>,
    ) -> Result<(), SceneError> {
        let dp = b.get_ref().dp;
        let x = set.positions();
        let mut across = f64::INFINITY;
        for axis in 0..D::D {
            let (lo, hi) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    let c = D::component(*p, axis);
                    (lo.min(c), hi.max(c))
                });
            across = across.min(((hi - lo) / dp).round() + 1.0);
        }
        if x.is_empty() || across < MIN_PARTICLES_ACROSS {
            let at = At {
                span: b.span(),
                key: "dp",
            };
            return Err(self.error_in(
                &at,
                &format!("body[{k}].dp"),
                format!(
                    "{} gives {} particle(s), {} across the body's narrowest side: a body needs \
                     at least {MIN_PARTICLES_ACROSS} particles across (make dp smaller)",
                    Num(dp),
                    x.len(),
                    if x.is_empty() { 0.0 } else { across }
                ),
            ));
        }
        Ok(())
    }

    /// Bodies may touch but not overlap at `t = 0`: a particle of one body inside the solid
    /// another body's particles fill (its shape, mesh or outline; bodies read from particle
    /// files have none and are not checked against) is refused, naming both bodies and the
    /// particle. Touching bodies pass: each body's particles lie inside its own solid, so none
    /// lies inside a neighbour that only shares a surface with it.
    pub(super) fn check_overlaps<D: Dim>(
        &self,
        set: &ParticleSet<D>,
        ranges: &[(String, Range<usize>)],
        solids: &[BodySolid<D>],
    ) -> Result<(), SceneError> {
        if ranges.len() < 2 {
            return Ok(());
        }
        let x = set.positions();
        for (k, solid) in solids.iter().enumerate() {
            let Some(solid) = solid else {
                continue;
            };
            let (lo, hi) = solid.bounds();
            let within = |p: D::Vector| {
                (0..D::D).all(|a| {
                    let c = D::component(p, a);
                    c >= D::component(lo, a) && c <= D::component(hi, a)
                })
            };
            for (j, (name, r)) in ranges.iter().enumerate() {
                if j == k {
                    continue;
                }
                if let Some(i) = r.clone().find(|&i| within(x[i]) && solid.contains(x[i])) {
                    let spec = &self.spec().bodies[j];
                    let at = At {
                        span: spec.span(),
                        key: "shape",
                    };
                    let coords: Vec<String> = (0..D::D)
                        .map(|a| Num(D::component(x[i], a)).to_string())
                        .collect();
                    return Err(self.error_in(
                        &at,
                        &format!("body[{j}]"),
                        format!(
                            "`{name}` overlaps body `{}` at t = 0 (its particle at [{}] lies \
                             inside `{}`): bodies may touch, not overlap; move them apart",
                            ranges[k].0,
                            coords.join(", "),
                            ranges[k].0
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// A solver's refusal, pointing at the table at fault: a numerical parameter at its key in
    /// `[numerics]`, a material constant in `[material]`, anything else (neighbours, coincident
    /// or too few particles) at the bodies.
    pub(super) fn solver_error(
        &self,
        e: sph_core::Error,
        numerics: &Range<usize>,
        keys: &[&str],
    ) -> SceneError {
        if let sph_core::Error::InvalidParameter { field, .. } = &e {
            if keys.contains(&field.as_str()) {
                let at = At {
                    span: numerics.clone(),
                    key: field,
                };
                return self.error_in(&at, &format!("numerics.{field}"), e.to_string());
            }
            if field == "material" {
                return self.error(self.spec.material.span(), "material.law", e.to_string());
            }
        }
        let body = &self.spec.bodies[0];
        let key = if self.spec.bodies.len() == 1 {
            "body[0]"
        } else {
            "body"
        };
        self.error(body.span(), key, e.to_string())
    }

    /// A refusal of the tools (`with_tools`), pointing at the tool whose name it gives.
    pub(super) fn tool_error(&self, e: sph_core::Error) -> SceneError {
        let text = e.to_string();
        let found = self
            .spec
            .tools
            .iter()
            .enumerate()
            .find(|(_, t)| text.contains(&format!("`{}`", t.get_ref().name)));
        match found {
            Some((k, t)) => {
                let at = At {
                    span: t.span(),
                    key: "speed",
                };
                self.error_in(&at, &format!("tool[{k}].speed"), text)
            }
            None => self.error(self.spec.tools[0].span(), "tool", text),
        }
    }
}
