//! Costed runs: a case run as a user runs it (`sph run … --threads 2 --no-output`) in a child
//! process, with its CPU time, wall time and peak memory (from `wait4`), stored as JSON under
//! `validation/results/tradeoff/` and reused when the same run is asked for again.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::path::PathBuf;

/// Threads of every costed run (the machine has two cores).
pub const THREADS: usize = 2;

/// One costed run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CostedRun {
    /// Identifier (file stem).
    pub id: String,
    /// Case.
    pub case: String,
    /// Method.
    pub method: String,
    /// The `--set` assignments.
    pub set: Vec<String>,
    /// The command that reproduces this run.
    pub command: String,
    /// Exit code of `sph` (0 completed, 1 failed during the run, 2 rejected input).
    pub exit_code: i32,
    /// User + system CPU seconds of the child process.
    pub cpu_seconds: f64,
    /// Wall seconds.
    pub wall_seconds: f64,
    /// Peak resident memory of the child (MiB).
    pub max_rss_mib: f64,
    /// The run's summary without its monitor history (absent when the input was rejected).
    pub summary: Map<String, Value>,
    /// The first line `sph` printed on stderr when it did not complete.
    pub message: String,
}

impl CostedRun {
    /// A summary number.
    pub fn num(&self, key: &str) -> Option<f64> {
        self.summary.get(key).and_then(Value::as_f64)
    }

    /// The summary's status, `rejected: …` when the input was refused before the run.
    pub fn status(&self) -> String {
        match self.summary.get("status").and_then(Value::as_str) {
            Some(s) => s.to_string(),
            None if self.exit_code == 2 => format!("rejected: {}", self.message),
            None => format!("failed: {}", self.message),
        }
    }

    /// The machine-independent work of the run: the summary's `pair_visits` (neighbour pairs
    /// visited by all force evaluations).
    pub fn work(&self) -> Option<f64> {
        self.num("pair_visits")
    }
}

/// Directory of the stored costed runs.
pub fn dir() -> PathBuf {
    crate::store::results_dir().join("tradeoff")
}

/// The stored run `id`, if present.
pub fn load(id: &str) -> Option<CostedRun> {
    let text = std::fs::read_to_string(dir().join(format!("{id}.json"))).ok()?;
    serde_json::from_str(&text).ok()
}

/// The `sph` binary next to this one (both built by `cargo build --release`).
/// The steps `sph run <case> --method <method> --set … --dry-run` estimates for the run (its
/// `steps_estimate`: end time over the stable step of the initial state; for UL the acoustic
/// steps), or `None` if the dry run fails or gives none.
pub fn estimated_steps(case: &str, method: &str, set: &[String]) -> Option<f64> {
    let mut cmd = std::process::Command::new(sph_binary().ok()?);
    cmd.args(["run", case, "--method", method]);
    for s in set {
        cmd.args(["--set", s]);
    }
    let out = cmd.arg("--dry-run").output().ok()?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("steps_estimate"))
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|n| n.is_finite() && *n > 0.0)
}

pub(crate) fn sph_binary() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let sph = exe.with_file_name("sph");
    if sph.is_file() {
        Ok(sph)
    } else {
        Err(format!(
            "{} not found: build it first with `cargo build --release -p sph-cases --bin sph`",
            sph.display()
        ))
    }
}

/// Runs `sph run case --method method --set …` (2 threads, no output) unless `id` is stored
/// with the same arguments (or `force`); stores and returns it.
pub fn run_or_load(
    id: &str,
    case: &str,
    method: &str,
    set: &[String],
    force: bool,
) -> Result<CostedRun, String> {
    run_or_load_writing(id, case, method, set, false, THREADS, force)
}

/// [`run_or_load`] on `threads` threads; with `output` the run writes its HDF5 results
/// (snapshots, probes) under `target/tradeoff-output/<id>/` instead of `--no-output`, as a user
/// who keeps results runs it; the files are deleted after the run (only the cost is kept).
pub fn run_or_load_writing(
    id: &str,
    case: &str,
    method: &str,
    set: &[String],
    output: bool,
    threads: usize,
    force: bool,
) -> Result<CostedRun, String> {
    if !force {
        if let Some(r) = load(id) {
            if r.set == set
                && r.method == method
                && r.case == case
                && r.command.contains("--no-output") != output
                && r.command.contains(&format!("--threads {threads} "))
            {
                return Ok(r);
            }
        }
    }
    let not_selected = crate::store::filtered_out(id);
    if crate::store::plan_only() || not_selected {
        // `validate --plan tradeoff`: list the run (made by `validate tradeoff`, which times
        // it), do not make it. `validate --runs PREFIX tradeoff`: make only the selected runs.
        if !not_selected {
            let sets: String = set.iter().map(|s| format!(" --set {s}")).collect();
            let how = if output { "" } else { " --no-output" };
            println!("{id}\tsph run {case} --method {method}{sets} --threads {threads}{how}");
        }
        return Ok(CostedRun {
            id: id.into(),
            case: case.into(),
            method: method.into(),
            set: set.to_vec(),
            command: String::new(),
            exit_code: -1,
            cpu_seconds: f64::NAN,
            wall_seconds: f64::NAN,
            max_rss_mib: f64::NAN,
            summary: Map::new(),
            message: if not_selected {
                "not selected (--runs)".into()
            } else {
                "planned, not run".into()
            },
        });
    }
    let sph = sph_binary()?;
    std::fs::create_dir_all(dir()).map_err(|e| format!("{}: {e}", dir().display()))?;
    let summary_path = dir().join(format!("{id}.summary.tmp.json"));
    let _ = std::fs::remove_file(&summary_path);
    let mut args: Vec<String> = vec!["run".into(), case.into(), "--method".into(), method.into()];
    for s in set {
        args.push("--set".into());
        args.push(s.clone());
    }
    args.extend(["--threads".into(), threads.to_string()]);
    let out_dir = crate::workspace_root()
        .join("target")
        .join("tradeoff-output")
        .join(id);
    if output {
        let _ = std::fs::remove_dir_all(&out_dir);
        args.extend(["--out".into(), format!("target/tradeoff-output/{id}")]);
    } else {
        args.push("--no-output".into());
    }
    let command = format!("sph {}", args.join(" "));
    if output {
        // The command as recorded is relative to the workspace root; run it there too.
        args.pop();
        args.push(out_dir.display().to_string());
    }
    args.push("--summary".into());
    args.push(summary_path.display().to_string());
    eprintln!("running {id}: {command}");
    let costed = sph_cases::process::run_costed(&sph, &args, None)?;
    if output {
        let _ = std::fs::remove_dir_all(&out_dir);
    }
    let exit_code = costed.exit_code;
    // 130/143 (SIGINT/SIGTERM: `sph` stopped cleanly) or 128 + n (killed): the run was stopped
    // from outside, which says nothing about the method; not stored.
    if exit_code >= 128 {
        let _ = std::fs::remove_file(&summary_path);
        return Err(format!(
            "{id}: sph was stopped from outside (exit status {exit_code}); not stored"
        ));
    }
    let mut summary: Map<String, Value> = std::fs::read_to_string(&summary_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    let _ = std::fs::remove_file(&summary_path);
    summary.remove("monitor");
    let message = if exit_code == 0 {
        String::new()
    } else {
        costed.message()
    };
    let run = CostedRun {
        id: id.into(),
        case: case.into(),
        method: method.into(),
        set: set.to_vec(),
        command,
        exit_code,
        cpu_seconds: costed.cpu_seconds(),
        wall_seconds: costed.wall_seconds,
        max_rss_mib: costed.peak_bytes / (1u64 << 20) as f64,
        summary,
        message,
    };
    let path = dir().join(format!("{id}.json"));
    std::fs::write(&path, serde_json::to_string(&run).expect("serialises"))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(run)
}
