//! Whole-run timings of benchmark scenes through the `sph` command, as a user runs them: wall,
//! user and system time and peak resident memory (of the child process), steps, particles and particle-steps per second,
//! each the median of `--repeats` runs (with the spread), at 1 and 2 threads. Writes
//! `benchmarks/results/case-timings.json`, which `perf-report` turns into the tables of
//! `docs/performance.md` (the anchor rows beside the recorded SPHinXsys reference).
//!
//! ```text
//! cargo build --release -p sph-cases --bin sph
//! cargo run --release -p sph-benchmarks --bin case-timings [-- --repeats 3] [--only anchors|extreme|impacts|memory]
//! cargo run --release -p sph-benchmarks --bin case-timings -- --sphinxsys DIR [--repeats 3]
//! ```
//! Time only on a quiet machine (no build, test or other run): the numbers are wall-clock.
//!
//! `--sphinxsys DIR` times the anchor rows beside SPHinXsys instead: `DIR` is a SPHinXsys build
//! with the three patched tests of `benchmarks/sphinxsys/`, and each round runs the SPHinXsys
//! test and then ours, so that both sides of a ratio see the same machine even when its speed
//! drifts. Writes `benchmarks/results/anchors-interleaved.json` (the per-round times and
//! ratios, with the date and build), which `perf-report` shows below the anchor table.

use serde_json::{json, Value};
use sph_benchmarks::scenes::{scenes, Scene};
use std::path::{Path, PathBuf};
use std::process::Command;

/// What one run of `sph` cost: wall, user and system seconds and its peak resident memory.
struct Cost {
    wall: f64,
    user: f64,
    system: f64,
    peak_rss_bytes: f64,
}

/// Runs `command` and measures it (`sph_cases::process::measure`: `wait4`, the child's own
/// resource usage).
fn run_measured(command: &mut Command) -> (std::process::ExitStatus, Cost) {
    use std::os::unix::process::ExitStatusExt;
    let c = sph_cases::process::measure(command).expect("run and wait for the command");
    let cost = Cost {
        wall: c.wall_seconds,
        user: c.user_seconds,
        system: c.system_seconds,
        peak_rss_bytes: c.peak_bytes,
    };
    let status = if c.exit_code >= 128 {
        std::process::ExitStatus::from_raw(c.exit_code - 128)
    } else {
        std::process::ExitStatus::from_raw(c.exit_code << 8)
    };
    (status, cost)
}

fn median_and_spread(mut v: Vec<f64>) -> Value {
    v.sort_by(f64::total_cmp);
    let median = v[v.len() / 2];
    json!({ "median": median, "min": v[0], "max": v[v.len() - 1], "all": v })
}

/// One run of our `sph` on `scene` (no output), its summary written to `summary`; exits with
/// an error if the run fails.
fn run_ours(sph: &Path, scene: &Scene, threads: usize, summary: &Path) -> Cost {
    let (status, cost) = run_measured(
        Command::new(sph)
            .arg("run")
            .args(&scene.args)
            .args(["--no-output", "--threads", &threads.to_string()])
            .arg("--summary")
            .arg(summary)
            .stdout(std::process::Stdio::null()),
    );
    if !status.success() {
        eprintln!("error: {} failed ({status})", scene.label);
        std::process::exit(1);
    }
    cost
}

/// One run of a SPHinXsys test with `threads` TBB threads, in a fresh directory `cwd` (the
/// library writes `output/`, `restart/`, `reload/` and a log there at start-up), removed after.
fn run_sphinxsys(binary: &Path, threads: usize, cwd: &Path) -> Cost {
    std::fs::create_dir_all(cwd).expect("scratch directory");
    let (status, cost) = run_measured(
        Command::new(binary)
            .current_dir(cwd)
            .env("SPHX_THREADS", threads.to_string())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null()),
    );
    let _ = std::fs::remove_dir_all(cwd);
    if !status.success() {
        eprintln!("error: {} failed ({status})", binary.display());
        std::process::exit(1);
    }
    cost
}

/// Writes `rows` into the results file `out` (`{"generated_by", "rows"}`), keeping its rows
/// whose `key` no new row has.
fn merge_rows(out: &Path, rows: Vec<Value>, key: impl Fn(&Value) -> String, generated_by: &str) {
    let mut all: Vec<Value> = std::fs::read_to_string(out)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|v| v.get("rows").and_then(Value::as_array).cloned())
        .unwrap_or_default();
    let fresh: Vec<String> = rows.iter().map(&key).collect();
    all.retain(|r| !fresh.contains(&key(r)));
    all.extend(rows);
    let doc = json!({ "generated_by": generated_by, "rows": all });
    std::fs::create_dir_all(out.parent().unwrap()).expect("results directory");
    std::fs::write(out, serde_json::to_string_pretty(&doc).unwrap()).expect("write results");
    println!("wrote {}", out.display());
}

/// The repository root above this binary (for the results directory).
fn repository_root(exe: &Path) -> PathBuf {
    exe.ancestors()
        .find(|p| p.join("Cargo.lock").exists())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// `--sphinxsys DIR`: each anchor row timed in rounds of (SPHinXsys, ours); the rows are added
/// to `benchmarks/results/anchors-interleaved.json` (a row of the same scene, threads, machine,
/// build and date is replaced).
fn interleaved(dir: &Path, sph: &Path, repeats: usize, scratch: &Path, root: &Path) {
    let anchors: Vec<(Scene, PathBuf)> = scenes()
        .into_iter()
        .filter_map(|s| {
            let binary = dir.join(s.sphinxsys?);
            Some((s, binary))
        })
        .collect();
    for (_, binary) in &anchors {
        if !binary.is_file() {
            eprintln!(
                "error: --sphinxsys: {} not found (a SPHinXsys build with the patched tests of \
                 benchmarks/sphinxsys/README.md)",
                binary.display()
            );
            std::process::exit(2);
        }
    }
    std::fs::create_dir_all(scratch).expect("scratch directory");
    let (date, build) = (sph_benchmarks::utc_date(), sph_benchmarks::build_name(root));
    let mut rows = Vec::new();
    for (scene, binary) in &anchors {
        for &threads in scene.threads {
            let mut rounds = Vec::new();
            let (mut theirs, mut ours, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
            for k in 0..repeats {
                let sx = run_sphinxsys(binary, threads, &scratch.join(format!("sphinxsys-{k}")));
                let me = run_ours(sph, scene, threads, &scratch.join(format!("s{k}.json")));
                let ratio = sx.wall / me.wall;
                eprintln!(
                    "{} ({threads} thread{}): round {}: SPHinXsys {:.2} s, ours {:.2} s, ratio {:.2}",
                    scene.label,
                    if threads == 1 { "" } else { "s" },
                    k + 1,
                    sx.wall,
                    me.wall,
                    ratio
                );
                rounds.push(json!({ "sphinxsys": sx.wall, "ours": me.wall, "ratio": ratio }));
                theirs.push(sx.wall);
                ours.push(me.wall);
                ratios.push(ratio);
            }
            rows.push(json!({
                "machine": sph_benchmarks::machine(),
                "date": date,
                "build": build,
                "label": scene.label,
                "threads": threads,
                "sphinxsys_test": scene.sphinxsys,
                "rounds": rounds,
                "sphinxsys_wall_seconds": median_and_spread(theirs),
                "wall_seconds": median_and_spread(ours),
                "ratio": median_and_spread(ratios),
            }));
        }
    }
    let out = root
        .join("benchmarks")
        .join("results")
        .join("anchors-interleaved.json");
    // A row is replaced by the same scene, threads, machine, build and date: the other days stay.
    let key = |r: &Value| {
        format!(
            "{}|{}|{}|{}|{}",
            r["label"], r["threads"], r["machine"], r["build"], r["date"]
        )
    };
    merge_rows(
        &out,
        rows,
        key,
        "cargo run --release -p sph-benchmarks --bin case-timings -- --sphinxsys DIR",
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    sph_benchmarks::check_flags(
        &args,
        &["--repeats", "--only", "--sphinxsys"],
        "usage: case-timings [--repeats N] [--only GROUP] [--sphinxsys DIR]",
    );
    let repeats: usize = match args.iter().position(|a| a == "--repeats") {
        None => 3,
        Some(k) => match args.get(k + 1).and_then(|v| v.parse().ok()) {
            Some(r) if r >= 1 => r,
            _ => {
                eprintln!("error: --repeats: a whole number of runs, at least 1");
                std::process::exit(2);
            }
        },
    };
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|k| args.get(k + 1))
        .cloned();
    let mut groups: Vec<&str> = scenes().iter().map(|s| s.group).collect();
    groups.dedup();
    if let Some(o) = only.as_deref().filter(|o| !groups.contains(o)) {
        eprintln!("error: --only {o}: one of {}", groups.join(", "));
        std::process::exit(2);
    }
    let exe = std::env::current_exe().expect("own path");
    let sph = exe.with_file_name("sph");
    if !sph.exists() {
        eprintln!(
            "error: {} not found: build it first (cargo build --release -p sph-cases --bin sph)",
            sph.display()
        );
        std::process::exit(2);
    }
    let scratch = std::env::temp_dir().join(format!("sph-case-timings-{}", std::process::id()));
    let root = repository_root(&exe);
    if let Some(dir) = args
        .iter()
        .position(|a| a == "--sphinxsys")
        .and_then(|k| args.get(k + 1))
        .map(PathBuf::from)
    {
        // `check_flags` refused `--sphinxsys` without its directory.
        if only.as_deref().is_some_and(|o| o != "anchors") {
            eprintln!("error: --sphinxsys times the anchor rows only (--only anchors or none)");
            std::process::exit(2);
        }
        interleaved(&dir, &sph, repeats, &scratch, &root);
        let _ = std::fs::remove_dir_all(&scratch);
        return;
    }
    std::fs::create_dir_all(&scratch).expect("scratch directory");
    let mut rows = Vec::new();
    for scene in scenes() {
        if only.as_deref().is_some_and(|o| o != scene.group) {
            continue;
        }
        for &threads in scene.threads {
            let (mut wall, mut user, mut sys, mut rss) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            let mut summary = Value::Null;
            for k in 0..repeats {
                let path: PathBuf = scratch.join(format!("s{k}.json"));
                let cost = run_ours(&sph, &scene, threads, &path);
                eprintln!(
                    "{} ({threads} thread{}): run {}: {:.2} s wall, {:.2} s user, {:.2} s sys, \
                     {:.0} MB peak",
                    scene.label,
                    if threads == 1 { "" } else { "s" },
                    k + 1,
                    cost.wall,
                    cost.user,
                    cost.system,
                    cost.peak_rss_bytes / 1e6
                );
                wall.push(cost.wall);
                user.push(cost.user);
                sys.push(cost.system);
                rss.push(cost.peak_rss_bytes);
                summary = serde_json::from_str(&std::fs::read_to_string(&path).unwrap())
                    .expect("summary JSON");
            }
            let pick = |k: &str| summary.get(k).cloned().unwrap_or(Value::Null);
            let command = format!(
                "sph run {} --threads {threads} --no-output",
                scene.args.join(" ")
            );
            rows.push(json!({
                "machine": sph_benchmarks::machine(),
                "group": scene.group,
                "label": scene.label,
                "command": command,
                "threads": threads,
                "repeats": repeats,
                "wall_seconds": median_and_spread(wall),
                "user_seconds": median_and_spread(user),
                "system_seconds": median_and_spread(sys),
                "peak_rss_bytes": median_and_spread(rss),
                "particles": pick("particles"),
                "steps": pick("steps"),
                "acoustic_steps": pick("acoustic_steps"),
                "solver_seconds": pick("solver_seconds"),
                "particle_steps_per_second": pick("particle_steps_per_second"),
            }));
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let out = root
        .join("benchmarks")
        .join("results")
        .join("case-timings.json");
    // The rows of groups not run this time stay. A row is replaced only by the same scene, thread count and machine: the rows of another
    // machine stay (each beside the SPHinXsys time of its own machine in the report).
    let key = |r: &Value| {
        format!(
            "{}|{}|{}",
            r["label"],
            r["threads"],
            r["machine"]
                .as_str()
                .unwrap_or(sph_benchmarks::EARLIER_MACHINE)
        )
    };
    merge_rows(
        &out,
        rows,
        key,
        "cargo run --release -p sph-benchmarks --bin case-timings",
    );
}
