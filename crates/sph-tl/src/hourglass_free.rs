//! The hourglass-free (HF) formulation (TL paper §3.3, eq 25–29).
//!
//! The Kirchhoff stress is split (eq 25) into the shear part `τ_s = J^(−2/d) G b`, whose
//! divergence is the Laplacian of position (eq 26) discretised pairwise (eq 27), and the
//! remaining isotropic stress plus damping `τ_r` (eq 28), whose divergence uses eq 20 **without**
//! the correction matrix: then the ζ terms of the two parts cancel exactly in the undeformed
//! state, free surfaces included, and a body at rest stays at rest (docs/methods.md). `d` is the
//! spatial dimension (`d = 2` in plane strain, as the paper uses it).
//!
//! The paper writes the split for its own law (TL eq. 10–14, [`sph_materials::KirchhoffVolDev`]).
//! Any other law is split the same way ([`Material::hf_split`]): the Laplacian carries
//! `τ_s = G g(J) b` and the remainder `τ_r = τ(F) − τ_s + …` goes through eq 20 without `B`, so
//! the scheme represents the chosen law (neo-Hookean takes `g = 1`, which keeps `τ_r`
//! isotropic as in the paper; for a law whose deviator is not `G g b`, `τ_r` carries the
//! difference).

use crate::damping::damping_kirchhoff;
use crate::original::nan_matrix;
use crate::reference_pairs::PairRows;
use serde::{Deserialize, Serialize};
use sph_core::parallel::gather;
use sph_core::Dim;
use sph_materials::Material;

/// Default ζ = 1.07 (TL paper §4, for the Wendland C2 kernel with h = 1.15 dp).
pub const DEFAULT_ZETA: f64 = 1.07;

/// Which ζ scales the Laplacian of eq 27 (and, with it, the trace term of eq 28 that cancels
/// it at rest).
///
/// The paper's constant ζ = 1.07 makes the Laplacian exact for none of the neighbourhoods a
/// body has: on a full square lattice at h = 1.15 dp the discrete second moment of its weights
/// ([`normalised_zeta`]) asks for 1.033 (2D) or 1.006 (3D), so the shear modulus is 3.6 % or
/// 6.4 % too stiff in the bulk at every resolution, and a particle of a free surface's outer
/// layer, which misses part of its neighbourhood, needs 1.4 (3D) to 1.6 (2D) and gets 1.07:
/// the surface layer's shear is too soft by a quarter to a third.
/// [`HfLaplacian::Normalised`] gives every particle the ζ of its own neighbourhood. Measured
/// (docs/validation.md, "TL-HF: the Laplacian normalised per particle"): the errors that did
/// not shrink with resolution converge (homogeneous compression, Lamé ring), the plate period
/// moves toward the finite-element one, and the undamped plate that inverts a particle with the
/// paper's ζ runs through.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HfLaplacian {
    /// The paper's constant ζ ([`crate::Shear::HourglassFree`]'s `zeta`, 1.07 by default):
    /// reproduces the TL paper's results.
    #[default]
    Paper,
    /// Each particle's own ζ from its reference neighbourhood ([`normalised_zeta`]); the
    /// shear's `zeta` is not used (and must stay at its default).
    Normalised,
}

impl HfLaplacian {
    /// The name a case or scene key spells (`paper`, `normalised`).
    pub fn name(self) -> &'static str {
        match self {
            HfLaplacian::Paper => "paper",
            HfLaplacian::Normalised => "normalised",
        }
    }

    /// The choice a key names.
    pub fn from_name(name: &str) -> Option<Self> {
        [HfLaplacian::Paper, HfLaplacian::Normalised]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

/// The normalised ζ of every particle: `ζ_i = d / m_i`, `m_i = −Σ_j |X_ij|² V_j W′(r⁰_ij)/r⁰_ij`
/// over its reference neighbours (`X_ij = X_i − X_j`; `V_j W′/r⁰` is the pair scalar of
/// eq 27).
///
/// The Laplacian of eq 27 applied to a quadratic field `½ Xᵀ H X` returns `H : M_i` with
/// `M_i = −Σ_j X_ij ⊗ X_ij V_j W′/r⁰`, and `M_i = I` in the continuum (by parts,
/// `−∫ r W′(r) dV = d ∫ W dV = d`), so `ζ_i = d / tr M_i` makes it exact for any neighbourhood
/// whose second moment is isotropic: 1 in the continuum, 1.033 (2D) and 1.006 (3D) on a full
/// square lattice at h = 1.15 dp, 1.58 (2D) and 1.41 (3D) in the outer layer of a flat face.
/// A particle without neighbours (a distributed run's outer halo layer, whose rows are left
/// empty and whose values no owned particle reads) gets 1. Eq 27 and eq 28 both take the
/// particle's own `ζ_i` (pairs carry `ζ_i g_i` and `ζ_j g_j`), so the two still cancel exactly
/// in the undeformed state and every pair force stays antisymmetric: momentum is conserved as
/// with the constant ζ.
pub fn normalised_zeta<D: Dim>(pairs: impl PairRows<D>, reference: &[D::Vector]) -> Vec<f64> {
    let d = D::D as f64;
    (0..reference.len())
        .map(|i| {
            let xi = reference[i];
            let m = pairs.fold(i, 0.0, |m, j, _, s| {
                let r = xi - reference[j];
                m - D::dot(r, r) * s
            });
            if m > 0.0 {
                d / m
            } else {
                1.0
            }
        })
        .collect()
}

/// Eq 28: the remaining Kirchhoff stress `τ_r` of the material's HF split
/// ([`Material::hf_split`]: for the paper's law `[(K/2)(J² − 1) − (ζ/d) G J^(−2/d) tr(b)] I`)
/// plus the damping stress `τ_d`, returned as `P_r = τ_r F⁻ᵀ`, together with the factor `g`
/// (`J^(−2/d)` for the paper's law) of the shear stress `τ_s = G g b` for eq 27.
#[inline(always)]
pub fn remaining_piola<D: Dim, M: Material<D>>(
    material: &M,
    zeta: f64,
    gamma: f64,
    f: D::Matrix,
    f_dot: D::Matrix,
) -> (D::Matrix, f64) {
    let (mut tau, g) = material.hf_split(f, zeta);
    if gamma > 0.0 {
        tau += damping_kirchhoff::<D>(gamma, f, f_dot);
    }
    let f_inv_t = D::transpose(D::try_inverse(f).unwrap_or_else(nan_matrix::<D>));
    (tau * f_inv_t, g)
}

/// Eq 29 in one pass over each particle's neighbours: the remaining-stress divergence (eq 20
/// structure with `P_r`, no `B`) plus the shear acceleration of eq 27,
/// `a_i = (1/ρ0) Σ_j (P_r,i + P_r,j) V_j ∇⁰_i W_ij
///      + (ζ G/ρ0) Σ_j (J_i^(−2/d) + J_j^(−2/d)) x_ij V_j W′(r⁰_ij)/r⁰_ij`,
/// with `V_j ∇⁰_i W_ij` and `V_j W′(r⁰_ij)/r⁰_ij` from `pairs`. Fusing the two sums reads each
/// neighbour once. In 3D with stored pair data, where the loops run their AVX2 copy, the sums
/// are taken with a vector in one AVX register (module `lanes`; the same bits).
#[allow(clippy::too_many_arguments)]
pub fn acceleration<D: Dim>(
    pairs: impl PairRows<D>,
    remaining: &[D::Matrix],
    positions: &[D::Vector],
    isochoric: &[f64],
    inv_density: f64,
    zeta_g_over_rho: f64,
    acc: &mut [D::Vector],
) {
    // 3D with stored pair data: the same sums with a vector in one AVX register.
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::available() {
        if let (Some((g, s)), Some(p), Some(x), Some(a)) = (
            pairs.stored(),
            D::as_mat3(remaining),
            D::as_vec3(positions),
            D::as_vec3_mut(acc),
        ) {
            if let (Some(g), false) = (D::as_vec3(g), s.is_empty()) {
                let list = pairs.list();
                crate::lanes::hf_acceleration(
                    list,
                    g,
                    s,
                    p,
                    x,
                    isochoric,
                    inv_density,
                    zeta_g_over_rho,
                    a,
                );
                return;
            }
        }
    }
    acceleration_generic(
        pairs,
        remaining,
        positions,
        isochoric,
        inv_density,
        zeta_g_over_rho,
        acc,
    );
}

/// Eq 29 from its two pair sums: `a_i = div/ρ0 + (ζ G/ρ0) shear`, with `div = Σ_j (P_r,i +
/// P_r,j) V_j ∇⁰_i W_ij` and `shear = Σ_j (J_i^(−2/d) + J_j^(−2/d)) x_ij V_j W′/r⁰`.
#[inline(always)]
pub(crate) fn acceleration_from_sums<D: Dim>(
    div: D::Vector,
    shear: D::Vector,
    inv_density: f64,
    zeta_g_over_rho: f64,
) -> D::Vector {
    div * inv_density + shear * zeta_g_over_rho
}

/// [`acceleration`] for any dimension and pair storage.
#[allow(clippy::too_many_arguments)]
pub(crate) fn acceleration_generic<D: Dim>(
    pairs: impl PairRows<D>,
    remaining: &[D::Matrix],
    positions: &[D::Vector],
    isochoric: &[f64],
    inv_density: f64,
    zeta_g_over_rho: f64,
    acc: &mut [D::Vector],
) {
    let list = pairs.list();
    let (p_j, x_j, iso_j) = (
        list.values(remaining),
        list.values(positions),
        list.values(isochoric),
    );
    gather(
        acc,
        #[inline(always)]
        |i, a| {
            let (pi, xi, ji) = (remaining[i], positions[i], isochoric[i]);
            let (div, shear) =
                pairs.fold(i, (D::zero(), D::zero()), move |(div, shear), j, g, s| {
                    // SAFETY: the rows visit the indices of `pairs.list()`, which made the views.
                    let (p_j, x_j, iso_j) = unsafe { (p_j.at(j), x_j.at(j), iso_j.at(j)) };
                    (
                        div + (pi + p_j) * g,
                        shear + (xi - x_j) * ((ji + iso_j) * s),
                    )
                });
            *a = acceleration_from_sums::<D>(div, shear, inv_density, zeta_g_over_rho);
        },
    );
}
