//! Checkpoint and restart (issue 14) against the `sph` command: a run resumed from a
//! checkpoint ends bit-identical to the run never interrupted (TL-HF, UL-ENOG with dual
//! stepping and particle reordering, MPS), writing checkpoints changes nothing in a run, a run
//! killed with SIGKILL resumes from its last checkpoint, and a bad checkpoint is refused
//! (rc 2, one line) before any work.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

#[path = "inputs/checkpoint.rs"]
mod inputs;
use inputs::{BAD_CHECKPOINTS, CHECKPOINT_REFUSED};

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
fn resumed_run_is_bit_identical(name: &str, case: &[&str], every: &str) -> PathBuf {
    let dir = scratch(name);
    if case[1].ends_with(".toml") {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes");
        std::fs::copy(scenes.join(case[1]), dir.join(case[1])).unwrap();
    }
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
    dir
}

#[test]
fn tl_hf_resumed_run_is_bit_identical() {
    let dir = resumed_run_is_bit_identical(
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
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn ul_enog_dual_stepping_resumed_run_is_bit_identical() {
    let dir = resumed_run_is_bit_identical(
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
    std::fs::remove_dir_all(dir).unwrap();
}

/// Two UL bodies in contact with the energy budget on: the resumed run carries the budget's
/// accumulated works, the momentum balance and the contact-force series (the summary's
/// `energy_residual*`, `momentum_balance` and `/series` compare equal).
#[test]
fn ul_contact_with_energy_budget_resumed_run_is_bit_identical() {
    let dir = resumed_run_is_bit_identical(
        "ul-contact",
        &[
            "run",
            "hertz-impact-3d",
            "--method",
            "ul-enog",
            "--set",
            "resolution=4",
            "--set",
            "snapshot_interval=0.004",
        ],
        "0.006",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Two TL bodies in contact (issue 43): the resumed run carries the contact-force series
/// `contact_force_<body>` (saved with the state only when the solver has contact).
#[test]
fn tl_contact_resumed_run_is_bit_identical() {
    let dir = resumed_run_is_bit_identical(
        "tl-contact",
        &[
            "run",
            "hertz-impact-3d",
            "--method",
            "tl-hf",
            "--set",
            "resolution=4",
            "--set",
            "snapshot_interval=0.004",
        ],
        "0.006",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn mps_resumed_run_is_bit_identical() {
    let dir = resumed_run_is_bit_identical(
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
        // Wall time: a checkpoint at every monitor sample.
        "1e-6s",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Bodies of two materials (examples/scenes/stiff_soft.toml, a stiffness ratio of 1000) in UL
/// and MPS: the resumed run puts the per-particle material ids back with the particles (UL
/// reorders them).
#[test]
fn several_materials_resumed_runs_are_bit_identical() {
    for method in ["ul-enog", "mps"] {
        let dir = resumed_run_is_bit_identical(
            &format!("materials-{method}"),
            &[
                "run",
                "stiff_soft.toml",
                "--method",
                method,
                "--set",
                "end_time=1.2e-3",
                "--set",
                "output.snapshot_interval=4e-4",
            ],
            "5e-4",
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}

/// The incline block with Coulomb friction in every family: the resumed run carries the
/// tools' meters, contact and sticking counts, their work on the body and their series (the
/// friction columns and the summary's `friction_work` compare equal).
#[test]
fn friction_resumed_runs_are_bit_identical_in_every_family() {
    for method in ["tl-hf", "ul-enog", "mps"] {
        let dir = resumed_run_is_bit_identical(
            &format!("friction-{method}"),
            &[
                "run",
                "incline-block",
                "--method",
                method,
                "--set",
                "resolution=4",
                "--set",
                "end_time=0.03",
                "--set",
                "ramp_time=0.01",
                "--set",
                "snapshot_interval=0.01",
            ],
            "0.012",
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}

/// The folding strip's watch (smallest gap, momentum and energy extremes, measured after every
/// step) travels with the checkpoint: resumed after the ends have met (12 ms at resolution 3),
/// the summary's `smallest_gap`, `energy_error` and the rest compare equal.
#[test]
fn a_folding_strip_resumes_with_its_watch_bit_identically() {
    let dir = resumed_run_is_bit_identical(
        "folding",
        &[
            "run",
            "folding-strip",
            "--method",
            "tl",
            "--set",
            "resolution=3",
            "--set",
            "end_time=0.016",
            "--set",
            "snapshot_interval=0.004",
        ],
        "0.0135",
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Issue 42: a scene run with overrides (a parameter, the method), probe fields and VTU frames
/// resumes bit-identically, with its overrides, and re-creates its frames and collection.
#[test]
fn a_scene_run_with_overrides_and_vtu_resumes_bit_identically() {
    let dir = resumed_run_is_bit_identical(
        "scene-set",
        &[
            "run",
            "pressurised_ring.toml",
            "--set",
            "settle=2",
            "--set",
            "load_time=5e-4",
            "--method",
            "tl",
            "--format",
            "vtu",
        ],
        "0.0004",
    );
    let pvd = std::fs::read_to_string(dir.join("ck/pressurised-ring-tl.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 51);
    let c = sph_driver::Checkpoint::load(&dir.join("run.ckpt")).unwrap();
    assert_eq!(c.run["overrides"][0], "method=tl");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A scene file's run resumes too; a scene file changed since the checkpoint is refused.
#[test]
fn a_scene_run_resumes_and_a_changed_scene_is_refused() {
    let dir = resumed_run_is_bit_identical("scene", &["run", "discs.toml"], "0.004");
    let scene = dir.join("discs.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, format!("{text}\n# edited\n")).unwrap();
    let before = listing(&dir);
    refused(
        &sph(&dir, &["resume", "run.ckpt"]),
        "has changed since the checkpoint was written",
        "an edited scene",
    );
    assert_eq!(listing(&dir), before);
    std::fs::remove_dir_all(dir).unwrap();
}

/// A run killed with SIGKILL after a checkpoint loses only what it computed since: resumed, it
/// ends bit-identical to the run never killed. A run stopped by SIGINT writes a checkpoint
/// where it stopped (rc 130), and resumes from there to the same end.
#[test]
#[cfg(unix)]
fn killed_and_interrupted_runs_resume_to_the_same_end() {
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
    ok(
        &sph(&dir, &with(&["--out", "plain"])),
        "the run never stopped",
    );
    let plain = contents(&results(&dir.join("plain")));
    let spawn = |more: &[&'static str]| {
        Command::new(env!("CARGO_BIN_EXE_sph"))
            .args(with(more))
            .current_dir(&dir)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    // A hang guard, not a timing assertion.
    let wait_for = |p: &Path| {
        let start = Instant::now();
        while !p.exists() {
            assert!(
                start.elapsed() < Duration::from_secs(120),
                "{}",
                p.display()
            );
            std::thread::sleep(Duration::from_millis(2));
        }
    };

    // SIGKILL right after the first checkpoint.
    let mut child = spawn(&[
        "--out",
        "killed",
        "--checkpoint-every",
        "0.005",
        "--checkpoint",
        "killed.ckpt",
    ]);
    wait_for(&dir.join("killed.ckpt"));
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "the run ended before the kill");
    assert!(!dir.join("killed/oscillating-plate-2d-tl-hf.h5").exists());
    let c = sph_driver::Checkpoint::load(&dir.join("killed.ckpt")).unwrap();
    let reached = c.driver.monitor.last().unwrap().time;
    assert!(reached > 0.0 && reached < 0.3, "{reached}");
    ok(
        &sph(&dir, &["resume", "killed.ckpt"]),
        "resume after SIGKILL",
    );
    assert_eq!(
        contents(&results(&dir.join("killed"))),
        plain,
        "after SIGKILL"
    );

    // SIGINT once the run is writing; no periodic checkpoint before the end.
    let mut child = spawn(&[
        "--out",
        "stopped",
        "--checkpoint-every",
        "1",
        "--checkpoint",
        "stopped.ckpt",
    ]);
    let start = Instant::now();
    while !std::fs::read_dir(dir.join("stopped"))
        .map(|d| d.count() > 0)
        .unwrap_or(false)
    {
        assert!(start.elapsed() < Duration::from_secs(120), "never wrote");
        std::thread::sleep(Duration::from_millis(2));
    }
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    assert_eq!(child.wait().unwrap().code(), Some(130), "SIGINT");
    let interrupted = sph_output::read_file(results(&dir.join("stopped"))).unwrap();
    assert!(interrupted.summary["status"]
        .as_str()
        .unwrap()
        .starts_with("interrupted at t = "));
    ok(
        &sph(&dir, &["resume", "stopped.ckpt"]),
        "resume after SIGINT",
    );
    assert_eq!(
        contents(&results(&dir.join("stopped"))),
        plain,
        "after SIGINT"
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
    for &(what, damage, needle) in BAD_CHECKPOINTS {
        let bytes = match damage {
            "missing" => None,
            "half" => Some(good[..good.len() / 2].to_vec()),
            "header" => Some(good[..20].to_vec()),
            "flip" => {
                let mut b = good.clone();
                b[good.len() / 2] ^= 0x10;
                Some(b)
            }
            "reserved" => {
                let mut b = good.clone();
                b[13] ^= 0x01;
                Some(b)
            }
            "version" => {
                let mut b = good.clone();
                b[8] = 99;
                Some(b)
            }
            "foreign" => Some(b"case = \"oscillating-plate-2d\"\n".to_vec()),
            "other-run" => {
                // The solver state of this run under the description of another resolution.
                std::fs::write(&ckpt, &good).unwrap();
                let c = sph_driver::Checkpoint::load(&ckpt).unwrap();
                let mut run = c.run.clone();
                for p in run["params"].as_array_mut().unwrap() {
                    if p.as_str().unwrap().starts_with("resolution=") {
                        *p = "resolution=5".into();
                    }
                }
                sph_driver::checkpoint::write(&ckpt, &run, &c.meta, &c.driver, &c.solver).unwrap();
                Some(std::fs::read(&ckpt).unwrap())
            }
            other => panic!("unknown damage {other}"),
        };
        match bytes {
            Some(b) => std::fs::write(&ckpt, b).unwrap(),
            None => std::fs::remove_file(&ckpt).unwrap(),
        }
        let before = listing(&dir);
        let out = sph(&dir, &["resume", "out/oscillating-plate-2d-tl-hf.ckpt"]);
        refused(&out, needle, what);
        assert_eq!(listing(&dir), before, "{what}: something was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Exit status 2, one line on stderr containing `needle`, nothing on stdout, no panic.
fn refused(out: &Output, needle: &str, what: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{what}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{what}: {err}");
    assert!(err.contains(needle), "{what}: `{needle}` not in {err}");
    assert!(
        !err.contains("panicked") && out.stdout.is_empty(),
        "{what}: {err}"
    );
}

/// Rows of `docs/reliability.md`: bad intervals and checkpoint destinations that are an input,
/// an output, a directory, a device or a file other than a checkpoint are refused before the
/// run (rc 2, one line); nothing is written.
#[test]
fn checkpoint_destinations_are_refused_before_the_run() {
    let dir = scratch("dest");
    std::fs::write(dir.join("cfg.toml"), "resolution = 4\nend_time = 0.002\n").unwrap();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    let base = [
        "run",
        "oscillating-plate-2d",
        "--method",
        "tl-hf",
        "--config",
        "cfg.toml",
        "--out",
        "out",
        "--summary",
        "s.json",
    ];
    ok(&sph(&dir, &base), "a first run (results and summary exist)");
    for &(what, args, needle) in CHECKPOINT_REFUSED {
        let before = listing(&dir);
        let all: Vec<&str> = base.iter().chain(args).copied().collect();
        refused(&sph(&dir, &all), needle, what);
        assert_eq!(listing(&dir), before, "{what}: something was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
