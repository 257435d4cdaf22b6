//! Error estimates from a resolution ladder, and the ladder that stops when a tolerance is met
//! or the next level would exceed a budget (`sph converge`; `sph_cases::converge::converge`
//! from Rust).
//!
//! A quantity `f` computed at particle spacings `h₁ > h₂ > … > hₙ` (finer and finer) is
//! fitted as `f(h) = f₀ + α hᵖ` in the manner of the grid convergence index (Roache 1998) and
//! of the least-squares procedure of Eça & Hoekstra (2014, J. Comput. Phys. 262, 104–130):
//!
//! The estimate rests on the finest [`FITTED_LEVELS`] levels (four): a longer ladder's coarser
//! levels are reported but not fitted, because they are the least likely to be in the
//! asymptotic range (a ladder started coarse would otherwise never verify one power law), and
//! because the factors below are calibrated on ladders of three and four levels.
//!
//! - **monotone ladders** (successive differences of one sign): `f₀`, `α`, `p` by least squares
//!   over those levels (exact through three); `δ = |f_n − f₀|` is the estimated error of the
//!   finest run and `U_s` the standard deviation of the fit (zero for three levels). The
//!   uncertainty is `U = F_s δ + U_s` for an observed order in `[0.95, 2.05)`; below it,
//!   `min(F_s δ + U_s, F_s Δ_M)` (`Δ_M`, the spread of the values: a slow order extrapolates
//!   far); above it, `max(F_s δ₂ + U_s, F_s Δ_M)` with `δ₂` the fit at `p = 2` (a fast order is
//!   not trusted below the data's own spread);
//! - **oscillating ladders**: `U = 3 Δ_M`, no order, never asymptotic;
//! - **two levels**: no order can be observed; `p = 1` (the lowest the methods show in
//!   docs/tradeoffs.md) is assumed and `F_s = 3`.
//!
//! The safety factor is `F_s = 2` when the ladder is *verified* asymptotic: monotone, an
//! order in `[0.95, 2.05)`, and at least four levels whose finest three give an order within
//! 15 % of the fitted one (one power law across the ladder); otherwise `F_s = 3`, Roache's
//! factor for an order that is not confirmed ([`Factors::CONVERGE`]: the CFD practice's 1.25
//! and 30 % were too optimistic for the particle methods' ladders, see docs/tradeoffs.md,
//! "Error estimates"). The estimate measures the discretisation error only: a method that
//! converges to a value other than the physical one (a model bias) shows no sign of it in its
//! own ladder (the same section measures both).

use serde::{Deserialize, Serialize};

pub mod ladder;

/// How many of the finest levels an estimate fits (the calibrated ladder length).
pub const FITTED_LEVELS: usize = 4;
/// The order assumed for a two-level estimate.
pub const ASSUMED_ORDER: f64 = 1.0;
/// The observed orders trusted as they are: `[lo, hi)` (Eça & Hoekstra).
pub const TRUSTED_ORDERS: (f64, f64) = (0.95, 2.05);

/// The estimator's factors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Factors {
    /// Safety factor of a verified asymptotic ladder.
    pub verified: f64,
    /// Safety factor when the order is not confirmed (two or three levels, an order outside
    /// the trusted range, or orders that disagree along the ladder).
    pub unverified: f64,
    /// Largest relative difference between the finest three levels' order and the whole
    /// ladder's for the ladder to count as one power law.
    pub order_agreement: f64,
}

impl Factors {
    /// The factors `sph converge` uses: 2 for a verified ladder whose orders agree within
    /// 15 %, 3 otherwise. Calibrated on the stored ladders of docs/tradeoffs.md ("Error
    /// estimates", which shows [`Factors::CFD_PRACTICE`] beside them): the particle methods'
    /// ladders stay pre-asymptotic longer than the grids the CFD practice was made for, and
    /// with its 1.25 and 30 % the estimate fell short of the methods' own limits in a fifth of
    /// the verified ladders.
    pub const CONVERGE: Factors = Factors {
        verified: 2.0,
        unverified: 3.0,
        order_agreement: 0.15,
    };

    /// The grid convergence index's practice (Roache; Eça & Hoekstra): 1.25 verified, 3
    /// otherwise, orders within 30 %.
    pub const CFD_PRACTICE: Factors = Factors {
        verified: 1.25,
        unverified: 3.0,
        order_agreement: 0.3,
    };
}

/// A value of the quantity at one spacing.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Particle spacing (any unit: only ratios matter).
    pub spacing: f64,
    /// The quantity.
    pub value: f64,
}

/// How the values approach their limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Behaviour {
    /// Every level gave the same value.
    Converged,
    /// Successive differences of one sign.
    Monotone,
    /// Differences that change sign.
    Oscillating,
    /// Two levels: one difference, no order.
    TwoLevels,
}

/// The estimate of one quantity from its ladder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// The extrapolated value `f₀` (the finest value when there is no extrapolation).
    pub value: f64,
    /// The finest run's value.
    pub finest: f64,
    /// Estimated error of the finest run, relative to it (`U / |f_n|`).
    pub error_estimate: f64,
    /// The observed order `p` (`None` without one).
    pub order: Option<f64>,
    /// Whether the ladder is verified to be in the asymptotic range (see the module
    /// documentation).
    pub asymptotic: bool,
    /// How the values approach their limit.
    pub behaviour: Behaviour,
    /// The safety factor used.
    pub safety_factor: f64,
    /// Why the estimate is not verified, in words (`None` when it is).
    pub warning: Option<String>,
}

/// Why no estimate can be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EstimateError {
    /// Fewer than two levels.
    #[error("{0} level(s): an estimate needs at least two")]
    TooFewLevels(usize),
    /// A value or spacing that is not a finite number (a positive one, for spacings).
    #[error("level {level}: {what} is {value}, not a finite number{positive}")]
    NotFinite {
        /// The level (0 the coarsest).
        level: usize,
        /// `value` or `spacing`.
        what: &'static str,
        /// As found.
        value: f64,
        /// `" > 0"` for spacings.
        positive: &'static str,
    },
    /// Two levels with the same spacing.
    #[error("two levels have the spacing {0}: each level needs its own")]
    RepeatedSpacing(f64),
    /// The finest value is zero: a relative error has no meaning.
    #[error("the finest value is 0: the relative error of a quantity that vanishes is undefined")]
    ZeroValue,
}

/// The least-squares fit `f = f₀ + α hᵖ` for a fixed `p`: `(f₀, α, sum of squared residuals)`.
fn fit_at(samples: &[Sample], p: f64) -> (f64, f64, f64) {
    let n = samples.len() as f64;
    let x: Vec<f64> = samples.iter().map(|s| s.spacing.powf(p)).collect();
    let mx = x.iter().sum::<f64>() / n;
    let my = samples.iter().map(|s| s.value).sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = x
        .iter()
        .zip(samples)
        .map(|(v, s)| (v - mx) * (s.value - my))
        .sum();
    let alpha = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let f0 = my - alpha * mx;
    let ssr = x
        .iter()
        .zip(samples)
        .map(|(v, s)| (f0 + alpha * v - s.value).powi(2))
        .sum();
    (f0, alpha, ssr)
}

/// The order `p ∈ [0.05, 10]` of the least-squares fit `f = f₀ + α hᵖ` (a scan on a fine grid
/// refined by golden sections; through three levels the fit is exact, Richardson's), with its
/// `(f₀, α, residual sum of squares)`.
fn fit(samples: &[Sample]) -> (f64, (f64, f64, f64)) {
    let ssr = |p: f64| fit_at(samples, p).2;
    let grid: Vec<f64> = (5..=1000).map(|k| 0.01 * k as f64).collect();
    let mut best = grid[0];
    for &p in &grid {
        if ssr(p) < ssr(best) {
            best = p;
        }
    }
    let (mut a, mut b) = ((best - 0.01).max(0.05), (best + 0.01).min(10.0));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if ssr(c) < ssr(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let p = 0.5 * (a + b);
    (p, fit_at(samples, p))
}

/// The estimate of a quantity from its values at several spacings (any order; see the module
/// documentation for the procedure).
///
/// # Errors
/// Fewer than two levels, a non-finite value or spacing, two levels of one spacing, or a
/// finest value of zero.
///
/// # Example
/// ```
/// use sph_driver::convergence::{estimate, Sample};
/// // f(h) = 1 + h²: four levels halving h.
/// let s: Vec<Sample> = [0.4, 0.2, 0.1, 0.05]
///     .iter()
///     .map(|&h: &f64| Sample { spacing: h, value: 1.0 + h * h })
///     .collect();
/// let e = estimate(&s).unwrap();
/// assert!((e.value - 1.0).abs() < 1e-9 && (e.order.unwrap() - 2.0).abs() < 1e-3);
/// assert!(e.asymptotic && e.error_estimate >= 0.0025 / 1.0025);
/// ```
pub fn estimate(samples: &[Sample]) -> Result<Estimate, EstimateError> {
    estimate_with(samples, &Factors::CONVERGE)
}

/// [`estimate`] with other factors (the calibration compares them).
///
/// # Errors
/// As [`estimate`].
pub fn estimate_with(samples: &[Sample], factors: &Factors) -> Result<Estimate, EstimateError> {
    if samples.len() < 2 {
        return Err(EstimateError::TooFewLevels(samples.len()));
    }
    for (k, s) in samples.iter().enumerate() {
        if !(s.spacing.is_finite() && s.spacing > 0.0) {
            return Err(EstimateError::NotFinite {
                level: k,
                what: "spacing",
                value: s.spacing,
                positive: " > 0",
            });
        }
        if !s.value.is_finite() {
            return Err(EstimateError::NotFinite {
                level: k,
                what: "value",
                value: s.value,
                positive: "",
            });
        }
    }
    let mut s = samples.to_vec();
    s.sort_by(|a, b| b.spacing.total_cmp(&a.spacing));
    if let Some(w) = s.windows(2).find(|w| w[0].spacing == w[1].spacing) {
        return Err(EstimateError::RepeatedSpacing(w[0].spacing));
    }
    // The finest levels only (see the module documentation).
    let s = s.split_off(s.len().saturating_sub(FITTED_LEVELS));
    let n = s.len();
    let finest = s[n - 1].value;
    if finest == 0.0 {
        return Err(EstimateError::ZeroValue);
    }
    let (lo, hi) = s
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x.value), hi.max(x.value))
        });
    let spread = hi - lo;
    let diffs: Vec<f64> = s.windows(2).map(|w| w[1].value - w[0].value).collect();
    let relative = |u: f64| u / finest.abs();
    if spread == 0.0 {
        return Ok(Estimate {
            value: finest,
            finest,
            error_estimate: 0.0,
            order: None,
            asymptotic: true,
            behaviour: Behaviour::Converged,
            safety_factor: factors.verified,
            warning: None,
        });
    }
    if n == 2 {
        let r = s[0].spacing / s[1].spacing;
        let delta = diffs[0].abs() / (r.powf(ASSUMED_ORDER) - 1.0);
        return Ok(Estimate {
            value: finest + diffs[0] / (r.powf(ASSUMED_ORDER) - 1.0),
            finest,
            error_estimate: relative(factors.unverified * delta),
            order: None,
            asymptotic: false,
            behaviour: Behaviour::TwoLevels,
            safety_factor: factors.unverified,
            warning: Some(format!(
                "two levels: the order is assumed ({ASSUMED_ORDER}), not observed; run a \
                 third level"
            )),
        });
    }
    let monotone = diffs
        .iter()
        .all(|d| *d != 0.0 && d.signum() == diffs[0].signum());
    if !monotone {
        return Ok(Estimate {
            value: finest,
            finest,
            error_estimate: relative(factors.unverified * spread),
            order: None,
            asymptotic: false,
            behaviour: Behaviour::Oscillating,
            safety_factor: factors.unverified,
            warning: Some(
                "oscillating: the values do not approach a limit monotonically, so the ladder \
                 is not in the asymptotic range; the estimate is 3 times their spread"
                    .into(),
            ),
        });
    }
    let (p, (f0, _, ssr)) = fit(&s);
    let scatter = if n > 3 {
        (ssr / (n - 3) as f64).sqrt()
    } else {
        0.0
    };
    let trusted = (TRUSTED_ORDERS.0..TRUSTED_ORDERS.1).contains(&p);
    let finest_three = (n >= 4).then(|| fit(&s[n - 3..]).0);
    let agrees = finest_three.is_some_and(|q| (q - p).abs() <= factors.order_agreement * p);
    let asymptotic = trusted && agrees;
    let fs = if asymptotic {
        factors.verified
    } else {
        factors.unverified
    };
    let delta = (finest - f0).abs();
    let u = if p < TRUSTED_ORDERS.0 {
        (fs * delta + scatter).min(fs * spread)
    } else if trusted {
        fs * delta + scatter
    } else {
        let (f02, _, _) = fit_at(&s, 2.0);
        (fs * (finest - f02).abs() + scatter).max(fs * spread)
    };
    let warning = if asymptotic {
        None
    } else if !trusted {
        Some(format!(
            "observed order {p:.2} outside [{}, {}): not in the asymptotic range (or a change \
             of regime); the estimate uses a safety factor of {}",
            TRUSTED_ORDERS.0, TRUSTED_ORDERS.1, factors.unverified
        ))
    } else if let Some(q) = finest_three {
        Some(format!(
            "the finest three levels give order {q:.2}, the whole ladder {p:.2}: not one power \
             law yet; the estimate uses a safety factor of {}",
            factors.unverified
        ))
    } else {
        Some(format!(
            "three levels: the order {p:.2} is not cross-checked (a fourth level would); the \
             estimate uses a safety factor of {}",
            factors.unverified
        ))
    };
    Ok(Estimate {
        value: f0,
        finest,
        error_estimate: relative(u),
        order: Some(p),
        asymptotic,
        behaviour: Behaviour::Monotone,
        safety_factor: fs,
        warning,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ladder(f: impl Fn(f64) -> f64, hs: &[f64]) -> Vec<Sample> {
        hs.iter()
            .map(|&h| Sample {
                spacing: h,
                value: f(h),
            })
            .collect()
    }

    /// A power law is recovered exactly (limit, order) and verified with four levels; the
    /// estimate is the verified safety factor times the true error of the finest level (the
    /// fit is exact: δ is the true error).
    #[test]
    fn a_power_law_is_recovered_and_its_error_bounded() {
        for p in [1.0, 1.5, 2.0] {
            let s = ladder(|h| 3.0 - 0.7 * h.powf(p), &[0.8, 0.4, 0.2, 0.1]);
            let e = estimate(&s).unwrap();
            assert!((e.value - 3.0).abs() < 1e-6, "{p}: {e:?}");
            assert!((e.order.unwrap() - p).abs() < 1e-3, "{p}: {e:?}");
            let truth = (s[3].value - 3.0).abs() / s[3].value;
            let ratio = e.error_estimate / truth;
            if p < 2.05 {
                assert!(e.asymptotic, "{p}: {e:?}");
                assert!(
                    (ratio - Factors::CONVERGE.verified).abs() < 1e-3,
                    "{p}: {ratio}"
                );
            }
        }
    }

    /// Three levels cannot cross-check the order: safety factor 3 and a warning.
    #[test]
    fn three_levels_are_not_verified() {
        let e = estimate(&ladder(|h| 1.0 + h, &[0.4, 0.2, 0.1])).unwrap();
        assert!(!e.asymptotic && e.safety_factor == 3.0, "{e:?}");
        assert!(e.warning.unwrap().contains("not cross-checked"));
        assert!((e.error_estimate - 3.0 * 0.1 / 1.1).abs() < 1e-6);
    }

    /// An oscillating ladder is flagged; its estimate is 3 times the spread of its values.
    #[test]
    fn oscillating_ladders_are_flagged() {
        let s = ladder(|h| 1.0 + (h * 37.0).sin() * h, &[0.4, 0.2, 0.1, 0.05]);
        let e = estimate(&s).unwrap();
        assert_eq!(e.behaviour, Behaviour::Oscillating);
        assert!(!e.asymptotic && e.warning.is_some());
    }

    /// Two power laws along the ladder (a change of regime) are not one asymptotic range.
    #[test]
    fn a_change_of_order_along_the_ladder_is_flagged() {
        // Order 1 on the coarse levels, order 2 on the fine ones.
        let s = ladder(
            |h| {
                1.0 + if h > 0.15 {
                    0.5 * h
                } else {
                    0.5 * h * h / 0.15 + 0.0
                }
            },
            &[0.8, 0.4, 0.2, 0.1, 0.05],
        );
        let e = estimate(&s).unwrap();
        assert!(!e.asymptotic, "{e:?}");
    }

    /// A ladder started coarse: its coarse levels off the power law do not spoil the estimate,
    /// which is that of its finest four levels.
    #[test]
    fn a_long_ladder_is_estimated_from_its_finest_four_levels() {
        let f = |h: f64| 1.0 + 0.3 * h + if h > 0.5 { 0.4 * h * h } else { 0.0 };
        let long = ladder(f, &[3.2, 1.6, 0.8, 0.4, 0.2, 0.1, 0.05]);
        let e = estimate(&long).unwrap();
        assert_eq!(e, estimate(&long[3..]).unwrap());
        assert!(
            e.asymptotic && (e.order.unwrap() - 1.0).abs() < 1e-3,
            "{e:?}"
        );
    }

    /// Two levels: the order is assumed, not observed.
    #[test]
    fn two_levels_assume_an_order() {
        let e = estimate(&ladder(|h| 2.0 + h, &[0.2, 0.1])).unwrap();
        assert_eq!(e.behaviour, Behaviour::TwoLevels);
        assert!((e.value - 2.0).abs() < 1e-12);
        assert!((e.error_estimate - 3.0 * 0.1 / 2.1).abs() < 1e-12);
    }

    /// Bad ladders are errors naming the problem.
    #[test]
    fn bad_ladders_are_refused() {
        let one = [Sample {
            spacing: 1.0,
            value: 1.0,
        }];
        assert!(matches!(
            estimate(&one),
            Err(EstimateError::TooFewLevels(1))
        ));
        let nan = ladder(|h| if h < 0.15 { f64::NAN } else { h }, &[0.2, 0.1]);
        assert!(estimate(&nan).unwrap_err().to_string().contains("NaN"));
        let same = ladder(|h| h, &[0.2, 0.2]);
        assert!(matches!(
            estimate(&same),
            Err(EstimateError::RepeatedSpacing(_))
        ));
        let zero = ladder(|h| h - 0.1, &[0.2, 0.1]);
        assert_eq!(estimate(&zero), Err(EstimateError::ZeroValue));
    }
}
