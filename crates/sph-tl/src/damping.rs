//! Kelvin–Voigt artificial damping (TL paper eq 23–24).

use sph_core::Dim;

/// Damping coefficient `γ = ρ0 c h / 2` with `c = √(K/ρ0)` (TL paper, after eq 23). The paper
/// writes ρ; the reference density is used (as in SPHinXsys), which makes `γ` a constant.
pub fn damping_coefficient(density: f64, sound_speed: f64, h: f64) -> f64 {
    0.5 * density * sound_speed * h
}

/// Damping Kirchhoff stress `τ_d = (γ/2) ḃ`, `ḃ = Ḟ Fᵀ + F Ḟᵀ` (TL paper eq 23–24).
#[inline(always)]
pub fn damping_kirchhoff<D: Dim>(gamma: f64, f: D::Matrix, f_dot: D::Matrix) -> D::Matrix {
    let fdft = f_dot * D::transpose(f);
    (fdft + D::transpose(fdft)) * (0.5 * gamma)
}

/// The damping contribution to the first Piola–Kirchhoff stress, `τ_d F⁻ᵀ`, given `F⁻ᵀ`.
#[inline(always)]
pub fn damping_piola<D: Dim>(
    gamma: f64,
    f: D::Matrix,
    f_dot: D::Matrix,
    f_inv_t: D::Matrix,
) -> D::Matrix {
    damping_kirchhoff::<D>(gamma, f, f_dot) * f_inv_t
}
