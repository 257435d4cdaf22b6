//! `sph converge`: a case run at a ladder of resolutions, each level a `sph run` of its own
//! (a child process, so its CPU time and peak memory are its own), stored and reused when the
//! same level is asked for again, and the estimate of every quantity's error
//! ([`sph_driver::convergence`]) after each level, until the tolerance is met or the budget
//! would be exceeded.

use crate::error::CaseError;
use crate::process::run_costed;
use crate::Case;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use sph_driver::convergence::ladder::{self, LadderError, LevelOutcome, Plan, Prediction, Report};
use std::path::{Path, PathBuf};

pub mod quantity;
pub mod report;
pub use quantity::{Quantity, Statistic};

/// How a case refines: the key that sets its resolution and which way is finer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refinement {
    /// The key (`resolution`, `dp`, `wall_layers`).
    pub key: &'static str,
    /// A finer run has a larger value (`resolution`: H/dp) rather than a smaller one (`dp`).
    pub finer_is_larger: bool,
    /// The key takes whole numbers.
    pub whole: bool,
    /// The case's default value of the key.
    pub default: f64,
}

/// The refinement key of `case` with `method`'s defaults: the first of `resolution` (H/dp),
/// `wall_layers` (layers across the wall) and `dp` (the spacing) the case has.
///
/// # Errors
/// A case with none of them.
pub fn refinement_of(case: &dyn Case, method: &str) -> Result<Refinement, CaseError> {
    let params = case.params_for(method);
    for (key, finer_is_larger) in [("resolution", true), ("wall_layers", true), ("dp", false)] {
        if let Some(v) = params.value(key) {
            let (default, whole) = match v {
                crate::Value::Int(i) => (*i as f64, true),
                crate::Value::Float(x) => (*x, false),
                _ => continue,
            };
            let key = params
                .specs()
                .iter()
                .find(|p| p.key == key)
                .map(|p| p.key)
                .expect("the key exists");
            return Ok(Refinement {
                key,
                finer_is_larger,
                whole,
                default,
            });
        }
    }
    Err(CaseError::Config(format!(
        "case `{}` has no resolution key (resolution, wall_layers or dp) to refine",
        case.info().name
    )))
}

/// The ladder's first level and ratio when not given: the case's default resolution is the
/// third level, two ratios finer than the first (`ratio` 1.5: the cost of a 2D level grows about
/// 3.4 times per level, a 3D one 5 times), the first at least 4 (H/dp, layers).
pub fn default_start(r: &Refinement, ratio: f64) -> f64 {
    if r.finer_is_larger {
        let first = r.default / (ratio * ratio);
        let first = if r.whole { first.round() } else { first };
        first.max(4.0_f64.min(r.default))
    } else {
        r.default * ratio * ratio
    }
}

/// One level as stored in the ladder's directory (`<level>.json`): the command it ran, what it
/// cost and its summary; reused when the same command is asked for again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredLevel {
    /// The `sph run` command (without its output paths).
    pub command: String,
    /// Its exit status.
    pub exit_code: i32,
    /// CPU seconds.
    pub cpu_seconds: f64,
    /// Wall seconds.
    pub wall_seconds: f64,
    /// Peak memory, bytes.
    pub peak_bytes: f64,
    /// The run's summary (without its monitor history).
    pub summary: Map<String, Value>,
}

/// What a ladder runs: a case with its method and parameters, or a scene file.
#[derive(Clone)]
pub enum Subject {
    /// A case.
    Case {
        /// The case.
        case: &'static dyn Case,
        /// The method.
        method: &'static str,
        /// `--config`, applied to every level.
        config: Option<PathBuf>,
        /// `--set` assignments, applied to every level (not the refinement key).
        set: Vec<String>,
    },
    /// A scene file, refined by its parameter `dp` when it has one (every value written with
    /// `${dp}` follows), else by the spacing of every body at once.
    Scene {
        /// The file.
        file: PathBuf,
        /// Its name (the results' and the levels' names).
        name: String,
        /// The method (`--method`, or the file's).
        method: String,
        /// `--set` overrides, applied to every level (not a body's `dp`).
        set: Vec<String>,
        /// Each body's spacing in the file (overrides applied).
        spacings: Vec<f64>,
        /// The file's parameter `dp`, if it has one (overrides applied).
        dp_parameter: Option<f64>,
    },
}

impl Subject {
    /// The case's or scene's name.
    pub fn name(&self) -> &str {
        match self {
            Subject::Case { case, .. } => case.info().name,
            Subject::Scene { name, .. } => name,
        }
    }

    /// The method.
    pub fn method(&self) -> &str {
        match self {
            Subject::Case { method, .. } => method,
            Subject::Scene { method, .. } => method,
        }
    }
}

/// A scene's spacings, body by body, and its parameter `dp` if it has one (overrides applied):
/// what [`scene_refinement`] and [`scene_level_sets`] take.
pub fn scene_spacings(scene: &sph_scene::Scene) -> (Vec<f64>, Option<f64>) {
    let spacings = scene.spec().bodies.iter().map(|b| b.get_ref().dp).collect();
    let dp_parameter = scene
        .parameters()
        .iter()
        .find(|(k, _)| k == "dp")
        .and_then(|(_, v)| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)));
    (spacings, dp_parameter)
}

/// How a scene refines: its parameter `dp`, else the spacing of its finest body (every body's
/// spacing scales with it).
pub fn scene_refinement(spacings: &[f64], dp_parameter: Option<f64>) -> Refinement {
    Refinement {
        key: "dp",
        finer_is_larger: false,
        whole: false,
        default: dp_parameter
            .unwrap_or_else(|| spacings.iter().copied().fold(f64::INFINITY, f64::min)),
    }
}

/// The `--set` assignments (`KEY=VALUE`) that give a scene the spacing `value` of its
/// refinement `r` ([`scene_refinement`]): its parameter `dp` when it has one (every value
/// written with `${dp}` follows), else every body's spacing scaled by one factor.
pub fn scene_level_sets(
    spacings: &[f64],
    dp_parameter: Option<f64>,
    r: &Refinement,
    value: f64,
) -> Vec<String> {
    if dp_parameter.is_some() {
        vec![format!("dp={value:?}")]
    } else {
        let scale = value / r.default;
        spacings
            .iter()
            .enumerate()
            .map(|(k, dp)| format!("body[{k}].dp={:?}", dp * scale))
            .collect()
    }
}

/// Where and how the levels run.
#[derive(Clone, Debug)]
pub struct Runner {
    /// The `sph` program.
    pub program: PathBuf,
    /// The ladder's directory: one `<level>.json` and one results directory per level.
    pub store: PathBuf,
    /// Worker threads of every level.
    pub threads: usize,
    /// The quantities (read from each level's summary and results).
    pub quantities: Vec<Quantity>,
    /// Told each command before it runs (the `sph` command prints it).
    pub announce: fn(&str),
}

/// A fast bound on the particle-steps a CPU-second does on this hardware (above every rate
/// measured in docs/performance.md, 2.4e6 to 7.7e6 per thread), so that a dry run's work
/// divided by it is a lower bound of a level's CPU time.
pub const FASTEST_PARTICLE_STEPS_PER_CPU_SECOND: f64 = 5e7;

impl Runner {
    fn level_name(subject: &Subject, r: &Refinement, value: f64) -> String {
        format!(
            "{}-{}-{}{}",
            subject.name(),
            subject.method(),
            r.key,
            crate::params::Value::Float(value)
        )
    }

    /// The `sph run` arguments of a level, without output destinations.
    fn args(&self, subject: &Subject, r: &Refinement, value: f64) -> Vec<String> {
        let mut a = vec!["run".to_string()];
        match subject {
            Subject::Case {
                case,
                method,
                config,
                set,
            } => {
                a.extend([
                    case.info().name.to_string(),
                    "--method".into(),
                    method.to_string(),
                ]);
                if let Some(c) = config {
                    a.extend(["--config".into(), c.display().to_string()]);
                }
                for s in set {
                    a.extend(["--set".into(), s.clone()]);
                }
                let shown = if r.whole {
                    format!("{}", value.round() as i64)
                } else {
                    format!("{value:?}")
                };
                a.extend(["--set".into(), format!("{}={shown}", r.key)]);
            }
            Subject::Scene {
                file,
                method,
                set,
                spacings,
                dp_parameter,
                ..
            } => {
                a.extend([
                    file.display().to_string(),
                    "--method".into(),
                    method.clone(),
                ]);
                for s in set {
                    a.extend(["--set".into(), s.clone()]);
                }
                for s in scene_level_sets(spacings, *dp_parameter, r, value) {
                    a.extend(["--set".into(), s]);
                }
            }
        }
        a.extend(["--threads".into(), self.threads.to_string()]);
        a
    }

    /// Runs (or reuses) the level of refinement `value`.
    ///
    /// # Errors
    /// [`LadderError::Level`]: the run cannot start, fails (its diagnostic) or is interrupted
    /// (`interrupted` holds the exit status); [`LadderError::Invalid`]: it lacks a quantity.
    pub fn level(
        &self,
        subject: &Subject,
        r: &Refinement,
        value: f64,
        interrupted: &mut Option<i32>,
    ) -> Result<LevelOutcome, LadderError> {
        let failed = |message: String| LadderError::Level {
            resolution: value,
            message,
        };
        let name = Self::level_name(subject, r, value);
        let args = self.args(subject, r, value);
        let command = format!("sph {}", args.join(" "));
        let stored_path = self.store.join(format!("{name}.json"));
        let out_dir = self.store.join(&name);
        let results = out_dir.join(format!("{}-{}.h5", subject.name(), subject.method()));
        let needs_results = self.quantities.iter().any(Quantity::needs_results);
        let reuse = std::fs::read_to_string(&stored_path)
            .ok()
            .and_then(|t| serde_json::from_str::<StoredLevel>(&t).ok())
            .filter(|s| s.command == command && s.exit_code == 0)
            .filter(|_| !needs_results || results.is_file());
        let (stored, reused) = match reuse {
            Some(s) => (s, true),
            None => {
                let summary_path = self.store.join(format!("{name}.summary.json"));
                let mut full = args.clone();
                if needs_results {
                    full.extend(["--out".into(), out_dir.display().to_string()]);
                } else {
                    full.push("--no-output".into());
                }
                full.extend(["--summary".into(), summary_path.display().to_string()]);
                std::fs::create_dir_all(&self.store)
                    .map_err(|e| failed(format!("{}: {e}", self.store.display())))?;
                (self.announce)(&command);
                let c = run_costed(&self.program, &full, None).map_err(failed)?;
                if c.exit_code >= 128 {
                    *interrupted = Some(c.exit_code);
                    return Err(failed(format!(
                        "interrupted (exit status {}); the levels done are stored in {}: run \
                         the same command again to continue",
                        c.exit_code,
                        self.store.display()
                    )));
                }
                let mut summary: Map<String, Value> = std::fs::read_to_string(&summary_path)
                    .ok()
                    .and_then(|t| serde_json::from_str(&t).ok())
                    .unwrap_or_default();
                let _ = std::fs::remove_file(&summary_path);
                if c.exit_code != 0 {
                    return Err(failed(format!("`{command}` failed: {}", c.message())));
                }
                summary.remove("monitor");
                let stored = StoredLevel {
                    command,
                    exit_code: c.exit_code,
                    cpu_seconds: c.cpu_seconds(),
                    wall_seconds: c.wall_seconds,
                    peak_bytes: c.peak_bytes,
                    summary,
                };
                let text = serde_json::to_string_pretty(&stored).expect("serialises");
                std::fs::write(&stored_path, text)
                    .map_err(|e| failed(format!("{}: {e}", stored_path.display())))?;
                (stored, false)
            }
        };
        let file = if needs_results {
            Some(sph_output::read_file(&results).map_err(|e| failed(e.to_string()))?)
        } else {
            None
        };
        let values = self
            .quantities
            .iter()
            .map(|q| q.value(&stored.summary, file.as_ref()))
            .collect::<Result<Vec<f64>, String>>()
            .map_err(LadderError::Invalid)?;
        Ok(LevelOutcome {
            values,
            cpu_seconds: stored.cpu_seconds,
            peak_bytes: stored.peak_bytes,
            reused,
        })
    }

    /// The coarsest of `r`'s default start and the levels between it and the case's (or
    /// scene's) own resolution whose dry run passes (a scene's body too thin at the default
    /// start moves it finer), else the own resolution.
    pub fn first_level(&self, subject: &Subject, r: &Refinement, ratio: f64) -> f64 {
        let six = |x: f64| {
            let scale = 10f64.powi(5 - x.abs().log10().floor() as i32);
            (x * scale).round() / scale
        };
        let mut candidate = if r.whole {
            default_start(r, ratio)
        } else {
            six(default_start(r, ratio))
        };
        for _ in 0..3 {
            if dry_run(&self.program, &self.args(subject, r, candidate)).is_some() {
                return candidate;
            }
            candidate = if r.finer_is_larger {
                let c = candidate * ratio;
                if r.whole {
                    c.round()
                } else {
                    c
                }
            } else {
                six(candidate / ratio)
            };
            let past = if r.finer_is_larger {
                candidate >= r.default
            } else {
                candidate <= r.default
            };
            if past {
                break;
            }
        }
        r.default
    }

    /// A level's cost before it runs, from a dry run: its particle-steps over
    /// [`FASTEST_PARTICLE_STEPS_PER_CPU_SECOND`] (a lower bound of its CPU time) and its
    /// memory estimate. `None` if the dry run gives none.
    pub fn predict(&self, subject: &Subject, r: &Refinement, value: f64) -> Option<Prediction> {
        let d = dry_run(&self.program, &self.args(subject, r, value))?;
        Some(Prediction {
            resolution: value,
            cpu_seconds: d.particle_steps / FASTEST_PARTICLE_STEPS_PER_CPU_SECOND,
            peak_bytes: d.memory_bytes,
        })
    }
}

/// What a dry run estimates of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DryRun {
    /// Particle-steps (UL: acoustic sub-steps).
    pub particle_steps: f64,
    /// Peak memory, bytes.
    pub memory_bytes: f64,
}

/// The estimates of `program run_args… --dry-run --no-output` (which prints them as
/// `key  value` lines, and writes nothing); `None` if the dry run fails.
pub fn dry_run(program: &Path, run_args: &[String]) -> Option<DryRun> {
    let out = std::process::Command::new(program)
        .args(run_args)
        .args(["--dry-run", "--no-output"])
        .stderr(std::process::Stdio::null())
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let number = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().parse::<f64>().ok())
    };
    Some(DryRun {
        particle_steps: number("particle_steps_estimate")?,
        memory_bytes: number("memory_bytes_estimate")?,
    })
}

/// Runs the ladder of `subject` (see the module documentation). An interruption of a level
/// (its exit status) is put in `interrupted`.
///
/// # Errors
/// As [`ladder::run`].
pub fn converge(
    subject: &Subject,
    refinement: &Refinement,
    plan: &Plan,
    runner: &Runner,
    names: &[String],
    interrupted: &mut Option<i32>,
) -> Result<Report, ladder::LadderError> {
    let mut stop = None;
    let report = ladder::run(
        plan,
        names,
        |r| runner.level(subject, refinement, r, &mut stop),
        |r| runner.predict(subject, refinement, r),
    );
    *interrupted = stop;
    report
}

/// The directory of a ladder's levels when `--store` is not given: `<out>/converge-<case>`.
pub fn default_store(out: &Path, case: &str) -> PathBuf {
    out.join(format!("converge-{case}"))
}
