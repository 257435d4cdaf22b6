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
