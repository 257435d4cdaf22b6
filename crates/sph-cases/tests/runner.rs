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
