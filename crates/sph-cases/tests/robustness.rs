//! Issue 14's reproductions against the `sph` command, at small sizes, with the behaviour each
//! must now have: the exit status, one line on stderr, no file written or replaced, no panic.
//! Every input class (the tables of `inputs/run.rs` and `inputs/checkpoint.rs`) is one row of
//! `docs/reliability.md`, which [`reliability_doc_is_current`] renders from the same tables the
//! tests run; regenerate it with
//!
//! ```text
//! SPH_UPDATE_DOCS=1 cargo test -p sph-cases --test robustness reliability_doc_is_current
//! ```
//!
//! Waits for a background run poll for its files with a generous cap (a hang guard, not a
//! timing assertion).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

#[path = "inputs/checkpoint.rs"]
mod checkpoint_inputs;
#[path = "inputs/run.rs"]
mod run_inputs;
use run_inputs::{
    extreme_inputs, malformed_inputs, ABSURD_VALUES, BAD_SCHEDULES, BLOW_UPS, CLOSED_PIPES,
    GOOD_SCHEDULES, RESULTS_REFUSED, SUMMARY_REFUSED, TOO_LARGE,
};
// Only counted here (the rows of `docs/reliability.md`); `hostile.rs` runs them.
#[allow(dead_code)]
#[path = "inputs/hostile.rs"]
mod hostile_inputs;
#[path = "inputs/reliability_doc.rs"]
mod reliability_doc;
use reliability_doc::render_doc;

// ------------------------------------------------------------------------------------ helpers

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn finished(out: Output) -> Run {
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into(),
        stderr: String::from_utf8_lossy(&out.stderr).into(),
    }
}

/// Runs `sph args` in `dir`.
fn sph(dir: &Path, args: &[&str]) -> Run {
    finished(
        Command::new(env!("CARGO_BIN_EXE_sph"))
            .args(args)
            .current_dir(dir)
            .output()
            .expect("run sph"),
    )
}

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn sph")
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-robust-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// What a directory holds (recursively): name → kind and content, to prove nothing changed.
fn listing(dir: &Path) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return m;
    };
    for e in entries {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        let t = std::fs::symlink_metadata(e.path()).unwrap().file_type();
        let what = if t.is_symlink() {
            format!("link {}", std::fs::read_link(e.path()).unwrap().display())
        } else if t.is_dir() {
            for (k, v) in listing(&e.path()) {
                m.insert(format!("{name}/{k}"), v);
            }
            "dir".into()
        } else if t.is_file() {
            format!("file {:?}", std::fs::read(e.path()).unwrap())
        } else {
            "special".into()
        };
        m.insert(name, what);
    }
    m
}

/// Exit status 2, one line on stderr containing `needle`, nothing on stdout, no panic.
fn assert_refused(r: &Run, needle: &str, what: &str) {
    assert_eq!(r.code, Some(2), "{what}: {}", r.stderr);
    assert!(!r.stderr.contains("panicked"), "{what}: {}", r.stderr);
    assert_eq!(r.stderr.trim().lines().count(), 1, "{what}: {}", r.stderr);
    assert!(
        r.stderr.contains(needle),
        "{what}: `{needle}` not in {}",
        r.stderr
    );
    assert!(r.stdout.is_empty(), "{what}: {}", r.stdout);
}

/// Temporary or lock files anywhere under `dir`.
fn leftovers(dir: &Path) -> Vec<String> {
    listing(dir)
        .into_keys()
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".lock"))
        .collect()
}

/// Polls until `path` exists and holds text (a hang guard of 120 s, not a timing assertion).
fn wait_for_text(path: &Path) -> String {
    let start = Instant::now();
    loop {
        if let Ok(t) = std::fs::read_to_string(path) {
            if !t.trim().is_empty() {
                return t;
            }
        }
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Polls until the run `child` has started writing into `out` (its own temporary file exists,
/// so it holds the results' lock): the writer takes the lock first and releases it only when
/// the file is complete.
fn wait_until_writing(out: &Path, child: &Child) {
    let mark = format!(".{}-", child.id());
    let start = Instant::now();
    while !listing(out)
        .keys()
        .any(|n| n.ends_with(".tmp") && n.contains(&mark))
    {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the run never started writing"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[cfg(unix)]
fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill")
        .args([&format!("-{sig}"), &child.id().to_string()])
        .status()
        .expect("kill")
        .success();
    assert!(ok, "kill -{sig}");
}

/// A small TL plate run that takes a second or so (or, with a long end time, until stopped).
const PLATE: &[&str] = &[
    "run",
    "oscillating-plate-2d",
    "--method",
    "tl",
    "--set",
    "resolution=4",
];

fn with<'a>(base: &[&'a str], more: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(more).copied().collect()
}

// --------------------------------------------------------------------------------- the tests

/// Item 1: every refused `--summary` destination is refused before the run, with one line,
/// and leaves the directory (and the device, FIFO or link) exactly as it was; an earlier
/// summary and a new file are written.
#[test]
#[cfg(unix)]
fn summary_destinations_are_refused_before_the_run() {
    let dir = scratch("summary");
    std::fs::write(dir.join("cfg.toml"), "resolution = 4\nend_time = 0.005\n").unwrap();
    std::fs::write(
        dir.join("old.json"),
        "{\"case\": \"x\", \"status\": \"completed\"}",
    )
    .unwrap();
    std::fs::write(dir.join("notes.txt"), "my notes").unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    std::os::unix::fs::symlink("old.json", dir.join("link.json")).unwrap();
    assert!(Command::new("mkfifo")
        .arg(dir.join("fifo"))
        .status()
        .unwrap()
        .success());
    let before = listing(&dir);
    for &(what, path, needle) in SUMMARY_REFUSED {
        let r = sph(
            &dir,
            &with(
                PLATE,
                &["--config", "cfg.toml", "--out", "out", "--summary", path],
            ),
        );
        assert_refused(&r, needle, what);
        assert!(r.stderr.contains("--summary"), "{what}: {}", r.stderr);
        assert_eq!(listing(&dir), before, "{what}: the directory changed");
    }
    let kinds = |p: &str| std::fs::symlink_metadata(p).unwrap().file_type();
    use std::os::unix::fs::FileTypeExt;
    assert!(kinds("/dev/full").is_char_device() && kinds("/dev/null").is_char_device());
    // The accepted ones: an earlier summary is replaced, a new directory is created.
    for path in ["old.json", "new/s.json"] {
        let r = sph(
            &dir,
            &with(
                PLATE,
                &["--config", "cfg.toml", "--out", "out", "--summary", path],
            ),
        );
        assert_eq!(r.code, Some(0), "{path}: {}", r.stderr);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join(path)).unwrap()).unwrap();
        assert_eq!(s["status"], "completed");
    }
    assert_eq!(
        std::fs::read_link(dir.join("link.json")).unwrap(),
        Path::new("old.json")
    );
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 1: result destinations that are not a writable directory, or whose `.h5`/`.xmf` a
/// run did not write, are refused before the run; nothing is written or replaced.
#[test]
#[cfg(unix)]
fn results_destinations_are_refused_before_the_run() {
    for &(what, setup, needle) in RESULTS_REFUSED {
        let dir = scratch(&format!("results-{setup}"));
        let out_dir = dir.join("out");
        let h5 = out_dir.join("oscillating-plate-2d-tl.h5");
        let xmf = out_dir.join("oscillating-plate-2d-tl.xmf");
        let mut out = "out".to_string();
        match setup {
            "out-file" => std::fs::write(&out_dir, "a file").unwrap(),
            "out-proc" => out = "/proc/sph-results".into(),
            "h5-text" => {
                std::fs::create_dir(&out_dir).unwrap();
                std::fs::write(&h5, "my notes").unwrap();
            }
            "h5-link" => {
                std::fs::create_dir(&out_dir).unwrap();
                std::fs::write(dir.join("precious"), "keep").unwrap();
                std::os::unix::fs::symlink(dir.join("precious"), &h5).unwrap();
            }
            "h5-fifo" => {
                std::fs::create_dir(&out_dir).unwrap();
                assert!(Command::new("mkfifo").arg(&h5).status().unwrap().success());
            }
            "xmf-dir" => std::fs::create_dir_all(&xmf).unwrap(),
            other => unreachable!("{other}"),
        }
        let before = listing(&dir);
        let r = sph(
            &dir,
            &with(PLATE, &["--set", "end_time=0.005", "--out", &out]),
        );
        assert_refused(&r, needle, what);
        assert_eq!(listing(&dir), before, "{what}: something changed");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Item 2: a second run into the results of a running one fails at once naming the first
/// (before, both wrote `<name>.h5.tmp` and 3 of 3 trials lost a run or mismatched the
/// sidecar); the first run's files stay complete and consistent.
#[test]
#[cfg(unix)]
fn a_second_run_into_the_same_results_fails_fast() {
    let dir = scratch("second");
    let first = spawn(
        &dir,
        &with(PLATE, &["--set", "end_time=1000", "--out", "out"]),
    );
    wait_until_writing(&dir.join("out"), &first);
    let holder = wait_for_text(&dir.join("out/oscillating-plate-2d-tl.h5.lock"));
    assert_eq!(holder.trim(), first.id().to_string());
    let r = sph(
        &dir,
        &with(PLATE, &["--set", "end_time=0.005", "--out", "out"]),
    );
    assert_refused(
        &r,
        &format!(
            "another run (process {}) is writing these results",
            first.id()
        ),
        "second run",
    );
    signal(&first, "TERM");
    let first = finished(first.wait_with_output().unwrap());
    assert_eq!(first.code, Some(143), "{}", first.stderr);
    let file = sph_output::read_file(dir.join("out/oscillating-plate-2d-tl.h5")).unwrap();
    let xmf = std::fs::read_to_string(dir.join("out/oscillating-plate-2d-tl.xmf")).unwrap();
    assert_eq!(
        xmf.matches("TopologyType=\"Polyvertex\"").count(),
        file.snapshots.len(),
        "the sidecar lists the file's snapshots"
    );
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 2 (and the SIGKILL remark of item 6): a run killed with SIGKILL leaves its lock file
/// and its own `.tmp`; the next run of the same results takes the (dead) lock, completes, and
/// leaves the killed run's partial file, a valid HDF5 file, alone.
#[test]
#[cfg(unix)]
fn a_run_after_a_killed_run_reuses_its_lock_and_keeps_its_partial_file() {
    let dir = scratch("killed");
    let mut first = spawn(
        &dir,
        &with(PLATE, &["--set", "end_time=1000", "--out", "out"]),
    );
    wait_until_writing(&dir.join("out"), &first);
    first.kill().unwrap();
    first.wait().unwrap();
    let partial: Vec<String> = leftovers(&dir)
        .into_iter()
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert_eq!(partial.len(), 1, "{partial:?}");
    let partial = dir.join(&partial[0]);
    let kept = std::fs::read(&partial).unwrap();
    assert!(sph_output::read_file(&partial).unwrap().snapshots.len() <= 1);
    let r = sph(
        &dir,
        &with(PLATE, &["--set", "end_time=0.005", "--out", "out"]),
    );
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_eq!(std::fs::read(&partial).unwrap(), kept);
    assert!(!dir.join("out/oscillating-plate-2d-tl.h5.lock").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Items 3 and 4: particle counts beyond the memory limit stop before allocating (before: a
/// capacity-overflow panic, rc 101; an allocation abort, rc 134; 50 s of allocation), with
/// one line giving the estimate and the limit; `--max-memory` moves the limit both ways.
#[test]
fn particle_counts_beyond_the_memory_limit_are_refused_before_allocating() {
    let dir = scratch("budget");
    for &(what, args, needle) in TOO_LARGE {
        let r = sph(&dir, &with(args, &["--out", "out", "--summary", "s.json"]));
        assert_refused(&r, needle, what);
        if needle.contains("generate") {
            assert!(
                r.stderr.contains("particles needing ≈"),
                "{what}: {}",
                r.stderr
            );
        }
    }
    let column = [
        "run",
        "bending-column-3d",
        "--set",
        "resolution=20",
        "--dry-run",
    ];
    let r = sph(&dir, &with(&column, &["--max-memory", "0.1"]));
    assert_refused(&r, "would generate ≈ ", "column in 0.1 GiB");
    let r = sph(&dir, &with(&column, &["--max-memory", "1"]));
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stdout.contains("49200"), "{}", r.stdout);
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 5: snapshot and monitor counts, end times and thread counts beyond their limits are
/// refused before the run (before: a full disk, or runs that never end); probes recording
/// every step are refused when they would not fit in memory; the disk estimate names
/// `snapshot_interval`; values at the limits are accepted.
#[test]
fn absurd_schedules_end_times_and_threads_are_refused() {
    let dir = scratch("schedules");
    let plate = ["run", "oscillating-plate-2d", "--out", "out"];
    for &(what, args, needle) in BAD_SCHEDULES {
        let r = sph(&dir, &with(&plate, args));
        assert_refused(&r, needle, what);
    }
    let r = sph(
        &dir,
        &[
            "run",
            "pressurised-ring-2d",
            "--set",
            "probe_interval=0",
            "--max-memory",
            "0.05",
            "--out",
            "out",
        ],
    );
    assert_refused(
        &r,
        "invalid probe_interval = 0.0: 16 probes record",
        "probes",
    );
    for &(what, args) in GOOD_SCHEDULES {
        let r = sph(&dir, &with(&with(&plate, args), &["--dry-run"]));
        assert_eq!(r.code, Some(0), "{what}: {}", r.stderr);
        assert!(r.stdout.contains("dry run"), "{what}: {}", r.stdout);
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // The disk estimate, in-process: snapshots larger than any disk.
    let schedule = sph_cases::Schedule {
        end_time: 1.0,
        snapshot_interval: 0.01,
        monitor_interval: 0.005,
        probe_interval: 0.0,
        max_steps: 0,
    };
    let estimate = sph_cases::guard::Estimate {
        particles: 1000,
        memory_bytes: 3e6,
        step: 1e-3,
        steps: 1000.0,
        particle_steps: 1e6,
        snapshots: 102.0,
        snapshot_bytes: 1e18,
        monitor_samples: 202.0,
        probes: 0,
        probe_bytes: 0.0,
    };
    let options = sph_cases::RunOptions {
        output: Some(dir.join("out/x")),
        ..Default::default()
    };
    let e = estimate.check(&schedule, &options).unwrap_err().to_string();
    assert!(
        e.starts_with("invalid snapshot_interval = 0.01: 102 snapshots of ")
            && e.contains("free in"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 6: SIGINT and SIGTERM no longer kill the run at once (before: an orphan `.h5.tmp`, no
/// status, no summary): the current step is finished, a last snapshot written, the file
/// completed with the status `interrupted at t = …`, the summary written, exit 130 / 143.
#[test]
#[cfg(unix)]
fn sigint_and_sigterm_finish_the_step_and_complete_the_results() {
    for (sig, code, name) in [("INT", 130, "SIGINT"), ("TERM", 143, "SIGTERM")] {
        let dir = scratch(&format!("signal-{sig}"));
        let child = spawn(
            &dir,
            &with(
                PLATE,
                &[
                    "--set",
                    "end_time=1000",
                    "--out",
                    "out",
                    "--summary",
                    "s.json",
                ],
            ),
        );
        wait_until_writing(&dir.join("out"), &child);
        signal(&child, sig);
        let r = finished(child.wait_with_output().unwrap());
        assert_eq!(r.code, Some(code), "{}", r.stderr);
        assert_eq!(r.stderr.trim().lines().count(), 1, "{}", r.stderr);
        assert!(r.stderr.contains(&format!("({name})")), "{}", r.stderr);
        let file = sph_output::read_file(dir.join("out/oscillating-plate-2d-tl.h5")).unwrap();
        let status = file.summary["status"].as_str().unwrap();
        assert!(
            status.starts_with("interrupted at t = ") && status.ends_with(&format!("({name})")),
            "{status}"
        );
        let reached = file.summary["time_reached"].as_f64().unwrap();
        assert_eq!(file.snapshots.last().unwrap().time, reached);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
        assert_eq!(s["status"], status);
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Item 7: values that were silently accepted are refused, naming the key and the range.
#[test]
fn silently_accepted_values_are_refused() {
    let dir = scratch("absurd");
    std::fs::write(dir.join("method.toml"), "method = \"tl\"\n").unwrap();
    let before = listing(&dir);
    for &(what, args, needle) in ABSURD_VALUES {
        let r = sph(&dir, &with(args, &["--out", "out"]));
        assert_refused(&r, needle, what);
    }
    assert_eq!(listing(&dir), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Item 8: a run that blows up stops with a diagnostic (exit 1, one line) and keeps everything
/// written: the `.h5` is completed with the snapshots before the failure and `status: failed:
/// …`, the summary is written.
#[test]
fn blow_ups_stop_with_a_diagnostic_and_keep_the_results() {
    for (k, &(what, args, needle)) in BLOW_UPS.iter().enumerate() {
        let dir = scratch(&format!("blowup-{k}"));
        let mut a = vec!["run"];
        a.extend_from_slice(args);
        a.extend_from_slice(&[
            "--set",
            "resolution=4",
            "--set",
            "end_time=0.05",
            "--out",
            "out",
            "--summary",
            "s.json",
        ]);
        let r = sph(&dir, &a);
        assert_eq!(r.code, Some(1), "{what}: {}", r.stderr);
        assert_eq!(r.stderr.trim().lines().count(), 1, "{what}: {}", r.stderr);
        assert!(
            r.stderr.contains("the run stopped early: "),
            "{what}: {}",
            r.stderr
        );
        assert!(r.stderr.contains(needle), "{what}: {}", r.stderr);
        let h5 = listing(&dir.join("out"))
            .into_keys()
            .find(|n| n.ends_with(".h5"))
            .expect("results");
        let file = sph_output::read_file(dir.join("out").join(h5)).unwrap();
        let status = file.summary["status"].as_str().unwrap();
        assert!(status.starts_with("failed: "), "{what}: {status}");
        assert!(!file.snapshots.is_empty());
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("s.json")).unwrap()).unwrap();
        assert_eq!(s["status"], status);
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Item 9: a reader that closes the pipe before `sph` writes is not an error (before:
/// `sph list --verbose | head -1` panicked, rc 101).
#[test]
fn a_closed_stdout_is_not_an_error() {
    let dir = scratch("pipe");
    for &(what, args) in CLOSED_PIPES {
        let mut child = spawn(&dir, args);
        drop(child.stdout.take());
        let r = finished(child.wait_with_output().unwrap());
        assert_eq!(r.code, Some(0), "{what}: {}", r.stderr);
        assert!(r.stderr.is_empty(), "{what}: {}", r.stderr);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every key of every case refuses malformed values with one line naming it; nothing is
/// written.
#[test]
fn malformed_values_of_every_key_are_refused() {
    let dir = scratch("malformed");
    for (case, key, value) in malformed_inputs() {
        let r = sph(
            &dir,
            &[
                "run",
                &case,
                "--set",
                &format!("{key}={value}"),
                "--out",
                "out",
            ],
        );
        assert_refused(
            &r,
            &format!("invalid {key} = {value}"),
            &format!("{case} {key}"),
        );
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every numeric key of every case (one method per family), set to `1e300`, `1e-300`, `0` or
/// `-1`, is either accepted or refused with one line, never a panic, an abort or a hang, and
/// nothing is written (`--dry-run` builds the scene and makes every check without running it; a 1 GiB
/// limit keeps the scenes small). Two threads share the inputs.
#[test]
fn extreme_values_of_every_key_never_crash() {
    let dir = scratch("extreme");
    let inputs = extreme_inputs();
    let (accepted, refused) = std::thread::scope(|s| {
        let workers: Vec<_> = inputs
            .chunks(inputs.len().div_ceil(2))
            .map(|chunk| {
                let dir = &dir;
                s.spawn(move || {
                    let (mut ok, mut no) = (0, 0);
                    for (case, method, key, value) in chunk {
                        let r = sph(
                            dir,
                            &[
                                "run",
                                case,
                                "--method",
                                method,
                                "--set",
                                &format!("{key}={value}"),
                                "--dry-run",
                                "--max-memory",
                                "1",
                                "--out",
                                "out",
                                "--summary",
                                "s.json",
                            ],
                        );
                        let what = format!("{case} {method} {key}={value}");
                        match r.code {
                            Some(0) => ok += 1,
                            Some(2) => {
                                assert_eq!(
                                    r.stderr.trim().lines().count(),
                                    1,
                                    "{what}: {}",
                                    r.stderr
                                );
                                no += 1;
                            }
                            other => panic!("{what}: exit {other:?}: {}", r.stderr),
                        }
                        assert!(!r.stderr.contains("panicked"), "{what}: {}", r.stderr);
                    }
                    (ok, no)
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().unwrap())
            .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    });
    assert_eq!(accepted + refused, inputs.len());
    assert!(refused > accepted, "{accepted} accepted, {refused} refused");
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

// ------------------------------------------------------------------------ docs/reliability.md

/// `docs/reliability.md` is what [`render_doc`] makes of the tables above (with
/// `SPH_UPDATE_DOCS=1`, writes it).
#[test]
fn reliability_doc_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/reliability.md");
    let doc = render_doc();
    if std::env::var_os("SPH_UPDATE_DOCS").is_some() {
        std::fs::write(&path, &doc).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == doc,
        "docs/reliability.md is out of date; regenerate it with \
         `SPH_UPDATE_DOCS=1 cargo test -p sph-cases --test robustness reliability_doc_is_current`"
    );
}
