//! The original (nested) shear treatment, SPH-OG: velocity gradient (eq 14, with the correction
//! matrix of eq 26–27 by default), the Jaumann rate of the shear stress (eq 6–8) and the
//! divergence of the shear stress (eq 13).

use sph_core::Dim;

/// Pair contribution to the velocity gradient, eq. (14)/(26) of the UL paper before the
/// correction matrix: `(v_j − v_i) ⊗ ∇_i W_ij V_j = −v_ij ⊗ (W′ e_ij) V_j`.
///
/// (The paper prints `v_ij ∇_i W_ij`; with `v_ij = v_i − v_j` and `∇_i W_ij` pointing toward `j`
/// that has the wrong sign for a linear field; docs/methods.md's `−Σ v_ij ⊗ ∇_i W_ij V_j` is exact:
/// for `v = G x` on a lattice the sum is `G M_i`, and `L_i = (Σ …) B_i = G` with
/// `B_i = M_i⁻¹`.)
#[inline(always)]
pub fn velocity_gradient_pair<D: Dim>(
    v_ij: D::Vector,
    e: D::Vector,
    dw: f64,
    v_j: f64,
) -> D::Matrix {
    D::outer(v_ij * (-v_j), e * dw)
}

/// Eq. (6)–(8) of the UL paper with the Jaumann (objective) rate of docs/methods.md:
/// `τ̇ = 2G (D − tr(D)/d I) + Ω τ − τ Ω`, `D = ½(L + Lᵀ)`, `Ω = ½(L − Lᵀ)`. In 2D `d = 2`
/// (the paper's deviator; the out-of-plane shear stress is zero).
#[inline(always)]
pub fn jaumann_rate<D: Dim>(l: D::Matrix, tau: D::Matrix, shear_modulus: f64) -> D::Matrix {
    let lt = D::transpose(l);
    let d = (l + lt) * 0.5;
    let w = (l - lt) * 0.5;
    let dev = d - D::identity() * (D::trace(d) / D::D as f64);
    dev * (2.0 * shear_modulus) + w * tau - tau * w
}

/// Pair term of eq. (13) of the UL paper, the divergence of the shear stress:
/// `m_j (τ_i + τ_j)/(ρ_i ρ_j) ∇_i W_ij = (τ_i + τ_j)(W′ e_ij) V_j/ρ_i`.
#[inline(always)]
pub fn shear_pair_acceleration<D: Dim>(
    tau_i: D::Matrix,
    tau_j: D::Matrix,
    e: D::Vector,
    dw: f64,
    v_j_over_rho_i: f64,
) -> D::Vector {
    (tau_i + tau_j) * (e * (dw * v_j_over_rho_i))
}

/// Elastic energy of the shear stress of a particle of volume `V` (linear elasticity):
/// `V τ:τ/(4G)`; with eq. (7) its rate is `V τ:D`, the stress power of the shear stress.
#[inline]
pub fn shear_energy<D: Dim>(tau: D::Matrix, volume: f64, shear_modulus: f64) -> f64 {
    volume * D::ddot(tau, tau) / (4.0 * shear_modulus)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat2;
    use sph_core::D2;

    #[test]
    fn jaumann_rate_rotates_stress_under_spin_and_is_deviatoric() {
        // Pure spin: L = Ω; τ̇ = Ωτ − τΩ, the rate of a rotated tensor.
        let omega = DMat2::from_cols_array(&[0.0, 1.0, -1.0, 0.0]) * 0.3;
        let tau = DMat2::from_cols_array(&[2.0, 0.5, 0.5, -2.0]);
        let r = jaumann_rate::<D2>(omega, tau, 10.0);
        assert!(D2::frobenius(r - (omega * tau - tau * omega)) < 1e-14);
        // Pure stretch: 2G dev(D), traceless.
        let l = DMat2::from_cols_array(&[1.0, 0.0, 0.0, 3.0]);
        let r = jaumann_rate::<D2>(l, DMat2::ZERO, 10.0);
        assert!(D2::trace(r).abs() < 1e-14);
        assert!((D2::matrix_get(r, 0, 0) + 20.0).abs() < 1e-14);
    }
}
