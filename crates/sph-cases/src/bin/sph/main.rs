//! `sph`: list the benchmark cases and run one.
//!
//! ```text
//! sph list [--verbose]
//! sph run <case> [--method M] [--set key=value]... [--config case.toml] [--out DIR]
//!         [--summary FILE.json] [--backend pure|hdf5-metno] [--compress[=LEVEL]]
//!         [--threads N] [--no-output]
//!         [--max-memory GIB] [--allow-long-run] [--dry-run]
//!         [--checkpoint-every INTERVAL] [--checkpoint FILE]
//! sph resume <checkpoint> [--threads N] [--max-memory GIB] [--log-every SECONDS]
//! sph preview <scene.toml> --out DIR [--summary FILE.json] [--set key=value]...
//! ```
//! Exit status: 0 on success, 2 for bad input (one line on stderr; nothing is written), 1 when
//! the run failed mid-way (the results file is completed with what was computed, its summary
//! says why), 128 + the signal (130 for SIGINT, 143 for SIGTERM) when interrupted (the current
//! step is finished, the file completed with the status `interrupted at t = …`, the summary
//! written; a second signal ends the process at once). See `docs/reliability.md`.
//!
//! With `--checkpoint-every` a run writes its full state atomically to a checkpoint file
//! (`<out>/<case>-<method>.ckpt` unless `--checkpoint`), every interval and when a signal stops
//! it; `sph resume <checkpoint>` rebuilds the run it records, re-creates the results and
//! continues to the end time, ending bit-identical to the run never stopped. A missing,
//! damaged or foreign checkpoint is exit status 2 before any work.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::Value as Json;
use sph_cases::preflight::{write_summary, RunFiles};
use sph_cases::runner::{Progress, ProgressSink};
use sph_cases::{all_cases, find_case, resolve_method, CaseError, RunOptions, Value};
use sph_core::budget::{self, Budget};
use sph_core::state::fnv1a64;
use sph_driver::{Checkpoint, CheckpointPlan, Every};
use sph_output::{Backend, Compression};
use sph_scene::Scene;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

mod advise;
mod console;
mod converge;
mod job;
mod progress;
mod resume;
mod signals;
mod threads;
use console::{print_or_fail, say};
use job::{job, Job};
use progress::progress_display;
use resume::{resume, run_description};

/// The ranks of a distributed run: set in `main` when the command is built with the `mpi`
/// feature and started under `mpirun` with more than one process; emptied at the end of
/// `main`, which finalises MPI.
static RANKS: Mutex<Option<Arc<dyn sph_core::comm::Communicator>>> = Mutex::new(None);

/// The ranks of this run, if it is distributed over more than one.
fn ranks() -> Option<Arc<dyn sph_core::comm::Communicator>> {
    RANKS.lock().ok()?.clone().filter(|c| c.size() > 1)
}

/// MPI itself, to abort every rank when one fails.
#[cfg(feature = "mpi")]
static MPI: std::sync::OnceLock<std::sync::Weak<sph_cases::mpi_ranks::MpiRanks>> =
    std::sync::OnceLock::new();

/// Starts MPI when the command is built with the `mpi` feature.
fn start_ranks() -> Result<(), String> {
    #[cfg(feature = "mpi")]
    if let Some(r) = sph_cases::mpi_ranks::MpiRanks::initialize()? {
        let r = Arc::new(r);
        let _ = MPI.set(Arc::downgrade(&r));
        *RANKS.lock().map_err(|e| e.to_string())? = Some(r);
    }
    Ok(())
}

/// On several ranks, a rank that ends with an error ends them all (exit status 1 under
/// `mpirun`): the others may be waiting for it. Returns on one rank.
fn abort_ranks_on_error(code: ExitCode) {
    #[cfg(feature = "mpi")]
    if code != ExitCode::SUCCESS && ranks().is_some() {
        if let Some(m) = MPI.get().and_then(|w| w.upgrade()) {
            m.abort(1);
        }
    }
    let _ = code;
}

#[derive(Parser)]
#[command(
    name = "sph",
    version,
    about = "Particle simulation of elastic solids: run the benchmark cases"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the cases with their methods (and, with --verbose, their parameters).
    List {
        /// Show every parameter with its default, range and meaning.
        #[arg(long, short)]
        verbose: bool,
        /// Print a commented parameter file for this case (its defaults; `--config` reads it).
        #[arg(long, value_name = "CASE")]
        toml: Option<String>,
        /// With --toml: the method whose defaults to print (default: the case's first).
        #[arg(long, short)]
        method: Option<String>,
    },
    /// Run a case.
    Run(Box<RunArgs>),
    /// Continue a run from its checkpoint (`sph run --checkpoint-every`) to its end time, into
    /// the same results; it ends bit-identical to the run never interrupted.
    Resume(ResumeArgs),
    /// Run a case at a ladder of resolutions until the estimated error of every quantity is
    /// within a tolerance (or the budget is spent), and report value ± error, the observed
    /// order and what each level cost.
    Converge(Box<converge::ConvergeArgs>),
    /// Build a scene's bodies (fitting meshes and outlines), regions and tools without running,
    /// and write the initial particles (HDF5 + XDMF), a picture (PNG) and the per-body report.
    Preview(PreviewArgs),
    /// Before any run: the method and resolution expected to be cheapest for a tolerance, from
    /// the project's stored trade-off runs (docs/tradeoffs.md), with how far they stand for
    /// the case asked about.
    Advise(advise::AdviseArgs),
}

#[derive(clap::Args)]
struct PreviewArgs {
    /// The scene file (`.toml`).
    scene: PathBuf,
    /// Directory for `<scene>-preview.h5`, `.xmf` and `.png`.
    #[arg(long)]
    out: PathBuf,
    /// Also write the per-body report as JSON to this file.
    #[arg(long)]
    summary: Option<PathBuf>,
    /// Set a scene key or parameter: key=value (repeatable).
    #[arg(long = "set", short = 's', value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(clap::Args)]
struct ResumeArgs {
    /// The checkpoint file.
    checkpoint: PathBuf,
    /// Worker threads, 1 to 1024 (default: the interrupted run's count, which the bit-identity
    /// needs).
    #[arg(long)]
    threads: Option<usize>,
    /// Memory the run may plan to use, GiB (default: 80 % of the memory available now).
    #[arg(long, value_name = "GIB")]
    max_memory: Option<f64>,
    /// When stderr is not a terminal: a progress line every this many seconds (0: none).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    log_every: f64,
    /// Also write the log to this file, appended (see `sph run --log`).
    #[arg(long, value_name = "FILE")]
    log: Option<PathBuf>,
}

#[derive(clap::Args)]
struct RunArgs {
    /// Case name (see `sph list`), or a scene file (`.toml`, see docs/user-guide.md).
    case: String,
    /// Method (default: the case's first method, or the case file's `method`).
    #[arg(long, short)]
    method: Option<String>,
    /// Set a parameter: key=value (repeatable; applied after --config).
    #[arg(long = "set", short = 's', value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// A TOML case file with `key = value` lines (optionally `case`, `method`).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Directory for the results (`<case>-<method>.h5` and `.xmf`).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Do not write HDF5 results.
    #[arg(long)]
    no_output: bool,
    /// Write the run's figures as JSON to this file.
    #[arg(long)]
    summary: Option<PathBuf>,
    /// Distributed runs: each rank writes the snapshots of its own particles to
    /// `<case>-<method>.rank<r>.h5`, nothing is gathered; `<case>-<method>.h5` holds the meta,
    /// probes, series and summary, `<case>-<method>.xmf` shows the ranks' files as one body.
    #[arg(long)]
    per_rank_output: bool,
    /// HDF5 backend: `pure` (default) or `hdf5-metno` (needs the cargo feature).
    #[arg(long, default_value = "pure")]
    backend: String,
    /// Compress the HDF5 datasets (shuffle + deflate; any HDF5 reader decodes them) at this
    /// zlib level, 1 (fastest) to 9 (smallest): `--compress=LEVEL`, or `--compress` for 4.
    #[arg(
        long,
        value_name = "LEVEL",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "4"
    )]
    compress: Option<u8>,
    /// Worker threads, 1 to 1024 (default: RAYON_NUM_THREADS if set, else all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Memory the run may plan to use, GiB (default: 80 % of the memory available now).
    #[arg(long, value_name = "GIB")]
    max_memory: Option<f64>,
    /// Run even if the estimated work exceeds 10^12 particle-steps (about a day).
    #[arg(long)]
    allow_long_run: bool,
    /// Build the scene, check everything and print the estimates; run and write nothing.
    #[arg(long)]
    dry_run: bool,
    /// When stderr is not a terminal: a progress line to stderr every this many seconds of
    /// wall time (0: none). On a terminal a progress bar is drawn instead.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    log_every: f64,
    /// Also write the log (the command, progress lines every --log-every seconds, warnings,
    /// errors, the figures) to this file, appended.
    #[arg(long, value_name = "FILE")]
    log: Option<PathBuf>,
    /// Results beside the HDF5 file: `vtu` also writes every snapshot as
    /// `<case>-<method>_<k>.vtu` and their collection `<case>-<method>.pvd` (ParaView,
    /// PyVista, meshio); `hdf5` (the default) only the HDF5 file and its XDMF sidecar.
    #[arg(long, value_name = "FORMAT", default_value = "hdf5")]
    format: String,
    /// Write a checkpoint (the full state, atomically) every this much simulated time (e.g.
    /// 0.01) or wall time (e.g. 5min, 90s); `sph resume` continues from it.
    #[arg(long, value_name = "INTERVAL")]
    checkpoint_every: Option<String>,
    /// The checkpoint file (default: `<out>/<case>-<method>.ckpt`).
    #[arg(long, value_name = "FILE")]
    checkpoint: Option<PathBuf>,
}

impl RunArgs {
    /// `sph run TARGET [--method METHOD] --set … [--config FILE]` (a case or a scene file),
    /// every other option at its default (as clap gives it).
    fn for_target(
        target: &str,
        method: Option<&str>,
        set: &[String],
        config: Option<PathBuf>,
    ) -> Result<Self, CaseError> {
        let mut argv: Vec<String> = vec!["sph".into(), "run".into(), target.into()];
        if let Some(m) = method {
            argv.extend(["--method".into(), m.into()]);
        }
        for s in set {
            argv.extend(["--set".into(), s.clone()]);
        }
        if let Some(c) = config {
            argv.extend(["--config".into(), c.display().to_string()]);
        }
        match Cli::try_parse_from(argv) {
            Ok(Cli {
                command: Command::Run(a),
            }) => Ok(*a),
            Ok(_) => unreachable!("the arguments name `run`"),
            Err(e) => Err(CaseError::Config(
                e.to_string().lines().next().unwrap_or("").into(),
            )),
        }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return console::argument_error(e),
    };
    if let Err(e) = start_ranks() {
        say(&format!("error: {e}"));
        return ExitCode::from(2);
    }
    let code = command(cli);
    abort_ranks_on_error(code);
    // The last handle: finalises MPI.
    if let Ok(mut r) = RANKS.lock() {
        r.take();
    }
    code
}

fn command(cli: Cli) -> ExitCode {
    let result = match cli.command {
        Command::List {
            toml: Some(case),
            method,
            ..
        } => template(&case, method.as_deref()).map(|t| print_or_fail(&t, ExitCode::SUCCESS)),
        Command::List { verbose, .. } => Ok(print_or_fail(&list(verbose), ExitCode::SUCCESS)),
        Command::Run(args) => run(*args),
        Command::Resume(args) => resume(args),
        Command::Converge(args) => converge::converge_command(*args),
        Command::Advise(args) => advise::advise_command(args),
        Command::Preview(args) => preview(args),
    };
    result.unwrap_or_else(|e| {
        say(&format!("error: {e}"));
        ExitCode::from(2)
    })
}

/// `sph preview`: the scene built, written and drawn, the report printed
/// (`sph_cases::preview`).
fn preview(a: PreviewArgs) -> Result<ExitCode, CaseError> {
    let overrides = a
        .set
        .iter()
        .map(|s| sph_scene::Override::parse(s).map_err(|e| CaseError::Config(format!("--set {e}"))))
        .collect::<Result<Vec<_>, _>>()?;
    let scene = Scene::from_file_with(&a.scene, &overrides)
        .map_err(|e| CaseError::Config(e.to_string()))?;
    let files = sph_cases::preview::preview(&scene, &a.scene, &a.out, a.summary.as_deref())?;
    let mut text = format!(
        "{}: {} particles\n",
        scene.name(),
        files.summary["particles"]
    );
    if let Some(Json::Object(bodies)) = files.summary.get("bodies") {
        for (name, b) in bodies {
            let f = |k: &str| match b[k].as_f64() {
                Some(v) => format!("{v:.4}"),
                None => "-".into(),
            };
            text.push_str(&format!(
                "  {name}: {} particles, volume {} (mesh {}, scale {}), surface distance rms {} max {} dp, volume spread {}\n",
                b["particles"],
                f("volume"),
                f("mesh_volume"),
                f("volume_scale"),
                f("surface_distance_rms"),
                f("surface_distance_max"),
                f("volume_spread")
            ));
        }
    }
    text.push_str(&format!(
        "wrote {} (+ .xmf) and {}\n",
        files.results.display(),
        files.picture.display()
    ));
    Ok(print_or_fail(&text, ExitCode::SUCCESS))
}

/// A parameter file for `case` with `method`'s defaults, every key commented with its meaning
/// and range: edit it and run `sph run <case> --config <file>`.
fn template(case_name: &str, method: Option<&str>) -> Result<String, CaseError> {
    use std::fmt::Write as _;
    let case = find_case(case_name)?;
    let method = resolve_method(case, method)?;
    let info = case.info();
    let params = case.params_for(method);
    let mut s = String::new();
    let _ = writeln!(s, "# {}: {}", info.name, info.description);
    let _ = writeln!(
        s,
        "# Every parameter with the defaults of method `{method}` (methods: {}).",
        info.methods.join(", ")
    );
    let _ = writeln!(
        s,
        "# Run: sph run {} --config <this file>
",
        info.name
    );
    let _ = writeln!(s, "case = \"{}\"\nmethod = \"{method}\"\n", info.name);
    // Only the method's keys: another method's would be refused.
    for p in params.specs().iter().filter(|p| p.applies_to(method)) {
        let value = match params.value(p.key) {
            Some(Value::Text(t)) => format!("\"{t}\""),
            Some(Value::Float(x)) => format!("{x:?}"),
            Some(v) => v.to_string(),
            None => continue,
        };
        let _ = writeln!(s, "# {} ({})", p.help, p.range.describe(p.key));
        let _ = writeln!(s, "{} = {value}\n", p.key);
    }
    Ok(s)
}

fn list(verbose: bool) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for case in all_cases() {
        let info = case.info();
        let _ = writeln!(
            s,
            "{:<24} {:<38} {}",
            info.name,
            info.methods.join(","),
            info.description
        );
        if verbose {
            let show = |v: &Value| match v {
                Value::Text(s) => format!("\"{s}\""),
                v => v.to_string(),
            };
            // The case's defaults (a case may set some beyond its keys' generic defaults).
            let base = case.params();
            let value = |p: &sph_cases::params::Params, key: &str| p.value(key).map(show);
            for p in base.specs() {
                let v = value(&base, p.key).unwrap_or_default();
                let _ = writeln!(s, "    {:<20} = {:<14} {}", p.key, v, p.help);
            }
            // Defaults that another method's paper sets differently.
            for m in info.methods.iter().skip(1) {
                let other = case.params_for(m);
                for p in base.specs() {
                    let b = value(&other, p.key);
                    if value(&base, p.key) != b {
                        let _ = writeln!(
                            s,
                            "    {:<20} = {:<14} with --method {m}",
                            p.key,
                            b.unwrap_or_default()
                        );
                    }
                }
            }
        }
    }
    s
}

/// What a run writes and how it runs: `sph run`'s options, or a checkpoint's record of them.
struct Settings {
    out: PathBuf,
    no_output: bool,
    summary: Option<PathBuf>,
    per_rank_output: bool,
    backend: String,
    compress: Option<u8>,
    threads: Option<usize>,
    max_memory: Option<f64>,
    allow_long_run: bool,
    dry_run: bool,
    log_every: f64,
    /// `--log`: the log also goes to this file.
    log: Option<PathBuf>,
    /// `--format vtu`: VTU frames and their collection beside the HDF5 file.
    vtu: bool,
    checkpoint_every: Option<String>,
    checkpoint: Option<PathBuf>,
    /// `--config`, an input of the run.
    config: Option<PathBuf>,
}

fn run(a: RunArgs) -> Result<ExitCode, CaseError> {
    let job = job(&a)?;
    if a.checkpoint.is_some() && a.checkpoint_every.is_none() {
        return Err(CaseError::Config(
            "--checkpoint FILE needs --checkpoint-every INTERVAL".into(),
        ));
    }
    let settings = Settings {
        out: a.out,
        no_output: a.no_output,
        summary: a.summary,
        per_rank_output: a.per_rank_output,
        backend: a.backend,
        compress: a.compress,
        threads: a.threads,
        max_memory: a.max_memory,
        allow_long_run: a.allow_long_run,
        dry_run: a.dry_run,
        log_every: a.log_every,
        log: a.log,
        vtu: match a.format.as_str() {
            "hdf5" => false,
            "vtu" => true,
            other => {
                return Err(CaseError::InvalidValue {
                    key: "--format".into(),
                    value: other.into(),
                    allowed: "hdf5 (the default) or vtu (VTU frames and a .pvd beside the HDF5 \
                              file)"
                        .into(),
                })
            }
        },
        checkpoint_every: a.checkpoint_every,
        checkpoint: a.checkpoint,
        config: a.config,
    };
    execute(job, settings, None)
}

/// The memory a run of `threads` worker threads may plan to use: `--max-memory GIB`, or 80 %
/// of what the machine, the process's cgroup and its limits leave ([`Budget::available_to`]).
fn memory_budget(max_memory: Option<f64>, threads: usize) -> Result<Budget, CaseError> {
    Ok(match max_memory {
        Some(gib) if gib.is_finite() && gib > 0.0 && gib <= 1e9 => Budget::with_limit(
            (gib * (1u64 << 30) as f64) as u64,
            format!("--max-memory {gib}"),
        ),
        Some(gib) => {
            return Err(CaseError::InvalidValue {
                key: "--max-memory".into(),
                value: sph_core::error::Num(gib).to_string(),
                allowed: "GiB, 0 < --max-memory <= 1e9".into(),
            })
        }
        None => {
            let b = Budget::available_to(threads);
            let origin = format!("{}; --max-memory GIB overrides it", b.origin);
            Budget { origin, ..b }
        }
    })
}

fn execute(
    job: Job,
    a: Settings,
    resume_from: Option<Arc<Checkpoint>>,
) -> Result<ExitCode, CaseError> {
    let ranks = ranks();
    let root = ranks.as_ref().is_none_or(|c| c.rank() == 0);
    if let Some(c) = &ranks {
        let method = match &job {
            Job::Case { method, .. } => method.to_string(),
            Job::Scene(scene, _) => scene.method().to_string(),
        };
        if !matches!(method.as_str(), "tl" | "tl-hf" | "tl-gm" | "mps") {
            return Err(CaseError::Config(format!(
                "the method {method} does not run distributed: sph was started on {} ranks \
                 (run it on one; tl, tl-hf, tl-gm and mps run on several)",
                c.size()
            )));
        }
    }
    let backend: Backend = a.backend.parse()?;
    if !backend.is_available() {
        return Err(CaseError::Config(format!(
            "backend `{backend}` needs sph built with `--features hdf5-metno`"
        )));
    }
    let compression = match a.compress {
        None => Compression::None,
        Some(level) => Compression::deflate(level).map_err(|_| CaseError::InvalidValue {
            key: "--compress".into(),
            value: level.to_string(),
            allowed: "a deflate level, 1 (fastest) to 9 (smallest)".into(),
        })?,
    };
    if a.no_output && a.per_rank_output {
        return Err(CaseError::Config(
            "--per-rank-output splits the results file by rank; --no-output writes none".into(),
        ));
    }
    if a.no_output && a.vtu {
        return Err(CaseError::Config(
            "--format vtu writes frames beside the results file; --no-output writes none".into(),
        ));
    }
    if a.per_rank_output && a.vtu {
        return Err(CaseError::Config(
            "--format vtu writes the gathered snapshots; --per-rank-output gathers none".into(),
        ));
    }
    if a.no_output && compression != Compression::None {
        return Err(CaseError::Config(
            "--compress compresses the results file; --no-output writes none".into(),
        ));
    }

    let threads = threads::configure(a.threads)?;
    let budget = memory_budget(a.max_memory, threads)?;
    let (name, method) = match &job {
        Job::Case { case, method, .. } => (case.info().name.to_string(), method.to_string()),
        Job::Scene(scene, _) => (scene.name().to_string(), scene.method().to_string()),
    };
    let results = (!a.no_output).then(|| a.out.join(format!("{name}-{method}")));
    let checkpoint = match &a.checkpoint_every {
        Some(every) => {
            let every: Every = every.parse()?;
            let path = a
                .checkpoint
                .clone()
                .unwrap_or_else(|| a.out.join(format!("{name}-{method}.ckpt")));
            let run = run_description(&job, &a, &path, threads)?;
            // On several ranks each writes its own file (rank 0's is `path`).
            let rank = ranks.as_ref().map_or(0, |c| c.rank());
            Some(CheckpointPlan {
                path: sph_driver::checkpoint::rank_path(&path, rank),
                every,
                run,
            })
        }
        None => None,
    };
    let mut inputs = Vec::new();
    if let Job::Scene(_, file) = &job {
        inputs.push(("the scene file".to_string(), file.clone()));
    }
    if let Some(c) = &a.config {
        inputs.push(("--config".to_string(), c.clone()));
    }
    if let Ok(exe) = std::env::current_exe() {
        inputs.push(("the sph program".to_string(), exe));
    }
    RunFiles {
        results: results.clone(),
        summary: a.summary.clone(),
        inputs,
        checkpoint: checkpoint.as_ref().map(|c| c.path.clone()),
        other_rank: !root,
        vtu: a.vtu,
        log: a.log.clone().filter(|_| root),
    }
    .check()?;
    if let (Some(path), true) = (&a.log, root) {
        console::open_log(path)?;
        let command: Vec<String> = std::env::args().collect();
        console::log_only(&format!(
            "sph {} (pid {}): {} {}",
            env!("CARGO_PKG_VERSION"),
            std::process::id(),
            command.join(" "),
            if resume_from.is_some() {
                "(resumed)"
            } else {
                ""
            }
        ));
    }
    let signals = signals::install()?;
    let options = RunOptions {
        output: results,
        backend,
        compression,
        progress: if root {
            progress_display(
                std::io::stderr().is_terminal(),
                a.log_every,
                signals.report,
                a.log.is_some(),
            )?
        } else {
            None
        },
        allow_long_run: a.allow_long_run,
        dry_run: a.dry_run,
        interrupt: Some(signals.stop),
        checkpoint,
        resume: resume_from,
        ranks,
        per_rank_output: a.per_rank_output,
        vtu: a.vtu,
    };
    let (record, summary) = budget::scoped(budget, || match &job {
        Job::Case {
            case,
            method,
            params,
        } => case.run(method, params, &options),
        Job::Scene(scene, _) => scene
            .run(&options)
            .map_err(|e| CaseError::Config(e.to_string())),
    })?;
    if !root {
        // Rank 0 reports; the others only say how they ended.
        return Ok(if record.failure.is_some() {
            ExitCode::from(1)
        } else if let Some(sig) = record.interrupted {
            ExitCode::from((128 + sig).min(255) as u8)
        } else {
            ExitCode::SUCCESS
        });
    }
    if let (Some(path), false) = (&a.summary, a.dry_run) {
        let text = serde_json::to_string_pretty(&Json::Object(summary.clone()))
            .expect("summary serialises");
        if let Err(e) = write_summary(path, &text) {
            // The run is done and its results are written: report, and fail the exit status.
            say(&format!("error: writing the summary: {e}"));
            if record.failure.is_none() && record.interrupted.is_none() {
                return Ok(ExitCode::from(1));
            }
        }
    }
    let mut text = String::new();
    for (k, v) in &summary {
        match v {
            // Curves and histories: in the summary file and the HDF5 results, not the console.
            Json::Array(_) | Json::Object(_) if k != "monitor" && v.to_string().len() > 160 => text
                .push_str(&format!(
                    "{k:<28} (a curve or table: see --summary or /summary in the results)\n"
                )),
            _ if k == "monitor" => {}
            v => text.push_str(&format!("{k:<28} {v}\n")),
        }
    }
    if let Some(f) = &record.file {
        text.push_str(&format!("{:<28} {}\n", "results", f.display()));
    }
    if let Some(f) = &record.collection {
        text.push_str(&format!("{:<28} {}\n", "vtu collection", f.display()));
    }
    console::log_only(text.trim_end());
    let code = if record.failure.is_some() {
        ExitCode::from(1)
    } else if let Some(sig) = record.interrupted {
        ExitCode::from((128 + sig).min(255) as u8)
    } else {
        ExitCode::SUCCESS
    };
    let code = print_or_fail(&text, code);
    if let Some(e) = &record.failure {
        say(&format!("error: the run stopped early: {e}"));
    } else if record.interrupted.is_some() {
        say(&format!(
            "stopped: {}; the results hold everything up to there",
            record.status()
        ));
    }
    Ok(code)
}
