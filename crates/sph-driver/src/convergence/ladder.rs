//! The ladder: levels of increasing resolution, run until every quantity's estimated error is
//! within the tolerance or the next level would exceed the budget.

use super::{estimate, Behaviour, Estimate, EstimateError, Sample};
use serde::{Deserialize, Serialize};

/// Fewest levels from which a ladder may stop as met: two levels only assume an order, and
/// a pre-asymptotic pair can agree closely far from the limit (the TL-HF plate at H/dp 4 and 6
/// differ by 0.4 % and are both 5 % off, docs/tradeoffs.md).
pub const MIN_LEVELS_TO_MEET: usize = 3;

/// How the ladder refines and when it stops.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The first level's refinement value (a case's `resolution`, or a spacing).
    pub first: f64,
    /// Each level is finer than the one before by this factor (> 1): the spacing divided by
    /// it.
    pub ratio: f64,
    /// Most levels (2 to 20; at least [`MIN_LEVELS_TO_MEET`] to stop as met).
    pub max_levels: usize,
    /// The refinement value is a whole number (rounded at each level, kept distinct).
    pub whole: bool,
    /// A finer level has a larger refinement value (`resolution`: H/dp) rather than a smaller
    /// one (a spacing `dp`).
    pub finer_is_larger: bool,
    /// The relative error every quantity must reach (> 0).
    pub tolerance: f64,
    /// The CPU seconds the whole ladder may take.
    pub cpu_budget: Option<f64>,
    /// The peak memory a level may take, bytes.
    pub memory_budget: Option<f64>,
}

impl Plan {
    /// The refinement value of level `k`.
    pub fn refinement(&self, k: usize) -> f64 {
        let mut r = self.first;
        for _ in 0..k {
            let next = if self.finer_is_larger {
                r * self.ratio
            } else {
                r / self.ratio
            };
            r = if self.whole {
                let rounded = next.round();
                if self.finer_is_larger {
                    rounded.max(r + 1.0)
                } else {
                    rounded.min(r - 1.0)
                }
            } else {
                // Six significant digits: levels with readable values, the same every time.
                let scale = 10f64.powi(5 - next.abs().log10().floor() as i32);
                (next * scale).round() / scale
            };
        }
        r
    }

    /// The spacing (relative) of refinement value `r`.
    pub fn spacing(&self, r: f64) -> f64 {
        if self.finer_is_larger {
            1.0 / r
        } else {
            r
        }
    }

    fn check(&self) -> Result<(), LadderError> {
        let bad = |what: &str, allowed: &str| {
            Err(LadderError::Invalid(format!("{what}: allowed {allowed}")))
        };
        if !(self.first.is_finite() && self.first > 0.0) {
            return bad(&format!("first level {}", self.first), "a finite value > 0");
        }
        if !(self.ratio.is_finite() && self.ratio > 1.0 && self.ratio <= 4.0) {
            return bad(&format!("--ratio {}", self.ratio), "1 < ratio <= 4");
        }
        if !(2..=20).contains(&self.max_levels) {
            return bad(&format!("--levels {}", self.max_levels), "2 to 20");
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return bad(
                &format!("--tolerance {}", self.tolerance),
                "0 < tolerance < 100 %",
            );
        }
        for (what, b) in [
            ("--budget (CPU time)", self.cpu_budget),
            ("--budget (memory)", self.memory_budget),
        ] {
            if b.is_some_and(|b| !(b.is_finite() && b > 0.0)) {
                return bad(what, "a finite amount > 0");
            }
        }
        Ok(())
    }
}

/// What one level gave: the value of every quantity (in the order asked) and what it cost.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelOutcome {
    /// The quantities' values.
    pub values: Vec<f64>,
    /// CPU seconds of the level's run.
    pub cpu_seconds: f64,
    /// Peak memory of the level's run, bytes.
    pub peak_bytes: f64,
    /// Taken from an earlier ladder's stored run (same command), not run again.
    pub reused: bool,
}

/// What a level is expected to cost before it runs (a dry run's estimate): a lower bound of
/// its CPU seconds and its peak memory, bytes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// The level's refinement value.
    pub resolution: f64,
    /// CPU seconds.
    pub cpu_seconds: f64,
    /// Peak memory, bytes.
    pub peak_bytes: f64,
}

/// One level of a quantity's ladder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Run {
    /// The refinement value.
    pub resolution: f64,
    /// The quantity's value.
    pub value: f64,
    /// CPU seconds of the level.
    pub cpu_seconds: f64,
}

/// One quantity's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuantityReport {
    /// The quantity as asked (`period`, `probe:tip:position.y:min`).
    pub quantity: String,
    /// The extrapolated value.
    pub value: f64,
    /// Estimated error of the finest run, relative.
    pub error_estimate: f64,
    /// The observed order (null without one).
    pub order: Option<f64>,
    /// Whether the ladder is verified to be in the asymptotic range.
    pub asymptotic: bool,
    /// Whether `error_estimate` is within the tolerance (never for oscillating values).
    pub met: bool,
    /// How the values approach their limit.
    pub behaviour: Behaviour,
    /// Why the estimate is not verified (null when it is).
    pub warning: Option<String>,
    /// The levels.
    pub runs: Vec<Run>,
}

/// One level of the ladder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Level {
    /// The refinement value.
    pub resolution: f64,
    /// Its relative spacing.
    pub spacing: f64,
    /// CPU seconds.
    pub cpu_seconds: f64,
    /// Peak memory, bytes.
    pub peak_bytes: f64,
    /// Taken from a stored run.
    pub reused: bool,
}

/// The ladder's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The tolerance asked for.
    pub tolerance: f64,
    /// Every quantity within the tolerance.
    pub met: bool,
    /// Why the ladder stopped, in words.
    pub stopped: String,
    /// The levels run.
    pub levels: Vec<Level>,
    /// Each quantity's estimate.
    pub quantities: Vec<QuantityReport>,
    /// The predicted cost of the next level (from the cost growth measured along the ladder).
    pub next: Option<Prediction>,
}

/// Why a ladder could not be run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LadderError {
    /// A plan value out of range.
    #[error("invalid {0}")]
    Invalid(String),
    /// The budget does not hold two levels (predicted before any run).
    #[error(
        "--budget {budget}: too small for two levels (the first two are predicted to need \
         {needed}); a ladder needs at least two"
    )]
    BudgetTooSmall {
        /// The budget, in words.
        budget: String,
        /// What two levels need, in words.
        needed: String,
    },
    /// A quantity that is not a finite number at some level.
    #[error("quantity {quantity} is {value} at resolution {resolution}, not a finite number")]
    NotFinite {
        /// The quantity.
        quantity: String,
        /// The level's refinement value.
        resolution: f64,
        /// As found.
        value: f64,
    },
    /// A level that failed to run.
    #[error("resolution {resolution}: {message}")]
    Level {
        /// The level's refinement value.
        resolution: f64,
        /// What failed.
        message: String,
    },
    /// An estimate that cannot be made (the quantity vanishes).
    #[error("quantity {quantity}: {source}")]
    Estimate {
        /// The quantity.
        quantity: String,
        /// Why.
        source: EstimateError,
    },
}

/// Whether an estimate meets the plan's tolerance: within it, and not from oscillating values.
fn meets(e: &Estimate, plan: &Plan) -> bool {
    e.error_estimate <= plan.tolerance && e.behaviour != Behaviour::Oscillating
}

/// A cost (`pick`) at `spacing`, from the growth measured over the last two levels: a power
/// law `cost ∝ spacing^−e`, its exponent bounded to `[lo, hi]` (timings of short runs are
/// noisy); `None` before two levels.
fn grown_cost(
    levels: &[Level],
    spacing: f64,
    pick: fn(&Level) -> f64,
    lo: f64,
    hi: f64,
) -> Option<f64> {
    let [.., a, b] = levels else { return None };
    let (ca, cb) = (pick(a), pick(b));
    if !(ca > 0.0 && cb > 0.0) {
        return None;
    }
    let e = ((cb / ca).ln() / (a.spacing / b.spacing).ln()).clamp(lo, hi);
    Some(cb * (b.spacing / spacing).powf(e))
}

/// Runs the ladder: `level(r)` runs (or reuses) the level of refinement value `r` and returns
/// the quantities' values in the order of `quantities` (or [`LadderError::Level`] when the run
/// fails, [`LadderError::Invalid`] for a quantity the run does not have); `predict(r)` estimates a level's cost
/// before it runs (a dry run), used to refuse a budget too small for two levels before any
/// work. After each level every quantity is estimated ([`estimate`]); the ladder stops when all
/// are within `plan.tolerance` (from [`MIN_LEVELS_TO_MEET`] levels on), when the next level's
/// cost, predicted from the measured growth, would exceed the budget, or after
/// `plan.max_levels` levels.
///
/// # Errors
/// An invalid plan, a budget too small for two levels, a level that fails, a quantity that is
/// not finite.
pub fn run(
    plan: &Plan,
    quantities: &[String],
    mut level: impl FnMut(f64) -> Result<LevelOutcome, LadderError>,
    mut predict: impl FnMut(f64) -> Option<Prediction>,
) -> Result<Report, LadderError> {
    plan.check()?;
    if quantities.is_empty() {
        return Err(LadderError::Invalid(
            "--quantity: none given; name at least one".into(),
        ));
    }
    let first_two: Vec<Option<Prediction>> = (0..2).map(|k| predict(plan.refinement(k))).collect();
    if let [Some(a), Some(b)] = first_two[..] {
        if let Some(budget) = plan.cpu_budget {
            if a.cpu_seconds + b.cpu_seconds > budget {
                return Err(LadderError::BudgetTooSmall {
                    budget: format!("{budget} s of CPU time"),
                    needed: format!("at least {:.3e} s", a.cpu_seconds + b.cpu_seconds),
                });
            }
        }
        if let Some(budget) = plan.memory_budget {
            if b.peak_bytes > budget {
                return Err(LadderError::BudgetTooSmall {
                    budget: format!("{:.3e} bytes of memory", budget),
                    needed: format!("{:.3e} bytes", b.peak_bytes),
                });
            }
        }
    }
    let mut levels: Vec<Level> = Vec::new();
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); quantities.len()];
    let mut estimates: Vec<Option<Estimate>> = vec![None; quantities.len()];
    let mut spent = 0.0;
    let mut stopped = format!("the most levels asked for ({})", plan.max_levels);
    let mut next = None;
    for k in 0..plan.max_levels {
        let r = plan.refinement(k);
        let spacing = plan.spacing(r);
        // The next level's cost from the growth measured so far (two levels needed).
        let predicted = Prediction {
            resolution: r,
            cpu_seconds: grown_cost(&levels, spacing, |l| l.cpu_seconds, 1.0, 6.0)
                .unwrap_or(f64::NAN),
            peak_bytes: grown_cost(&levels, spacing, |l| l.peak_bytes, 0.0, 4.0)
                .unwrap_or(f64::NAN),
        };
        if k >= 2 {
            let over_cpu = plan
                .cpu_budget
                .is_some_and(|b| spent + predicted.cpu_seconds > b);
            let over_memory = plan.memory_budget.is_some_and(|b| predicted.peak_bytes > b);
            if over_cpu || over_memory {
                stopped = format!(
                    "the next level (resolution {r}) would exceed the budget: {}",
                    if over_cpu {
                        format!(
                            "{:.3e} s of CPU time predicted, {:.3e} s left",
                            predicted.cpu_seconds,
                            plan.cpu_budget.unwrap_or(0.0) - spent
                        )
                    } else {
                        format!("{:.3e} bytes of memory predicted", predicted.peak_bytes)
                    }
                );
                next = Some(predicted);
                break;
            }
        }
        let outcome = level(r)?;
        for (q, &v) in quantities.iter().zip(&outcome.values) {
            if !v.is_finite() {
                return Err(LadderError::NotFinite {
                    quantity: q.clone(),
                    resolution: r,
                    value: v,
                });
            }
        }
        spent += outcome.cpu_seconds;
        levels.push(Level {
            resolution: r,
            spacing,
            cpu_seconds: outcome.cpu_seconds,
            peak_bytes: outcome.peak_bytes,
            reused: outcome.reused,
        });
        for (k, v) in outcome.values.iter().enumerate() {
            values[k].push(*v);
        }
        if levels.len() >= 2 {
            for (k, q) in quantities.iter().enumerate() {
                let samples: Vec<Sample> = levels
                    .iter()
                    .zip(&values[k])
                    .map(|(l, &value)| Sample {
                        spacing: l.spacing,
                        value,
                    })
                    .collect();
                estimates[k] =
                    Some(estimate(&samples).map_err(|source| LadderError::Estimate {
                        quantity: q.clone(),
                        source,
                    })?);
            }
            // Met only from three levels on (two cannot observe an order, GCI practice), and
            // never on oscillating values: their spread does not bound their distance to a
            // limit they have not begun to approach.
            let within = estimates
                .iter()
                .all(|e| e.as_ref().is_some_and(|e| meets(e, plan)));
            if within && levels.len() >= MIN_LEVELS_TO_MEET {
                stopped = "every quantity is within the tolerance".into();
                break;
            }
        }
    }
    if next.is_none() && levels.len() < plan.max_levels {
        // Met: what one more level would cost.
        let r = plan.refinement(levels.len());
        let s = plan.spacing(r);
        next = Some(Prediction {
            resolution: r,
            cpu_seconds: grown_cost(&levels, s, |l| l.cpu_seconds, 1.0, 6.0).unwrap_or(f64::NAN),
            peak_bytes: grown_cost(&levels, s, |l| l.peak_bytes, 0.0, 4.0).unwrap_or(f64::NAN),
        });
    }
    let quantities: Vec<QuantityReport> = quantities
        .iter()
        .zip(&estimates)
        .zip(&values)
        .map(|((q, e), v)| {
            let e = e.clone().expect("two levels ran");
            QuantityReport {
                quantity: q.clone(),
                value: e.value,
                error_estimate: e.error_estimate,
                order: e.order,
                asymptotic: e.asymptotic,
                met: meets(&e, plan),
                behaviour: e.behaviour,
                warning: e.warning,
                runs: levels
                    .iter()
                    .zip(v)
                    .map(|(l, &value)| Run {
                        resolution: l.resolution,
                        value,
                        cpu_seconds: l.cpu_seconds,
                    })
                    .collect(),
            }
        })
        .collect();
    Ok(Report {
        tolerance: plan.tolerance,
        met: quantities.iter().all(|q| q.met),
        stopped,
        levels,
        quantities,
        next,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(tolerance: f64) -> Plan {
        Plan {
            first: 4.0,
            ratio: 2.0,
            max_levels: 8,
            whole: true,
            finer_is_larger: true,
            tolerance,
            cpu_budget: None,
            memory_budget: None,
        }
    }

    /// A level of a synthetic scene: f = 1 + 0.5 h^1.5 at h = 1/r, cost r³ s and r² bytes.
    fn synthetic(r: f64) -> Result<LevelOutcome, LadderError> {
        Ok(LevelOutcome {
            values: vec![1.0 + 0.5 * (1.0 / r).powf(1.5)],
            cpu_seconds: r.powi(3) * 1e-3,
            peak_bytes: r * r,
            reused: false,
        })
    }

    /// The ladder refines until the estimate is within the tolerance, and the estimate bounds
    /// the true error of the finest level.
    #[test]
    fn the_ladder_stops_when_the_tolerance_is_met() {
        let q = vec!["f".to_string()];
        let report = run(&plan(1e-3), &q, synthetic, |_| None).unwrap();
        assert!(report.met, "{report:?}");
        let finest = report.quantities[0].runs.last().unwrap();
        let truth = (finest.value - 1.0).abs() / finest.value;
        assert!(report.quantities[0].error_estimate >= truth);
        assert!(report.quantities[0].error_estimate <= 1e-3);
        // Each level twice as fine: 4, 8, 16, …
        let res: Vec<f64> = report.levels.iter().map(|l| l.resolution).collect();
        assert_eq!(&res[..3], &[4.0, 8.0, 16.0]);
        // The cost growth r³ is measured and extrapolated to the next level.
        let next = report.next.unwrap();
        let last = report.levels.last().unwrap();
        assert!(
            (next.cpu_seconds / last.cpu_seconds - 8.0).abs() < 1e-9,
            "{next:?}"
        );
    }

    /// A CPU budget stops the ladder before a level predicted to exceed it; a budget too small
    /// for two levels is refused before any run.
    #[test]
    fn budgets_stop_the_ladder_or_refuse_it() {
        let q = vec!["f".to_string()];
        let mut p = plan(1e-9);
        p.cpu_budget = Some(5.0);
        let report = run(&p, &q, synthetic, |_| None).unwrap();
        assert!(!report.met);
        assert!(
            report.stopped.contains("would exceed the budget"),
            "{}",
            report.stopped
        );
        let spent: f64 = report.levels.iter().map(|l| l.cpu_seconds).sum();
        assert!(spent <= 5.0, "{spent}");
        let dry = |r: f64| {
            Some(Prediction {
                resolution: r,
                cpu_seconds: r.powi(3),
                peak_bytes: r * r,
            })
        };
        p.cpu_budget = Some(10.0);
        let mut ran = 0;
        let e = run(
            &p,
            &q,
            |r| {
                ran += 1;
                synthetic(r)
            },
            dry,
        )
        .unwrap_err();
        assert!(matches!(e, LadderError::BudgetTooSmall { .. }), "{e}");
        assert_eq!(ran, 0, "nothing runs");
    }

    /// A quantity that is not finite at some level is an error naming it and the level.
    #[test]
    fn a_quantity_that_is_not_finite_is_an_error() {
        let q = vec!["period".to_string()];
        let e = run(
            &plan(1e-3),
            &q,
            |r| {
                let mut o = synthetic(r)?;
                if r > 10.0 {
                    o.values[0] = f64::NAN;
                }
                Ok(o)
            },
            |_| None,
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "quantity period is NaN at resolution 16, not a finite number"
        );
    }

    /// Whole-number refinement values stay distinct; spacings refine by the ratio.
    #[test]
    fn refinement_values_are_distinct_whole_numbers() {
        let mut p = plan(0.01);
        p.first = 3.0;
        p.ratio = 1.2;
        let r: Vec<f64> = (0..4).map(|k| p.refinement(k)).collect();
        assert_eq!(r, [3.0, 4.0, 5.0, 6.0]);
        p.whole = false;
        p.finer_is_larger = false;
        p.first = 1e-3;
        assert!((p.refinement(2) - 1e-3 / 1.44).abs() < 1e-8);
        assert_eq!(p.refinement(2), 0.000694444);
        assert_eq!(p.spacing(2e-3), 2e-3);
    }
}
