//! Scalar stress measures for output.

use glam::DMat3;

/// Von Mises equivalent stress `√(3/2 s:s)`, `s = σ − ⅓ tr(σ) I` the deviator of the 3×3 Cauchy
/// stress; equals docs/methods.md's
/// `√(σxx² + σyy² + σzz² − σxxσyy − σyyσzz − σzzσxx + 3(σxy² + σyz² + σzx²))`.
/// 2D plane strain is handled by passing [`crate::Material::cauchy_stress_3d`], which includes
/// `σzz`. The TL and UL papers colour their figures by this `σ̄`.
#[inline]
pub fn von_mises(sigma: DMat3) -> f64 {
    let mean = (sigma.x_axis.x + sigma.y_axis.y + sigma.z_axis.z) / 3.0;
    let s = sigma - DMat3::IDENTITY * mean;
    let ss = s.x_axis.length_squared() + s.y_axis.length_squared() + s.z_axis.length_squared();
    (1.5 * ss).sqrt()
}
