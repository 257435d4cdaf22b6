//! Energy of a UL body and its budget ([`sph_core::EnergyBudget`]).
//!
//! **Stored energies** (state functions, computed when asked):
//! - kinetic `Σ ½ m v²` — exact;
//! - volumetric, the potential of the equation of state (eq 4), `Σ m c0² (ln(ρ/ρ0) + ρ0/ρ − 1)`
//!   ([`crate::riemann::pressure_energy`]) — exact for the pressure part `½(p_i + p_j)` of
//!   eq 12 and the motion part `u_ij` of continuity (eq 11): its rate is minus the power of
//!   that part, pair by pair. The paper's pressure jump in continuity also changes the density
//!   (a diffusion); that change of the volumetric energy is accumulated as `diffused`;
//! - shear `Σ V τ:τ/(4G)` ([`crate::nested::shear_energy`]). OG/OAS: `τ` is the state the force
//!   derives from, and with the uncorrected velocity gradient of eq 14 its rate is minus the
//!   shear power exactly, up to the `V̇ τ:τ/(4G)` term of hypoelasticity (second order in the
//!   strain). ENOG: the force is the accumulated `A_s` of eq 20, not the divergence of a
//!   stress; `τ` here is the output stress integrated with eq 26 — an **estimate** of the
//!   energy the shear force stores. The exact work of `A_s` is kept beside it (`shear_work`);
//! - contact `Σ κ c0² m ρ_c²/(2ρ0²)` ([`crate::contact::contact_energy`]) — an estimate (see
//!   [`crate::contact`]); the exact work of the contact forces is kept beside it
//!   (`contact_work`).
//!
//! **Accumulated work** ([`AccumulatedWork`]), per acoustic step and exact for the position-Verlet
//! step (eq 23–25): with `v_mid = v^n + ½ Δt a = ½(v^n + v^{n+1})`, the kinetic energy changes by
//! `Σ m a·v_mid Δt`, and each force part contributes `Σ m a_part·v_mid Δt` ([`kick_with_works`]).
//! Accumulated are the parts no stored energy holds: the dissipative part
//! `−½ β ρ0 c0 u_ij` of the Riemann interface pressure (eq 12), OAS's artificial stress, loads,
//! the pressure jump's change of the volumetric energy;
//! and, for the notes, the contact forces and ENOG's `A_s`. Constrained particles do no work
//! (fixed particles have `v_mid = 0`, fixed components a zero component of it); a constraint
//! that prescribes a non-zero velocity does work this budget does not count.
//!
//! **Budget.** `total = kinetic + volumetric + shear + contact + dissipated + diffused −
//! artificial work − external work` (+ `plastic`, the plastic work, for a plastic body: see
//! [`crate::plastic`]), conserved by the continuous problem; the residual `total − total(t = 0)`
//! measures what the discrete scheme and the estimates leave unaccounted.

use serde::{Deserialize, Serialize};
use sph_core::{Dim, EnergyBudget};

/// Kinetic and elastic energy of the body (see the module documentation for what is exact).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// `Σ ½ m v²`.
    pub kinetic: f64,
    /// Energy of the equation of state, `Σ m c0² (ln(ρ/ρ0) + ρ0/ρ − 1)`.
    pub volumetric: f64,
    /// Shear energy `Σ V τ:τ/(4G)` (for ENOG from the output shear stress: an estimate; ENOG
    /// without it: the exact work done against `A_s` when the budget keeps it, else NaN).
    pub shear: f64,
}

impl Energy {
    /// Kinetic plus elastic energy.
    pub fn total(&self) -> f64 {
        self.kinetic + self.volumetric + self.shear
    }
}

/// Work done on the particles since `t = 0` by force parts, accumulated per acoustic step with
/// [`kick_with_works`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AccumulatedWork {
    /// The dissipative part of the Riemann interface pressure, `−½ β ρ0 c0 u_ij` (eq 12):
    /// negative (it removes energy) up to the time-stepping error.
    pub riemann: f64,
    /// OAS: the artificial stress.
    pub artificial: f64,
    /// The contact forces between bodies.
    pub contact: f64,
    /// ENOG: the accumulated shear acceleration `A_s` (eq 20).
    pub shear: f64,
    /// Loads (body accelerations, point forces).
    pub loads: f64,
    /// The change of the volumetric energy made by the pressure jump of the paper's continuity
    /// equation (eq 11), `∫ Σ m p/ρ² ρ̇_jump dt` (≤ 0 semi-discretely; integrated over the
    /// drifts of eq 23/25, second order).
    pub density_jump: f64,
}

/// The kick of eq 24, `v_i += Δt a_i`, and in the same pass the work of `K` force parts
/// (`parts(i)` = their accelerations of particle `i`) over the acoustic step of the
/// position-Verlet scheme: `W_k = Σ_i m_i a_k,i · (v_i + ½ Δt a_i) Δt`, with `a` the total
/// acceleration after constraints and `v` the velocities before the kick. Summing it over all
/// parts gives the change of the kinetic energy exactly. Summed per block of
/// [`sph_core::parallel::blocks`] on the team, each block in particle order and the blocks'
/// sums in block order: the same bits for every thread count (as a serial loop it took about
/// 4 % of the stepping thread's time on the UL plate with two threads, the helper waiting);
/// each block kicks its particles once its sum is taken (the kick and the sums were two
/// parallel regions of every acoustic step before).
pub fn kick_with_works<D: Dim, const K: usize>(
    parts: impl Fn(usize) -> [D::Vector; K] + Sync + Send,
    a: &[D::Vector],
    v: &mut [D::Vector],
    masses: &[f64],
    dt: f64,
) -> [f64; K] {
    assert!(
        v.len() == a.len() && masses.len() == a.len(),
        "kick_with_works lengths"
    );
    sph_core::parallel::map_block_columns(
        a.len(),
        (v,),
        #[inline(always)]
        |rows, (v,)| {
            let mut w = [0.0; K];
            for (k, i) in rows.clone().enumerate() {
                let mv = (v[k] + a[i] * (0.5 * dt)) * (masses[i] * dt);
                for (wk, p) in w.iter_mut().zip(parts(i)) {
                    *wk += D::dot(p, mv);
                }
            }
            for (k, i) in rows.enumerate() {
                v[k] += a[i] * dt;
            }
            w
        },
    )
    .into_iter()
    .fold([0.0; K], |mut total, w| {
        total.iter_mut().zip(w).for_each(|(t, w)| *t += w);
        total
    })
}

/// The budget of a UL body: terms `kinetic`, `volumetric`, `shear`, `contact`, `dissipated`
/// (`−` Riemann work), `diffused` (`−` the pressure jump's change of the volumetric energy),
/// `artificial_stress` (`−` its work), `external` (`−` work of loads);
/// notes `contact_work` (energy taken up by the contact forces, `−` their work) and, with
/// `enog`, `shear_work` (`−` the work of `A_s`). For ENOG without a tracked stress
/// (`stress_tracked = false`) the shear term is the exact `shear_work` instead of the estimate.
pub fn ul_budget(
    energy: &Energy,
    contact: f64,
    work: &AccumulatedWork,
    enog: bool,
    stress_tracked: bool,
    initial_total: f64,
) -> EnergyBudget {
    let shear = if enog && !stress_tracked {
        -work.shear
    } else {
        energy.shear
    };
    let mut notes = vec![("contact_work", -work.contact)];
    if enog {
        notes.push(("shear_work", -work.shear));
    }
    EnergyBudget {
        terms: vec![
            ("kinetic", energy.kinetic),
            ("volumetric", energy.volumetric),
            ("shear", shear),
            ("contact", contact),
            ("dissipated", -work.riemann),
            ("diffused", -work.density_jump),
            ("artificial_stress", -work.artificial),
            ("external", -work.loads),
        ],
        notes,
        initial_total,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use sph_core::D2;

    #[test]
    fn step_work_of_all_parts_is_the_kinetic_energy_change() {
        // Two particles, two force parts: ΔKE of v += a Δt equals the summed part works to
        // round-off (1e-14 relative).
        let v = [DVec2::new(1.0, -2.0), DVec2::new(0.3, 0.5)];
        let p1 = [DVec2::new(0.5, 1.0), DVec2::new(-2.0, 0.1)];
        let p2 = [DVec2::new(-0.2, 0.4), DVec2::new(1.5, -0.7)];
        let a: Vec<DVec2> = p1.iter().zip(&p2).map(|(x, y)| *x + *y).collect();
        let (m, dt) = ([2.0, 3.0], 0.1);
        let ke = |v: &[DVec2]| 0.5 * (m[0] * v[0].length_squared() + m[1] * v[1].length_squared());
        let v1: Vec<DVec2> = v.iter().zip(&a).map(|(v, a)| *v + *a * dt).collect();
        let mut kicked = v;
        let [w1, w2] = kick_with_works::<D2, 2>(|i| [p1[i], p2[i]], &a, &mut kicked, &m, dt);
        assert_eq!(kicked.to_vec(), v1);
        let w = w1 + w2;
        assert!((ke(&v1) - ke(&v) - w).abs() < 1e-14 * ke(&v), "{w}");
    }

    #[test]
    fn works_are_the_same_bits_on_every_thread_count_and_the_block_sums_of_the_serial_sum() {
        // 5,000 particles: several blocks, each summed in particle order.
        let n = 5000;
        let f = |i: usize, k: f64| DVec2::new((i as f64 * k).sin(), (i as f64 * 0.7 + k).cos());
        let (v, a): (Vec<_>, Vec<_>) = (0..n).map(|i| (f(i, 0.3), f(i, 1.1))).unzip();
        let p: Vec<DVec2> = (0..n).map(|i| f(i, 2.3)).collect();
        let m: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
        let dt = 1e-3;
        let mut expected = 0.0;
        for rows in sph_core::parallel::blocks(n) {
            let mut block = 0.0;
            for i in rows {
                block += p[i].dot((v[i] + a[i] * (0.5 * dt)) * (m[i] * dt));
            }
            expected += block;
        }
        for threads in 1..=3 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut kicked = v.clone();
            let [w] =
                pool.install(|| kick_with_works::<D2, 1>(|i| [p[i]], &a, &mut kicked, &m, dt));
            assert_eq!(w.to_bits(), expected.to_bits(), "{threads} threads");
            assert!(kicked
                .iter()
                .zip(v.iter().zip(&a))
                .all(|(k, (v, a))| *k == *v + *a * dt));
        }
    }
}
