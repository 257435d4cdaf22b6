//! A scene built without running it: the bodies' particles, which particles the constraints and
//! loads hold, the tools, and how well each fitted body fits its mesh or outline (what
//! `sph preview` writes and draws).

use super::*;

/// One body of a [`Preview`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BodyPreview {
    /// The body's name.
    pub name: String,
    /// Its particles: indices `range` of the preview's arrays.
    pub range: Range<usize>,
    /// Its spacing.
    pub dp: f64,
    /// Number of particles.
    pub particles: usize,
    /// Total particle volume (area in 2D): what the body holds (a fitted body's after the
    /// scaling [`volume_scale`](Self::volume_scale); its raw fill `N dp^d` is
    /// `volume / volume_scale`).
    pub volume: f64,
    /// The volume (area) its mesh or outline encloses (`None` for other shapes).
    pub mesh_volume: Option<f64>,
    /// The factor the fitted layout scaled every particle's volume by so the body holds
    /// `mesh_volume` (`sph_geometry::fit::FitOptions::match_volume`; `None` for other layouts,
    /// which are never scaled).
    pub volume_scale: Option<f64>,
    /// RMS distance of its surface particles from depth `dp/2`, in units of `dp` (fitted
    /// layout only; see `sph_geometry::fit`).
    pub surface_distance_rms: Option<f64>,
    /// Largest such distance, in units of `dp`.
    pub surface_distance_max: Option<f64>,
    /// Relative standard deviation of the kernel-sum particle volumes.
    pub volume_spread: Option<f64>,
}

/// A scene built without running: see [`Scene::preview`].
#[derive(Clone, Debug, PartialEq)]
pub struct Preview {
    /// 2 or 3.
    pub dimension: usize,
    /// Every particle's initial position (`z = 0` in 2D), bodies one after the other.
    pub positions: Vec<[f64; 3]>,
    /// Every particle's volume.
    pub volumes: Vec<f64>,
    /// Every particle's body (index into `bodies`).
    pub body: Vec<u32>,
    /// Every particle's region: `k + 1` for the first constraint `k` that holds it, else 0.
    pub constraint: Vec<u32>,
    /// The bodies.
    pub bodies: Vec<BodyPreview>,
    /// The tools' names.
    pub tools: Vec<String>,
}

impl Scene {
    /// Builds the scene's bodies (fitting meshes and outlines), constraints, loads, probes and
    /// tools as a run would, checking everything a run checks before its solver exists, and
    /// returns the particles with their bodies and regions, without running.
    ///
    /// # Errors
    /// As [`Scene::run`] for everything built before the solver.
    pub fn preview(&self) -> Result<Preview, SceneError> {
        match *self.spec.dimension.get_ref() {
            2 => self.preview_in::<D2>(),
            3 => self.preview_in::<D3>(),
            d => Err(self.error(
                self.spec.dimension.span(),
                "dimension",
                format!("{d}: allowed values are 2 (plane strain) and 3"),
            )),
        }
    }

    fn preview_in<D: SceneDim>(&self) -> Result<Preview, SceneError> {
        let spec = &self.spec;
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
        let mut bodies = Vec::new();
        let mut dps = Vec::new();
        let mut solids = Vec::new();
        for (k, b) in spec.bodies.iter().enumerate() {
            let ((part, _, report), solid) = self.body_and_solid::<D>(k, b)?;
            solids.push(solid);
            self.check_body_size(k, b, &part)?;
            let r = set
                .extend(&part)
                .map_err(|e| self.core(b.span(), &format!("body[{k}]"), e))?;
            let s = b.get_ref();
            bodies.push(BodyPreview {
                name: s.name.clone(),
                range: r.clone(),
                dp: s.dp,
                particles: r.len(),
                volume: part.total_volume(),
                mesh_volume: report.as_ref().map(|r| r.mesh_volume),
                volume_scale: report.as_ref().map(|r| r.volume_scale),
                surface_distance_rms: report.as_ref().map(|r| r.surface_distance_rms),
                surface_distance_max: report.as_ref().map(|r| r.surface_distance_max),
                volume_spread: report.as_ref().map(|r| r.volume_spread),
            });
            ranges.push((s.name.clone(), r));
            dps.push(s.dp);
        }
        self.check_overlaps(&set, &ranges, &solids)?;
        // What a run builds before its solver: each checks its own keys.
        self.constraints::<D>(&set, &ranges)?;
        self.loads::<D>(&set, &ranges, &dps)?;
        let tools = self.tools::<D>()?;
        let mut constraint = vec![0u32; set.len()];
        for (k, c) in spec.constraints.iter().enumerate() {
            let s = c.get_ref();
            let at = At {
                span: c.span(),
                key: "region",
            };
            let held = self.region(
                &at,
                &format!("constraint[{k}].region"),
                &set,
                &ranges,
                &s.region,
                s.body.as_ref(),
            )?;
            for i in held {
                if constraint[i as usize] == 0 {
                    constraint[i as usize] = k as u32 + 1;
                }
            }
        }
        let positions = set
            .positions()
            .iter()
            .map(|&x| D::to_vec3(x).to_array())
            .collect();
        let body = bodies
            .iter()
            .enumerate()
            .flat_map(|(k, b)| std::iter::repeat_n(k as u32, b.particles))
            .collect();
        Ok(Preview {
            dimension: D::D,
            positions,
            volumes: set.volumes().to_vec(),
            body,
            constraint,
            bodies,
            tools: tools.iter().map(|t| t.name.clone()).collect(),
        })
    }

    /// The files a scene reads besides itself: particle files, meshes and outlines (relative
    /// to the scene file), so a command can refuse to write over them.
    pub fn input_files(&self) -> Vec<PathBuf> {
        fn walk(s: &ShapeSpec, out: &mut Vec<String>) {
            if let Some(g) = s.geometry_file() {
                out.push(g.file.to_string());
            }
            match s {
                ShapeSpec::Union(v) | ShapeSpec::Intersection(v) => {
                    v.iter().for_each(|p| walk(p, out))
                }
                ShapeSpec::Difference { base, cut } => {
                    walk(base, out);
                    walk(cut, out);
                }
                _ => {}
            }
        }
        let mut files = Vec::new();
        for b in &self.spec.bodies {
            let b = b.get_ref();
            if let Some(s) = &b.shape {
                walk(s, &mut files);
            }
            files.extend(b.particles.clone());
        }
        for c in &self.spec.constraints {
            walk(&c.get_ref().region, &mut files);
        }
        for l in &self.spec.loads {
            if let Some(r) = &l.get_ref().region {
                walk(r, &mut files);
            }
        }
        files.into_iter().map(|f| self.dir.join(f)).collect()
    }
}
