//! What `sph converge` writes: the report as JSON (`--report FILE.json`), the same numbers as
//! HDF5 beside it (`FILE.h5`) and a convergence plot (`FILE.png`).
//!
//! JSON, per method (the key `methods`, one entry per `--method`):
//!
//! ```text
//! { "case": …, "tolerance": 0.01, "met": true,
//!   "methods": { "tl-hf": { "met": true, "stopped": "…", "refinement": "resolution",
//!       "quantities": { "period": { "value": …, "error_estimate": …, "order": …,
//!                                    "asymptotic": …, "met": …, "behaviour": …, "warning": …,
//!                                    "runs": [ { "resolution": …, "value": …,
//!                                                "cpu_seconds": … }, … ] } },
//!       "levels": [ { "resolution", "spacing", "cpu_seconds", "peak_bytes", "reused" } ],
//!       "next": { "resolution", "cpu_seconds", "peak_bytes" } } },
//!   … and, for one method, the same keys at the top level too }
//! ```
//!
//! HDF5: `/` attributes `format = "sph-solids-convergence"`, `json` (the report); a group per
//! method and in it one per quantity with datasets `resolution`, `spacing`, `value`,
//! `cpu_seconds` and attributes `value`, `error_estimate`, `order`, `asymptotic`, `met`.

use serde_json::{json, Map, Value};
use sph_driver::convergence::ladder::Report;
use std::path::Path;

/// The report of the ladders of `methods` as JSON (see the module documentation).
pub fn to_json(case: &str, refinement: &str, tolerance: f64, methods: &[(&str, &Report)]) -> Value {
    let mut per = Map::new();
    for (m, r) in methods {
        let quantities: Map<String, Value> = r
            .quantities
            .iter()
            .map(|q| {
                let mut v = serde_json::to_value(q).expect("serialises");
                v.as_object_mut().expect("an object").remove("quantity");
                (q.quantity.clone(), v)
            })
            .collect();
        per.insert(
            m.to_string(),
            json!({
                "met": r.met,
                "stopped": r.stopped,
                "refinement": refinement,
                "quantities": quantities,
                "levels": r.levels,
                "next": r.next,
            }),
        );
    }
    let mut top = json!({
        "case": case,
        "tolerance": tolerance,
        "met": methods.iter().all(|(_, r)| r.met),
        "methods": per.clone(),
    });
    if let [(m, _)] = methods {
        // One method: its report at the top level as well (the interface of issue 44).
        let o = top.as_object_mut().expect("an object");
        o.insert("method".into(), json!(m));
        for (k, v) in per[*m].as_object().expect("an object") {
            o.insert(k.clone(), v.clone());
        }
    }
    top
}

/// Writes `report` (from [`to_json`]) as HDF5 to `path`, through a temporary file renamed into
/// place.
///
/// # Errors
/// The file cannot be written.
pub fn write_h5(path: &Path, report: &Value, methods: &[(&str, &Report)]) -> Result<(), String> {
    use hdf5_pure::{AttrValue, FileBuilder};
    let mut fb = FileBuilder::new();
    fb.set_attr(
        "format",
        AttrValue::VarLenString("sph-solids-convergence".into()),
    );
    fb.set_attr("json", AttrValue::VarLenString(report.to_string()));
    for (m, r) in methods {
        let mut g = fb.create_group(m);
        for q in &r.quantities {
            let mut qg = g.create_group(&q.quantity.replace('/', "_"));
            let col = |f: fn(&sph_driver::convergence::ladder::Run) -> f64| -> Vec<f64> {
                q.runs.iter().map(f).collect()
            };
            qg.create_dataset("resolution")
                .with_f64_data(&col(|x| x.resolution));
            let spacing: Vec<f64> = r.levels.iter().map(|l| l.spacing).collect();
            qg.create_dataset("spacing").with_f64_data(&spacing);
            qg.create_dataset("value").with_f64_data(&col(|x| x.value));
            qg.create_dataset("cpu_seconds")
                .with_f64_data(&col(|x| x.cpu_seconds));
            qg.set_attr("value", AttrValue::F64(q.value));
            qg.set_attr("error_estimate", AttrValue::F64(q.error_estimate));
            qg.set_attr("order", AttrValue::F64(q.order.unwrap_or(f64::NAN)));
            qg.set_attr("asymptotic", AttrValue::U8(u8::from(q.asymptotic)));
            qg.set_attr("met", AttrValue::U8(u8::from(q.met)));
            g.add_group(qg.finish());
        }
        fb.add_group(g.finish());
    }
    let bytes = fb
        .finish()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    write_replacing(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary file of its own, renamed into place.
fn write_replacing(path: &Path, bytes: &[u8]) -> Result<(), String> {
    sph_output::safety::check_destination(path).map_err(|e| e.to_string())?;
    let mut tmp = sph_output::safety::TempFile::beside(path, true).map_err(|e| e.to_string())?;
    tmp.write_all(bytes).map_err(|e| e.to_string())?;
    tmp.persist(path).map_err(|e| e.to_string())
}

/// Writes the report's JSON to `path` (temporary file, renamed).
///
/// # Errors
/// The file cannot be written.
pub fn write_json(path: &Path, report: &Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(report).expect("serialises");
    write_replacing(path, text.as_bytes())
}

/// The convergence plot: for every quantity and method, the estimated error of each level
/// against the CPU time spent up to it (log–log), the levels labelled by resolution; with
/// several methods, the points no other method beats on both (the Pareto front) circled.
///
/// # Errors
/// The PNG cannot be drawn or written.
pub fn write_png(path: &Path, case: &str, methods: &[(&str, &Report)]) -> Result<(), String> {
    use sph_driver::convergence::{estimate, Sample};
    let mut series = Vec::new();
    let mut points: Vec<(f64, f64)> = Vec::new();
    for (m, r) in methods {
        for q in &r.quantities {
            let mut pts = Vec::new();
            let mut spent = 0.0;
            for k in 0..q.runs.len() {
                spent += q.runs[k].cpu_seconds;
                if k == 0 {
                    continue;
                }
                let samples: Vec<Sample> = r.levels[..=k]
                    .iter()
                    .zip(&q.runs[..=k])
                    .map(|(l, x)| Sample {
                        spacing: l.spacing,
                        value: x.value,
                    })
                    .collect();
                if let Ok(e) = estimate(&samples) {
                    pts.push((
                        spent,
                        100.0 * e.error_estimate,
                        format!("{}", q.runs[k].resolution),
                    ));
                }
            }
            points.extend(pts.iter().map(|p| (p.0, p.1)));
            let label = if methods.len() > 1 {
                format!("{m}: {}", q.quantity)
            } else {
                q.quantity.clone()
            };
            series.push(sph_plot::LabelledSeries { label, points: pts });
        }
    }
    let front: Vec<(f64, f64)> = if methods.len() > 1 {
        points
            .iter()
            .copied()
            .filter(|&(c, e)| {
                !points
                    .iter()
                    .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
            })
            .collect()
    } else {
        Vec::new()
    };
    sph_plot::log_log_plot(
        path,
        &format!("{case}: estimated error against cost"),
        "CPU seconds spent (cumulative)",
        "estimated error of the finest run (%)",
        &series,
        &front,
    )
}
