//! What the run driver checks before a run starts, once the scene is built and nothing is
//! written yet: an estimate of the work, the output and the memory of the run, against limits.
//! Each failed check is one line naming the parameter, the estimate and what is allowed.
//!
//! | estimate | limit | parameter named |
//! |---|---|---|
//! | snapshots `end_time/snapshot_interval + 2` | [`MAX_SNAPSHOTS`] | `snapshot_interval` |
//! | their size on disk | the free space of the output directory | `snapshot_interval` |
//! | monitor samples `end_time/monitor_interval` | [`MAX_MONITOR_SAMPLES`] | `monitor_interval` |
//! | probe memory (samples × probes × 56 B) | the memory budget left by the particles | `probe_interval` |
//! | particle-steps (particles × `end_time/Δt`) | [`MAX_PARTICLE_STEPS`] unless confirmed | `end_time` |
//! | steps `end_time/Δt` | [`MAX_STEPS`], always | `end_time` |
//! | with checkpoints: the snapshots they carry, in memory and in the checkpoint file | the memory left by the particles and probes; twice the file in the free space of its directory | `--checkpoint-every` |
//!
//! `Δt` is [`Solver::substep_dt`] of the initial state (for UL's dual stepping the acoustic
//! sub-step), so a run that speeds up later takes more steps than estimated: the estimate is
//! for catching absurd inputs (`end_time = 1e300`, `snapshot_interval = 1e-300`), not a
//! schedule. The particle count itself was checked by the generators (`sph_core::budget`).

use crate::error::DriverError;
use crate::run::{RunOptions, Schedule};
use serde_json::{json, Map, Value as Json};
use sph_core::budget::{self, format_bytes, format_count};
use sph_core::{Dim, Field, Solver};

/// An upper bound of the solver state per particle in a checkpoint: the largest, UL in 3D,
/// writes 37 numbers of 8 bytes (296 B); TL 27, MPS 30.
pub const STATE_BYTES_PER_PARTICLE: f64 = 400.0;

/// Most snapshots a run may write.
pub const MAX_SNAPSHOTS: f64 = 100_000.0;
/// Most monitor samples (disorder and energies) a run may take.
pub const MAX_MONITOR_SAMPLES: f64 = 1_000_000.0;
/// Most particle-steps a run may take without [`RunOptions::allow_long_run`]: about a day at
/// the 10⁷ particle-steps per second of a 2-core desktop.
pub const MAX_PARTICLE_STEPS: f64 = 1e12;
/// Most steps a run may take at all: beyond, `t + Δt` no longer resolves the step in `f64`.
pub const MAX_STEPS: f64 = 1e15;
/// HDF5 bookkeeping per snapshot group, bytes (on top of the data).
const SNAPSHOT_OVERHEAD: f64 = 4096.0;
/// Bytes per probe sample: time, position and velocity as three `f64` each (3D-padded).
const PROBE_SAMPLE_BYTES: f64 = 56.0;

/// The estimates of a run, made before it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// Particles.
    pub particles: usize,
    /// Estimated peak memory of the particles (`sph_core::budget::bytes_per_particle`).
    pub memory_bytes: f64,
    /// The step the work is counted in ([`Solver::substep_dt`] at the start).
    pub step: f64,
    /// Steps to the end time (plus one per output event that cuts a step short).
    pub steps: f64,
    /// Particles × steps.
    pub particle_steps: f64,
    /// Snapshots written (0 without output).
    pub snapshots: f64,
    /// Bytes of one snapshot on disk.
    pub snapshot_bytes: f64,
    /// Monitor samples.
    pub monitor_samples: f64,
    /// Probes attached by the scene.
    pub probes: usize,
    /// Bytes the probes record over the run.
    pub probe_bytes: f64,
}

impl Estimate {
    /// Estimates `solver`'s run to `schedule.end_time`, writing `fields` with every snapshot
    /// (evaluated once here, on the initial state, for their size).
    pub fn of<D: Dim>(
        solver: &dyn Solver<D>,
        schedule: &Schedule,
        fields: &[&str],
        options: &RunOptions,
    ) -> Self {
        let n = solver.len();
        let end = schedule.end_time;
        let step = solver.substep_dt();
        let events = |interval: f64| {
            if interval > 0.0 {
                (end / interval).floor() + 2.0
            } else {
                2.0
            }
        };
        let snapshots = if options.output.is_some() {
            events(schedule.snapshot_interval)
        } else {
            0.0
        };
        let monitor_samples = events(schedule.monitor_interval);
        let steps = end / step + snapshots + monitor_samples;
        // `position` (3 f64) and `id` (u64) per particle, then the fields.
        let mut snapshot_bytes = SNAPSHOT_OVERHEAD + 32.0 * n as f64;
        if options.output.is_some() {
            for &name in fields {
                snapshot_bytes += match solver.field(name) {
                    Some(Field::Scalar(v)) => 8.0 * v.len() as f64,
                    Some(Field::Vector(v)) => 24.0 * v.len() as f64,
                    Some(Field::Matrix(v)) => 72.0 * v.len() as f64,
                    None => 0.0,
                };
            }
        }
        let probes = solver.probes().len();
        let probe_samples = if schedule.probe_interval > 0.0 {
            (end / schedule.probe_interval + 1.0).min(steps)
        } else {
            steps
        };
        Estimate {
            particles: n,
            memory_bytes: n as f64 * budget::bytes_per_particle::<D>() as f64,
            step,
            steps,
            particle_steps: n as f64 * steps,
            snapshots,
            snapshot_bytes,
            monitor_samples,
            probes,
            probe_bytes: probes as f64 * probe_samples * PROBE_SAMPLE_BYTES,
        }
    }

    /// Checks the estimates against the limits (see the module documentation); the first that
    /// fails is the error.
    pub fn check(&self, schedule: &Schedule, options: &RunOptions) -> Result<(), DriverError> {
        let end = schedule.end_time;
        let bad = |key: &str, value: f64, allowed: String| {
            Err(DriverError::InvalidValue {
                key: key.into(),
                value: format!("{value:?}"),
                allowed,
            })
        };
        if self.snapshots > MAX_SNAPSHOTS {
            return bad(
                "snapshot_interval",
                schedule.snapshot_interval,
                format!(
                    "gives {} snapshots, more than {}; allowed: snapshot_interval >= {:.3e} \
                     (end_time/{})",
                    format_count(self.snapshots),
                    format_count(MAX_SNAPSHOTS),
                    end / (MAX_SNAPSHOTS - 2.0),
                    format_count(MAX_SNAPSHOTS - 2.0)
                ),
            );
        }
        if let Some(dir) = options.output.as_deref().and_then(|p| p.parent()) {
            let disk = self.snapshots * self.snapshot_bytes;
            if let Some(free) = sph_output::safety::free_space(dir) {
                if disk > free as f64 {
                    let fit = (free as f64 / self.snapshot_bytes).floor() - 2.0;
                    return bad(
                        "snapshot_interval",
                        schedule.snapshot_interval,
                        format!(
                            "{} snapshots of {} need ≈ {}, more than the {} free in {}; \
                             allowed: snapshot_interval >= {:.3e} (an interval >= end_time = \
                             {:?} writes the first and last only)",
                            format_count(self.snapshots),
                            format_bytes(self.snapshot_bytes),
                            format_bytes(disk),
                            format_bytes(free as f64),
                            dir.display(),
                            if fit >= 1.0 { end / fit } else { end },
                            end
                        ),
                    );
                }
            }
        }
        if self.monitor_samples > MAX_MONITOR_SAMPLES {
            return bad(
                "monitor_interval",
                schedule.monitor_interval,
                format!(
                    "gives {} monitor samples, more than {}; allowed: monitor_interval >= {:.3e} \
                     (end_time/{}), or 0 for end_time/200",
                    format_count(self.monitor_samples),
                    format_count(MAX_MONITOR_SAMPLES),
                    end / (MAX_MONITOR_SAMPLES - 2.0),
                    format_count(MAX_MONITOR_SAMPLES - 2.0)
                ),
            );
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(DriverError::Config(format!(
                "the initial state gives a time step of {:e} s: an initial speed or load far \
                 beyond the sound speed (the run would stop at once as collapsed)",
                self.step
            )));
        }
        let needs = format!(
            "end_time = {end:?} needs ≈ {} steps of Δt ≈ {:.3e} s (from the spacing, the CFL \
             number and the initial speeds)",
            format_count(self.steps),
            self.step
        );
        if self.steps > MAX_STEPS {
            return Err(DriverError::Config(format!(
                "{needs}, more than the {MAX_STEPS:e} after which the time variable no longer \
                 resolves the step; allowed: end_time <= {:.3e}",
                MAX_STEPS * self.step
            )));
        }
        if self.particle_steps > MAX_PARTICLE_STEPS && !options.allow_long_run {
            return Err(DriverError::Config(format!(
                "{needs} for {} particles, ≈ {:.1e} particle-steps, more than the \
                 {MAX_PARTICLE_STEPS:e} (about a day) a run may take unconfirmed: end_time <= \
                 {:.3e} runs as it is; pass --allow-long-run to run it anyway",
                format_count(self.particles as f64),
                self.particle_steps,
                MAX_PARTICLE_STEPS / self.particles.max(1) as f64 * self.step
            )));
        }
        if let Some(plan) = &options.checkpoint {
            self.check_checkpoints(plan)?;
        }
        if self.probes > 0 {
            let budget = budget::current();
            if let Some(limit) = budget.max_bytes {
                let left = limit as f64 - self.memory_bytes;
                if self.probe_bytes > left {
                    let per_sample = self.probes as f64 * PROBE_SAMPLE_BYTES;
                    let samples = (left.max(0.0) / per_sample).floor();
                    return bad(
                        "probe_interval",
                        schedule.probe_interval,
                        format!(
                            "{} record ≈ {} samples each, ≈ {}, more than the {} the memory \
                             limit ({}) leaves beside the particles; allowed: probe_interval \
                             >= {:.3e}",
                            if self.probes == 1 {
                                "1 probe".to_string()
                            } else {
                                format!("{} probes", self.probes)
                            },
                            format_count(self.probe_bytes / per_sample),
                            format_bytes(self.probe_bytes),
                            format_bytes(left.max(0.0)),
                            budget.origin,
                            if samples >= 1.0 { end / samples } else { end }
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// A run with checkpoints keeps every snapshot it writes in memory and in each checkpoint
    /// (so a resumed run re-creates its results whole): their size must fit in the memory the
    /// particles and probes leave, and twice the last checkpoint (the previous one stays until
    /// the new one is complete) in the free space of the checkpoint's directory.
    fn check_checkpoints(
        &self,
        plan: &crate::checkpoint::CheckpointPlan,
    ) -> Result<(), DriverError> {
        let kept = self.snapshots * self.snapshot_bytes;
        let budget = budget::current();
        let refuse = |what: String| {
            Err(DriverError::Config(format!(
                "--checkpoint-every: the checkpoints carry the {} snapshots of the run (≈ {}), \
                 {what}; write fewer snapshots (a larger snapshot_interval) or no checkpoints",
                format_count(self.snapshots),
                format_bytes(kept)
            )))
        };
        if let Some(limit) = budget.max_bytes {
            let left = limit as f64 - self.memory_bytes - self.probe_bytes;
            if kept > left {
                return refuse(format!(
                    "more than the {} the memory limit ({}) leaves beside the particles",
                    format_bytes(left.max(0.0)),
                    budget.origin
                ));
            }
        }
        let dir = match plan.path.parent().filter(|d| !d.as_os_str().is_empty()) {
            Some(d) => d.to_path_buf(),
            None => std::path::PathBuf::from("."),
        };
        if let Some(free) = sph_output::safety::free_space(&dir) {
            let need = 2.0 * (kept + STATE_BYTES_PER_PARTICLE * self.particles as f64);
            if need > free as f64 {
                return refuse(format!(
                    "and two checkpoints need ≈ {}, more than the {} free in {}",
                    format_bytes(need),
                    format_bytes(free as f64),
                    dir.display()
                ));
            }
        }
        Ok(())
    }

    /// The estimates as summary figures (what `sph run --dry-run` prints).
    pub fn to_json(&self) -> Map<String, Json> {
        let mut m = Map::new();
        m.insert("particles".into(), json!(self.particles));
        m.insert(
            "memory_estimate".into(),
            json!(format_bytes(self.memory_bytes)),
        );
        m.insert(
            "memory_bytes_estimate".into(),
            json!(self.memory_bytes.round()),
        );
        m.insert("step_estimate".into(), json!(self.step));
        m.insert("steps_estimate".into(), json!(self.steps.round()));
        m.insert(
            "particle_steps_estimate".into(),
            json!(self.particle_steps.round()),
        );
        m.insert("snapshots_estimate".into(), json!(self.snapshots));
        m.insert(
            "disk_estimate".into(),
            json!(format_bytes(self.snapshots * self.snapshot_bytes)),
        );
        m.insert(
            "monitor_samples_estimate".into(),
            json!(self.monitor_samples),
        );
        m.insert(
            "probe_memory_estimate".into(),
            json!(format_bytes(self.probe_bytes)),
        );
        m
    }
}
