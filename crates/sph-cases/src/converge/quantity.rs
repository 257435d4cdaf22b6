//! What a ladder measures: a number of the run's summary (`period`, `contact_time`), or a
//! probe's or series' time history reduced to one number by a named statistic
//! (`probe:tip:position.y:min`, `series:punch:reaction_y:max`).

use serde_json::{Map, Value};
use sph_output::FileContents;

/// How a time history becomes one number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Statistic {
    /// The smallest value.
    Min,
    /// The largest value.
    Max,
    /// The largest magnitude.
    AbsMax,
    /// The last value.
    Final,
    /// The mean over the samples.
    Mean,
    /// Half the range, `(max − min)/2`.
    Amplitude,
}

impl Statistic {
    const NAMES: &'static [(&'static str, Statistic)] = &[
        ("min", Statistic::Min),
        ("max", Statistic::Max),
        ("absmax", Statistic::AbsMax),
        ("final", Statistic::Final),
        ("mean", Statistic::Mean),
        ("amplitude", Statistic::Amplitude),
    ];

    /// The statistic of `values` (NaN for none).
    pub fn of(self, values: &[f64]) -> f64 {
        if values.is_empty() {
            return f64::NAN;
        }
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        match self {
            Statistic::Min => lo,
            Statistic::Max => hi,
            Statistic::AbsMax => lo.abs().max(hi.abs()),
            Statistic::Final => values[values.len() - 1],
            Statistic::Mean => values.iter().sum::<f64>() / values.len() as f64,
            Statistic::Amplitude => 0.5 * (hi - lo),
        }
    }
}

/// A quantity of a ladder.
#[derive(Clone, Debug, PartialEq)]
pub enum Quantity {
    /// A number of the summary.
    Summary(String),
    /// A probe's position or velocity component, reduced.
    Probe {
        /// The probe.
        name: String,
        /// `position` or `velocity`.
        velocity: bool,
        /// 0, 1, 2 for x, y, z.
        axis: usize,
        /// The reduction.
        statistic: Statistic,
    },
    /// A column of a series, reduced.
    Series {
        /// The series.
        name: String,
        /// The column.
        column: String,
        /// The reduction.
        statistic: Statistic,
    },
}

/// The grammar, for error messages.
pub const GRAMMAR: &str = "a summary key (e.g. period), probe:NAME:position.x|y|z:STAT, \
                           probe:NAME:velocity.x|y|z:STAT or series:NAME:COLUMN:STAT, STAT one \
                           of min, max, absmax, final, mean, amplitude";

impl std::str::FromStr for Quantity {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad = |why: &str| format!("invalid --quantity {s}: {why}; allowed: {GRAMMAR}");
        let parts: Vec<&str> = s.split(':').collect();
        let stat = |t: &str| {
            Statistic::NAMES
                .iter()
                .find(|(n, _)| *n == t)
                .map(|(_, st)| *st)
                .ok_or_else(|| bad(&format!("unknown statistic `{t}`")))
        };
        match parts[..] {
            [key] if !key.is_empty() => Ok(Quantity::Summary(key.into())),
            ["probe", name, field, st] if !name.is_empty() => {
                let (kind, axis) = field
                    .split_once('.')
                    .ok_or_else(|| bad("a probe field is position.x|y|z or velocity.x|y|z"))?;
                let velocity = match kind {
                    "position" => false,
                    "velocity" => true,
                    _ => return Err(bad(&format!("unknown probe field `{kind}`"))),
                };
                let axis = ["x", "y", "z"]
                    .iter()
                    .position(|a| *a == axis)
                    .ok_or_else(|| bad(&format!("unknown component `{axis}`")))?;
                Ok(Quantity::Probe {
                    name: name.into(),
                    velocity,
                    axis,
                    statistic: stat(st)?,
                })
            }
            ["series", name, column, st] if !name.is_empty() && !column.is_empty() => {
                Ok(Quantity::Series {
                    name: name.into(),
                    column: column.into(),
                    statistic: stat(st)?,
                })
            }
            _ => Err(bad("not of that form")),
        }
    }
}

impl Quantity {
    /// Whether reading it needs the run's results file (probes and series are not in the
    /// summary).
    pub fn needs_results(&self) -> bool {
        !matches!(self, Quantity::Summary(_))
    }

    /// Its value in a run's summary and (for probes and series) results file.
    ///
    /// # Errors
    /// A key, probe, series or column the run lacks (naming what it has), or a summary value
    /// that is not a number.
    pub fn value(
        &self,
        summary: &Map<String, Value>,
        results: Option<&FileContents>,
    ) -> Result<f64, String> {
        match self {
            Quantity::Summary(key) => match summary.get(key) {
                Some(Value::Number(n)) => Ok(n.as_f64().unwrap_or(f64::NAN)),
                // JSON has no NaN: a summary writes it as null.
                Some(Value::Null) => Ok(f64::NAN),
                Some(other) => Err(format!(
                    "--quantity {key}: the summary's {key} is {other}, not a number"
                )),
                None => {
                    let numeric: Vec<&str> = summary
                        .iter()
                        .filter(|(_, v)| v.is_number() || v.is_null())
                        .map(|(k, _)| k.as_str())
                        .collect();
                    Err(format!(
                        "--quantity {key}: not in the run's summary; its numbers: {}",
                        numeric.join(", ")
                    ))
                }
            },
            Quantity::Probe {
                name,
                velocity,
                axis,
                statistic,
            } => {
                let file = results.ok_or("the results file is needed for a probe")?;
                let p = file.probes.get(name).ok_or_else(|| {
                    format!(
                        "--quantity probe:{name}: no such probe; the run's probes: {}",
                        file.probes.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                })?;
                let rows = if *velocity {
                    &p.velocities
                } else {
                    &p.positions
                };
                let v: Vec<f64> = rows.iter().map(|r| r[*axis]).collect();
                Ok(statistic.of(&v))
            }
            Quantity::Series {
                name,
                column,
                statistic,
            } => {
                let file = results.ok_or("the results file is needed for a series")?;
                let s = file.series.get(name).ok_or_else(|| {
                    format!(
                        "--quantity series:{name}: no such series; the run's series: {}",
                        file.series.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                })?;
                let c = s.columns.get(column).ok_or_else(|| {
                    format!(
                        "--quantity series:{name}:{column}: no such column; its columns: {}",
                        s.columns.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                })?;
                Ok(statistic.of(c))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantities_parse_and_bad_ones_name_the_problem() {
        assert_eq!(
            "period".parse::<Quantity>().unwrap(),
            Quantity::Summary("period".into())
        );
        assert_eq!(
            "probe:tip:position.y:min".parse::<Quantity>().unwrap(),
            Quantity::Probe {
                name: "tip".into(),
                velocity: false,
                axis: 1,
                statistic: Statistic::Min
            }
        );
        assert!(matches!(
            "series:punch:reaction_y:absmax"
                .parse::<Quantity>()
                .unwrap(),
            Quantity::Series {
                statistic: Statistic::AbsMax,
                ..
            }
        ));
        for (bad, why) in [
            ("", "not of that form"),
            ("probe:tip:position.w:min", "unknown component `w`"),
            ("probe:tip:accel.x:min", "unknown probe field `accel`"),
            ("series:punch:fy:median", "unknown statistic `median`"),
            ("probe:tip:min", "not of that form"),
        ] {
            let e = bad.parse::<Quantity>().unwrap_err();
            assert!(
                e.starts_with("invalid --quantity") && e.contains(why),
                "{bad}: {e}"
            );
        }
    }

    #[test]
    fn statistics_reduce_a_history() {
        let v = [1.0, -3.0, 2.0];
        assert_eq!(Statistic::Min.of(&v), -3.0);
        assert_eq!(Statistic::Max.of(&v), 2.0);
        assert_eq!(Statistic::AbsMax.of(&v), 3.0);
        assert_eq!(Statistic::Final.of(&v), 2.0);
        assert_eq!(Statistic::Mean.of(&v), 0.0);
        assert_eq!(Statistic::Amplitude.of(&v), 2.5);
        assert!(Statistic::Max.of(&[]).is_nan());
    }

    #[test]
    fn a_missing_summary_key_lists_the_numbers() {
        let s: Map<String, Value> =
            serde_json::from_str(r#"{"period": 0.25, "status": "completed", "amplitude": null}"#)
                .unwrap();
        let q = Quantity::Summary("periodd".into());
        let e = q.value(&s, None).unwrap_err();
        assert!(e.contains("its numbers: amplitude, period"), "{e}");
        assert!(Quantity::Summary("amplitude".into())
            .value(&s, None)
            .unwrap()
            .is_nan());
        let e = Quantity::Summary("status".into())
            .value(&s, None)
            .unwrap_err();
        assert!(e.contains("not a number"), "{e}");
    }
}
