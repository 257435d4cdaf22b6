//! The run driver keeps what was computed when a run fails mid-way: the results file is
//! completed with the snapshots up to the failure and the diagnostic in its summary.

use glam::DVec2;
use serde_json::Map;
use sph_cases::runner::{drive, RunOptions, Schedule};
use sph_core::{Error, Field, Probe, Solver, StepInfo, D2};

/// A solver that moves a particle at unit speed and fails at `fail_at` steps.
struct Failing {
    x: Vec<DVec2>,
    v: Vec<DVec2>,
    t: f64,
    n: u64,
    fail_at: u64,
}

impl Solver<D2> for Failing {
    fn method(&self) -> &'static str {
        "failing"
    }
    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        if self.n == self.fail_at {
            return Err(Error::NonFinite {
                field: "velocity".into(),
                particle: 0,
                step: self.n,
                time: self.t,
            });
        }
        let dt = self.stable_dt().min(max_dt);
        self.x[0] += self.v[0] * dt;
        self.t += dt;
        self.n += 1;
        Ok(StepInfo {
            dt,
            time: self.t,
            step: self.n,
        })
    }
    fn stable_dt(&self) -> f64 {
        0.01
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn step_count(&self) -> u64 {
        self.n
    }
    fn positions(&self) -> &[DVec2] {
        &self.x
    }
    fn velocities(&self) -> &[DVec2] {
        &self.v
    }
    fn field_names(&self) -> Vec<&'static str> {
        vec!["disorder"]
    }
    fn field(&self, name: &str) -> Option<Field<D2>> {
        (name == "disorder").then(|| Field::Scalar(vec![0.0; self.x.len()]))
    }
    fn probes(&self) -> &[Probe<D2>] {
        &[]
    }
}

#[test]
fn a_failure_mid_run_completes_the_file_with_the_diagnostic() {
    let dir = std::env::temp_dir().join(format!("sph-runner-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut s = Failing {
        x: vec![DVec2::ZERO, DVec2::ONE],
        v: vec![DVec2::X, DVec2::ZERO],
        t: 0.0,
        n: 0,
        fail_at: 25,
    };
    let mut meta = Map::new();
    meta.insert("case".into(), "failing".into());
    let options = RunOptions {
        output: Some(dir.join("f")),
        ..Default::default()
    };
    let schedule = Schedule {
        end_time: 1.0,
        snapshot_interval: 0.1,
        monitor_interval: 0.05,
        probe_interval: 0.0,
        max_steps: 0,
    };
    let (record, summary) = drive::<D2>(&mut s, meta, schedule, &["disorder"], &options, |_, _| {
        Map::new()
    })
    .unwrap();
    assert_eq!(record.steps, 25);
    assert!(record
        .failure
        .as_deref()
        .unwrap()
        .contains("non-finite velocity"));
    let status = summary["status"].as_str().unwrap();
    assert!(
        status.starts_with("failed: non-finite velocity"),
        "{status}"
    );
    let file = sph_output::read_file(dir.join("f.h5")).unwrap();
    // Snapshots at t = 0, 0.1, 0.2 were written before the failure at t = 0.25.
    assert_eq!(file.snapshots.len(), 3);
    let last = &file.snapshots[2];
    assert!((last.time - 0.2).abs() < 1e-12);
    assert_eq!(file.summary["status"], summary["status"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The driver checks the interrupt flag between steps: a signal during step 10 lets that step
/// finish, then the run stops with a last snapshot at the time reached and the status
/// `interrupted at t = …`, and the file is completed.
#[test]
fn an_interrupt_stops_after_the_current_step_and_completes_the_file() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    struct Signalled {
        inner: Failing,
        flag: Arc<AtomicUsize>,
    }
    impl Solver<D2> for Signalled {
        fn method(&self) -> &'static str {
            "signalled"
        }
        fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
            let info = self.inner.step(max_dt)?;
            if info.step == 10 {
                self.flag.store(2, Ordering::SeqCst);
            }
            Ok(info)
        }
        fn stable_dt(&self) -> f64 {
            self.inner.stable_dt()
        }
        fn time(&self) -> f64 {
            self.inner.time()
        }
        fn step_count(&self) -> u64 {
            self.inner.step_count()
        }
        fn positions(&self) -> &[DVec2] {
            self.inner.positions()
        }
        fn velocities(&self) -> &[DVec2] {
            self.inner.velocities()
        }
        fn field_names(&self) -> Vec<&'static str> {
            self.inner.field_names()
        }
        fn field(&self, name: &str) -> Option<Field<D2>> {
            self.inner.field(name)
        }
        fn probes(&self) -> &[Probe<D2>] {
            &[]
        }
    }
    let dir = std::env::temp_dir().join(format!("sph-runner-int-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let flag = Arc::new(AtomicUsize::new(0));
    let mut s = Signalled {
        inner: Failing {
            x: vec![DVec2::ZERO, DVec2::ONE],
            v: vec![DVec2::X, DVec2::ZERO],
            t: 0.0,
            n: 0,
            fail_at: u64::MAX,
        },
        flag: flag.clone(),
    };
    let mut meta = Map::new();
    meta.insert("case".into(), "signalled".into());
    let options = RunOptions {
        output: Some(dir.join("f")),
        interrupt: Some(flag),
        ..Default::default()
    };
    let schedule = Schedule {
        end_time: 1.0,
        snapshot_interval: 0.25,
        monitor_interval: 0.05,
        probe_interval: 0.0,
        max_steps: 0,
    };
    let (record, summary) = drive::<D2>(&mut s, meta, schedule, &["disorder"], &options, |_, _| {
        Map::new()
    })
    .unwrap();
    assert_eq!(record.steps, 10);
    assert_eq!(record.interrupted, Some(2));
    assert!(record.failure.is_none());
    let status = summary["status"].as_str().unwrap();
    assert_eq!(
        status,
        format!("interrupted at t = {} s (SIGINT)", record.time)
    );
    assert!((record.time - 0.1).abs() < 1e-12, "{}", record.time);
    let file = sph_output::read_file(dir.join("f.h5")).unwrap();
    // The snapshot at t = 0 and the last one where the run stopped.
    assert_eq!(file.snapshots.len(), 2);
    assert!((file.snapshots[1].time - record.time).abs() < 1e-15);
    assert_eq!(file.summary["status"], summary["status"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A dry run builds nothing on disk and returns the estimates.
#[test]
fn a_dry_run_estimates_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("sph-runner-dry-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut s = Failing {
        x: vec![DVec2::ZERO, DVec2::ONE],
        v: vec![DVec2::X, DVec2::ZERO],
        t: 0.0,
        n: 0,
        fail_at: u64::MAX,
    };
    let options = RunOptions {
        output: Some(dir.join("f")),
        dry_run: true,
        ..Default::default()
    };
    let schedule = Schedule {
        end_time: 1.0,
        snapshot_interval: 0.1,
        monitor_interval: 0.05,
        probe_interval: 0.0,
        max_steps: 0,
    };
    let (record, summary) = drive::<D2>(
        &mut s,
        Map::new(),
        schedule,
        &["disorder"],
        &options,
        |_, _| Map::new(),
    )
    .unwrap();
    assert_eq!(record.steps, 0);
    let e = record.estimate.unwrap();
    // 1/0.01 steps, plus the 12 snapshot and 22 monitor events that may cut one short.
    assert_eq!(
        (e.steps, e.snapshots, e.monitor_samples),
        (134.0, 12.0, 22.0)
    );
    assert_eq!(summary["particles"], 2);
    assert!(!dir.exists());
}

/// A solver whose step returns without advancing time (a zero step) stops the run as collapsed
/// instead of looping for ever in the driver.
#[test]
fn a_step_that_does_not_advance_time_stops_the_run() {
    struct Stuck(Failing);
    impl Solver<D2> for Stuck {
        fn method(&self) -> &'static str {
            "stuck"
        }
        fn step(&mut self, _max_dt: f64) -> Result<StepInfo, Error> {
            self.0.n += 1;
            Ok(StepInfo {
                dt: 0.0,
                time: self.0.t,
                step: self.0.n,
            })
        }
        fn stable_dt(&self) -> f64 {
            0.01
        }
        fn time(&self) -> f64 {
            self.0.t
        }
        fn step_count(&self) -> u64 {
            self.0.n
        }
        fn positions(&self) -> &[DVec2] {
            &self.0.x
        }
        fn velocities(&self) -> &[DVec2] {
            &self.0.v
        }
        fn field_names(&self) -> Vec<&'static str> {
            vec![]
        }
        fn field(&self, _name: &str) -> Option<Field<D2>> {
            None
        }
        fn probes(&self) -> &[Probe<D2>] {
            &[]
        }
    }
    let mut s = Stuck(Failing {
        x: vec![DVec2::ZERO],
        v: vec![DVec2::ZERO],
        t: 0.0,
        n: 0,
        fail_at: u64::MAX,
    });
    let schedule = Schedule {
        end_time: 1.0,
        snapshot_interval: 0.0,
        monitor_interval: 0.5,
        probe_interval: 0.0,
        max_steps: 0,
    };
    let (record, _) = drive::<D2>(
        &mut s,
        Map::new(),
        schedule,
        &[],
        &RunOptions::default(),
        |_, _| Map::new(),
    )
    .unwrap();
    assert_eq!(record.steps, 1);
    assert!(record.failure.unwrap().contains("time step 0e0 fell below"));
}
