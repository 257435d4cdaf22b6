//! Checkpoint and restart (issue 14) against the `sph` command: a run resumed from a
//! checkpoint ends bit-identical to the run never interrupted (TL-HF, UL-ENOG with dual
//! stepping and particle reordering, MPS), writing checkpoints changes nothing in a run, a run
//! killed with SIGKILL resumes from its last checkpoint, and a bad checkpoint is refused
//! (rc 2, one line) before any work.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn sph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sph")
}

fn ok(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {:?} {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-ckpt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Everything in a results file that a run determines: meta, snapshots (every dataset), probes,
/// series and the summary without its wall-clock figures. `Debug` prints floats in their
/// shortest exact form, so equal text means equal bits.
fn contents(h5: &Path) -> String {
    let mut f = sph_output::read_file(h5).unwrap_or_else(|e| panic!("{}: {e}", h5.display()));
    for k in [
        "wall_seconds",
        "solver_seconds",
        "particle_steps_per_second",
    ] {
        assert!(f.summary.remove(k).is_some(), "summary has {k}");
    }
    format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n{:?}",
        f.meta, f.snapshots, f.probes, f.series, f.summary
    )
}

/// The run's results file in `out`.
fn results(out: &Path) -> PathBuf {
    let h5: Vec<PathBuf> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "h5"))
        .collect();
    assert_eq!(h5.len(), 1, "{h5:?}");
    h5[0].clone()
}

/// Runs `case` without checkpoints, then with them (same results), then resumes from the last
/// checkpoint of the second run (same results again, re-created whole).
fn resumed_run_is_bit_identical(name: &str, case: &[&str], every: &str) {
    let dir = scratch(name);
    let with = |more: &[&str]| -> Vec<String> {
        case.iter()
            .chain(["--threads", "2"].iter())
            .chain(more)
            .map(|s| s.to_string())
            .collect()
    };
    let run = |args: Vec<String>| sph(&dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    ok(&run(with(&["--out", "plain"])), "plain run");
    let plain = contents(&results(&dir.join("plain")));
    let ckpt = dir.join("run.ckpt");
    let args = ["--out", "ck", "--checkpoint-every", every, "--checkpoint"];
    let mut args = with(&args);
    args.push(ckpt.display().to_string());
    ok(&run(args), "run with checkpoints");
    assert_eq!(
        contents(&results(&dir.join("ck"))),
        plain,
        "{name}: checkpoints changed the run"
    );
    // The last checkpoint is from within the run, not its end.
    let c = sph_driver::Checkpoint::load(&ckpt).unwrap();
    let t = c.driver.monitor.last().unwrap().time;
    assert!(t > 0.0 && !c.driver.snapshots.is_empty(), "{name}: t = {t}");
    std::fs::remove_file(results(&dir.join("ck"))).unwrap();
    ok(&sph(&dir, &["resume", "run.ckpt"]), "resume");
    assert_eq!(
        contents(&results(&dir.join("ck"))),
        plain,
        "{name}: the resumed run differs"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tl_hf_resumed_run_is_bit_identical() {
    resumed_run_is_bit_identical(
        "tl",
        &[
            "run",
            "oscillating-plate-2d",
            "--method",
            "tl-hf",
            "--set",
            "resolution=4",
            "--set",
            "end_time=0.02",
            "--set",
            "snapshot_interval=0.005",
        ],
        "0.0075",
    );
}

#[test]
fn ul_enog_dual_stepping_resumed_run_is_bit_identical() {
    resumed_run_is_bit_identical(
        "ul",
        &[
            "run",
            "oscillating-plate-2d",
            "--method",
            "ul-enog",
            "--set",
            "stepping=dual",
            "--set",
            "resolution=4",
            "--set",
            "end_time=0.02",
            "--set",
            "snapshot_interval=0.005",
        ],
        "0.0075",
    );
}

#[test]
fn mps_resumed_run_is_bit_identical() {
    resumed_run_is_bit_identical(
        "mps",
        &[
            "run",
            "pressurised-ring-2d",
            "--set",
            "dp=0.25",
            "--set",
            "end_time=0.002",
            "--set",
            "snapshot_interval=0.0005",
        ],
        "0.0007",
    );
}

/// A run killed with SIGKILL after a checkpoint loses only what it computed since: resumed, it
/// ends bit-identical to the run never killed.
#[test]
#[cfg(unix)]
fn a_run_killed_after_a_checkpoint_resumes_to_the_same_end() {
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("kill");
    let case = [
        "run",
        "oscillating-plate-2d",
        "--method",
        "tl-hf",
        "--set",
        "resolution=4",
        "--set",
        "end_time=0.3",
        "--set",
        "snapshot_interval=0.05",
        "--threads",
        "2",
    ];
    let with = |more: &[&'static str]| -> Vec<&str> { case.iter().chain(more).copied().collect() };
    let mut child = Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(with(&[
            "--out",
            "ck",
            "--checkpoint-every",
            "0.005",
            "--checkpoint",
            "run.ckpt",
        ]))
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // A hang guard, not a timing assertion.
    let start = Instant::now();
    while !dir.join("run.ckpt").exists() {
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "the run ended before the kill");
    assert!(!dir.join("ck/oscillating-plate-2d-tl-hf.h5").exists());
    let c = sph_driver::Checkpoint::load(&dir.join("run.ckpt")).unwrap();
    let reached = c.driver.monitor.last().unwrap().time;
    assert!(reached > 0.0 && reached < 0.3, "{reached}");
    ok(&sph(&dir, &["resume", "run.ckpt"]), "resume");
    ok(
        &sph(&dir, &with(&["--out", "plain"])),
        "the run never killed",
    );
    assert_eq!(
        contents(&results(&dir.join("ck"))),
        contents(&results(&dir.join("plain")))
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// What a directory holds, to prove a refused resume wrote nothing.
fn listing(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            for (k, v) in listing(&p) {
                m.insert(format!("{name}/{k}"), v);
            }
        } else {
            m.insert(name, std::fs::read(&p).unwrap());
        }
    }
    m
}

/// Rows of `docs/reliability.md` (see `robustness.rs`): a missing, truncated, corrupt,
/// foreign or other-version checkpoint, or one of another case's run, is refused with rc 2
/// and one line naming the file, before any work; nothing is written.
#[test]
fn bad_checkpoints_are_refused_before_any_work() {
    let dir = scratch("bad");
    let case = [
        "run",
        "oscillating-plate-2d",
        "--method",
        "tl-hf",
        "--set",
        "resolution=4",
        "--set",
        "end_time=0.01",
        "--out",
        "out",
        "--checkpoint-every",
        "0.004",
    ];
    ok(&sph(&dir, &case), "run");
    let ckpt = dir.join("out/oscillating-plate-2d-tl-hf.ckpt");
    let good = std::fs::read(&ckpt).unwrap();
    let refused = |bytes: Option<&[u8]>, needle: &str| {
        match bytes {
            Some(b) => std::fs::write(&ckpt, b).unwrap(),
            None => std::fs::remove_file(&ckpt).unwrap(),
        }
        let before = listing(&dir);
        let out = sph(&dir, &["resume", "out/oscillating-plate-2d-tl-hf.ckpt"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{needle}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            err.contains(needle) && !err.contains("panicked"),
            "{needle}: {err}"
        );
        assert!(out.stdout.is_empty());
        assert_eq!(listing(&dir), before, "{needle}: something was written");
    };
    refused(None, "cannot read it");
    refused(Some(&good[..good.len() / 2]), "truncated");
    refused(Some(&good[..20]), "truncated");
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x10;
    refused(Some(&flipped), "checksum");
    let mut version = good.clone();
    version[8] = 2;
    refused(Some(&version), "format version 2; this sph");
    refused(
        Some(b"case = \"oscillating-plate-2d\"\n"),
        "not an sph checkpoint",
    );
    // A checkpoint whose solver state belongs to another run: the parameters it records differ
    // from those of the run it describes.
    std::fs::write(&ckpt, &good).unwrap();
    let c = sph_driver::Checkpoint::load(&ckpt).unwrap();
    let mut run = c.run.clone();
    let params = run["params"].as_array_mut().unwrap();
    for p in params.iter_mut() {
        if p.as_str().unwrap().starts_with("resolution=") {
            *p = "resolution=5".into();
        }
    }
    sph_driver::checkpoint::write(&ckpt, &run, &c.meta, &c.driver, &c.solver).unwrap();
    let other = std::fs::read(&ckpt).unwrap();
    refused(Some(&other), "written by another run");
    std::fs::remove_dir_all(&dir).unwrap();
}
