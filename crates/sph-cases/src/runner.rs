//! The run driver shared by every case: steps a solver to the end time, lands exactly on
//! snapshot and monitor times, samples the disorder indicator and the energies, writes the
//! HDF5 results, and on a failure mid-run still completes the file with everything computed so
//! far and the diagnostic in its summary.

use crate::error::CaseError;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Map, Value as Json};
use sph_core::disorder::DisorderStats;
use sph_core::{Dim, EnergyBudget, Field, Solver};
use sph_output::{create_writer, Backend, Dataset, ResultWriter};
use std::path::PathBuf;
use std::time::Instant;

/// The output-schedule keys every case accepts: `snapshot_interval`, `monitor_interval` and
/// `probe_interval` (all 0 by default: first and last snapshot, end_time/200, every step).
pub fn output_params() -> Vec<crate::params::Param> {
    use crate::params::{Param, Range};
    vec![
        Param::float(
            "snapshot_interval",
            0.0,
            Range::NonNegative,
            "simulated time between HDF5 snapshots (0: first and last only)",
        ),
        Param::float(
            "monitor_interval",
            0.0,
            Range::NonNegative,
            "time between disorder/energy samples (0: end_time/200)",
        ),
        Param::float(
            "probe_interval",
            0.0,
            Range::NonNegative,
            "time between probe samples (0: every step)",
        ),
    ]
}

/// Where and how to write results.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Results file path without extension (`.h5` and `.xmf` are appended); `None` writes none.
    pub output: Option<PathBuf>,
    /// HDF5 backend.
    pub backend: Backend,
    /// Show a progress bar (only drawn when stderr is a terminal).
    pub progress: bool,
}

/// When things happen during a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// Simulated end time.
    pub end_time: f64,
    /// Interval between snapshots (0: only the first and the last).
    pub snapshot_interval: f64,
    /// Interval between samples of the disorder indicator and the energies.
    pub monitor_interval: f64,
}

/// One sample of the run monitor.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MonitorSample {
    /// Simulated time.
    pub time: f64,
    /// Disorder indicator statistics over the particles.
    pub disorder: DisorderStats,
    /// Kinetic energy (NaN if the method has none).
    pub kinetic: f64,
    /// Strain energy (NaN if the method has none).
    pub strain: f64,
    /// The energy budget, for methods that keep one.
    pub budget: Option<EnergyBudget>,
    /// Connected pieces of the particles' neighbour graph (from the field `fragment`), for
    /// methods that label them: a body that breaks apart adds pieces.
    pub pieces: Option<usize>,
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct RunRecord {
    /// Particles.
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached.
    pub time: f64,
    /// Wall time of the whole run, output included.
    pub wall_seconds: f64,
    /// Wall time spent inside `Solver::step`.
    pub solver_seconds: f64,
    /// Monitor samples.
    pub monitor: Vec<MonitorSample>,
    /// The error that stopped the run early, if any.
    pub failure: Option<String>,
    /// The results file, if one was written.
    pub file: Option<PathBuf>,
}

impl RunRecord {
    /// Particle-steps per second of the solver (time inside `step` only).
    pub fn particle_steps_per_second(&self) -> f64 {
        if self.solver_seconds > 0.0 {
            self.particles as f64 * self.steps as f64 / self.solver_seconds
        } else {
            0.0
        }
    }

    /// Largest disorder indicator seen.
    pub fn max_disorder(&self) -> f64 {
        self.monitor
            .iter()
            .map(|m| m.disorder.max)
            .fold(0.0, f64::max)
    }

    /// Relative change of total energy between the first and the last monitor sample, where the
    /// method has a strain energy.
    pub fn energy_drift(&self) -> Option<f64> {
        let (a, b) = (self.monitor.first()?, self.monitor.last()?);
        let (e0, e1) = (a.kinetic + a.strain, b.kinetic + b.strain);
        (e0.is_finite() && e1.is_finite() && e0 > 0.0).then(|| (e1 - e0) / e0)
    }

    /// The energy-budget residual (`total − initial total`, see [`EnergyBudget`]) over the
    /// initial total, at the last monitor sample and its largest magnitude over the samples,
    /// where the method keeps a budget.
    pub fn energy_residual(&self) -> Option<(f64, f64)> {
        let rel = |b: &EnergyBudget| b.residual() / b.initial_total;
        let last = self.monitor.last()?.budget.as_ref()?;
        if last.initial_total.is_nan() || last.initial_total <= 0.0 {
            return None;
        }
        let max = self
            .monitor
            .iter()
            .filter_map(|m| m.budget.as_ref().map(rel))
            .fold(0.0, |m: f64, r| if r.abs() > m.abs() { r } else { m });
        Some((rel(last), max))
    }

    /// The figures every case reports (issue: case, method, particles, steps, wall_seconds,
    /// particle_steps_per_second, max_disorder, energy_drift), plus the status; for methods
    /// with an energy budget also `energy_residual` (at the end) and `energy_residual_max`
    /// (largest magnitude over the monitor samples), both relative to the initial total, and
    /// the budget's terms over time under `monitor.energy_budget`; for methods that label
    /// connected pieces (field `fragment`) `pieces_initial`, `pieces_max` and
    /// `first_break_time` (the first monitor sample with more pieces than at the start).
    pub fn standard_summary(&self, case: &str, method: &str) -> Map<String, Json> {
        let mut m = Map::new();
        m.insert("case".into(), json!(case));
        m.insert("method".into(), json!(method));
        m.insert("particles".into(), json!(self.particles));
        m.insert("steps".into(), json!(self.steps));
        m.insert("time_reached".into(), json!(self.time));
        m.insert("wall_seconds".into(), json!(self.wall_seconds));
        m.insert("solver_seconds".into(), json!(self.solver_seconds));
        m.insert(
            "particle_steps_per_second".into(),
            json!(self.particle_steps_per_second()),
        );
        m.insert("threads".into(), json!(rayon::current_num_threads()));
        m.insert("max_disorder".into(), finite_or_null(self.max_disorder()));
        m.insert(
            "energy_drift".into(),
            self.energy_drift().map_or(Json::Null, finite_or_null),
        );
        let pieces: Vec<usize> = self.monitor.iter().filter_map(|s| s.pieces).collect();
        if let (Some(&p0), Some(&max)) = (pieces.first(), pieces.iter().max()) {
            m.insert("pieces_initial".into(), json!(p0));
            m.insert("pieces_max".into(), json!(max));
            let broke = self
                .monitor
                .iter()
                .find(|s| s.pieces.is_some_and(|p| p > p0))
                .map(|s| s.time);
            m.insert(
                "first_break_time".into(),
                broke.map_or(Json::Null, |t| json!(t)),
            );
        }
        if let Some((last, max)) = self.energy_residual() {
            m.insert("energy_residual".into(), finite_or_null(last));
            m.insert("energy_residual_max".into(), finite_or_null(max));
        }
        m.insert(
            "status".into(),
            json!(match &self.failure {
                None => "completed".to_string(),
                Some(e) => format!("failed: {e}"),
            }),
        );
        let mut monitor = json!({
            "time": self.monitor.iter().map(|s| s.time).collect::<Vec<_>>(),
            "disorder_max": self.monitor.iter().map(|s| finite_or_null(s.disorder.max)).collect::<Vec<_>>(),
            "disorder_p99": self.monitor.iter().map(|s| finite_or_null(s.disorder.p99)).collect::<Vec<_>>(),
            "kinetic_energy": self.monitor.iter().map(|s| finite_or_null(s.kinetic)).collect::<Vec<_>>(),
            "strain_energy": self.monitor.iter().map(|s| finite_or_null(s.strain)).collect::<Vec<_>>(),
        });
        if self.monitor.iter().any(|s| s.pieces.is_some()) {
            monitor["pieces"] = json!(self.monitor.iter().map(|s| s.pieces).collect::<Vec<_>>());
        }
        if let Some(budget) = budget_series(&self.monitor) {
            monitor["energy_budget"] = budget;
        }
        m.insert("monitor".into(), monitor);
        m
    }
}

/// The budget's terms and notes over the monitor samples, `{name: [values]}` plus `residual`,
/// when every sample has a budget.
fn budget_series(samples: &[MonitorSample]) -> Option<Json> {
    let budgets: Vec<&EnergyBudget> = samples
        .iter()
        .map(|s| s.budget.as_ref())
        .collect::<Option<_>>()?;
    let first = budgets.first()?;
    let mut out = Map::new();
    for &(name, _) in first.terms.iter().chain(&first.notes) {
        let v: Vec<Json> = budgets
            .iter()
            .map(|b| b.get(name).map_or(Json::Null, finite_or_null))
            .collect();
        out.insert(name.into(), Json::Array(v));
    }
    let residual: Vec<Json> = budgets
        .iter()
        .map(|b| finite_or_null(b.residual()))
        .collect();
    out.insert("residual".into(), Json::Array(residual));
    out.insert("initial_total".into(), finite_or_null(first.initial_total));
    Some(Json::Object(out))
}

/// A JSON number, or null for NaN/∞ (JSON has no such numbers).
pub fn finite_or_null(x: f64) -> Json {
    if x.is_finite() {
        json!(x)
    } else {
        Json::Null
    }
}

/// Runs `solver` to `schedule.end_time`. `meta` goes to `/meta`; `summarise` turns the record
/// and the solver's probes into the case's figures (merged over the standard ones). Returns the
/// record and the summary; a failure mid-run is recorded (status, diagnostic), the results file
/// is still completed, and the caller decides the exit status from `record.failure`.
pub fn drive<D: Dim>(
    solver: &mut dyn Solver<D>,
    meta: Map<String, Json>,
    schedule: Schedule,
    fields: &[&str],
    options: &RunOptions,
    summarise: impl FnOnce(&dyn Solver<D>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), CaseError> {
    let started = Instant::now();
    let mut writer: Option<Box<dyn ResultWriter>> = match &options.output {
        Some(path) => {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(|e| CaseError::Io {
                    path: dir.display().to_string(),
                    source: e,
                })?;
            }
            let mut w = create_writer(path, options.backend)?;
            w.write_meta(&meta)?;
            Some(w)
        }
        None => None,
    };
    let mut record = RunRecord {
        particles: solver.len(),
        ..Default::default()
    };
    let bar = progress_bar(options.progress, schedule.end_time);
    let end = schedule.end_time;
    let eps = 1e-12 * end.max(1e-300);
    let mut next_snapshot = 0.0;
    let mut next_monitor = 0.0;
    loop {
        let t = solver.time();
        if t + eps >= next_monitor {
            record.monitor.push(sample(solver));
            next_monitor = next_event(t, schedule.monitor_interval, end);
        }
        if t + eps >= next_snapshot {
            if let Some(w) = writer.as_mut() {
                write_snapshot(w.as_mut(), solver, fields)?;
            }
            next_snapshot = next_event(t, schedule.snapshot_interval, end);
        }
        if t + eps >= end {
            break;
        }
        let target = next_snapshot.min(next_monitor).min(end);
        let t0 = Instant::now();
        let mut failed = None;
        while solver.time() + eps < target {
            if let Err(e) = solver.step(target - solver.time()) {
                failed = Some(e);
                break;
            }
        }
        record.solver_seconds += t0.elapsed().as_secs_f64();
        bar.set_position(progress_units(solver.time()));
        bar.set_message(format!(
            "{:.3e} particle-steps/s",
            solver.len() as f64 * solver.step_count() as f64 / record.solver_seconds.max(1e-9)
        ));
        if let Some(e) = failed {
            record.failure = Some(e.to_string());
            break;
        }
    }
    bar.finish_and_clear();
    record.steps = solver.step_count();
    record.time = solver.time();
    record.wall_seconds = started.elapsed().as_secs_f64();
    let mut summary = record.standard_summary(&meta_str(&meta, "case"), solver.method());
    for (k, v) in summarise(solver, &record) {
        summary.insert(k, v);
    }
    if let Some(mut w) = writer {
        for p in solver.probes() {
            let pos: Vec<[f64; 3]> = p
                .positions
                .iter()
                .map(|&x| D::to_vec3(x).to_array())
                .collect();
            let vel: Vec<[f64; 3]> = p
                .velocities
                .iter()
                .map(|&x| D::to_vec3(x).to_array())
                .collect();
            w.write_probe(&p.name, &p.times, &pos, &vel)?;
        }
        for s in solver.series() {
            let columns: Vec<(&str, &[f64])> = s
                .columns
                .iter()
                .zip(&s.values)
                .map(|(c, v)| (c.as_str(), v.as_slice()))
                .collect();
            w.write_series(&s.name, &s.time, &columns)?;
        }
        w.write_summary(&summary)?;
        record.file = Some(w.finish()?);
    }
    record.wall_seconds = started.elapsed().as_secs_f64();
    summary.insert("wall_seconds".into(), json!(record.wall_seconds));
    Ok((record, summary))
}

fn meta_str(meta: &Map<String, Json>, key: &str) -> String {
    meta.get(key)
        .and_then(|v| v.as_str())
        .unwrap_or("")
        .to_string()
}

/// The next multiple of `interval` after `t` (or the end if the interval is 0).
fn next_event(t: f64, interval: f64, end: f64) -> f64 {
    if interval > 0.0 {
        let k = (t / interval + 1e-9).floor() + 1.0;
        (k * interval).min(end)
    } else {
        end
    }
}

fn sample<D: Dim>(solver: &dyn Solver<D>) -> MonitorSample {
    let disorder = match solver.field("disorder") {
        Some(Field::Scalar(v)) => DisorderStats::of(&v),
        _ => DisorderStats::default(),
    };
    let (kinetic, strain) = solver.energies().unwrap_or((f64::NAN, f64::NAN));
    let pieces = match solver.field("fragment") {
        Some(Field::Scalar(v)) => Some(v.iter().fold(0.0f64, |m, &x| m.max(x)) as usize + 1),
        _ => None,
    };
    MonitorSample {
        time: solver.time(),
        disorder,
        kinetic,
        strain,
        budget: solver.energy_budget(),
        pieces,
    }
}

/// Converts a solver field to a dataset (vectors as `[n, 3]`, matrices as `[n, 3, 3]`, 2D
/// padded: z = 0 for vectors, the plane-strain `F_zz = 1` for matrices).
pub fn field_dataset<D: Dim>(name: &str, field: Field<D>) -> Dataset {
    match field {
        Field::Scalar(v) => Dataset::scalars(name, &v),
        Field::Vector(v) => {
            let a: Vec<[f64; 3]> = v.iter().map(|&x| D::to_vec3(x).to_array()).collect();
            Dataset::vectors(name, &a)
        }
        Field::Matrix(m) => {
            let a: Vec<[[f64; 3]; 3]> = m
                .iter()
                .map(|&x| {
                    let m3 = D::to_mat3(x, 1.0);
                    // Row-major rows for the file.
                    [
                        m3.row(0).to_array(),
                        m3.row(1).to_array(),
                        m3.row(2).to_array(),
                    ]
                })
                .collect();
            Dataset::matrices(name, &a)
        }
    }
}

fn write_snapshot<D: Dim>(
    w: &mut dyn ResultWriter,
    solver: &dyn Solver<D>,
    fields: &[&str],
) -> Result<(), CaseError> {
    let pos: Vec<[f64; 3]> = solver
        .positions()
        .iter()
        .map(|&x| D::to_vec3(x).to_array())
        .collect();
    let mut sets = vec![Dataset::vectors("position", &pos)];
    for &name in fields {
        if let Some(f) = solver.field(name) {
            sets.push(field_dataset::<D>(name, f));
        }
    }
    w.write_snapshot(solver.time(), solver.step_count(), &sets)?;
    Ok(())
}

const PROGRESS_SCALE: f64 = 1e6;

fn progress_units(t: f64) -> u64 {
    (t * PROGRESS_SCALE).round().max(0.0) as u64
}

fn progress_bar(show: bool, end: f64) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(
        Some(progress_units(end)),
        ProgressDrawTarget::stderr_with_hz(4),
    );
    bar.set_style(
        ProgressStyle::with_template("{bar:30} t = {pos_time} / {end_time} s  ETA {eta}  {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .with_key(
                "pos_time",
                |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.4}", s.pos() as f64 / PROGRESS_SCALE);
                },
            )
            .with_key(
                "end_time",
                |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.4}", s.len().unwrap_or(0) as f64 / PROGRESS_SCALE);
                },
            ),
    );
    bar
}
