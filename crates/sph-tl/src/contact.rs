//! Contact between TL bodies and within a TL body (self-contact), see
//! [`crate::TlSolver::with_bodies`] and [`crate::TlSolver::with_self_contact`].
//!
//! Each body is its own reference configuration: its reference neighbours (kernel sums,
//! correction matrices, HF Laplacian) never cross bodies. In the current configuration, the
//! pairs found by [`sph_core::contact::ContactBodies::detect`] (particles of different bodies,
//! and, with self-contact, particles of one body whose reference distance is beyond the kernel
//! support) push each other apart with the contact pressure of the UL contact model
//! (`sph_ul::contact`, docs/methods.md "Separate bodies", after SPHinXsys's contact density):
//!
//! `ρ_c,i = Σ_j max(W_ij − W(dp), 0) m_j`,  `p_c,i = κ c0² ρ_c,i`,
//! `m_i a_i = −Σ_j (p_c,i + p_c,j) V_i V_j W′_ij e_ij`  over pairs with `r_ij < dp`,
//!
//! with `V = V⁰ = m/ρ0` (TL's reference volumes) and the scale `κ`
//! ([`crate::TlSolver::with_contact_scale`], [`crate::solver::DEFAULT_CONTACT_SCALE`] = 2 by
//! default, measured; UL's `contact_scale` is 1). Restricting the force to the pairs
//! that raise the contact density (`r < dp`) makes it exactly `−∂U_c/∂x_i` of
//! `U_c = Σ_i κ c0² m_i ρ_c,i² / (2 ρ0²)` ([`contact_energy`]), so the contact is conservative
//! and `U_c` is its stored energy (UL also lets pairs between `dp` and `2h` carry force, which
//! `U_c` does not contain). Every pair term is computed with the same operands from both ends,
//! so the pair forces are equal and opposite bit for bit: linear momentum is conserved to
//! round-off. Repulsive only. Contact starts when surface particles (half a spacing inside the
//! surface) come closer than `dp`, i.e. when the surfaces touch.
//!
//! **Stiffness.** `p_c = c0² ρ_c` is the body's own equation of state applied to the contact
//! density, so the contact wave speed is of order `c0` and eq 33's acoustic step (with its
//! acceleration criterion) keeps the step stable; no extra time-step limit is needed.
//!
//! Detection runs every step on the current positions (a cell list of edge `dp`), only when the
//! solver has several bodies or a self-contact: a one-body solver pays nothing.

use sph_core::contact::{body_force_series, record_body_forces, ContactBodies};
use sph_core::contact_friction::ContactFriction;
use sph_core::parallel::gather;
use sph_core::scene::Series;
use sph_core::{Dim, Error, Kernel, NeighborList, WendlandC2};

/// The stored energy `κ c0² m ρ_c² / (2 ρ0²)` of one particle's contact density (docs/methods.md
/// "Separate bodies"; the potential of the contact force above).
pub fn contact_energy(mass: f64, contact_density: f64, stiffness: f64, rho0: f64) -> f64 {
    0.5 * stiffness * mass * contact_density * contact_density / (rho0 * rho0)
}

/// Contact state of a TL solver with several bodies or a self-contact.
#[derive(Clone, Debug)]
pub(crate) struct TlContact<D: Dim> {
    pub bodies: ContactBodies,
    /// Contact pairs of the last detection.
    list: NeighborList,
    /// `dp`: the contact range and the distance where the contact density starts.
    dp: f64,
    /// `W(dp)`.
    w_dp: f64,
    /// `κ c0²`.
    stiffness: f64,
    rho0: f64,
    /// Reference distance beyond which particles of one body may touch (the kernel support).
    reference_cutoff: f64,
    density: Vec<f64>,
    /// The contact accelerations of the last force evaluation.
    accelerations: Vec<D::Vector>,
    /// Per body, the series `contact_force_<body>` (the UL series of that name).
    pub series: Vec<Series>,
}

impl<D: Dim> TlContact<D> {
    pub fn new(
        bodies: ContactBodies,
        dp: f64,
        kernel: &WendlandC2<D>,
        scale: f64,
        sound_speed: f64,
        rho0: f64,
    ) -> Self {
        let n = bodies.body.len();
        let series = body_force_series(bodies.bodies(), D::D);
        Self {
            bodies,
            list: NeighborList::default(),
            dp,
            w_dp: kernel.w(dp),
            stiffness: scale * sound_speed * sound_speed,
            rho0,
            reference_cutoff: kernel.cutoff(),
            density: vec![0.0; n],
            accelerations: vec![D::zero(); n],
            series,
        }
    }

    /// Total contact force on each body, `Σ_{i ∈ b} m_i a_c,i`, of the last force evaluation
    /// (the other bodies' push, and with self-contact the body's own, which sums to zero).
    pub fn body_forces(&self, masses: &[f64]) -> Vec<D::Vector> {
        let mut f = vec![D::zero(); self.bodies.bodies()];
        for ((&b, &a), &m) in self.bodies.body.iter().zip(&self.accelerations).zip(masses) {
            f[b as usize] += a * m;
        }
        f
    }

    /// Appends one row, the force of [`TlContact::body_forces`], to every body's series.
    pub fn record(&mut self, time: f64, masses: &[f64]) {
        let forces = self.body_forces(masses);
        record_body_forces::<D>(&mut self.series, time, &forces);
    }

    /// Detects the contact pairs at `positions` and adds the contact accelerations to `out`.
    pub fn add_accelerations(
        &mut self,
        positions: &[D::Vector],
        reference: &[D::Vector],
        masses: &[f64],
        volumes: &[f64],
        kernel: &WendlandC2<D>,
        out: &mut [D::Vector],
    ) -> Result<(), Error> {
        self.list =
            self.bodies
                .detect::<D>(positions, reference, self.dp, self.reference_cutoff)?;
        contact_density::<D>(
            &self.list,
            positions,
            kernel,
            masses,
            self.w_dp,
            &mut self.density,
        );
        let (list, rho_c, k) = (&self.list, &self.density, self.stiffness);
        gather(
            &mut self.accelerations,
            #[inline(always)]
            |i, a| {
                let mut acc = D::zero();
                for &j in list.neighbors(i) {
                    let j = j as usize;
                    let d = positions[i] - positions[j];
                    let r = D::norm(d);
                    if r <= 0.0 {
                        continue;
                    }
                    // Operands combined commutatively: the same bits from both ends.
                    let p = k * rho_c[i] + k * rho_c[j];
                    let vv = volumes[i] * volumes[j];
                    acc += d * (-(p * vv * kernel.dw_dr(r)) / r);
                }
                *a = acc / masses[i];
            },
        );
        out.iter_mut()
            .zip(&self.accelerations)
            .for_each(|(o, &a)| *o += a);
        Ok(())
    }

    /// The Coulomb friction pass of [`sph_core::contact_friction`] over the contact pairs of
    /// the last detection, at the positions of that force evaluation: each pair's normal force
    /// is the magnitude of its contact force `−(p_c,i + p_c,j) V_i V_j W′(r)` along
    /// `e_ij = (x_i − x_j)/r`. Returns the momentum change.
    #[allow(clippy::too_many_arguments)]
    pub fn apply_friction(
        &self,
        friction: &mut ContactFriction<D>,
        positions: &[D::Vector],
        velocities: &mut [D::Vector],
        masses: &[f64],
        volumes: &[f64],
        free: &[bool],
        kernel: &WendlandC2<D>,
        dt: f64,
    ) -> D::Vector {
        let (rho_c, k) = (&self.density, self.stiffness);
        let normal = |i: usize, _: usize, j: usize| {
            let d = positions[i] - positions[j];
            let r = D::norm(d);
            if r <= 0.0 {
                return (D::zero(), 0.0);
            }
            let p = k * rho_c[i] + k * rho_c[j];
            (d / r, -(p * (volumes[i] * volumes[j]) * kernel.dw_dr(r)))
        };
        friction.apply(
            &self.list,
            &self.bodies.body,
            normal,
            &self.accelerations,
            velocities,
            masses,
            free,
            dt,
        )
    }

    /// Sets the scale `κ` of the contact stiffness `κ c0²`.
    pub fn set_scale(&mut self, scale: f64, sound_speed: f64) {
        self.stiffness = scale * sound_speed * sound_speed;
    }

    /// Contact pairs (directed) of the last detection.
    pub fn num_pairs(&self) -> usize {
        self.list.num_pairs()
    }

    /// The stored contact energy `U_c` at `positions` (detects afresh; for diagnostics).
    pub fn energy(
        &self,
        positions: &[D::Vector],
        reference: &[D::Vector],
        masses: &[f64],
        kernel: &WendlandC2<D>,
    ) -> Result<f64, Error> {
        let list = self
            .bodies
            .detect::<D>(positions, reference, self.dp, self.reference_cutoff)?;
        let mut density = vec![0.0; masses.len()];
        contact_density::<D>(&list, positions, kernel, masses, self.w_dp, &mut density);
        Ok(masses
            .iter()
            .zip(&density)
            .map(|(&m, &rho_c)| contact_energy(m, rho_c, self.stiffness, self.rho0))
            .sum())
    }

    /// The smallest current distance between contact candidates: particles of different
    /// bodies, or of one self-contacting body beyond the reference support, closer than
    /// `search` (infinity when none).
    pub fn smallest_gap(
        &self,
        positions: &[D::Vector],
        reference: &[D::Vector],
        search: f64,
    ) -> Result<f64, Error> {
        let list = self
            .bodies
            .detect::<D>(positions, reference, search, self.reference_cutoff)?;
        let mut gap = f64::INFINITY;
        for i in 0..positions.len() {
            for &j in list.neighbors(i) {
                gap = gap.min(D::norm(positions[i] - positions[j as usize]));
            }
        }
        Ok(gap)
    }
}

/// The contact density `ρ_c,i = Σ_j max(W_ij − W(dp), 0) m_j` over the pairs of `list`.
fn contact_density<D: Dim>(
    list: &NeighborList,
    positions: &[D::Vector],
    kernel: &WendlandC2<D>,
    masses: &[f64],
    w_dp: f64,
    out: &mut Vec<f64>,
) {
    out.resize(masses.len(), 0.0);
    gather(
        out,
        #[inline(always)]
        |i, rho| {
            *rho = list
                .neighbors(i)
                .iter()
                .map(|&j| {
                    let r = D::norm(positions[i] - positions[j as usize]);
                    (kernel.w(r) - w_dp).max(0.0) * masses[j as usize]
                })
                .sum();
        },
    );
}
