//! Gray–Monaghan–Swift artificial stress for SPH-OAS (Gray, Monaghan & Swift 2001; docs/methods.md),
//! in 2D and 3D through the symmetric eigen-decomposition of the total stress.

use crate::nested::shear_pair_acceleration;
use crate::shear::ShearForce;
use sph_core::{Dim, PairKernel};
use sph_core::{Kernel, WendlandC2};

/// Default strength `ε` (Gray et al. 2001; the UL paper's OAS runs).
pub const DEFAULT_EPSILON: f64 = 0.3;
/// Default exponent `n` of the pair factor `f_ij^n`.
pub const DEFAULT_EXPONENT: u32 = 4;

/// Gray, Monaghan & Swift (2001), as in docs/methods.md: with the total stress `σ = τ − p I`
/// eigen-decomposed as `Q diag(σ_k) Qᵀ`, `R̄_k = −ε σ_k/ρ²` for `σ_k > 0` (tension), else 0, and
/// `R = Q diag(R̄) Qᵀ`. The eigen-solver replaces the 2D angle formula, which makes the same code
/// serve 3D (the UL paper notes OAS had no 3D form).
#[inline]
pub fn artificial_stress<D: Dim>(sigma: D::Matrix, rho: f64, epsilon: f64) -> D::Matrix {
    let (vals, q) = D::symmetric_eigen(sigma);
    let mut r = vals;
    let scale = -epsilon / (rho * rho);
    for k in 0..D::D {
        let s = D::component(vals, k);
        D::set_component(&mut r, k, if s > 0.0 { scale * s } else { 0.0 });
    }
    D::from_eigen(r, q)
}

/// Pair term of the artificial stress, Gray et al. (2001):
/// `m_j f_ij^n (R_i + R_j) ∇_i W_ij`, `f_ij = W(r_ij)/W(dp)` (`w = W(r_ij)`, `∇_i W_ij` from
/// `pair`).
#[inline(always)]
pub fn artificial_pair_acceleration<D: Dim>(
    r_i: D::Matrix,
    r_j: D::Matrix,
    pair: &PairKernel<D>,
    w: f64,
    inv_w_dp: f64,
    exponent: u32,
    m_j: f64,
) -> D::Vector {
    let f = (w * inv_w_dp).powi(exponent as i32);
    (r_i + r_j) * (pair.e * (pair.dw * m_j * f))
}

/// OAS's shear term. The artificial stress's pair factor `f_ij = W(r_ij)/W(dp)` is evaluated
/// at the *current* distance in every acoustic sub-step, not from the kernel data frozen at the
/// rebuild: `f_ij^n` (n = 4) is a stiff short-range repulsion, and with the distance frozen
/// over an advection step it lags the motion and pumps energy in — measured: the plate
/// (H/dp = 10, v_f = 0.05) blew up at t = 0.077 s and the rings at 0.07 c0 at t = 0.006 s with
/// frozen `f`, both run through with single stepping or with the current `f`. With
/// [`crate::UlParams::refresh_kernel_data`] the pair data are current already.
pub(crate) struct ArtificialShear<'a, D: Dim> {
    pub tau: &'a [D::Matrix],
    pub r: &'a [D::Matrix],
    pub masses: &'a [f64],
    /// Current positions when the kernel data are frozen (`W` recomputed here), else `None`.
    pub positions: Option<&'a [D::Vector]>,
    pub kernel: &'a WendlandC2<D>,
    pub inv_w_dp: f64,
    pub n: u32,
}

impl<D: Dim> ShearForce<D> for ArtificialShear<'_, D> {
    #[inline(always)]
    fn pair(
        &self,
        i: usize,
        j: usize,
        pk: &PairKernel<D>,
        vj_rho_i: f64,
    ) -> (D::Vector, D::Vector) {
        let w = match self.positions {
            Some(x) => self.kernel.w(D::norm(x[i] - x[j])),
            None => pk.w(self.kernel),
        };
        (
            shear_pair_acceleration::<D>(self.tau[i], self.tau[j], pk.e, pk.dw, vj_rho_i),
            artificial_pair_acceleration::<D>(
                self.r[i],
                self.r[j],
                pk,
                w,
                self.inv_w_dp,
                self.n,
                self.masses[j],
            ),
        )
    }
    #[inline(always)]
    fn particle(&self, _i: usize) -> D::Vector {
        D::zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat2, DMat3, DVec3};
    use sph_core::{D2, D3};

    #[test]
    fn artificial_stress_acts_on_tensile_principal_directions_only_2d() {
        // 2D: compare with the closed form of Gray et al. (angle tan 2θ = 2σxy/(σxx − σyy)).
        let (sxx, syy, sxy) = (3.0, -1.0, 1.5);
        let sigma = DMat2::from_cols_array(&[sxx, sxy, sxy, syy]);
        let r = artificial_stress::<D2>(sigma, 2.0, 0.3);
        let theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
        let (s, c) = theta.sin_cos();
        let s1 = c * c * sxx + 2.0 * s * c * sxy + s * s * syy;
        let s2 = s * s * sxx - 2.0 * s * c * sxy + c * c * syy;
        let r1 = if s1 > 0.0 { -0.3 * s1 / 4.0 } else { 0.0 };
        let r2 = if s2 > 0.0 { -0.3 * s2 / 4.0 } else { 0.0 };
        let rxx = c * c * r1 + s * s * r2;
        let ryy = s * s * r1 + c * c * r2;
        let rxy = s * c * (r1 - r2);
        let expect = DMat2::from_cols_array(&[rxx, rxy, rxy, ryy]);
        assert!(D2::frobenius(r - expect) < 1e-14, "{r:?} vs {expect:?}");
    }

    #[test]
    fn artificial_stress_3d_rotates_with_the_stress() {
        let q = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        let diag = DMat3::from_diagonal(DVec3::new(2.0, -1.0, 0.5));
        let r = artificial_stress::<D3>(q * diag * q.transpose(), 1.0, 0.3);
        let expect = q * DMat3::from_diagonal(DVec3::new(-0.6, 0.0, -0.15)) * q.transpose();
        assert!(D3::frobenius(r - expect) < 1e-13);
        // Pure compression: no artificial stress.
        let r = artificial_stress::<D3>(DMat3::IDENTITY * -5.0, 1.0, 0.3);
        assert_eq!(r, DMat3::ZERO);
    }
}
