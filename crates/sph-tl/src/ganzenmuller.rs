//! Ganzenmüller's hourglass control (CMAME 2015), as in LAMMPS `pair_smd_tlsph.cpp` and
//! TrixiParticles' `PenaltyForceGanzenmueller` (docs/methods.md):
//!
//! `f_i += ½ α Σ_j V_i V_j W(r⁰_ij)/|X_ij|² E ((F_i + F_j) X_ij − 2 x_ij)·x̂ x̂`, `a = f/m_i`,
//!
//! with `X_ij = X_i − X_j`, `x_ij = x_i − x_j`, `x̂ = x_ij/|x_ij|`: a pairwise spring that pulls
//! each pair back toward the separation the two deformation gradients predict. Zero for affine
//! motion; it costs the tuning parameter α, which the TL paper criticises.

use crate::reference_pairs::PairRows;
use sph_core::parallel::gather;
use sph_core::Dim;

/// Default α = 0.1 (published values span 0.01–0.3; LAMMPS's `hg` is 2α).
pub const DEFAULT_ALPHA: f64 = 0.1;

/// Adds the penalty acceleration to `acc`; the pair weight `V_j W(r⁰_ij)/|X_ij|²` from `pairs`
/// ([`crate::reference_pairs::penalty_weight`]) and
/// `scale = α E / (2 ρ0)` (the `V_i` of the force cancels against `m_i = ρ0 V_i`).
#[allow(clippy::too_many_arguments)]
pub fn add_penalty_acceleration<D: Dim>(
    pairs: impl PairRows<D>,
    reference: &[D::Vector],
    positions: &[D::Vector],
    deformation: &[D::Matrix],
    scale: f64,
    acc: &mut [D::Vector],
) {
    let list = pairs.list();
    let (x_j, x0_j, f_j) = (
        list.values(positions),
        list.values(reference),
        list.values(deformation),
    );
    gather(
        acc,
        #[inline(always)]
        |i, a| {
            let (xi, x0i, fi) = (positions[i], reference[i], deformation[i]);
            let sum = pairs.fold(i, D::zero(), move |sum, j, _, w| {
                // SAFETY: the rows visit the indices of `pairs.list()`, which made the views.
                let (x_j, x0_j, f_j) = unsafe { (x_j.at(j), x0_j.at(j), f_j.at(j)) };
                let xij = xi - x_j;
                let r = D::norm(xij);
                if r <= 0.0 {
                    return sum;
                }
                let e = xij * (1.0 / r);
                let predicted = (fi + f_j) * (x0i - x0_j);
                sum + e * (w * D::dot(predicted - xij * 2.0, e))
            });
            *a += sum * scale;
        },
    );
}
