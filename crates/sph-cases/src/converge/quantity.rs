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
    /// A component of a probe's position, velocity or sampled field (`displacement`,
    /// `von_mises`, …), reduced.
    Probe {
        /// The probe.
        name: String,
        /// `position`, `velocity`, or a field the probe samples.
        field: String,
        /// The component: `[row, column]` of a matrix, `[axis]` of a vector, none of a scalar
        /// (x, y, z = 0, 1, 2).
        component: Vec<usize>,
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
pub const GRAMMAR: &str = "a summary key (e.g. period), probe:NAME:FIELD[.COMPONENT]:STAT (FIELD \
                           position, velocity or a field the probe samples; COMPONENT x, y, z or \
                           xx, xy, … for a matrix, none for a scalar) or series:NAME:COLUMN:STAT, \
                           STAT one of min, max, absmax, final, mean, amplitude";

/// `x` → `[0]`, `xy` → `[0, 1]`, `` → `[]`.
fn component(text: &str) -> Option<Vec<usize>> {
    text.chars()
        .map(|c| match c {
            'x' => Some(0),
            'y' => Some(1),
            'z' => Some(2),
            _ => None,
        })
        .collect::<Option<Vec<usize>>>()
        .filter(|c| c.len() <= 2)
}

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
            ["probe", name, field, st] if !name.is_empty() && !field.is_empty() => {
                let (field, comp) = field.split_once('.').unwrap_or((field, ""));
                let component =
                    component(comp).ok_or_else(|| bad(&format!("unknown component `{comp}`")))?;
                if matches!(field, "position" | "velocity") && component.len() != 1 {
                    return Err(bad(&format!("{field} needs one component x, y or z")));
                }
                Ok(Quantity::Probe {
                    name: name.into(),
                    field: field.into(),
                    component,
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
                field,
                component,
                statistic,
            } => {
                let file = results.ok_or("the results file is needed for a probe")?;
                let p = file.probes.get(name).ok_or_else(|| {
                    format!(
                        "--quantity probe:{name}: no such probe; the run's probes: {}",
                        file.probes.keys().cloned().collect::<Vec<_>>().join(", ")
                    )
                })?;
                let v: Vec<f64> = match field.as_str() {
                    "position" => p.positions.iter().map(|r| r[component[0]]).collect(),
                    "velocity" => p.velocities.iter().map(|r| r[component[0]]).collect(),
                    _ => field_component(p, name, field, component)?,
                };
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

/// The history of one component of a field a probe samples (shape `[k]`, `[k, 3]` or
/// `[k, 3, 3]`).
fn field_component(
    p: &sph_output::Probe,
    name: &str,
    field: &str,
    component: &[usize],
) -> Result<Vec<f64>, String> {
    let sampled: Vec<&str> = p
        .fields
        .iter()
        .map(|d| d.name.as_str())
        .filter(|n| *n != "time")
        .collect();
    let d = p.field(field).ok_or_else(|| {
        format!(
            "--quantity probe:{name}:{field}: the probe samples no such field; it has position, \
             velocity{}",
            sampled.iter().map(|f| format!(", {f}")).collect::<String>()
        )
    })?;
    let shape = d.data.shape();
    let sph_output::DatasetData::F64 { values, .. } = &d.data else {
        return Err(format!(
            "--quantity probe:{name}:{field}: not a real-valued field"
        ));
    };
    let per: usize = shape[1..].iter().product();
    let offset = match (shape.len(), component) {
        (1, []) => 0,
        (2, [i]) => *i,
        (3, [i, j]) => i * shape[2] + j,
        _ => {
            return Err(format!(
                "--quantity probe:{name}:{field}: {} component(s) given for a field of shape \
                 {shape:?} (none for a scalar, x|y|z for a vector, xx|xy|… for a matrix)",
                component.len()
            ))
        }
    };
    Ok(values.chunks(per.max(1)).map(|row| row[offset]).collect())
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
                field: "position".into(),
                component: vec![1],
                statistic: Statistic::Min
            }
        );
        assert!(matches!(
            "probe:tip:stress.xy:final".parse::<Quantity>().unwrap(),
            Quantity::Probe { component, .. } if component == [0, 1]
        ));
        assert!(matches!(
            "probe:tip:von_mises:max".parse::<Quantity>().unwrap(),
            Quantity::Probe { component, .. } if component.is_empty()
        ));
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
            ("probe:tip:position:min", "position needs one component"),
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
