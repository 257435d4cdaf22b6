//! The generalized non-hourglass shear treatment, SPH-GNOG (Zhang, Wu, Lourenço & Hu 2024,
//! "A generalized non-hourglass updated Lagrangian formulation for SPH solid dynamics",
//! arXiv 2409.11474): OG's nested shear stress — velocity gradient with the correction matrix,
//! Jaumann rate, stress divergence (eq 6–8, 13, 26 of the UL paper), so any constitutive law that
//! gives a shear stress, plastic ones included — plus a penalty acceleration on the difference
//! between the actual velocity difference of a pair and the one the two velocity gradients
//! predict linearly, which is what a zigzag (hourglass) mode has and a smooth field has not.
//!
//! The penalty is accumulated like ENOG's `A_s` and rotated with the particle's spin so that it
//! is objective; per acoustic step `Δt`, with `v^{n+1}` and its gradients `L`:
//!
//! `A_i ← R(Ω_i Δt) A_i + Δt Σ_j ξ G [(v_ij − ½(L_i + L_j) r_ij e_ij)·e_ij] e_ij W′_ij V_j /(ρ_i r_ij)`,
//!
//! `R` the Rodrigues rotation of the spin `Ω = ½(L − Lᵀ)` over `Δt`. The formula and the
//! rotation are those of the authors' code (SPHinXsys,
//! `continuum_integration.cpp`, `ShearStressRelaxationHourglassControl2ndHalf`), whose
//! elastic default is used here (`ξ = 2`, [`DEFAULT_XI`]). Their J2 variant
//! (`ShearStressRelaxationHourglassControlJ2Plasticity`, the one their UL Taylor bar runs)
//! defaults to `ξ = 0.2` and scales it by the ratio of the yield radius to the step's trial
//! stress, which is `1 − O(Δt)` for one acoustic step's trial; here `ξ` is one value for elastic
//! and plastic particles, and the `taylor-bar-3d` case sets 0.2 (measured there: ξ = 2 holds
//! the mushroom's rim back).
//!
//! Each pair term is antisymmetric (`m_i` times it is `ξ G s_ij e_ij W′ V_i V_j / r_ij` with
//! `s_ij = s_ji`), so without spin (where `R = I`) linear momentum is conserved to round-off; a
//! linear velocity field (rigid motion, homogeneous strain) gives no penalty at all, since the
//! corrected gradient reproduces it exactly.

use crate::shear::ShearForce;
use sph_core::{Dim, PairKernel};

/// The authors' penalty factor ξ of the elastic variant (SPHinXsys's default, used in their
/// oscillating beam; their plastic Taylor bar runs the J2 variant's 0.2).
pub const DEFAULT_XI: f64 = 2.0;

/// Pair term of the penalty rate (without `Δt`):
/// `ξ G [(v_ij − ½(L_i + L_j) r e)·e] e W′ V_j/(ρ_i r)` (arXiv 2409.11474; see the module docs),
/// with `vj_rho_i = V_j/ρ_i` (the solver passes `V_i V_j/m_i` of one volume array, so that
/// `m_i` times the term is symmetric in `i, j`).
#[inline(always)]
pub fn penalty_pair<D: Dim>(
    v_ij: D::Vector,
    l_i: D::Matrix,
    l_j: D::Matrix,
    pk: &PairKernel<D>,
    vj_rho_i: f64,
    xi_g: f64,
) -> D::Vector {
    let predicted = (l_i + l_j) * (pk.e * (0.5 * pk.r));
    let mismatch = D::dot(v_ij - predicted, pk.e);
    pk.e * (xi_g * mismatch * pk.dw * vj_rho_i / pk.r)
}

/// The Rodrigues rotation `exp(Ω Δt) = I + sin θ Ω̂ + (1 − cos θ) Ω̂²` of the spin
/// `Ω = ½(L − Lᵀ)` over `dt`, with `ω = √(−½ tr Ω²)`, `θ = ω Δt`, `Ω̂ = Ω/ω` (identity for
/// `θ` below 1e-14; the authors' `computeRotationMatrixRodrigues`).
#[inline(always)]
pub fn spin_rotation<D: Dim>(l: D::Matrix, dt: f64) -> D::Matrix {
    let omega = (l - D::transpose(l)) * 0.5;
    let norm = (-0.5 * D::trace(omega * omega)).max(0.0).sqrt();
    let theta = norm * dt;
    if theta.abs() < 1e-14 {
        return D::identity();
    }
    let unit = omega * (1.0 / norm);
    D::identity() + unit * theta.sin() + unit * unit * (1.0 - theta.cos())
}

/// GNOG's shear term of the force gather: eq. (13) with the tracked `τ` plus the accumulated
/// penalty acceleration.
pub(crate) struct GeneralizedShear<'a, D: Dim> {
    pub tau: &'a [D::Matrix],
    pub penalty: &'a [D::Vector],
}

impl<D: Dim> ShearForce<D> for GeneralizedShear<'_, D> {
    #[inline(always)]
    fn pair(
        &self,
        i: usize,
        j: usize,
        pk: &PairKernel<D>,
        vj_rho_i: f64,
    ) -> (D::Vector, D::Vector) {
        (
            crate::nested::shear_pair_acceleration::<D>(
                self.tau[i],
                self.tau[j],
                pk.e,
                pk.dw,
                vj_rho_i,
            ),
            D::zero(),
        )
    }
    #[inline(always)]
    fn particle(&self, i: usize) -> D::Vector {
        self.penalty[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat2, DMat3, DVec2, DVec3};
    use sph_core::{D2, D3};

    #[test]
    fn spin_rotation_is_the_rotation_by_the_spin_angle() {
        // 2D: L = [[0, −w], [w, 0]] rotates by w Δt.
        let w = 3.0;
        let l =
            DMat2::from_cols_array(&[0.0, w, -w, 0.0]) + DMat2::from_diagonal(DVec2::splat(0.7));
        let r = spin_rotation::<D2>(l, 0.1);
        let expect = DMat2::from_angle(0.3);
        assert!(D2::frobenius(r - expect) < 1e-15);
        // 3D: spin about z; orthogonal with det 1.
        let l = DMat3::from_cols_array(&[0.0, 2.0, -1.0, -2.0, 0.0, 0.5, 1.0, -0.5, 0.0]);
        let r = spin_rotation::<D3>(l, 0.05);
        assert!(D3::frobenius(r.transpose() * r - DMat3::IDENTITY) < 1e-14);
        assert!((D3::det(r) - 1.0).abs() < 1e-14);
        // The axis (ω = (−0.5·(−1)…)) is invariant: Ω ω = 0.
        let omega = (l - l.transpose()) * 0.5;
        let axis = DVec3::new(omega.y_axis.z, omega.z_axis.x, omega.x_axis.y);
        assert!((r * axis - axis).length() < 1e-14);
    }

    #[test]
    fn a_linear_field_has_no_penalty_and_a_zigzag_has() {
        let l = DMat2::from_cols_array(&[0.1, -0.4, 0.3, 0.2]);
        let pk = PairKernel::<D2> {
            e: DVec2::new(0.6, 0.8),
            r: 0.02,
            dw: -50.0,
        };
        let v_ij = l * (pk.e * pk.r);
        let a = penalty_pair::<D2>(v_ij, l, l, &pk, 1e-7, 2.0 * 1e6);
        assert!(a.length() < 1e-15 * 2e6, "{a}");
        // A pair moving apart faster than predicted is pulled together (toward j: −e_ij).
        let a = penalty_pair::<D2>(v_ij + pk.e * 0.01, l, l, &pk, 1e-7, 2.0 * 1e6);
        assert!(a.dot(pk.e) < 0.0);
    }
}
