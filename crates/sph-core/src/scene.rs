//! Small types a scene attaches to a body: constraints, body and point forces, and probes.
//! Each method applies them at the point of its scheme its paper prescribes; a scene that
//! attaches none pays nothing for them.

use crate::amplitude::Amplitude;
use crate::dim::Dim;
use crate::error::{check_name, check_positive, Error};
use crate::kernel::Kernel;
use std::fmt;
use std::sync::Arc;

/// A vector-valued function of time (prescribed velocity, time-dependent force).
pub struct TimeFunction<D: Dim>(Arc<dyn Fn(f64) -> D::Vector + Send + Sync>);

impl<D: Dim> TimeFunction<D> {
    /// Wraps a closure `t ↦ value`.
    pub fn new(f: impl Fn(f64) -> D::Vector + Send + Sync + 'static) -> Self {
        Self(Arc::new(f))
    }
    /// A constant value.
    pub fn constant(v: D::Vector) -> Self {
        Self::new(move |_| v)
    }
    /// `v · a(t)`: a magnitude and direction scaled by an amplitude curve (a grip's velocity
    /// that starts smoothly, a force that follows a table).
    pub fn scaled(v: D::Vector, amplitude: Amplitude) -> Self {
        Self::new(move |t| v * amplitude.at(t))
    }
    /// Evaluates at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> D::Vector {
        (self.0)(t)
    }
}

impl<D: Dim> Clone for TimeFunction<D> {
    fn clone(&self) -> Self {
        Self(self.0.clone())
    }
}

impl<D: Dim> fmt::Debug for TimeFunction<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "TimeFunction(value at t=0: {:?})", self.at(0.0))
    }
}

/// A kinematic constraint on a set of particles.
#[derive(Clone, Debug)]
pub enum Constraint<D: Dim> {
    /// Particles held fixed (zero velocity, zero acceleration): clamps, bearings.
    Fixed {
        /// Constrained particle indices.
        particles: Vec<u32>,
    },
    /// Particles moved with a prescribed velocity `v(t)`: punches, pulled rows, accelerated ends.
    PrescribedVelocity {
        /// Constrained particle indices.
        particles: Vec<u32>,
        /// The velocity as a function of time.
        velocity: TimeFunction<D>,
    },
    /// Some velocity components held at zero (simple supports: `z` fixed).
    FixedComponents {
        /// Constrained particle indices.
        particles: Vec<u32>,
        /// Which components (x, y, z) are fixed.
        components: [bool; 3],
    },
    /// Some velocity components prescribed by `v(t)`, the others free: a frictionless
    /// (roller) grip that pulls along one axis and lets the particles slide along the others.
    PrescribedComponents {
        /// Constrained particle indices.
        particles: Vec<u32>,
        /// The velocity (only the selected components are imposed).
        velocity: TimeFunction<D>,
        /// Which components (x, y, z) are prescribed.
        components: [bool; 3],
    },
}

impl<D: Dim> Constraint<D> {
    /// The constrained particles.
    pub fn particles(&self) -> &[u32] {
        match self {
            Constraint::Fixed { particles }
            | Constraint::PrescribedVelocity { particles, .. }
            | Constraint::FixedComponents { particles, .. }
            | Constraint::PrescribedComponents { particles, .. } => particles,
        }
    }

    fn particles_mut(&mut self) -> &mut Vec<u32> {
        match self {
            Constraint::Fixed { particles }
            | Constraint::PrescribedVelocity { particles, .. }
            | Constraint::FixedComponents { particles, .. }
            | Constraint::PrescribedComponents { particles, .. } => particles,
        }
    }

    /// Which velocity components the constraint imposes (all for fixed and prescribed).
    pub fn components(&self) -> [bool; 3] {
        match self {
            Constraint::Fixed { .. } | Constraint::PrescribedVelocity { .. } => [true; 3],
            Constraint::FixedComponents { components, .. }
            | Constraint::PrescribedComponents { components, .. } => *components,
        }
    }
}

/// The constraints of a body, applied in order (a later one overrides an earlier one on the
/// same particle). A constraint may carry a name: a solver then records the reaction force it
/// receives (a grip's pulling force) as the series `/series/<name>`.
#[derive(Clone, Debug, Default)]
pub struct Constraints<D: Dim> {
    list: Vec<Constraint<D>>,
    names: Vec<Option<String>>,
}

impl<D: Dim> Constraints<D> {
    /// No constraints.
    pub fn new() -> Self {
        Self {
            list: Vec::new(),
            names: Vec::new(),
        }
    }

    /// The particles `particles` of a body of `n` particles held fixed (a clamp).
    ///
    /// # Errors
    /// An index outside the body.
    pub fn fixed(particles: Vec<u32>, n: usize) -> Result<Self, Error> {
        let mut c = Self::new();
        c.push(Constraint::Fixed { particles }, n)?;
        Ok(c)
    }

    /// Adds a constraint, checking its particle indices against the body size `n`.
    pub fn push(&mut self, c: Constraint<D>, n: usize) -> Result<(), Error> {
        if let Some(&bad) = c.particles().iter().find(|&&i| i as usize >= n) {
            return Err(Error::invalid(
                "constraint particle index",
                bad,
                &format!("0..{n} (the body's particles)"),
            ));
        }
        self.list.push(c);
        self.names.push(None);
        Ok(())
    }

    /// Adds a named constraint (see [`Constraints::reactions`]).
    ///
    /// # Errors
    /// A name that is not a name ([`check_name`]) or repeats another constraint's; an index
    /// outside the body.
    pub fn push_named(&mut self, name: &str, c: Constraint<D>, n: usize) -> Result<(), Error> {
        check_name("constraint name", name)?;
        if self.names.iter().flatten().any(|x| x == name) {
            return Err(Error::invalid(
                "constraint name",
                format!("{name:?}"),
                "non-empty and unique among the body's constraints",
            ));
        }
        self.push(c, n)?;
        *self.names.last_mut().expect("just pushed") = Some(name.to_string());
        Ok(())
    }

    /// The named constraints: `(index in the list, name)`.
    pub fn named(&self) -> impl Iterator<Item = (usize, &str)> {
        self.names
            .iter()
            .enumerate()
            .filter_map(|(k, n)| n.as_deref().map(|n| (k, n)))
    }

    /// The `k`-th constraint.
    pub fn get(&self, k: usize) -> Option<&Constraint<D>> {
        self.list.get(k)
    }

    /// The reaction on each named constraint before it is imposed: `Σ_i m_i a_i` over its
    /// particles and imposed components, with `a` the accelerations of every force on them —
    /// the force the body exerts on the grip (quasi-statically, minus the force the grip
    /// applies; the grip's own inertia `m a_prescribed` is not included). Same order as
    /// [`Constraints::named`].
    pub fn reactions(&self, a: &[D::Vector], masses: &[f64]) -> Vec<D::Vector> {
        self.named()
            .map(|(k, _)| {
                let c = &self.list[k];
                let comp = c.components();
                let mut sum = D::zero();
                for &i in c.particles() {
                    sum += a[i as usize] * masses[i as usize];
                }
                for (k, &on) in comp.iter().enumerate().take(D::D) {
                    if !on {
                        D::set_component(&mut sum, k, 0.0);
                    }
                }
                sum
            })
            .collect()
    }

    /// Whether there are no constraints.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The constraints.
    pub fn iter(&self) -> impl Iterator<Item = &Constraint<D>> {
        self.list.iter()
    }

    /// Imposes the constraints on velocities at time `t`.
    pub fn apply_to_velocities(&self, t: f64, v: &mut [D::Vector]) {
        for c in &self.list {
            match c {
                Constraint::Fixed { particles } => {
                    for &i in particles {
                        v[i as usize] = D::zero();
                    }
                }
                Constraint::PrescribedVelocity {
                    particles,
                    velocity,
                } => {
                    let value = velocity.at(t);
                    for &i in particles {
                        v[i as usize] = value;
                    }
                }
                Constraint::FixedComponents {
                    particles,
                    components,
                } => {
                    for &i in particles {
                        zero_components::<D>(&mut v[i as usize], components);
                    }
                }
                Constraint::PrescribedComponents {
                    particles,
                    velocity,
                    components,
                } => {
                    let value = velocity.at(t);
                    for &i in particles {
                        for (k, &on) in components.iter().enumerate().take(D::D) {
                            if on {
                                D::set_component(&mut v[i as usize], k, D::component(value, k));
                            }
                        }
                    }
                }
            }
        }
    }

    /// Removes accelerations along constrained directions (all components for fixed and
    /// prescribed-velocity particles).
    pub fn apply_to_accelerations(&self, a: &mut [D::Vector]) {
        self.remove_accelerations(a, |_, _| {});
    }

    /// [`Self::apply_to_accelerations`], returning the force the constraints take away,
    /// `Σ m_i (a_i before − a_i after)` over the constrained particles in constraint order
    /// (a momentum balance's constraint impulse per unit time, without a pass over the free
    /// particles).
    pub fn apply_to_accelerations_removed_force(
        &self,
        a: &mut [D::Vector],
        masses: &[f64],
    ) -> D::Vector {
        let mut removed = D::zero();
        self.remove_accelerations(a, |i, da| removed += da * masses[i]);
        removed
    }

    /// The one loop behind both: `taken(i, a_i before − a_i after)` for every change.
    fn remove_accelerations(&self, a: &mut [D::Vector], mut taken: impl FnMut(usize, D::Vector)) {
        for c in &self.list {
            let (particles, components) = (c.particles(), c.components());
            for &i in particles {
                let i = i as usize;
                let before = a[i];
                zero_components::<D>(&mut a[i], &components);
                taken(i, before - a[i]);
            }
        }
    }

    /// `mask[i]` is true for particles whose motion is fully prescribed (fixed or prescribed
    /// velocity): excluded from the time-step maxima.
    pub fn prescribed_mask(&self, n: usize) -> Vec<bool> {
        let mut mask = vec![false; n];
        for c in &self.list {
            if let Constraint::Fixed { particles }
            | Constraint::PrescribedVelocity { particles, .. } = c
            {
                for &i in particles {
                    mask[i as usize] = true;
                }
            }
        }
        mask
    }

    /// `mask[i]` is true for particles whose motion is not fully prescribed: the negation of
    /// [`Self::prescribed_mask`], the particles the time-step maxima run over.
    pub fn free_mask(&self, n: usize) -> Vec<bool> {
        self.prescribed_mask(n).into_iter().map(|c| !c).collect()
    }

    /// Relabels particle indices after a reordering (`inv[old] = new`).
    pub fn remap(&mut self, inv: &[u32]) {
        for c in &mut self.list {
            let p = c.particles_mut();
            for i in p.iter_mut() {
                *i = inv[*i as usize];
            }
            p.sort_unstable();
        }
    }

    /// Keeps only the particles of a subset and relabels them (`inv[old] = new`, or
    /// `u32::MAX` for a particle outside the subset): the constraints of one rank's particles
    /// in a distributed run.
    pub fn restrict(&mut self, inv: &[u32]) {
        for c in &mut self.list {
            let p = c.particles_mut();
            p.retain(|&i| inv[i as usize] != u32::MAX);
            for i in p.iter_mut() {
                *i = inv[*i as usize];
            }
            p.sort_unstable();
        }
    }
}

#[inline]
fn zero_components<D: Dim>(v: &mut D::Vector, components: &[bool; 3]) {
    for (k, &fixed) in components.iter().enumerate().take(D::D) {
        if fixed {
            D::set_component(v, k, 0.0);
        }
    }
}

/// External loads: a uniform body acceleration (gravity) on all or some particles, and point
/// forces on single particles (divided by the particle mass).
#[derive(Clone, Debug, Default)]
pub struct Loads<D: Dim> {
    body: Vec<(Option<Vec<u32>>, TimeFunction<D>)>,
    point: Vec<(u32, TimeFunction<D>)>,
}

impl<D: Dim> Loads<D> {
    /// No loads.
    pub fn new() -> Self {
        Self {
            body: Vec::new(),
            point: Vec::new(),
        }
    }

    /// Adds a body acceleration `g(t)` on `particles` (all particles if `None`).
    pub fn add_body_acceleration(&mut self, particles: Option<Vec<u32>>, g: TimeFunction<D>) {
        self.body.push((particles, g));
    }

    /// Adds a point force `f(t)` (newtons) on one particle.
    pub fn add_point_force(&mut self, particle: u32, f: TimeFunction<D>) {
        self.point.push((particle, f));
    }

    /// Whether there are no loads (methods skip the load stage entirely).
    pub fn is_empty(&self) -> bool {
        self.body.is_empty() && self.point.is_empty()
    }

    /// Adds the load accelerations at time `t` to `acc` (`masses` per particle).
    pub fn add_accelerations(&self, t: f64, masses: &[f64], acc: &mut [D::Vector]) {
        for (particles, g) in &self.body {
            let g = g.at(t);
            match particles {
                None => acc.iter_mut().for_each(|a| *a += g),
                Some(p) => p.iter().for_each(|&i| acc[i as usize] += g),
            }
        }
        for (i, f) in &self.point {
            acc[*i as usize] += f.at(t) / masses[*i as usize];
        }
    }

    /// Relabels particle indices after a reordering (`inv[old] = new`).
    pub fn remap(&mut self, inv: &[u32]) {
        for (p, _) in &mut self.body {
            if let Some(p) = p {
                p.iter_mut().for_each(|i| *i = inv[*i as usize]);
            }
        }
        for (i, _) in &mut self.point {
            *i = inv[*i as usize];
        }
    }

    /// Keeps only the loads on particles of a subset and relabels them (`inv[old] = new`, or
    /// `u32::MAX` for a particle outside the subset). A body acceleration on all particles
    /// stays on all.
    pub fn restrict(&mut self, inv: &[u32]) {
        for (p, _) in &mut self.body {
            if let Some(p) = p {
                p.retain(|&i| inv[i as usize] != u32::MAX);
                p.iter_mut().for_each(|i| *i = inv[*i as usize]);
            }
        }
        self.point.retain(|(i, _)| inv[*i as usize] != u32::MAX);
        for (i, _) in &mut self.point {
            *i = inv[*i as usize];
        }
    }
}

/// `h / dp` of the kernel of [`Probe::at`].
pub const PROBE_H_OVER_DP: f64 = 1.3;

/// What a probe observes.
#[derive(Clone, Debug)]
pub enum ProbeTarget<D: Dim> {
    /// One particle.
    Particle(u32),
    /// A material point between particles: its displacement is the Shepard (kernel-weighted)
    /// average of the displacements of the particles around its reference position, with
    /// weights `V_j W(|X* − X_j|)` fixed in the reference configuration. Exact for uniform
    /// displacement, and for linear displacement where the neighbourhood is symmetric (e.g. the
    /// mid-thickness tip of a plate with an even number of layers).
    Point {
        /// Reference position `X*`.
        reference: D::Vector,
        /// `(j, normalised weight, X_j)`.
        weights: Vec<(u32, f64, D::Vector)>,
    },
}

/// A time series of a probe's position and velocity, and of any output fields asked for.
///
/// The solver records the position and velocity (every step or every probe interval); the
/// run driver samples the [`Probe::fields`] (von Mises stress, `jacobian`, `disorder`, …, any
/// name of [`crate::Solver::field_names`]) at every monitor sample, into
/// `/probes/<name>/fields` of the results file.
#[derive(Clone, Debug)]
pub struct Probe<D: Dim> {
    /// Name (used as the HDF5 group name).
    pub name: String,
    /// What is observed.
    pub target: ProbeTarget<D>,
    /// Output fields sampled at the probe by the run driver (none by default).
    pub fields: Vec<String>,
    /// Recorded times.
    pub times: Vec<f64>,
    /// Recorded positions.
    pub positions: Vec<D::Vector>,
    /// Recorded velocities.
    pub velocities: Vec<D::Vector>,
}

impl<D: Dim> Probe<D> {
    /// A probe on particle `i`.
    pub fn particle(name: &str, i: u32) -> Self {
        Self::with_target(name, ProbeTarget::Particle(i))
    }

    /// A probe on the material point with reference position `x_star`, interpolated from the
    /// particles within the kernel support (`reference` positions and `volumes` of the body).
    pub fn point<K: Kernel>(
        name: &str,
        x_star: D::Vector,
        reference: &[D::Vector],
        volumes: &[f64],
        kernel: &K,
    ) -> Result<Self, Error> {
        let mut weights: Vec<(u32, f64, D::Vector)> = reference
            .iter()
            .enumerate()
            .filter_map(|(j, &xj)| {
                let w = volumes[j] * kernel.w(D::norm(x_star - xj));
                (w > 0.0).then_some((j as u32, w, xj))
            })
            .collect();
        let total: f64 = weights.iter().map(|w| w.1).sum();
        if weights.is_empty() || total <= 0.0 {
            return Err(Error::invalid(
                &format!("probe `{name}` position"),
                format!("{x_star:?}"),
                "within the kernel support of at least one particle",
            ));
        }
        weights.iter_mut().for_each(|w| w.1 /= total);
        Ok(Self::with_target(
            name,
            ProbeTarget::Point {
                reference: x_star,
                weights,
            },
        ))
    }

    /// A probe on the material point with reference position `x_star` of `body`, in one call:
    /// [`Probe::point`] with the body's positions and volumes and the Wendland C2 kernel of
    /// `h = 1.3 dp` (what scene files use, whatever the method).
    ///
    /// ```
    /// use sph_core::{glam::DVec2, Body, Probe, D2};
    ///
    /// // A 0.1 × 0.01 plate, 100 × 10 particles (sph-geometry's lattice fill, by hand).
    /// let dp = 1e-3;
    /// let x: Vec<DVec2> = (0..10)
    ///     .flat_map(|j| (0..100).map(move |i| DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * dp))
    ///     .collect();
    /// let body = Body::<D2>::new(x, vec![dp * dp; 1000], dp);
    /// let tip = Probe::at("tip", DVec2::new(0.1, 0.005), &body)?.with_fields(&["von_mises"]);
    /// assert_eq!(tip.fields, ["von_mises"]);
    /// # Ok::<(), sph_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// A position outside the kernel support of every particle, or an invalid spacing.
    pub fn at(name: &str, x_star: D::Vector, body: &crate::Body<D>) -> Result<Self, Error> {
        let kernel = crate::WendlandC2::<D>::from_spacing(body.dp, PROBE_H_OVER_DP)?;
        Self::point(name, x_star, &body.positions, &body.volumes, &kernel)
    }

    /// Asks the run driver to sample these output fields at the probe (see [`Probe::fields`]).
    pub fn with_fields(mut self, fields: &[&str]) -> Self {
        self.fields = fields.iter().map(|f| f.to_string()).collect();
        self
    }

    /// The value of `field` at the probe: the particle's, or the Shepard average of the
    /// neighbourhood's with the probe's weights; padded to 3D as in the results file (vectors
    /// `[3]`, matrices `[3, 3]` row-major with `zz = 1` in 2D).
    pub fn sample_field(&self, field: &crate::Field<D>) -> Vec<f64> {
        use crate::Field;
        let weights: Vec<(usize, f64)> = match &self.target {
            ProbeTarget::Particle(i) => vec![(*i as usize, 1.0)],
            ProbeTarget::Point { weights, .. } => {
                weights.iter().map(|&(j, w, _)| (j as usize, w)).collect()
            }
        };
        match field {
            Field::Scalar(v) => vec![weights.iter().map(|&(j, w)| v[j] * w).sum()],
            Field::Vector(v) => {
                let mut s = D::zero();
                for &(j, w) in &weights {
                    s += v[j] * w;
                }
                D::to_vec3(s).to_array().to_vec()
            }
            Field::Matrix(m) => {
                let mut s = D::zero_matrix();
                for &(j, w) in &weights {
                    s += m[j] * w;
                }
                let m3 = D::to_mat3(s, 1.0);
                (0..3).flat_map(|r| m3.row(r).to_array()).collect()
            }
        }
    }

    fn with_target(name: &str, target: ProbeTarget<D>) -> Self {
        Self {
            name: name.to_string(),
            target,
            fields: Vec::new(),
            times: Vec::new(),
            positions: Vec::new(),
            velocities: Vec::new(),
        }
    }

    /// The probe's current position and velocity.
    pub fn sample(
        &self,
        positions: &[D::Vector],
        velocities: &[D::Vector],
    ) -> (D::Vector, D::Vector) {
        match &self.target {
            ProbeTarget::Particle(i) => (positions[*i as usize], velocities[*i as usize]),
            ProbeTarget::Point { reference, weights } => {
                let mut u = D::zero();
                let mut v = D::zero();
                for &(j, w, xj) in weights {
                    u += (positions[j as usize] - xj) * w;
                    v += velocities[j as usize] * w;
                }
                (*reference + u, v)
            }
        }
    }

    /// Appends the current sample at time `t`.
    pub fn record(&mut self, t: f64, positions: &[D::Vector], velocities: &[D::Vector]) {
        let (x, v) = self.sample(positions, velocities);
        self.times.push(t);
        self.positions.push(x);
        self.velocities.push(v);
    }

    /// Relabels particle indices after a reordering (`inv[old] = new`).
    pub fn remap(&mut self, inv: &[u32]) {
        match &mut self.target {
            ProbeTarget::Particle(i) => *i = inv[*i as usize],
            ProbeTarget::Point { weights, .. } => {
                weights.iter_mut().for_each(|w| w.0 = inv[w.0 as usize])
            }
        }
    }
}

/// A recorded time series of named scalar columns: a tool's travel and reaction force, a
/// grip's reaction, or any other figure a solver samples on the probe schedule. Written to the
/// results file as `/series/<name>` (dataset `time` and one dataset per column).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Name (the HDF5 group name).
    pub name: String,
    /// Column names.
    pub columns: Vec<String>,
    /// Sample times.
    pub time: Vec<f64>,
    /// `values[c][k]`: column `c` at sample `k`.
    pub values: Vec<Vec<f64>>,
    /// What the columns are, their units and signs (written as the series' `description`;
    /// see [`crate::conventions`]).
    pub description: String,
}

impl Series {
    /// An empty series with these columns.
    pub fn new(name: &str, columns: &[&str]) -> Self {
        Self {
            name: name.to_string(),
            columns: columns.iter().map(|c| c.to_string()).collect(),
            time: Vec::new(),
            values: vec![Vec::new(); columns.len()],
            description: String::new(),
        }
    }

    /// With the description of its columns.
    pub fn with_description(mut self, description: &str) -> Self {
        self.description = description.to_string();
        self
    }

    /// Appends one sample (`row` has one value per column).
    pub fn push(&mut self, t: f64, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns.len());
        self.time.push(t);
        for (c, &x) in self.values.iter_mut().zip(row) {
            c.push(x);
        }
    }

    /// The values of column `name`, if present.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let k = self.columns.iter().position(|c| c == name)?;
        Some(&self.values[k])
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}

/// Most probes one body records: each is a group of the results file, and 200,000 probes on 50
/// particles took over a minute to write while telling nothing a field does not.
pub const MAX_PROBES: usize = 10_000;

/// Checks the probes a solver is given, before any work: at most [`MAX_PROBES`], each name a
/// name ([`check_name`]: it becomes the group `/probes/<name>`) and used once.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `probes` or `probe name`.
pub fn check_probes<D: Dim>(probes: &[Probe<D>]) -> Result<(), Error> {
    if probes.len() > MAX_PROBES {
        return Err(Error::invalid(
            "probes",
            probes.len(),
            &format!("at most {MAX_PROBES} probes (record a field instead)"),
        ));
    }
    let mut names: Vec<&str> = Vec::with_capacity(probes.len());
    for p in probes {
        check_name("probe name", &p.name)?;
        names.push(&p.name);
    }
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(Error::invalid(
            "probe name",
            format!("{:?} (given twice)", w[0]),
            "a name used by one probe only",
        ));
    }
    Ok(())
}

/// How often probes record: every `interval` of simulated time (0 records every step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSchedule {
    interval: f64,
    next: f64,
}

impl ProbeSchedule {
    /// Records at `t = 0, interval, 2 interval, ...` (the first step at or after each).
    pub fn every(interval: f64) -> Result<Self, Error> {
        if interval != 0.0 {
            check_positive("probe_interval", interval)?;
        }
        Ok(Self {
            interval,
            next: 0.0,
        })
    }

    /// The time of the next sample (checkpoints).
    pub fn next(&self) -> f64 {
        self.next
    }

    /// Sets the time of the next sample (restoring a checkpoint).
    pub fn set_next(&mut self, next: f64) {
        self.next = next;
    }

    /// Whether a sample is due at time `t`; advances the schedule if so.
    pub fn due(&mut self, t: f64) -> bool {
        if t + 1e-12 * self.interval.max(t.abs()) < self.next {
            return false;
        }
        if self.interval > 0.0 {
            // Skip missed slots so a large step does not trigger a burst of samples.
            self.next = ((t / self.interval).floor() + 1.0) * self.interval;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D2;
    use crate::kernel::WendlandC2;
    use glam::DVec2;

    #[test]
    fn constraints_fix_prescribe_and_mask_components() {
        let n = 4;
        let mut c = Constraints::<D2>::new();
        c.push(Constraint::Fixed { particles: vec![0] }, n).unwrap();
        c.push(
            Constraint::PrescribedVelocity {
                particles: vec![1],
                velocity: TimeFunction::new(|t| DVec2::new(0.0, 2.0 * t)),
            },
            n,
        )
        .unwrap();
        c.push(
            Constraint::FixedComponents {
                particles: vec![2],
                components: [false, true, false],
            },
            n,
        )
        .unwrap();
        let mut v = vec![DVec2::ONE; n];
        c.apply_to_velocities(1.5, &mut v);
        assert_eq!(
            v,
            vec![
                DVec2::ZERO,
                DVec2::new(0.0, 3.0),
                DVec2::new(1.0, 0.0),
                DVec2::ONE
            ]
        );
        let mut a = vec![DVec2::ONE; n];
        c.apply_to_accelerations(&mut a);
        assert_eq!(
            a,
            vec![DVec2::ZERO, DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::ONE]
        );
        assert_eq!(c.prescribed_mask(n), vec![true, true, false, false]);
        assert_eq!(c.free_mask(n), vec![false, false, true, true]);
        let e = c
            .push(Constraint::Fixed { particles: vec![9] }, n)
            .unwrap_err()
            .to_string();
        assert!(e.contains("constraint particle index"), "{e}");
    }

    #[test]
    fn point_probe_reproduces_uniform_and_symmetric_linear_displacement() {
        // 2 × 2 block of particles around the origin; a probe at the centre.
        let dp = 0.1;
        let x0: Vec<DVec2> = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
            .iter()
            .map(|&(a, b)| DVec2::new(a * dp, b * dp))
            .collect();
        let k = WendlandC2::<D2>::from_spacing(dp, 1.15).unwrap();
        let p = Probe::<D2>::point("tip", DVec2::ZERO, &x0, &[dp * dp; 4], &k).unwrap();
        let shift = DVec2::new(0.3, -0.2);
        let x: Vec<DVec2> = x0.iter().map(|&x| x + shift).collect();
        let (xp, _) = p.sample(&x, &x);
        // Tolerance: exact up to round-off of a 4-term weighted sum.
        assert!((xp - shift).length() < 1e-15);
        let g = glam::DMat2::from_cols_array(&[1.1, 0.2, -0.3, 0.9]);
        let x: Vec<DVec2> = x0.iter().map(|&x| g * x).collect();
        let (xp, _) = p.sample(&x, &x);
        assert!(xp.length() < 1e-15, "{xp:?}");
        let far = Probe::<D2>::point("far", DVec2::new(5.0, 5.0), &x0, &[dp * dp; 4], &k);
        assert!(far.unwrap_err().to_string().contains("probe `far`"));
    }

    #[test]
    fn probe_schedule_samples_once_per_interval() {
        let mut s = ProbeSchedule::every(0.1).unwrap();
        let due: Vec<bool> = [0.0, 0.05, 0.1, 0.12, 0.35, 0.36, 0.4]
            .iter()
            .map(|&t| s.due(t))
            .collect();
        assert_eq!(due, vec![true, false, true, false, true, false, true]);
        assert!(ProbeSchedule::every(-1.0).is_err());
    }
}
