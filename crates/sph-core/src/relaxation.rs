//! Quasi-static loading by dynamic relaxation: the splitting random-choice pairwise damping of
//! Zhu, Zhang & Hu (J. Comput. Phys. 2022, the TL paper's ref. 68) that the TL paper uses for
//! its punching and pulling cases (docs/methods.md, "Quasi-static cases").
//!
//! A physical viscosity `η` acts between neighbours, `m_i dv_i/dt = Σ_j η W′_ij V_i V_j/r_ij
//! (v_i − v_j)`. It is integrated **pair by pair, implicitly**: for a pair with
//! `b = η W′(r_ij) V_i V_j Δt′/r_ij` (`≤ 0`), backward Euler on the two particles alone gives
//!
//! `inc = b (v_i − v_j) / (m_i m_j − b (m_i + m_j))`, `v_i += m_j inc`, `v_j −= m_i inc`,
//!
//! which conserves `m_i v_i + m_j v_j` exactly, never increases the pair's kinetic energy, and is
//! stable for any `b` — so a viscosity strong enough to damp the lowest mode of the whole body
//! (far beyond an explicit viscosity's stability limit at the acoustic step) can be used. The
//! pairs are swept in a fixed order (Gauss–Seidel), and the sweep runs only in a random fraction
//! `p` of the steps with `Δt′ = Δt/p` (the "random choice", which cuts the cost by `1/p` at the
//! same mean damping). The random choice is a counter-based generator of the step number, so a
//! run is deterministic whatever the thread count.
//!
//! A particle whose motion is prescribed (a grip, a clamp) acts as an infinite mass: only its
//! free partner is damped toward its velocity. Then momentum is exchanged with the grip, as a
//! grip exchanges it anyway.
//!
//! Cost: one sequential pass over the pairs per chosen step (2D, 20 neighbours: about 10 pair
//! updates per particle). SPHinXsys parallelises the sweep by splitting cells into
//! non-interacting colours; a sequential sweep is deterministic by construction and, at
//! `p = 0.2`, a small fraction of a step's cost.

use crate::dim::Dim;
use crate::error::{check_non_negative, Error};
use crate::kernel::Kernel;
use crate::neighbor::NeighborList;
use crate::pairs::pair_kernel;

/// The damping's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairwiseDamping {
    /// Physical viscosity `η` (Pa·s). See [`PairwiseDamping::viscosity_for`].
    pub viscosity: f64,
    /// Probability `p` that a step damps (0.2 as in the TL paper's cases).
    pub probability: f64,
    /// Seed of the random choice.
    pub seed: u64,
}

impl PairwiseDamping {
    /// Default probability of the random choice.
    pub const DEFAULT_PROBABILITY: f64 = 0.2;

    /// Damping with viscosity `η` and the default probability.
    ///
    /// # Errors
    /// `η` negative or not finite.
    pub fn new(viscosity: f64) -> Result<Self, Error> {
        let d = Self {
            viscosity,
            probability: Self::DEFAULT_PROBABILITY,
            seed: 0x5eed_0fd4_3b1e,
        };
        d.validate()?;
        Ok(d)
    }

    /// The viscosity scale of docs/methods.md, `η = (β/4) √(ρ0 E) L`, for a body of size `L`:
    /// a viscosity of order `√(ρ0 E) L` damps the body's lowest elastic mode (wavenumber `π/L`,
    /// frequency `c π/L`) about critically, and `β` scales it.
    pub fn viscosity_for(beta: f64, density: f64, youngs_modulus: f64, length: f64) -> f64 {
        0.25 * beta * (density * youngs_modulus).sqrt() * length
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// Names the offending field.
    pub fn validate(&self) -> Result<(), Error> {
        check_non_negative("relaxation viscosity", self.viscosity)?;
        if !(self.probability > 0.0 && self.probability <= 1.0) {
            return Err(Error::invalid(
                "relaxation probability",
                self.probability,
                "0 < p <= 1",
            ));
        }
        Ok(())
    }

    /// Whether step number `step` damps (deterministic in `seed` and `step`).
    pub fn chosen(&self, step: u64) -> bool {
        let x = splitmix64(self.seed ^ step.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        ((x >> 11) as f64) * (1.0 / (1u64 << 53) as f64) < self.probability
    }
}

/// One step of the SplitMix64 generator (Steele, Lea & Flood 2014): a well-mixed 64-bit hash.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The pairwise damping bound to a fixed neighbour list (each pair once, `j > i`, with
/// `c_ij = W′(r_ij) V_i V_j / r_ij` precomputed).
#[derive(Clone, Debug)]
pub struct PairwiseDamper {
    params: PairwiseDamping,
    first: Vec<u32>,
    second: Vec<u32>,
    coefficient: Vec<f64>,
}

impl PairwiseDamper {
    /// Binds the damping to the neighbour list `list` of the configuration `positions` (the
    /// reference configuration for a TL body), with `kernel` and the particle volumes. The
    /// kernel data of each pair are computed here, once per pair.
    ///
    /// # Errors
    /// Invalid parameters, or `positions`/`volumes` not matching the list.
    pub fn new<D: Dim, K: Kernel>(
        params: PairwiseDamping,
        list: &NeighborList,
        positions: &[D::Vector],
        kernel: &K,
        volumes: &[f64],
    ) -> Result<Self, Error> {
        params.validate()?;
        if positions.len() != list.len() || volumes.len() != list.len() {
            return Err(Error::invalid(
                "relaxation pair data",
                format!("{} positions, {} volumes", positions.len(), volumes.len()),
                &format!("{} of each", list.len()),
            ));
        }
        let (mut first, mut second, mut coefficient) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..list.len() {
            for &j in list.neighbors(i) {
                if (j as usize) <= i {
                    continue;
                }
                let p = pair_kernel::<D, K>(positions[i] - positions[j as usize], kernel);
                if p.r > 0.0 {
                    first.push(i as u32);
                    second.push(j);
                    coefficient.push(p.dw * volumes[i] * volumes[j as usize] / p.r);
                }
            }
        }
        Ok(Self {
            params,
            first,
            second,
            coefficient,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &PairwiseDamping {
        &self.params
    }

    /// Number of pairs swept.
    pub fn num_pairs(&self) -> usize {
        self.first.len()
    }

    /// Damps the velocities if step `step` is chosen (returns whether it was), with
    /// `Δt′ = Δt/p`. `free[i]` is false for particles of prescribed motion (infinite mass).
    pub fn apply<D: Dim>(
        &self,
        step: u64,
        dt: f64,
        velocities: &mut [D::Vector],
        masses: &[f64],
        free: &[bool],
    ) -> bool {
        if self.params.viscosity == 0.0 || !self.params.chosen(step) {
            return false;
        }
        let scale = self.params.viscosity * dt / self.params.probability;
        for ((&i, &j), &c) in self.first.iter().zip(&self.second).zip(&self.coefficient) {
            let (i, j) = (i as usize, j as usize);
            let b = c * scale;
            let dv = velocities[i] - velocities[j];
            match (free[i], free[j]) {
                (true, true) => {
                    let (mi, mj) = (masses[i], masses[j]);
                    let inc = dv * (b / (mi * mj - b * (mi + mj)));
                    velocities[i] += inc * mj;
                    velocities[j] -= inc * mi;
                }
                (true, false) => velocities[i] += dv * (b / (masses[i] - b)),
                (false, true) => velocities[j] -= dv * (b / (masses[j] - b)),
                (false, false) => {}
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D2;
    use crate::kernel::{Kernel, WendlandC2};
    use crate::neighbor::CellGrid;
    use crate::testing::cell_centres;
    use glam::DVec2;

    fn block() -> (NeighborList, Vec<DVec2>, WendlandC2<D2>, Vec<f64>, Vec<f64>) {
        let dp = 0.1;
        let x = cell_centres::<D2>([10, 6, 1], dp);
        let k = WendlandC2::<D2>::from_spacing(dp, 1.15).unwrap();
        let list = CellGrid::<D2>::build(&x, k.cutoff())
            .unwrap()
            .neighbor_list(&x, k.cutoff())
            .unwrap();
        let volumes = vec![dp * dp; x.len()];
        let masses = volumes.iter().map(|v| 1000.0 * v).collect();
        (list, x, k, volumes, masses)
    }

    /// A rough velocity field: deterministic pseudo-random components.
    fn rough(n: usize) -> Vec<DVec2> {
        (0..n as u64)
            .map(|i| {
                let a = splitmix64(i) as f64 / u64::MAX as f64 - 0.5;
                let b = splitmix64(i + 1_000_000) as f64 / u64::MAX as f64 - 0.5;
                DVec2::new(a, b)
            })
            .collect()
    }

    #[test]
    fn damping_conserves_momentum_and_removes_kinetic_energy() {
        let (list, x, k, volumes, masses) = block();
        let mut d = PairwiseDamping::new(1.0e4).unwrap();
        d.probability = 1.0;
        let damper = PairwiseDamper::new::<D2, _>(d, &list, &x, &k, &volumes).unwrap();
        let n = list.len();
        let mut v = rough(n);
        let momentum = |v: &[DVec2]| v.iter().zip(&masses).map(|(&v, &m)| v * m).sum::<DVec2>();
        let energy = |v: &[DVec2]| {
            v.iter()
                .zip(&masses)
                .map(|(v, m)| 0.5 * m * v.length_squared())
                .sum::<f64>()
        };
        let (p0, e0) = (momentum(&v), energy(&v));
        let mut e_prev = e0;
        for step in 0..20 {
            assert!(damper.apply::<D2>(step, 1e-3, &mut v, &masses, &vec![true; n]));
            let e = energy(&v);
            // Every exchange is dissipative: the energy never grows (round-off allowance).
            assert!(e <= e_prev * (1.0 + 1e-14), "step {step}: {e} > {e_prev}");
            e_prev = e;
        }
        // Momentum to round-off: relative to Σ m |v|.
        let scale: f64 = masses.iter().sum::<f64>();
        assert!(
            (momentum(&v) - p0).length() < 1e-14 * scale,
            "{:?}",
            momentum(&v) - p0
        );
        // A strong viscosity removes most of a rough field's energy in 20 sweeps.
        assert!(energy(&v) < 0.05 * e0, "{} of {e0}", energy(&v));
    }

    #[test]
    fn uniform_motion_is_not_damped_and_prescribed_particles_keep_their_velocity() {
        let (list, x, k, volumes, masses) = block();
        let mut d = PairwiseDamping::new(1.0e3).unwrap();
        d.probability = 1.0;
        let damper = PairwiseDamper::new::<D2, _>(d, &list, &x, &k, &volumes).unwrap();
        let n = list.len();
        let mut v = vec![DVec2::new(0.3, -0.2); n];
        damper.apply::<D2>(0, 1e-3, &mut v, &masses, &vec![true; n]);
        assert!(v.iter().all(|&x| x == DVec2::new(0.3, -0.2)));
        // Particle 0 prescribed at rest: its neighbours are pulled toward it, it stays.
        let mut free = vec![true; n];
        free[0] = false;
        v[0] = DVec2::ZERO;
        damper.apply::<D2>(0, 1e-3, &mut v, &masses, &free);
        assert_eq!(v[0], DVec2::ZERO);
        let j = list.neighbors(0)[0] as usize;
        assert!(v[j].length() < DVec2::new(0.3, -0.2).length());
    }

    #[test]
    fn random_choice_is_deterministic_with_the_requested_frequency() {
        let d = PairwiseDamping::new(1.0).unwrap();
        let chosen: Vec<bool> = (0..100_000).map(|s| d.chosen(s)).collect();
        let again: Vec<bool> = (0..100_000).map(|s| d.chosen(s)).collect();
        assert_eq!(chosen, again);
        let f = chosen.iter().filter(|&&c| c).count() as f64 / 1e5;
        // Binomial standard deviation √(p(1−p)/n) = 1.3e-3; 5 σ.
        assert!((f - 0.2).abs() < 6.5e-3, "{f}");
        assert!(PairwiseDamping::new(-1.0).is_err());
        let bad = PairwiseDamping {
            probability: 0.0,
            ..d
        };
        assert!(bad.validate().is_err());
    }
}
