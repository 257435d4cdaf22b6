//! Regression checks of the validated figures: a small version of each stored trade-off scene,
//! re-run through the library, must reproduce its stored value, so that a change that moves a
//! validated number fails `cargo test` (validation/tests/regression.rs) instead of silently
//! changing docs/tradeoffs.md.
//!
//! For every scene and method, the cheapest stored run that completed with a measured value
//! (the base line of the method, not a variant) is a check when it cost at most the limit given
//! (CPU seconds as stored: 2 threads, release build). The full ladders stay in
//! `validate tradeoff`.

use super::{measured_key, scene_run_id, scene_set, scenes, stored_runs, value_of, Measure};
use sph_cases::{find_case, RunOptions};

/// One check: a stored run and the figure it must reproduce.
#[derive(Clone, Debug)]
pub struct Check {
    /// The stored run (`validation/results/tradeoff/<id>.json`).
    pub id: String,
    /// Its case.
    pub case: String,
    /// Its method.
    pub method: String,
    /// Its settings.
    pub set: Vec<String>,
    /// The summary key measured.
    pub key: &'static str,
    /// The stored value of `key`.
    pub stored: f64,
    /// The stored run's relative error against the scene's reference.
    pub error: f64,
    measure: Measure,
}

/// The checks whose stored run cost at most `max_cpu_seconds`.
pub fn checks(max_cpu_seconds: f64) -> Vec<Check> {
    let mut out = Vec::new();
    for scene in scenes() {
        let runs = stored_runs(&scene);
        let mut methods: Vec<&str> = scene.lines.iter().map(|l| l.method).collect();
        methods.dedup();
        for method in methods {
            let cheapest = runs
                .iter()
                .filter(|(l, _, r)| {
                    l.method == method
                        && l.extra.is_empty()
                        && r.exit_code == 0
                        && r.cpu_seconds <= max_cpu_seconds
                        && value_of(r, scene.measure, method).is_some()
                })
                .min_by(|a, b| a.2.cpu_seconds.total_cmp(&b.2.cpu_seconds));
            let Some((line, res, run)) = cheapest else {
                continue;
            };
            let key = measured_key(scene.measure);
            out.push(Check {
                id: scene_run_id(&scene, line, *res),
                case: scene.case.to_string(),
                method: method.to_string(),
                set: scene_set(&scene, line, *res),
                key,
                stored: run.num(key).expect("checked by value_of"),
                error: value_of(run, scene.measure, method).expect("filtered"),
                measure: scene.measure,
            });
        }
    }
    out
}

impl Check {
    /// Runs the check's case through the library (default options: no output) and returns
    /// the measured value and its relative error against the scene's reference.
    ///
    /// # Errors
    /// The case refuses the settings, fails, or gives no value.
    pub fn rerun(&self) -> Result<(f64, f64), String> {
        let case = find_case(&self.case).map_err(|e| e.to_string())?;
        // The method's own defaults, as `sph run` (and the stored run) uses them.
        let mut p = case.params_for(&self.method);
        for a in &self.set {
            p.apply_assignment(a).map_err(|e| e.to_string())?;
        }
        let (record, summary) = case
            .run(&self.method, &p, &RunOptions::default())
            .map_err(|e| e.to_string())?;
        if let Some(f) = record.failure {
            return Err(format!("{}: {f:?}", self.id));
        }
        let run = crate::cost::CostedRun {
            id: self.id.clone(),
            case: self.case.clone(),
            method: self.method.clone(),
            set: self.set.clone(),
            command: String::new(),
            exit_code: 0,
            cpu_seconds: 0.0,
            wall_seconds: 0.0,
            max_rss_mib: 0.0,
            summary,
            message: String::new(),
        };
        let value = run
            .num(self.key)
            .ok_or_else(|| format!("{}: no `{}` in the summary", self.id, self.key))?;
        let error = value_of(&run, self.measure, &self.method)
            .ok_or_else(|| format!("{}: no error measured", self.id))?;
        Ok((value, error))
    }
}

/// Summary keys that measure the machine, not the physics (left out of [`compare`]).
const MACHINE_KEYS: &[&str] = &[
    "solver_seconds",
    "wall_seconds",
    "particle_steps_per_second",
    "threads",
    "monitor",
];

/// The stored validation runs of docs/validation.md (`validation/results/*.json`) whose solver
/// took at most `max_solver_seconds` as stored, cheapest first.
pub fn validation_runs(max_solver_seconds: f64) -> Vec<crate::store::StoredRun> {
    let mut runs: Vec<crate::store::StoredRun> = std::fs::read_dir(crate::store::results_dir())
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
        .filter_map(|e| serde_json::from_str(&std::fs::read_to_string(e.path()).ok()?).ok())
        .filter(|r: &crate::store::StoredRun| {
            r.num("solver_seconds")
                .is_some_and(|s| s <= max_solver_seconds)
        })
        .collect();
    runs.sort_by(|a, b| {
        let s = |r: &crate::store::StoredRun| r.num("solver_seconds").unwrap_or(0.0);
        s(a).total_cmp(&s(b)).then(a.id.cmp(&b.id))
    });
    runs
}

/// Re-runs a stored validation run through the library (the method's defaults, its
/// settings, and a results file, in a temporary folder, where the stored run wrote one: ENOG
/// integrates its output-only shear stress then, and its budget's shear term is that
/// stress's estimate instead of the exact work) and lists every physics figure of its summary
/// that differs from the stored one by more than `tolerance` (relative; absolute below
/// 1e-12), and a status that differs.
///
/// # Errors
/// The case refuses the stored settings.
pub fn compare(run: &crate::store::StoredRun, tolerance: f64) -> Result<Vec<String>, String> {
    let case = find_case(&run.case).map_err(|e| e.to_string())?;
    let mut p = case.params_for(&run.method);
    for a in &run.set {
        p.apply_assignment(a).map_err(|e| e.to_string())?;
    }
    let dir =
        std::env::temp_dir().join(format!("sph-regression-{}-{}", run.id, std::process::id()));
    let options = RunOptions {
        output: run.results_file.is_some().then(|| dir.join("run")),
        ..Default::default()
    };
    let result = case.run(&run.method, &p, &options);
    let _ = std::fs::remove_dir_all(&dir);
    let (_, summary) = result.map_err(|e| format!("{}: {e}", run.id))?;
    let mut moved = Vec::new();
    for (key, stored) in &run.summary {
        if MACHINE_KEYS.contains(&key.as_str()) {
            continue;
        }
        let now = summary.get(key);
        // Stored before a run from rest had no relative energy drift (RunRecord::energy_drift):
        // the stored value is a change relative to round-off (10¹¹ to 10³³), not a figure.
        if key == "energy_drift"
            && now.is_none_or(serde_json::Value::is_null)
            && stored.as_f64().is_some_and(|e| e.abs() > 1.0)
        {
            continue;
        }
        let same = match (stored.as_f64(), now.and_then(serde_json::Value::as_f64)) {
            (Some(a), Some(b)) => {
                (a - b).abs() <= tolerance * a.abs().max(b.abs()).max(1e-12 / tolerance)
            }
            _ => Some(stored) == now || stored.is_array() || stored.is_object(),
        };
        if !same {
            moved.push(format!(
                "{}: {key} = {}, stored {stored}",
                run.id,
                now.map_or("(absent)".to_string(), |v| v.to_string())
            ));
        }
    }
    Ok(moved)
}
