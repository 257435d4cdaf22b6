//! `sph`: list the benchmark cases and run one.
//!
//! ```text
//! sph list [--verbose]
//! sph run <case> [--method M] [--set key=value]... [--config case.toml] [--out DIR]
//!         [--summary FILE.json] [--backend pure|hdf5-metno] [--threads N] [--no-output]
//! ```
//! Exit status: 0 on success, 2 for bad input (nothing is written), 1 when the run failed
//! mid-way (the results file is completed with what was computed, its summary says why).

use clap::{Parser, Subcommand};
use serde_json::Value as Json;
use sph_cases::{all_cases, find_case, resolve_method, CaseError, RunOptions, Value};
use sph_output::Backend;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

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
    },
    /// Run a case.
    Run {
        /// Case name (see `sph list`).
        case: String,
        /// Method (default: the case's first method).
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
        /// HDF5 backend: `pure` (default) or `hdf5-metno` (needs the cargo feature).
        #[arg(long, default_value = "pure")]
        backend: String,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::List { verbose } => {
            list(verbose);
            ExitCode::SUCCESS
        }
        Command::Run {
            case,
            method,
            set,
            config,
            out,
            no_output,
            summary,
            backend,
            threads,
        } => match run(
            case, method, set, config, out, no_output, summary, backend, threads,
        ) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::from(1),
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
    }
}

fn list(verbose: bool) {
    for case in all_cases() {
        let info = case.info();
        println!(
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
                println!("    {:<20} = {:<14} {}", p.key, v, p.help);
            }
            // Defaults that another method's paper sets differently.
            for m in info.methods.iter().skip(1) {
                let other = case.params_for(m);
                for p in base.specs() {
                    let b = value(&other, p.key);
                    if value(&base, p.key) != b {
                        println!(
                            "    {:<20} = {:<14} with --method {m}",
                            p.key,
                            b.unwrap_or_default()
                        );
                    }
                }
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn run(
    case_name: String,
    method: Option<String>,
    set: Vec<String>,
    config: Option<PathBuf>,
    out: PathBuf,
    no_output: bool,
    summary_path: Option<PathBuf>,
    backend: String,
    threads: Option<usize>,
) -> Result<bool, CaseError> {
    let case = find_case(&case_name)?;
    let mut method = method;
    // The method decides the defaults (`Case::params_for`), so it is resolved before the
    // configuration file and the assignments are applied on top of its defaults.
    let toml = match &config {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| CaseError::Io {
                path: path.display().to_string(),
                source: e,
            })?;
            let extras = case
                .params()
                .apply_toml(&text, &path.display().to_string())?;
            if let Some(c) = extras.case {
                if c != case_name {
                    return Err(CaseError::Config(format!(
                        "{}: names case `{c}` but `{case_name}` was asked for",
                        path.display()
                    )));
                }
            }
            if method.is_none() {
                method = extras.method;
            }
            Some((text, path.display().to_string()))
        }
        None => None,
    };
    let method = resolve_method(case, method.as_deref())?;
    let mut params = case.params_for(method);
    if let Some((text, name)) = &toml {
        params.apply_toml(text, name)?;
    }
    for a in &set {
        params.apply_assignment(a)?;
    }
    let backend: Backend = backend.parse()?;
    if !backend.is_available() {
        return Err(CaseError::Config(format!(
            "backend `{backend}` needs sph built with `--features hdf5-metno`"
        )));
    }
    if let Some(n) = threads {
        if n == 0 {
            return Err(CaseError::InvalidValue {
                key: "threads".into(),
                value: "0".into(),
                allowed: "at least 1".into(),
            });
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| CaseError::Config(format!("thread pool: {e}")))?;
    }
    let options = RunOptions {
        output: (!no_output).then(|| out.join(format!("{}-{}", case.info().name, method))),
        backend,
        progress: std::io::stderr().is_terminal(),
    };
    let (record, summary) = case.run(method, &params, &options)?;
    if let Some(path) = &summary_path {
        let text = serde_json::to_string_pretty(&Json::Object(summary.clone()))
            .expect("summary serialises");
        write_atomically(path, &text)?;
    }
    for (k, v) in &summary {
        match v {
            // Curves and histories: in the summary file and the HDF5 results, not the console.
            Json::Array(_) | Json::Object(_) if k != "monitor" && v.to_string().len() > 160 => {
                println!("{k:<28} (a curve or table: see --summary or /summary in the results)")
            }
            _ if k == "monitor" => {}
            v => println!("{k:<28} {v}"),
        }
    }
    if let Some(f) = &record.file {
        println!("{:<28} {}", "results", f.display());
    }
    if let Some(e) = &record.failure {
        eprintln!("error: the run stopped early: {e}");
        return Ok(false);
    }
    Ok(true)
}

fn write_atomically(path: &PathBuf, text: &str) -> Result<(), CaseError> {
    let io = |e| CaseError::Io {
        path: path.display().to_string(),
        source: e,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let mut tmp = path.as_os_str().to_os_string();
    tmp.push(".tmp");
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}
