//! The run loop: steps a solver to the end time, lands exactly on snapshot and monitor times,
//! samples the disorder indicator and the energies, writes the HDF5 results, and on a failure
//! mid-run still completes the file with everything computed so far and the diagnostic in its
//! summary.

use crate::checkpoint::{self, Checkpoint, CheckpointPlan, DriverState, Every, SavedSnapshot};
use crate::error::DriverError;
use serde_json::{json, Map, Value as Json};
use sph_core::conventions;
use sph_core::disorder::DisorderStats;
use sph_core::{Dim, EnergyBudget, Field, Solver, StateReader, StateWriter};
use sph_output::vtu::VtuSeries;
use sph_output::{create_writer_with, Backend, Compression, Dataset, ResultWriter};
use std::path::Path;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

mod output;
mod record;
pub use output::field_dataset;
pub(crate) use output::snapshot_datasets;
use output::{check_compression, write_snapshot};
pub use record::{finite_or_null, signal_name, MonitorSample, RunRecord};

/// What the driver tells a progress display: after every stretch of steps between two output
/// events (at least 200 per run: the monitor samples), and once more at the end. A display
/// throttles itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Simulated time reached.
    pub time: f64,
    /// Simulated end time.
    pub end_time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Particles.
    pub particles: usize,
    /// Wall seconds inside `Solver::step` so far.
    pub solver_seconds: f64,
    /// Wall seconds since the run started.
    pub wall_seconds: f64,
    /// Whether the run is over (the last call).
    pub finished: bool,
}

impl Progress {
    /// Particle-steps per second so far.
    pub fn particle_steps_per_second(&self) -> f64 {
        self.particles as f64 * self.steps as f64 / self.solver_seconds.max(1e-9)
    }
}

/// A progress display: called by [`drive`] with the run's progress.
#[derive(Clone)]
pub struct ProgressSink(pub Arc<dyn Fn(&Progress) + Send + Sync>);

impl std::fmt::Debug for ProgressSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ProgressSink")
    }
}

impl ProgressSink {
    /// A sink from a closure.
    pub fn new(f: impl Fn(&Progress) + Send + Sync + 'static) -> Self {
        Self(Arc::new(f))
    }
}

/// Where and how to write results, and what the driver may do.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Results file path without extension (`.h5` and `.xmf` are appended); `None` writes none.
    pub output: Option<PathBuf>,
    /// HDF5 backend.
    pub backend: Backend,
    /// Dataset compression (none by default; `Compression::Deflate(level)` for shuffle +
    /// deflate, which every HDF5 reader decodes).
    pub compression: Compression,
    /// Where to report progress (nothing when `None`).
    pub progress: Option<ProgressSink>,
    /// Run even if the estimated work exceeds [`crate::guard::MAX_PARTICLE_STEPS`].
    pub allow_long_run: bool,
    /// Build the scene and make every check and estimate, then stop: nothing is run or
    /// written; the summary holds the estimates ([`crate::guard::Estimate::to_json`]).
    pub dry_run: bool,
    /// Set to a signal number (by a signal handler) to stop the run after the current step:
    /// the driver writes a last snapshot and completes the file with the status
    /// `interrupted at t = …`.
    pub interrupt: Option<Interrupt>,
    /// Write checkpoints ([`crate::checkpoint`]): at the first snapshot or monitor time after
    /// each interval (so checkpoints never change the steps taken).
    pub checkpoint: Option<CheckpointPlan>,
    /// Continue from this checkpoint: the solver handed to [`drive`] must be built from the
    /// same case, method and parameters (its `/meta` must equal the checkpoint's); its state
    /// is restored before anything is written, and the results file is re-created whole
    /// (the snapshots written before the checkpoint, then the rest of the run).
    pub resume: Option<Arc<Checkpoint>>,
    /// The ranks of a distributed run (`None`: one process). The solver handed to [`drive`]
    /// must then be distributed over them (a
    /// [`DistributedSolver`](sph_core::distributed::DistributedSolver)); every rank runs the
    /// driver, rank 0 writes the results, and each rank writes its own checkpoint (the plan's
    /// path is then the rank's, [`crate::checkpoint::rank_path`]).
    pub ranks: Option<Arc<dyn sph_core::comm::Communicator>>,
    /// Per-rank output ([`sph_output::read_ranks`] reads it back): every rank writes the
    /// snapshots of the particles it owns to `<output>.rank<r>.h5`, without gathering them;
    /// rank 0 writes `<output>.h5` (meta, probes, series, summary with the rank count) and
    /// `<output>.xmf`, which presents the ranks' files as one body. Off: rank 0 gathers the
    /// snapshots into the one file `<output>.h5`. Needs `output`.
    pub per_rank_output: bool,
    /// Also write every snapshot as a VTK XML file `<output>_<k>.vtu` and their collection
    /// `<output>.pvd` ([`sph_output::vtu`]), which ParaView, PyVista and meshio read without
    /// an XDMF reader. Needs `output`; not with `per_rank_output`.
    pub vtu: bool,
}

/// A flag a signal handler sets to the signal's number (0: not interrupted).
pub type Interrupt = std::sync::Arc<std::sync::atomic::AtomicUsize>;

/// Snapshots a run writes by default after the initial one (the `sph` command's `snapshots`
/// key): an interval of `end_time / DEFAULT_SNAPSHOTS`, 51 frames. 50 divides the default
/// monitor rate (`end_time/200`) by a power of two, so these snapshot times are monitor times
/// exactly and the snapshots do not change the step sequence of a run.
pub const DEFAULT_SNAPSHOTS: u32 = 50;

/// When things happen during a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// Simulated end time.
    pub end_time: f64,
    /// Interval between snapshots: one at t = 0, at every multiple of it and at the end time
    /// (0: only the first and the last; `end_time /` [`DEFAULT_SNAPSHOTS`] is the default of
    /// the `sph` command).
    pub snapshot_interval: f64,
    /// Interval between samples of the disorder indicator and the energies.
    pub monitor_interval: f64,
    /// Interval between probe samples (0: every step); the probes record on their own, this
    /// is for the estimate of their memory.
    pub probe_interval: f64,
    /// Most steps the run may take (0: no limit); reaching it before `end_time` stops the run
    /// with [`sph_core::Error::StepLimitReached`], everything written kept.
    pub max_steps: u64,
}

/// The output fields a run writes: each offered by the solver, none twice; checked before the
/// run (a bad list found only at the first snapshot would cost the run).
fn check_fields<D: Dim>(solver: &dyn Solver<D>, fields: &[&str]) -> Result<(), DriverError> {
    let offered = solver.field_names();
    for (k, f) in fields.iter().enumerate() {
        if !offered.contains(f) {
            return Err(DriverError::InvalidValue {
                key: "fields".into(),
                value: format!("`{f}`"),
                allowed: format!("{} offers {}", solver.method(), offered.join(", ")),
            });
        }
        if fields[..k].contains(f) {
            return Err(DriverError::InvalidValue {
                key: "fields".into(),
                value: format!("`{f}` (given twice)"),
                allowed: "each field once".into(),
            });
        }
    }
    Ok(())
}

/// Runs `solver` to `schedule.end_time`. `meta` goes to `/meta`; `summarise` turns the record
/// and the solver's probes into the case's figures (merged over the standard ones). Returns the
/// record and the summary.
///
/// Before anything is written, the run is estimated and checked ([`crate::guard`]): an absurd
/// schedule or end time is an `Err` naming the parameter, and nothing is written. With
/// [`RunOptions::dry_run`] the driver stops there. Once the results file is started, nothing is
/// an `Err` any more: a failure mid-run (a blow-up, a write error) is recorded (status,
/// diagnostic), an interruption ([`RunOptions::interrupt`]) stops after the current step with
/// a last snapshot, and in every case the file is completed with everything computed; the
/// caller decides the exit status from `record.failure` and `record.interrupted`.
pub fn drive<D: Dim>(
    solver: &mut dyn Solver<D>,
    mut meta: Map<String, Json>,
    schedule: Schedule,
    fields: &[&str],
    options: &RunOptions,
    summarise: impl FnOnce(&dyn Solver<D>, &RunRecord) -> Map<String, Json>,
) -> Result<(RunRecord, Map<String, Json>), DriverError> {
    let started = Instant::now();
    check_compression(options)?;
    if let Some(comm) = &options.ranks {
        crate::ranks::check(solver, comm)?;
    }
    let comm = options.ranks.as_ref().filter(|c| c.size() > 1);
    let root = comm.is_none_or(|c| c.rank() == 0);
    if options.vtu && (options.output.is_none() || options.per_rank_output) {
        return Err(DriverError::InvalidValue {
            key: "vtu".into(),
            value: "on".into(),
            allowed: "off when no results file is written, or with per-rank output".into(),
        });
    }
    if options.per_rank_output && options.output.is_none() {
        return Err(DriverError::InvalidValue {
            key: "per_rank_output".into(),
            value: "on".into(),
            allowed: "off when no results file is written".into(),
        });
    }
    check_fields(solver, fields)?;
    check_probe_fields(solver, comm.is_some())?;
    // What the numbers mean, in the file itself (the user guide quotes the same sentences).
    meta.insert("units".into(), json!(conventions::UNITS));
    meta.insert("dimension".into(), json!(D::D));
    if D::D == 2 {
        meta.insert("per_unit_depth".into(), json!(conventions::PLANE_STRAIN));
    }
    meta.insert("reaction_forces".into(), json!(conventions::REACTIONS));
    meta.insert("probes".into(), json!(conventions::PROBES));
    let estimate = crate::guard::Estimate::of(solver, &schedule, fields, options);
    estimate.check(&schedule, options)?;
    if options.resume.is_none() {
        solver
            .check_time_step()
            .map_err(|e| DriverError::Config(format!("the run cannot take its first step: {e}: the initial velocities or loads are far faster than the material's sound speed (a very soft material?)")))?;
    }
    let mut record = RunRecord {
        particles: solver.len(),
        estimate: Some(estimate.clone()),
        ..Default::default()
    };
    if options.per_rank_output {
        // Part of the run's identity: a checkpoint of one layout cannot resume the other.
        meta.insert("output".into(), json!("per rank"));
    }
    let resumed = match &options.resume {
        Some(c) => Some(restore(solver, &meta, c)?),
        None => None,
    };
    if options.dry_run {
        let mut summary = estimate.to_json();
        summary.insert("case".into(), json!(meta_str(&meta, "case")));
        summary.insert("method".into(), json!(solver.method()));
        summary.insert(
            "status".into(),
            json!("dry run: checked and estimated; nothing run or written"),
        );
        return Ok((record, summary));
    }
    // Held for the run: a second run checkpointing to the same file fails at once. Taken
    // here, after every check, so a refused run creates no directory.
    let _checkpoint_lock = match &options.checkpoint {
        Some(plan) => {
            if let Some(dir) = plan.path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(|e| DriverError::Io {
                    path: dir.display().to_string(),
                    source: e,
                })?;
            }
            Some(sph_output::safety::OutputLock::acquire(&plan.path)?)
        }
        None => None,
    };
    let mut writer: Option<Box<dyn ResultWriter>> = match &options.output {
        Some(path) if !root => Some(Box::new(crate::ranks::Discard(path.clone()))),
        Some(path) => {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir).map_err(|e| DriverError::Io {
                    path: dir.display().to_string(),
                    source: e,
                })?;
            }
            let mut w = create_writer_with(path, options.backend, options.compression)?;
            w.write_meta(&meta)?;
            if !options.per_rank_output {
                for snap in resumed.iter().flat_map(|d| &d.snapshots) {
                    w.write_snapshot(snap.time, snap.step, &snap.datasets)?;
                }
            }
            Some(w)
        }
        None => None,
    };
    // Per-rank output: this rank's own file of snapshots, and on rank 0 what the XDMF file
    // presenting them as one body needs.
    // Per-frame VTU files and their collection (rank 0).
    let mut frames: Option<VtuSeries> = match &options.output {
        Some(path) if options.vtu && root => {
            let mut v = VtuSeries::create(path)?;
            for snap in resumed.iter().flat_map(|d| &d.snapshots) {
                v.write_frame(snap.time, snap.step, &snap.datasets)?;
            }
            Some(v)
        }
        _ => None,
    };
    let mut own: Option<crate::ranks::RankOutput> = match &options.output {
        Some(path) if options.per_rank_output => {
            let rank = comm.map_or(0, |c| c.rank());
            let mut o = crate::ranks::RankOutput::create(path, rank, &meta, options)?;
            for snap in resumed.iter().flat_map(|d| &d.snapshots) {
                o.write(snap.time, snap.step, &snap.datasets)?;
            }
            Some(o)
        }
        _ => None,
    };
    let interrupted = || {
        let sig = options
            .interrupt
            .as_ref()
            .map_or(0, |f| f.load(std::sync::atomic::Ordering::SeqCst));
        // All ranks stop at the same point, on the first signal any of them got.
        comm.map_or(sig, |c| c.max(sig as f64) as usize)
    };
    let report = |solver: &dyn Solver<D>, record: &RunRecord, finished: bool| {
        if let Some(sink) = &options.progress {
            (sink.0)(&Progress {
                time: solver.time(),
                end_time: schedule.end_time,
                steps: solver.step_count(),
                particles: solver.len(),
                solver_seconds: record.solver_seconds,
                wall_seconds: started.elapsed().as_secs_f64(),
                finished,
            });
        }
    };
    let end = schedule.end_time;
    let eps = 1e-12 * end.max(1e-300);
    let mut next_snapshot = 0.0;
    let mut next_monitor = 0.0;
    let mut last_snapshot = f64::NEG_INFINITY;
    // Snapshots kept for the checkpoints (the results file is re-created from them on resume).
    let mut kept: Vec<SavedSnapshot> = Vec::new();
    if let Some(d) = resumed {
        (next_snapshot, next_monitor) = (d.next_snapshot, d.next_monitor);
        last_snapshot = d.last_snapshot;
        record.solver_seconds = d.solver_seconds;
        record.monitor = d.monitor;
        kept = d.snapshots;
    }
    let mut due = CheckpointClock::new(options.checkpoint.as_ref(), solver.time(), end);
    // The monitor's sample of the state the last steps ended in, taken by `steps_until`.
    let mut ahead: Option<MonitorSample> = None;
    loop {
        let t = solver.time();
        if t + eps >= next_monitor {
            record
                .monitor
                .push(ahead.take().unwrap_or_else(|| sample(solver)));
            next_monitor = next_event(t, schedule.monitor_interval, end);
        }
        if t + eps >= next_snapshot {
            let written = write_snapshot(own.as_mut(), writer.as_mut(), solver, fields);
            if let Some((result, sets)) = written {
                let result = result.and_then(|()| match frames.as_mut() {
                    Some(v) => v.write_frame(t, solver.step_count(), &sets),
                    None => Ok(()),
                });
                match result {
                    Err(e) => record.failure = Some(format!("writing the results: {e}")),
                    Ok(()) => {
                        last_snapshot = t;
                        // The checkpoint re-creates the results file: rank 0's, or with
                        // per-rank output each rank's.
                        if options.checkpoint.is_some() && (root || own.is_some()) {
                            kept.push(SavedSnapshot {
                                time: t,
                                step: solver.step_count(),
                                datasets: sets,
                            });
                        }
                    }
                }
            }
            next_snapshot = next_event(t, schedule.snapshot_interval, end);
        }
        if let Some(c) = comm {
            if !c.all(record.failure.is_none()) {
                record
                    .failure
                    .get_or_insert_with(|| "writing the results failed on another rank".into());
            }
        }
        if record.failure.is_some() {
            break;
        }
        if t + eps >= end {
            break;
        }
        let sig = interrupted();
        // A checkpoint when one is due, and on an interruption (the run can go on from there).
        // On several ranks: all write when one is due (a wall-time interval ends at
        // different steps on different ranks), so the ranks' checkpoints hold the same step.
        let due_now = options.checkpoint.is_some() && {
            let d = due.is_due(t);
            comm.map_or(d, |c| !c.all(!d))
        };
        if let Some(plan) = options.checkpoint.as_ref().filter(|_| sig != 0 || due_now) {
            let state = DriverState {
                next_snapshot,
                next_monitor,
                last_snapshot,
                solver_seconds: record.solver_seconds,
                monitor: record.monitor.clone(),
                snapshots: std::mem::take(&mut kept),
                pending_budgets: None,
            };
            let written = write_checkpoint(solver, plan, &meta, &state);
            kept = state.snapshots;
            if let Err(e) = written {
                record.failure = Some(format!("writing the checkpoint: {e}"));
                break;
            }
            due.written(t);
        }
        if sig != 0 {
            record.interrupted = Some(sig);
            break;
        }
        let target = next_snapshot.min(next_monitor).min(end);
        let t0 = Instant::now();
        // On several ranks a signal is acted on between these stretches, agreed above.
        let own_interrupt = options.interrupt.as_ref().filter(|_| comm.is_none());
        let limit = (schedule.max_steps > 0).then_some((schedule.max_steps, end));
        let (failed, sampled) =
            steps_until(solver, target, eps, own_interrupt, limit, next_monitor);
        // The solver's time is the steps' only, as when the sample was taken out here.
        let sampling = sampled.as_ref().map_or(Duration::ZERO, |s| s.1);
        ahead = sampled.map(|s| s.0);
        record.solver_seconds += t0.elapsed().saturating_sub(sampling).as_secs_f64();
        report(solver, &record, false);
        if let Some(e) = failed {
            record.failure = Some(e.to_string());
            break;
        }
    }
    report(solver, &record, true);
    // Interrupted between snapshots: keep the state reached (it is a good one).
    if record.interrupted.is_some() && record.failure.is_none() && solver.time() > last_snapshot {
        let written = write_snapshot(own.as_mut(), writer.as_mut(), solver, fields);
        if let Some((result, sets)) = written {
            let result = result.and_then(|()| match frames.as_mut() {
                Some(v) => v.write_frame(solver.time(), solver.step_count(), &sets),
                None => Ok(()),
            });
            if let Err(e) = result {
                record.failure = Some(format!("writing the results: {e}"));
            }
        }
    }
    record.steps = solver.step_count();
    record.pair_visits = solver.pair_visits();
    record.time = solver.time();
    record.wall_seconds = started.elapsed().as_secs_f64();
    let mut summary = record.standard_summary(&meta_str(&meta, "case"), solver.method());
    if comm.is_some() || own.is_some() {
        summary.insert("ranks".into(), json!(comm.map_or(1, |c| c.size())));
    }
    if own.is_some() {
        summary.insert("output".into(), json!("per rank"));
    }
    for (k, v) in summarise(solver, &record) {
        summary.insert(k, v);
    }
    // Each rank completes its own file; rank 0 then presents them as one body.
    let mut collection = None;
    if let Some(o) = own {
        match o.complete(&summary) {
            Ok(c) => collection = Some(c),
            Err(e) => {
                record
                    .failure
                    .get_or_insert(format!("completing this rank's results: {e}"));
            }
        }
        if let Some(c) = comm {
            if !c.all(collection.is_some()) {
                record
                    .failure
                    .get_or_insert_with(|| "completing the results failed on another rank".into());
            }
        }
        summary.insert("status".into(), json!(record.status()));
    }
    if let Some(w) = writer {
        let temp = w.temp_path().to_path_buf();
        match complete::<D>(w, solver, &record.monitor, &summary) {
            Ok(file) => {
                if let (Some(c), Some(base)) = (collection.filter(|_| root), &options.output) {
                    let counts = solver
                        .owned_share()
                        .map_or_else(|| vec![solver.len()], |s| s.counts());
                    if let Err(e) = c.write(base, &counts) {
                        record
                            .failure
                            .get_or_insert(format!("writing the XDMF file: {e}"));
                        summary.insert("status".into(), json!(record.status()));
                    }
                }
                record.file = Some(file);
            }
            Err(e) => {
                let first = record.failure.take();
                record.failure = Some(format!(
                    "{}completing the results failed: {e} (what was written is in {})",
                    first.map(|f| format!("{f}; ")).unwrap_or_default(),
                    temp.display()
                ));
                summary.insert("status".into(), json!(record.status()));
            }
        }
    }
    if let Some(v) = frames {
        match v.finish() {
            Ok(pvd) => record.collection = Some(pvd),
            Err(e) => {
                record
                    .failure
                    .get_or_insert(format!("writing the VTU collection: {e}"));
                summary.insert("status".into(), json!(record.status()));
            }
        }
    }
    record.wall_seconds = started.elapsed().as_secs_f64();
    summary.insert("wall_seconds".into(), json!(record.wall_seconds));
    Ok((record, summary))
}

/// Checks that `checkpoint` belongs to this run (same `/meta`: case, method, parameters) and
/// restores the solver's state from it; returns the driver's state.
fn restore<D: Dim>(
    solver: &mut dyn Solver<D>,
    meta: &Map<String, Json>,
    checkpoint: &Checkpoint,
) -> Result<DriverState, DriverError> {
    let fail = |what: String| {
        DriverError::Config(format!("checkpoint {}: {what}", checkpoint.path.display()))
    };
    if serde_json::to_string(meta).unwrap_or_default() != checkpoint.meta_text {
        let differing: Vec<&str> = meta
            .keys()
            .chain(checkpoint.meta.keys())
            .filter(|k| meta.get(*k) != checkpoint.meta.get(*k))
            .map(String::as_str)
            .collect();
        return Err(fail(format!(
            "written by another run (case {} method {}); differs in {}",
            checkpoint.meta.get("case").unwrap_or(&Json::Null),
            checkpoint.meta.get("method").unwrap_or(&Json::Null),
            differing.join(", ")
        )));
    }
    let mut input = StateReader::new(&checkpoint.solver);
    solver
        .restore_state(&mut input)
        .map_err(|e| fail(e.to_string()))?;
    if !input.is_at_end() {
        return Err(fail("bytes left after the solver state".into()));
    }
    let mut driver = checkpoint.driver.clone();
    if let Some(pending) = driver.pending_budgets.take() {
        pending
            .resolve(solver.energy_budget(), &mut driver.monitor)
            .map_err(fail)?;
    }
    Ok(driver)
}

fn write_checkpoint<D: Dim>(
    solver: &dyn Solver<D>,
    plan: &CheckpointPlan,
    meta: &Map<String, Json>,
    state: &DriverState,
) -> Result<(), DriverError> {
    let mut out = StateWriter::new();
    solver.save_state(&mut out)?;
    checkpoint::write(&plan.path, &plan.run, meta, state, &out.into_bytes())
}

/// When the next checkpoint is due: after each interval of simulated time or of wall time.
struct CheckpointClock {
    every: Option<Every>,
    next_time: f64,
    end: f64,
    last_wall: Instant,
}

impl CheckpointClock {
    fn new(plan: Option<&CheckpointPlan>, t: f64, end: f64) -> Self {
        let every = plan.map(|p| p.every);
        let next_time = match every {
            Some(Every::SimulatedTime(dt)) => next_event(t, dt, f64::INFINITY),
            _ => f64::INFINITY,
        };
        Self {
            every,
            next_time,
            end,
            last_wall: Instant::now(),
        }
    }

    fn is_due(&self, t: f64) -> bool {
        match self.every {
            None => false,
            Some(Every::SimulatedTime(_)) => t + 1e-12 * self.end.max(1e-300) >= self.next_time,
            Some(Every::WallTime(d)) => self.last_wall.elapsed() >= d,
        }
    }

    fn written(&mut self, t: f64) {
        if let Some(Every::SimulatedTime(dt)) = self.every {
            self.next_time = next_event(t, dt, f64::INFINITY);
        }
        self.last_wall = Instant::now();
    }
}

/// The path of a run's default checkpoint: `<results>.ckpt`.
pub fn default_checkpoint_path(results_without_ext: &Path) -> std::path::PathBuf {
    let mut s = results_without_ext.as_os_str().to_os_string();
    s.push(".ckpt");
    s.into()
}

/// Steps `solver` until `target` (or an interruption, or an error), **on a worker thread of
/// the rayon pool**: every parallel loop of a step then starts on a pool thread, which runs its
/// share in place while the other workers steal the rest. Called from outside the pool, each
/// parallel loop would instead be handed from the caller's thread to the pool and back — two
/// context switches per loop, dozens per step, most of the run's time in the kernel on a small
/// body (measured: 22 voluntary context switches per step on the 2D plate).
///
/// The monitor's sample is also taken there (returned with the time it took) when the steps
/// end at or after `next_monitor` without an error (the loop of `drive` would take it next, on the
/// calling thread): its loops then follow the steps' on the same thread while the team's
/// helpers still spin, instead of waking parked helpers from another thread (on the twisting
/// column with two threads the calling thread did three quarters of the disorder indicator).
fn steps_until<D: Dim>(
    solver: &mut dyn Solver<D>,
    target: f64,
    eps: f64,
    interrupt: Option<&Interrupt>,
    limit: Option<(u64, f64)>,
    next_monitor: f64,
) -> (Option<sph_core::Error>, Option<(MonitorSample, Duration)>) {
    let interrupted =
        || interrupt.is_some_and(|f| f.load(std::sync::atomic::Ordering::SeqCst) != 0);
    let steps = |solver: &mut dyn Solver<D>| {
        while solver.time() + eps < target && !interrupted() {
            let before = solver.time();
            if let Some((limit, end)) = limit.filter(|&(l, _)| solver.step_count() >= l) {
                return Some(sph_core::Error::StepLimitReached {
                    limit,
                    time: before,
                    end,
                    mean_dt: before / solver.step_count().max(1) as f64,
                });
            }
            if let Err(e) = solver.step(target - before) {
                return Some(e);
            }
            // A step that does not advance time would repeat for ever.
            if solver.time().is_nan() || solver.time() <= before {
                return Some(sph_core::Error::TimeStepCollapsed {
                    dt: solver.time() - before,
                    min: 0.0,
                    step: solver.step_count(),
                    time: before,
                });
            }
        }
        None
    };
    let mut run = move || {
        let failed = steps(&mut *solver);
        let sample = (failed.is_none() && solver.time() + eps >= next_monitor).then(|| {
            let started = Instant::now();
            (sample(solver), started.elapsed())
        });
        (failed, sample)
    };
    if rayon::current_thread_index().is_some() {
        run()
    } else {
        // `join` called from outside the pool runs its first closure on a worker.
        rayon::join(run, || ()).0
    }
}

/// Writes the probes (with the fields sampled at them), the series and the summary and
/// finishes the file.
fn complete<D: Dim>(
    mut w: Box<dyn ResultWriter>,
    solver: &dyn Solver<D>,
    monitor: &[MonitorSample],
    summary: &Map<String, Json>,
) -> Result<PathBuf, sph_output::OutputError> {
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
    for (name, times, sets) in probe_field_datasets(solver, monitor) {
        w.write_probe_fields(&name, &times, &sets)?;
    }
    for s in solver.series() {
        let columns: Vec<(&str, &[f64])> = s
            .columns
            .iter()
            .zip(&s.values)
            .map(|(c, v)| (c.as_str(), v.as_slice()))
            .collect();
        w.write_series(&s.name, &s.time, &columns, &s.description)?;
    }
    w.write_summary(summary)?;
    w.finish()
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
        probe_fields: sample_probe_fields(solver),
    }
}

/// The output fields the probes ask for, sampled at them (each field computed once).
fn sample_probe_fields<D: Dim>(solver: &dyn Solver<D>) -> Vec<f64> {
    let mut computed: Vec<(&str, Option<Field<D>>)> = Vec::new();
    let mut out = Vec::new();
    for p in solver.probes() {
        for name in &p.fields {
            let k = match computed.iter().position(|(n, _)| n == name) {
                Some(k) => k,
                None => {
                    computed.push((name, solver.field(name)));
                    computed.len() - 1
                }
            };
            // Checked before the run ([`check_probe_fields`]): the solver offers it.
            if let Some(f) = &computed[k].1 {
                out.extend(p.sample_field(f));
            }
        }
    }
    out
}

/// Probe fields must be fields the solver offers, once per probe, and are not sampled on
/// several ranks (the probes hold a rank's local indices, the fields the whole body).
fn check_probe_fields<D: Dim>(
    solver: &dyn Solver<D>,
    distributed: bool,
) -> Result<(), DriverError> {
    let offered = solver.field_names();
    for p in solver.probes() {
        for (k, name) in p.fields.iter().enumerate() {
            let bad = |allowed: String| DriverError::InvalidValue {
                key: format!("probe `{}` field", p.name),
                value: name.clone(),
                allowed,
            };
            if !offered.contains(&name.as_str()) {
                return Err(bad(format!(
                    "a field of {}: {}",
                    solver.method(),
                    offered.join(", ")
                )));
            }
            if p.fields[..k].contains(name) {
                return Err(bad("each field once".into()));
            }
            if distributed {
                return Err(bad(
                    "no probe fields on more than one rank (not supported yet)".into(),
                ));
            }
        }
    }
    Ok(())
}

/// The probe fields of the monitor samples, per probe that has some: its name, the sample
/// times and one dataset per field (`[k]`, `[k, 3]` or `[k, 3, 3]` by the field's kind).
fn probe_field_datasets<D: Dim>(
    solver: &dyn Solver<D>,
    monitor: &[MonitorSample],
) -> Vec<(String, Vec<f64>, Vec<Dataset>)> {
    let width = |name: &str| match solver.field(name) {
        Some(Field::Vector(_)) => 3,
        Some(Field::Matrix(_)) => 9,
        _ => 1,
    };
    let probes: Vec<_> = solver
        .probes()
        .iter()
        .filter(|p| !p.fields.is_empty())
        .map(|p| (p.name.clone(), p.fields.clone()))
        .collect();
    let widths: Vec<Vec<usize>> = probes
        .iter()
        .map(|(_, f)| f.iter().map(|n| width(n)).collect())
        .collect();
    let total: usize = widths.iter().flatten().sum();
    // Samples taken with the probe fields (all of them, unless resumed from a checkpoint
    // written before the fields were recorded).
    let samples: Vec<&MonitorSample> = monitor
        .iter()
        .filter(|m| m.probe_fields.len() == total)
        .collect();
    let times: Vec<f64> = samples.iter().map(|m| m.time).collect();
    let mut offset = 0;
    let mut out = Vec::new();
    for ((name, fields), widths) in probes.iter().zip(&widths) {
        let mut sets = Vec::new();
        for (field, &w) in fields.iter().zip(widths) {
            let values: Vec<f64> = samples
                .iter()
                .flat_map(|m| m.probe_fields[offset..offset + w].iter().copied())
                .collect();
            sets.push(match w {
                1 => Dataset::scalars(field, &values),
                3 => Dataset::vectors(
                    field,
                    &values
                        .chunks_exact(3)
                        .map(|c| [c[0], c[1], c[2]])
                        .collect::<Vec<_>>(),
                ),
                _ => Dataset::matrices(
                    field,
                    &values
                        .chunks_exact(9)
                        .map(|c| [[c[0], c[1], c[2]], [c[3], c[4], c[5]], [c[6], c[7], c[8]]])
                        .collect::<Vec<_>>(),
                ),
            });
            offset += w;
        }
        out.push((name.clone(), times.clone(), sets));
    }
    out
}

/// A run of a scene built in Rust, with the `sph` command's defaults: an end time, snapshots
/// every `end_time/`[`DEFAULT_SNAPSHOTS`] (51 frames), monitor samples every `end_time/200`, the kinematic and stress fields
/// the solver offers, and (optionally) an HDF5 results file.
///
/// ```no_run
/// # use sph_driver::Run;
/// # fn demo(solver: &mut dyn sph_core::Solver<sph_core::D2>) -> Result<(), sph_driver::DriverError> {
/// let (record, summary) = Run::until(0.5)
///     .named("my-wall")
///     .snapshot_every(0.01)
///     .write_to("out/my-wall")
///     .execute(solver)?;
/// # Ok(()) }
/// ```
#[derive(Clone, Debug)]
pub struct Run {
    name: String,
    end_time: f64,
    snapshot_interval: Option<f64>,
    monitor_interval: Option<f64>,
    fields: Option<Vec<String>>,
    options: RunOptions,
}

/// The fields [`Run`] writes by default, where the solver offers them (`plastic_strain`:
/// plastic bodies only).
pub const DEFAULT_FIELDS: [&str; 7] = [
    "velocity",
    "displacement",
    "von_mises",
    "jacobian",
    "density",
    "disorder",
    "plastic_strain",
];

impl Run {
    /// A run to `end_time` (simulated seconds).
    pub fn until(end_time: f64) -> Self {
        Self {
            name: "scene".into(),
            end_time,
            snapshot_interval: None,
            monitor_interval: None,
            fields: None,
            options: RunOptions::default(),
        }
    }

    /// The scene's name in `/meta` and the summary.
    pub fn named(mut self, name: &str) -> Self {
        self.name = name.into();
        self
    }

    /// Snapshots every `dt` (0: the first and the last only).
    pub fn snapshot_every(mut self, dt: f64) -> Self {
        self.snapshot_interval = Some(dt);
        self
    }

    /// Monitor samples (disorder, energies) every `dt`.
    pub fn monitor_every(mut self, dt: f64) -> Self {
        self.monitor_interval = Some(dt);
        self
    }

    /// The fields written with every snapshot.
    pub fn fields(mut self, names: &[&str]) -> Self {
        self.fields = Some(names.iter().map(|s| s.to_string()).collect());
        self
    }

    /// Writes the results to `path` (`.h5` and `.xmf` are appended).
    pub fn write_to(mut self, path: impl Into<PathBuf>) -> Self {
        self.options.output = Some(path.into());
        self
    }

    /// Compresses the results file's datasets (shuffle + deflate at `level`, 1 fastest to 9
    /// smallest; both backends). A level outside 1..=9, or compression without
    /// [`Run::write_to`], is an error from [`Run::execute`].
    pub fn compress(mut self, level: u8) -> Self {
        self.options.compression = Compression::Deflate(level);
        self
    }

    /// Also writes every snapshot as a VTU file and their `.pvd` collection beside the results
    /// ([`RunOptions::vtu`]; needs [`Run::write_to`]).
    pub fn vtu(mut self) -> Self {
        self.options.vtu = true;
        self
    }

    /// Every other option of the driver.
    pub fn options(mut self, options: RunOptions) -> Self {
        self.options = options;
        self
    }

    /// Runs `solver` (see [`drive`]): the record and the standard summary.
    ///
    /// # Errors
    /// An end time or schedule the driver refuses ([`crate::guard`]), or an output that cannot
    /// be started. A failure mid-run is in `record.failure`, the results file completed.
    pub fn execute<D: Dim>(
        self,
        solver: &mut dyn Solver<D>,
    ) -> Result<(RunRecord, Map<String, Json>), DriverError> {
        if !(self.end_time.is_finite() && self.end_time > 0.0) {
            return Err(DriverError::InvalidValue {
                key: "end_time".into(),
                value: sph_core::error::Num(self.end_time).to_string(),
                allowed: "finite and > 0".into(),
            });
        }
        let schedule = Schedule {
            end_time: self.end_time,
            snapshot_interval: self
                .snapshot_interval
                .unwrap_or(self.end_time / f64::from(DEFAULT_SNAPSHOTS)),
            monitor_interval: self.monitor_interval.unwrap_or(self.end_time / 200.0),
            probe_interval: 0.0,
            max_steps: 0,
        };
        let offered = solver.field_names();
        let fields: Vec<String> = match self.fields {
            Some(f) => f,
            None => DEFAULT_FIELDS
                .iter()
                .filter(|f| offered.contains(f))
                .map(|f| f.to_string())
                .collect(),
        };
        let names: Vec<&str> = fields.iter().map(String::as_str).collect();
        let mut meta = Map::new();
        meta.insert("case".into(), json!(self.name));
        meta.insert("method".into(), json!(solver.method()));
        meta.insert("particles".into(), json!(solver.len()));
        meta.insert("crate_version".into(), json!(env!("CARGO_PKG_VERSION")));
        drive(solver, meta, schedule, &names, &self.options, |_, _| {
            Map::new()
        })
    }
}
