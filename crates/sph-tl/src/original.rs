//! The original TL-SPH stress divergence (TL paper eq 20) and the deformation rate (eq 22),
//! shared by all variants (the HF variant uses eq 20's structure without `B` for its remaining
//! stress, see [`crate::hourglass_free`]).

use crate::damping::damping_piola;
use crate::reference_pairs::PairRows;
use rayon::prelude::*;
use sph_core::parallel::{gather, MIN_PARTICLES_PER_TASK};
use sph_core::Dim;
use sph_materials::Material;

/// First Piola–Kirchhoff stress with damping, premultiplied for eq 20: `(P_i + τ_d F_i⁻ᵀ) B_iᵀ`.
#[inline(always)]
pub fn corrected_piola<D: Dim, M: Material<D>>(
    material: &M,
    gamma: f64,
    f: D::Matrix,
    f_dot: D::Matrix,
    b: D::Matrix,
) -> D::Matrix {
    let mut p = material.first_piola_kirchhoff(f);
    if gamma > 0.0 {
        let f_inv_t = D::transpose(D::try_inverse(f).unwrap_or_else(nan_matrix::<D>));
        p += damping_piola::<D>(gamma, f, f_dot, f_inv_t);
    }
    p * D::transpose(b)
}

/// A matrix of NaN: a singular `F` surfaces as a non-finite acceleration, which the step
/// reports, instead of a panic.
pub(crate) fn nan_matrix<D: Dim>() -> D::Matrix {
    D::matrix_from_fn(|_, _| f64::NAN)
}

/// Eq 20: `a_i = (1/ρ0) Σ_j (S_i + S_j) (V_j ∇⁰_i W_ij)` for per-particle matrices `S`
/// (`P B ᵀ` for the original form, `P_r` for HF), written into `acc`.
/// In 3D with stored pair data, where the loops run their AVX2 copy, the sum is taken with a
/// vector in one AVX register (module `lanes`; the same bits).
pub fn stress_divergence<D: Dim>(
    pairs: impl PairRows<D>,
    stress: &[D::Matrix],
    inv_density: f64,
    acc: &mut [D::Vector],
) {
    // 3D with stored pair data: the same sums with a vector in one AVX register.
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::available() {
        if let (Some((g, _)), Some(s), Some(a)) =
            (pairs.stored(), D::as_mat3(stress), D::as_vec3_mut(acc))
        {
            if let Some(g) = D::as_vec3(g) {
                crate::lanes::stress_divergence(pairs.list(), g, s, inv_density, a);
                return;
            }
        }
    }
    stress_divergence_generic(pairs, stress, inv_density, acc);
}

/// [`stress_divergence`] for any dimension and pair storage.
pub(crate) fn stress_divergence_generic<D: Dim>(
    pairs: impl PairRows<D>,
    stress: &[D::Matrix],
    inv_density: f64,
    acc: &mut [D::Vector],
) {
    let stress_j = pairs.list().values(stress);
    gather(
        acc,
        #[inline(always)]
        |i, a| {
            let si = stress[i];
            let sum = pairs.fold_gradient(i, D::zero(), move |sum, j, g| {
                // SAFETY: the rows visit the indices of `pairs.list()`, which made the view.
                sum + (si + unsafe { stress_j.at(j) }) * g
            });
            *a = sum * inv_density;
        },
    );
}

/// Eq 22: `Ḟ_i = (Σ_j (v_j − v_i) ⊗ V_j ∇⁰_i W_ij) B_i`, written into `f_dot`.
/// In 3D with stored pair data, where the loops run their AVX2 copy, the sum is taken with a
/// vector in one AVX register (module `lanes`; the same bits).
pub fn deformation_rate<D: Dim>(
    pairs: impl PairRows<D>,
    correction: &[D::Matrix],
    velocities: &[D::Vector],
    f_dot: &mut [D::Matrix],
) {
    // 3D with stored pair data: the same sums with a vector in one AVX register.
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::available() {
        if let (Some((g, _)), Some(b), Some(v), Some(fd)) = (
            pairs.stored(),
            D::as_mat3(correction),
            D::as_vec3(velocities),
            D::as_mat3_mut(f_dot),
        ) {
            if let Some(g) = D::as_vec3(g) {
                crate::lanes::deformation_rate(pairs.list(), g, b, v, fd);
                return;
            }
        }
    }
    deformation_rate_generic(pairs, correction, velocities, f_dot);
}

/// [`deformation_rate`] for any dimension and pair storage.
pub(crate) fn deformation_rate_generic<D: Dim>(
    pairs: impl PairRows<D>,
    correction: &[D::Matrix],
    velocities: &[D::Vector],
    f_dot: &mut [D::Matrix],
) {
    let velocity_j = pairs.list().values(velocities);
    gather(
        f_dot,
        #[inline(always)]
        |i, fd| {
            let vi = velocities[i];
            let sum = pairs.fold_gradient(i, D::zero_matrix(), move |sum, j, g| {
                // SAFETY: the rows visit the indices of `pairs.list()`, which made the view.
                sum + D::outer(unsafe { velocity_j.at(j) } - vi, g)
            });
            *fd = sum * correction[i];
        },
    );
}

/// `F_i = I + (Σ_j (u_j − u_i) ⊗ V_j ∇⁰_i W_ij) B_i` for displacements `u = x − X`: the
/// deformation gradient the SPH gradient of eq 22 assigns to a configuration (used to start from
/// a prescribed deformed state).
pub fn deformation_gradient<D: Dim>(
    pairs: impl PairRows<D>,
    correction: &[D::Matrix],
    reference: &[D::Vector],
    current: &[D::Vector],
) -> Vec<D::Matrix> {
    (0..pairs.list().len())
        .into_par_iter()
        .with_min_len(MIN_PARTICLES_PER_TASK)
        .map(|i| {
            let ui = current[i] - reference[i];
            let sum = pairs.fold_gradient(i, D::zero_matrix(), move |sum, j, g| {
                sum + D::outer(current[j] - reference[j] - ui, g)
            });
            D::identity() + sum * correction[i]
        })
        .collect()
}
