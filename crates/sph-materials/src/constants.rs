//! Isotropic elastic constants and the relations between them (TL paper eq. 5–6).

use serde::{Deserialize, Serialize};
use sph_core::error::{check_closed_range, check_open_range};
use sph_core::Error;

/// Densities a material may have, kg/m³: from a thousandth of air to fifty times osmium, so SI
/// solids, foams and gels, and non-dimensional runs (ρ = 1) pass, and `1e300` does not.
pub const DENSITY_RANGE: (f64, f64) = (1e-3, 1e6);

/// Elastic moduli a material may have, Pa: from soft gels (and non-dimensional runs, E = 1) to
/// ten times diamond.
pub const MODULUS_RANGE: (f64, f64) = (1e-3, 1e13);

/// `Ok` if `density` is within [`DENSITY_RANGE`].
pub(crate) fn check_density(density: f64) -> Result<(), Error> {
    check_closed_range("density", density, DENSITY_RANGE.0, DENSITY_RANGE.1)
}

/// `Ok` if the modulus `field` is within [`MODULUS_RANGE`].
pub(crate) fn check_modulus(field: &str, value: f64) -> Result<(), Error> {
    check_closed_range(field, value, MODULUS_RANGE.0, MODULUS_RANGE.1)
}

/// Relative tolerance with which derived constants given in a case file must agree with the ones
/// computed from the independent pair.
const CONSISTENCY_TOL: f64 = 1e-9;

/// Isotropic linear-elastic constants of a solid, all in SI units, always mutually consistent.
///
/// Relations (TL paper eq. 5–6; docs/methods.md "Materials"):
/// `K = E / (3(1 − 2ν))`, `G = μ = E / (2(1 + ν))`, `λ = E ν / ((1 + ν)(1 − 2ν))`,
/// `K = λ + 2G/3`. (The TL paper's eq. 6 prints `E = 2G(1 + 2ν)`, a typo for `E = 2G(1 + ν)`.)
///
/// The sound speed is the bulk one, `c0 = √(K / ρ0)`, as in all three papers (TL paper §3 damping
/// and time step, UL paper EOS `c0 = √(E / (3(1 − 2ν) ρ0))`, MPS paper `c0 = √(K / ρs)`).
/// For E = 2 MPa, ν = 0.3975, ρ0 = 1000 kg/m³ (TL oscillating plate) it is ≈ 57.03 m/s.
///
/// Build with [`ElasticConstants::from_youngs`] or [`ElasticConstants::from_bulk_shear`]. In a
/// case file give either `youngs_modulus` and `poisson_ratio`, or `bulk_modulus` and
/// `shear_modulus`, plus `density`; any further field given must agree with the computed one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ElasticConstantsRepr")]
pub struct ElasticConstants {
    /// Young's modulus `E` (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν`, in the open interval (−1, 0.5).
    pub poisson_ratio: f64,
    /// Reference density `ρ0` (kg/m³).
    pub density: f64,
    /// Bulk modulus `K = E / (3(1 − 2ν))` (Pa).
    pub bulk_modulus: f64,
    /// Shear modulus `G = μ = E / (2(1 + ν))` (Pa), Lamé's second constant.
    pub shear_modulus: f64,
    /// Lamé's first constant `λ = E ν / ((1 + ν)(1 − 2ν))` (Pa).
    pub lame_lambda: f64,
    /// Bulk sound speed `c0 = √(K / ρ0)` (m/s).
    pub sound_speed: f64,
}

impl ElasticConstants {
    /// Constants from Young's modulus `E` (within [`MODULUS_RANGE`]), Poisson's ratio
    /// `−1 < ν < 0.5` and reference density `ρ0` (within [`DENSITY_RANGE`]); the relations of
    /// TL paper eq. 5–6.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `youngs_modulus`, `poisson_ratio` or `density`.
    pub fn from_youngs(
        youngs_modulus: f64,
        poisson_ratio: f64,
        density: f64,
    ) -> Result<Self, Error> {
        check_modulus("youngs_modulus", youngs_modulus)?;
        check_open_range("poisson_ratio", poisson_ratio, -1.0, 0.5)?;
        check_density(density)?;
        let (e, nu) = (youngs_modulus, poisson_ratio);
        let bulk = e / (3.0 * (1.0 - 2.0 * nu));
        let shear = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        Self::finish(e, nu, density, bulk, shear, lambda)
    }

    /// Constants from the bulk modulus `K` and shear modulus `G` (within [`MODULUS_RANGE`]) and
    /// reference density `ρ0` (within [`DENSITY_RANGE`]) (the MPS paper gives K and μ): `E = 9KG / (3K + G)`,
    /// `ν = (3K − 2G) / (2(3K + G))`, `λ = K − 2G/3`. Any `K, G > 0` gives `−1 < ν < 0.5`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `bulk_modulus`, `shear_modulus` or `density`.
    pub fn from_bulk_shear(
        bulk_modulus: f64,
        shear_modulus: f64,
        density: f64,
    ) -> Result<Self, Error> {
        check_modulus("bulk_modulus", bulk_modulus)?;
        check_modulus("shear_modulus", shear_modulus)?;
        check_density(density)?;
        let (k, g) = (bulk_modulus, shear_modulus);
        let e = 9.0 * k * g / (3.0 * k + g);
        let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
        Self::finish(e, nu, density, k, g, k - 2.0 * g / 3.0)
    }

    fn finish(e: f64, nu: f64, rho: f64, k: f64, g: f64, lambda: f64) -> Result<Self, Error> {
        let c = Self {
            youngs_modulus: e,
            poisson_ratio: nu,
            density: rho,
            bulk_modulus: k,
            shear_modulus: g,
            lame_lambda: lambda,
            sound_speed: (k / rho).sqrt(),
        };
        // Overflow (e.g. E near f64::MAX, or ν a hair below 0.5) must not slip through.
        for (field, v) in [
            ("youngs_modulus", c.youngs_modulus),
            ("bulk_modulus", c.bulk_modulus),
            ("shear_modulus", c.shear_modulus),
            ("lame_lambda", c.lame_lambda),
            ("sound_speed", c.sound_speed),
        ] {
            if !v.is_finite() {
                return Err(Error::invalid(
                    field,
                    v,
                    "finite (derived constants overflowed)",
                ));
            }
        }
        Ok(c)
    }

    /// Lamé's second constant `μ` (= [`Self::shear_modulus`]).
    #[inline]
    pub fn mu(&self) -> f64 {
        self.shear_modulus
    }
}

/// What a case file may give: one independent pair plus density, other fields optional checks.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ElasticConstantsRepr {
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    density: f64,
    bulk_modulus: Option<f64>,
    shear_modulus: Option<f64>,
    lame_lambda: Option<f64>,
    sound_speed: Option<f64>,
}

impl TryFrom<ElasticConstantsRepr> for ElasticConstants {
    type Error = Error;
    fn try_from(r: ElasticConstantsRepr) -> Result<Self, Error> {
        let c = match (
            r.youngs_modulus,
            r.poisson_ratio,
            r.bulk_modulus,
            r.shear_modulus,
        ) {
            (Some(e), Some(nu), _, _) => Self::from_youngs(e, nu, r.density)?,
            (_, _, Some(k), Some(g)) => Self::from_bulk_shear(k, g, r.density)?,
            _ => {
                return Err(Error::invalid(
                    "elastic constants",
                    "incomplete",
                    "youngs_modulus and poisson_ratio, or bulk_modulus and shear_modulus",
                ))
            }
        };
        for (field, given, computed) in [
            ("youngs_modulus", r.youngs_modulus, c.youngs_modulus),
            ("poisson_ratio", r.poisson_ratio, c.poisson_ratio),
            ("bulk_modulus", r.bulk_modulus, c.bulk_modulus),
            ("shear_modulus", r.shear_modulus, c.shear_modulus),
            ("lame_lambda", r.lame_lambda, c.lame_lambda),
            ("sound_speed", r.sound_speed, c.sound_speed),
        ] {
            if let Some(v) = given {
                // Written so that a NaN `v` fails the check.
                let agrees = (v - computed).abs() <= CONSISTENCY_TOL * computed.abs().max(1.0);
                if !agrees {
                    return Err(Error::invalid(
                        field,
                        v,
                        &format!("consistent with the other constants ({computed})"),
                    ));
                }
            }
        }
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sound_speed_of_the_tl_oscillating_plate_is_57_03() {
        let c = ElasticConstants::from_youngs(2.0e6, 0.3975, 1000.0).unwrap();
        // K = 2e6 / (3 · 0.205) = 3.2520e6 Pa; c0 = √3252.03 = 57.027 m/s. The paper-level figure
        // is quoted to 4 digits, so 0.01 m/s absolute.
        assert!((c.sound_speed - 57.03).abs() < 0.01, "{}", c.sound_speed);
        // Exact relations to round-off (1e-14 relative: a few operations on O(1) ratios).
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(rel(c.bulk_modulus, c.lame_lambda + 2.0 * c.shear_modulus / 3.0) < 1e-14);
        assert!(
            rel(
                c.youngs_modulus,
                2.0 * c.shear_modulus * (1.0 + c.poisson_ratio)
            ) < 1e-14
        );
    }

    #[test]
    fn bulk_shear_round_trips_through_youngs() {
        // The MPS paper's rubber: K = 3.25e6, μ = 7.15e5.
        let a = ElasticConstants::from_bulk_shear(3.25e6, 7.15e5, 1000.0).unwrap();
        let b = ElasticConstants::from_youngs(a.youngs_modulus, a.poisson_ratio, 1000.0).unwrap();
        // Round-off of two chains of ~5 flops each: 1e-13 relative.
        for (x, y) in [
            (a.bulk_modulus, b.bulk_modulus),
            (a.shear_modulus, b.shear_modulus),
            (a.lame_lambda, b.lame_lambda),
            (a.sound_speed, b.sound_speed),
        ] {
            assert!((x - y).abs() <= 1e-13 * y.abs(), "{x} vs {y}");
        }
    }

    #[test]
    fn poisson_ratio_error_names_the_allowed_range() {
        let err = ElasticConstants::from_youngs(1.0, 0.5, 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("poisson_ratio") && err.contains("0.5") && err.contains("-1"),
            "{err}"
        );
    }

    #[test]
    fn near_incompressible_overflow_is_rejected() {
        let nu = 0.5 - 1e-17; // rounds to 0.5 → rejected by the range check itself
        assert!(ElasticConstants::from_youngs(1.0, nu, 1.0).is_err());
        // A modulus that would overflow is outside the physical range, and within it nothing
        // overflows, however close to incompressible.
        let err = ElasticConstants::from_youngs(f64::MAX, 0.49, 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("youngs_modulus") && err.contains("1e13"),
            "{err}"
        );
        let nu = 0.5 - f64::EPSILON;
        let c = ElasticConstants::from_youngs(MODULUS_RANGE.1, nu, DENSITY_RANGE.0).unwrap();
        assert!(c.bulk_modulus.is_finite() && c.sound_speed.is_finite());
    }
}
