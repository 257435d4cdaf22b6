//! Stored results of validation runs: one small JSON file per run under `validation/results/`
//! (committed: the report is regenerated from them), and the run's full HDF5 file (snapshots,
//! probes, series, summary) under `target/validation-results/<id>/` (outside git), next to a
//! `command.txt` holding the `sph run` command that recreates it.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use sph_cases::{find_case, resolve_method, CaseError, RunOptions};
use std::path::{Path, PathBuf};

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
    /// The run's HDF5 file relative to the workspace root (`None` for runs stored before the
    /// files were kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub results_file: Option<String>,
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

static PLAN_ONLY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Plan instead of run: [`run_or_load_then`] prints `id`, a tab and the command of each run
/// that is neither stored nor adoptable, and returns it unrun (empty summary). For starting
/// long runs from the shell (`sh -c "$command"`, with the command written to
/// `<run_dir>/command.txt` so that a later `validate` adopts the file).
pub fn set_plan_only(plan: bool) {
    PLAN_ONLY.store(plan, std::sync::atomic::Ordering::Relaxed);
}

/// Whether runs are planned, not made ([`set_plan_only`]).
pub fn plan_only() -> bool {
    PLAN_ONLY.load(std::sync::atomic::Ordering::Relaxed)
}

static RUN_FILTER: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// Make only the runs whose id starts with `prefix` ([`run_or_load_then`] returns the others
/// unrun, with an empty summary, unless stored or adoptable); `None` makes every run.
pub fn set_run_filter(prefix: Option<String>) {
    *RUN_FILTER.lock().expect("filter lock") = prefix;
}

/// Whether run `id` is filtered out by [`set_run_filter`].
pub(crate) fn filtered_out(id: &str) -> bool {
    RUN_FILTER
        .lock()
        .expect("filter lock")
        .as_ref()
        .is_some_and(|p| !id.starts_with(p.as_str()))
}

/// The kept HDF5 results, relative to the workspace root (outside git: under `target/`).
pub const RESULTS_FILES_DIR: &str = "target/validation-results";

/// Where run `id` keeps its HDF5 file: the directory `sph run --out` is given.
pub fn run_dir(id: &str) -> PathBuf {
    crate::workspace_root().join(RESULTS_FILES_DIR).join(id)
}

/// The `sph run` command that makes run `id` (its results file included).
pub fn command_for(id: &str, case: &str, method: &str, set: &[String]) -> String {
    let sets: String = set.iter().map(|s| format!(" --set {s}")).collect();
    format!(
        "cargo run --release -p sph-cases --bin sph -- run {case} --method {method}{sets} \
         --out {RESULTS_FILES_DIR}/{id}"
    )
}

/// The stored run `id`, if present.
pub fn load(id: &str) -> Option<StoredRun> {
    let text = std::fs::read_to_string(results_dir().join(format!("{id}.json"))).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs `case` with `method` and `set` unless `id` is stored already (or `force`), stores and
/// returns it. Runs write their HDF5 file under [`run_dir`] (read back for the probes, and
/// kept).
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
/// snapshots) — for pictures, which are written next to the report, and figures measured on
/// the snapshots, which are stored in the summary under `snapshots`. The file is kept under
/// [`run_dir`] with the command that recreates it (`command.txt`).
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
    // The same file `sph run … --out <run_dir>` writes.
    let dir = run_dir(id);
    let out = dir.join(format!("{case}-{method}"));
    let command = command_for(id, case, method, set);
    let (file, mut summary) = match adoptable(&dir, &out, &command) {
        // A finished run made with exactly this command (e.g. a long run started from the
        // shell): read it instead of running again.
        Some((file, summary)) => {
            eprintln!("adopting {id} from {}", file.display());
            (Some(file), summary)
        }
        None if PLAN_ONLY.load(std::sync::atomic::Ordering::Relaxed) || filtered_out(id) => {
            if !filtered_out(id) {
                println!("{id}\t{command}");
            }
            return Ok(StoredRun {
                id: id.into(),
                case: case.into(),
                method: method.into(),
                set: set.to_vec(),
                command,
                summary: Map::new(),
                probes: Map::new(),
                series: Map::new(),
                results_file: None,
            });
        }
        None => {
            let options = RunOptions {
                output: Some(out),
                ..Default::default()
            };
            eprintln!("running {id}: {case} --method {method} {}", set.join(" "));
            let (record, summary) = c.run(method, &params, &options)?;
            (record.file, summary)
        }
    };
    let mut probes = Map::new();
    let mut series = Map::new();
    let mut results_file = None;
    if let Some(file) = &file {
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
        let io = |e: std::io::Error| CaseError::Io {
            path: dir.display().to_string(),
            source: e,
        };
        std::fs::write(dir.join("command.txt"), format!("{command}\n")).map_err(io)?;
        results_file = file
            .strip_prefix(crate::workspace_root())
            .ok()
            .map(|p| p.display().to_string());
    }
    let run = StoredRun {
        id: id.into(),
        case: case.into(),
        method: method.into(),
        set: set.to_vec(),
        command,
        summary,
        probes,
        series,
        results_file,
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

/// The finished results file of `out` and its summary, if `dir/command.txt` records exactly
/// `command` (the file was made by it) and the run ended by itself (its summary has a status
/// that is not `interrupted …`).
fn adoptable(dir: &Path, out: &Path, command: &str) -> Option<(PathBuf, Map<String, Value>)> {
    let recorded = std::fs::read_to_string(dir.join("command.txt")).ok()?;
    if recorded.trim() != command {
        return None;
    }
    let file = sph_output::h5_path(out);
    let summary = sph_output::read_file(&file).ok()?.summary;
    // A run stopped from outside (`interrupted at t = …`) is not what the command makes.
    let status = summary.get("status")?.as_str()?;
    (!status.starts_with("interrupted")).then_some((file, summary))
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

/// The cost of a run not made: its dry-run estimate (`sph run … --dry-run`: the scene is
/// built and checked, nothing is run) and the wall time it would take at the particle-step
/// rates the stored runs `like` reached on this machine (their `particle_steps_per_second`,
/// slowest and fastest). Returns e.g. "21,952 particles × 1.24·10⁵ steps = 2.7·10⁹
/// particle-steps, 6–16 min at the 2.8–7.7·10⁶ particle-steps/s of 3 stored runs", or `None`
/// when the case rejects the set or no stored run gives a rate.
pub fn cost_estimate(case: &str, method: &str, set: &[String], like: &[String]) -> Option<String> {
    let c = find_case(case).ok()?;
    let method = resolve_method(c, Some(method)).ok()?;
    let mut params = c.params_for(method);
    for a in set {
        params.apply_assignment(a).ok()?;
    }
    let options = RunOptions {
        dry_run: true,
        ..Default::default()
    };
    let (_, summary) = c.run(method, &params, &options).ok()?;
    let particles = summary.get("particles")?.as_f64()?;
    let steps = summary.get("steps_estimate")?.as_f64()?;
    let rates: Vec<f64> = like
        .iter()
        .filter_map(|id| load(id)?.num("particle_steps_per_second"))
        .collect();
    let lo = rates.iter().copied().reduce(f64::min)?;
    let hi = rates.iter().copied().reduce(f64::max)?;
    let work = particles * steps;
    let minutes = |rate: f64| work / rate / 60.0;
    let at = if rates.len() == 1 {
        format!(
            "{} min of wall time at the {} particle-steps/s of the stored run",
            minutes(lo).round(),
            sci(lo)
        )
    } else {
        format!(
            "{}–{} min of wall time at the {}–{} particle-steps/s of {} stored runs",
            minutes(hi).round(),
            minutes(lo).round(),
            sci(lo),
            sci(hi),
            rates.len()
        )
    };
    Some(format!(
        "{} particles × {} steps = {} particle-steps, {at}",
        thousands(particles),
        sci(steps),
        sci(work),
    ))
}

/// `12572` → `12,572`.
fn thousands(x: f64) -> String {
    let s = format!("{:.0}", x);
    let mut out = String::new();
    for (i, ch) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(ch);
    }
    out
}

/// `2.7e9` → `2.7·10⁹`.
fn sci(x: f64) -> String {
    let e = x.abs().log10().floor() as i32;
    let m = x / 10f64.powi(e);
    let sup: String =
        e.to_string()
            .chars()
            .map(|c| match c {
                '-' => '⁻',
                d => ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹']
                    [d.to_digit(10).unwrap() as usize],
            })
            .collect();
    format!("{m:.2}·10{sup}")
}

#[cfg(test)]
mod tests {
    use super::{adoptable, sci, thousands};

    /// A results file whose summary has `status`, made by `command`, in a fresh directory.
    fn made(name: &str, command: &str, status: &str) -> (std::path::PathBuf, std::path::PathBuf) {
        let dir = std::env::temp_dir().join(format!("sph-adopt-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("command.txt"), format!("{command}\n")).unwrap();
        let out = dir.join("r");
        let mut w = sph_output::create_writer(&out, sph_output::Backend::Pure).unwrap();
        let summary = serde_json::json!({ "status": status });
        w.write_summary(summary.as_object().unwrap()).unwrap();
        w.finish().unwrap();
        (dir, out)
    }

    #[test]
    fn only_runs_that_ended_by_themselves_are_adopted() {
        for (status, adopted) in [
            ("completed", true),
            ("failed: non-finite velocity", true),
            ("interrupted at t = 0.0052 s (SIGTERM)", false),
        ] {
            let (dir, out) = made(&status[..4], "sph run x", status);
            assert_eq!(
                adoptable(&dir, &out, "sph run x").is_some(),
                adopted,
                "{status}"
            );
            assert!(
                adoptable(&dir, &out, "sph run y").is_none(),
                "another command"
            );
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }

    #[test]
    fn numbers_print_readably() {
        assert_eq!(thousands(12572.0), "12,572");
        assert_eq!(thousands(200000.0), "200,000");
        assert_eq!(thousands(830.0), "830");
        assert_eq!(sci(2.73e9), "2.73·10⁹");
        assert_eq!(sci(115706.0), "1.16·10⁵");
        assert_eq!(sci(3.5e-6), "3.50·10⁻⁶");
    }
}
