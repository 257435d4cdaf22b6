//! Stored results of validation runs: one JSON file per run under `validation/results/`.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use sph_cases::{find_case, resolve_method, CaseError, RunOptions};
use std::path::PathBuf;

/// One validation run's stored figures.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StoredRun {
    /// Identifier (file stem).
    pub id: String,
    /// Case.
    pub case: String,
    /// Method.
    pub method: String,
    /// The `--set` assignments.
    pub set: Vec<String>,
    /// The command that reproduces this run alone.
    pub command: String,
    /// The run's summary (the monitor history included).
    pub summary: Map<String, Value>,
    /// Probe time series (downsampled to at most 2,000 samples): name → (t, x, y, z).
    pub probes: Map<String, Value>,
    /// Series the solver recorded (e.g. contact forces, columns `x`, `y`, `z`; downsampled to
    /// at most 2,000 samples, keeping the largest magnitude of each stride): name → (`t`, one
    /// array per column).
    #[serde(default)]
    pub series: Map<String, Value>,
}

impl StoredRun {
    /// A summary number.
    pub fn num(&self, key: &str) -> Option<f64> {
        self.summary.get(key).and_then(Value::as_f64)
    }

    /// A probe series `(t, component k)`.
    pub fn probe_series(&self, name: &str, k: usize) -> Vec<(f64, f64)> {
        let Some(p) = self.probes.get(name) else {
            return Vec::new();
        };
        let t = p
            .get("t")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let key = ["x", "y", "z"][k];
        let c = p
            .get(key)
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        t.iter()
            .zip(&c)
            .filter_map(|(a, b)| Some((a.as_f64()?, b.as_f64()?)))
            .collect()
    }

    /// A solver series `(t, component k)` (e.g. `contact_force_0`, columns `x`, `y`, `z`).
    pub fn series_values(&self, name: &str, k: usize) -> Vec<(f64, f64)> {
        let Some(p) = self.series.get(name) else {
            return Vec::new();
        };
        let get = |key: &str| {
            p.get(key)
                .and_then(Value::as_array)
                .cloned()
                .unwrap_or_default()
        };
        get("t")
            .iter()
            .zip(&get(["x", "y", "z"][k]))
            .filter_map(|(a, b)| Some((a.as_f64()?, b.as_f64()?)))
            .collect()
    }

    /// A series of the energy budget over the monitor samples (`residual`, `kinetic`,
    /// `dissipated`, ...), as `(t, value)`.
    pub fn budget_series(&self, key: &str) -> Vec<(f64, f64)> {
        let m = self.summary.get("monitor");
        let t = m
            .and_then(|m| m.get("time"))
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let v = m
            .and_then(|m| m.get("energy_budget"))
            .and_then(|b| b.get(key))
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        t.iter()
            .zip(&v)
            .filter_map(|(a, b)| Some((a.as_f64()?, b.as_f64()?)))
            .collect()
    }

    /// A monitor series `(t, value)` (`disorder_max`, `kinetic_energy`, ...).
    pub fn monitor_series(&self, key: &str) -> Vec<(f64, f64)> {
        let m = self.summary.get("monitor");
        let get = |k: &str| {
            m.and_then(|m| m.get(k))
                .and_then(Value::as_array)
                .cloned()
                .unwrap_or_default()
        };
        get("time")
            .iter()
            .zip(&get(key))
            .filter_map(|(a, b)| Some((a.as_f64()?, b.as_f64()?)))
            .collect()
    }
}

/// Directory of stored results.
pub fn results_dir() -> PathBuf {
    crate::workspace_root().join("validation").join("results")
}

/// The stored run `id`, if present.
pub fn load(id: &str) -> Option<StoredRun> {
    let text = std::fs::read_to_string(results_dir().join(format!("{id}.json"))).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs `case` with `method` and `set` unless `id` is stored already (or `force`), stores and
/// returns it. Runs write their HDF5 file to `target/validation/` (read back for the probes).
pub fn run_or_load(
    id: &str,
    case: &str,
    method: &str,
    set: &[String],
    force: bool,
) -> Result<StoredRun, CaseError> {
    run_or_load_then(id, case, method, set, force, &|_| Ok(Map::new()))
}

/// What [`run_or_load_then`] does with a fresh run's results file: figures measured on the
/// snapshots (stored under `snapshots` in the summary), or an error.
pub type AfterRun<'a> =
    dyn Fn(&sph_output::FileContents) -> Result<Map<String, Value>, String> + 'a;

/// [`run_or_load`], and when the run is actually made, `after` reads its results file (the
/// snapshots) before it is deleted — for pictures, which are written next to the report, and
/// figures measured on the snapshots, which are stored in the summary under `snapshots`.
pub fn run_or_load_then(
    id: &str,
    case: &str,
    method: &str,
    set: &[String],
    force: bool,
    after: &AfterRun<'_>,
) -> Result<StoredRun, CaseError> {
    if !force {
        if let Some(r) = load(id) {
            if r.set == set && r.method == method && r.case == case {
                return Ok(r);
            }
        }
    }
    let c = find_case(case)?;
    let method = resolve_method(c, Some(method))?;
    let mut params = c.params_for(method);
    for a in set {
        params.apply_assignment(a)?;
    }
    let out = crate::workspace_root()
        .join("target")
        .join("validation")
        .join(id);
    let options = RunOptions {
        output: Some(out),
        ..Default::default()
    };
    eprintln!("running {id}: {case} --method {method} {}", set.join(" "));
    let (record, mut summary) = c.run(method, &params, &options)?;
    let mut probes = Map::new();
    let mut series = Map::new();
    if let Some(file) = &record.file {
        let contents = sph_output::read_file(file)?;
        let extra = after(&contents).map_err(CaseError::Config)?;
        if !extra.is_empty() {
            summary.insert("snapshots".into(), Value::Object(extra));
        }
        for (name, p) in contents.probes {
            let stride = p.times.len().div_ceil(2000).max(1);
            let pick = |k: usize| -> Vec<f64> {
                p.positions.iter().step_by(stride).map(|x| x[k]).collect()
            };
            let t: Vec<f64> = p.times.iter().step_by(stride).copied().collect();
            probes.insert(
                name,
                serde_json::json!({ "t": t, "x": pick(0), "y": pick(1), "z": pick(2) }),
            );
        }
        for (name, s) in contents.series {
            let n = s.times.len();
            let stride = n.div_ceil(2000).max(1);
            // Keep each stride's sample of largest magnitude over the columns, so peaks survive.
            let magnitude =
                |i: usize| -> f64 { s.columns.values().map(|c| c[i] * c[i]).sum::<f64>() };
            let picks: Vec<usize> = (0..n)
                .step_by(stride)
                .map(|a| {
                    (a..(a + stride).min(n))
                        .max_by(|&i, &j| magnitude(i).total_cmp(&magnitude(j)))
                        .unwrap_or(a)
                })
                .collect();
            let mut out = Map::new();
            out.insert(
                "t".into(),
                serde_json::json!(picks.iter().map(|&i| s.times[i]).collect::<Vec<_>>()),
            );
            for (col, v) in &s.columns {
                out.insert(
                    col.clone(),
                    serde_json::json!(picks.iter().map(|&i| v[i]).collect::<Vec<_>>()),
                );
            }
            series.insert(name, Value::Object(out));
        }
        let _ = std::fs::remove_file(file);
        let _ = std::fs::remove_file(sph_output::xmf_path(&file.with_extension("")));
    }
    let sets: String = set.iter().map(|s| format!(" --set {s}")).collect();
    let run = StoredRun {
        id: id.into(),
        case: case.into(),
        method: method.into(),
        set: set.to_vec(),
        command: format!(
            "cargo run --release -p sph-cases --bin sph -- run {case} --method {method}{sets}"
        ),
        summary,
        probes,
        series,
    };
    std::fs::create_dir_all(results_dir()).map_err(|e| CaseError::Io {
        path: results_dir().display().to_string(),
        source: e,
    })?;
    let path = results_dir().join(format!("{id}.json"));
    std::fs::write(&path, serde_json::to_string(&run).expect("serialises")).map_err(|e| {
        CaseError::Io {
            path: path.display().to_string(),
            source: e,
        }
    })?;
    Ok(run)
}

/// A number with `digits` decimals, or `–` when absent.
pub fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |v| format!("{v:.digits$}"))
}

/// A relative difference as a signed percentage, or `–` when absent.
pub fn pct(x: Option<f64>) -> String {
    x.map_or("–".into(), |v| format!("{:+.2} %", 100.0 * v))
}

/// The run's status (`completed` or `failed: …`).
pub fn status(r: &StoredRun) -> &str {
    r.summary
        .get("status")
        .and_then(|s| s.as_str())
        .unwrap_or("?")
}

/// `a/b − 1` when both are present.
pub fn rel(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    a.zip(b).map(|(a, b)| a / b - 1.0)
}
