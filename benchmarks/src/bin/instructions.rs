//! Instructions executed by the anchor scenes (`valgrind --tool=cachegrind`), the whole run and
//! per function: a measure of the work a build does that, unlike wall time, does not move with
//! the load of the machine (a shared virtual machine can drift by ±20 % between two runs of the
//! same binary). Each anchor of `case-timings` runs on one thread (a waiting thread's spinning
//! would count) over its first `--end` seconds of simulated time (default 0.02), with the
//! monitor sampling as often per simulated second as in the full run. Appends one row per scene
//! and build to `benchmarks/results/instructions.json`, which `perf-report` turns into a table of
//! `docs/performance.md`.
//!
//! ```text
//! cargo build --release -p sph-cases --bin sph
//! cargo run --release -p sph-benchmarks --bin instructions [-- --sph PATH --build NAME --end 0.02]
//! ```
//! `--sph` measures another build of `sph` (default: the one beside this binary), `--build` names
//! it (default: the commit of the checkout, with `+changes` when the tree differs from it).
//! Needs valgrind; without it the binary says so and writes nothing.

use serde_json::{json, Value};
use sph_benchmarks::scenes::scenes;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Functions listed per row, by instructions.
const TOP_FUNCTIONS: usize = 6;

/// The value of `--name` in `args`.
fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|k| args.get(k + 1))
        .cloned()
}

/// The simulated end time an argument list sets (`--set end_time=…`).
fn end_time(args: &[&str]) -> Option<f64> {
    args.iter()
        .rev()
        .find_map(|a| a.strip_prefix("end_time="))
        .and_then(|v| v.parse().ok())
}

/// Total instructions and instructions per function of a cachegrind output file (events `Ir`
/// only, as `--cache-sim=no` writes them).
fn read_cachegrind(path: &Path) -> (u64, BTreeMap<String, u64>) {
    parse_cachegrind(&std::fs::read_to_string(path).expect("cachegrind output"))
}

/// [`read_cachegrind`] of the file's text: `fn=` names the function of the `line count` lines
/// that follow (the same name in several files adds up), `summary:` the total.
fn parse_cachegrind(text: &str) -> (u64, BTreeMap<String, u64>) {
    let mut total = 0;
    let mut per_function: BTreeMap<String, u64> = BTreeMap::new();
    let mut current = String::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("fn=") {
            current = loop_name(name);
        } else if let Some(n) = line.strip_prefix("summary:") {
            total = n.trim().parse().expect("cachegrind summary");
        } else if line.starts_with(|c: char| c.is_ascii_digit()) {
            let count: u64 = line
                .split_whitespace()
                .nth(1)
                .and_then(|c| c.parse().ok())
                .unwrap_or(0);
            *per_function.entry(current.clone()).or_default() += count;
        }
    }
    (total, per_function)
}

/// The top-level generic arguments of `s`, which starts just after a `<` (up to its `>`).
fn generic_args(s: &str) -> Vec<&str> {
    let (mut depth, mut start, mut args) = (0usize, 0, Vec::new());
    for (k, c) in s.char_indices() {
        match c {
            '<' | '(' | '[' => depth += 1,
            '>' | ')' | ']' if depth == 0 => {
                args.push(s[start..k].trim());
                return args;
            }
            '>' | ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                args.push(s[start..k].trim());
                start = k + 1;
            }
            _ => {}
        }
    }
    args.push(s[start..].trim());
    args
}

/// `name` without generic arguments and closure suffixes: `a::b<T>::{closure#0}` → `a::b`,
/// `<a::S<T> as a::Tr<T>>::f` → `<a::S as a::Tr>::f`.
fn without_generics(name: &str) -> String {
    let mut out = String::new();
    // How deep inside generic arguments being dropped.
    let mut depth = 0usize;
    for c in name.chars() {
        if depth > 0 {
            match c {
                '<' => depth += 1,
                '>' => depth -= 1,
                _ => {}
            }
            continue;
        }
        match c {
            // The bracket of a qualified path `<T as Trait>::f` stays.
            '<' if out.is_empty() || out.ends_with('<') => out.push(c),
            '<' => {
                depth = 1;
                if out.ends_with("::") {
                    out.truncate(out.len() - 2);
                }
            }
            _ => out.push(c),
        }
    }
    if let Some(k) = out.find("::{") {
        out.truncate(k);
    }
    out
}

/// The name a profile should show for a function of cachegrind's output. A particle loop's
/// AVX2 copy is one instantiation of `sph_core::wide::with_avx2_fma` (v0 symbol names carry
/// the instantiation): it is named after the loop it runs, the innermost closure given to a
/// `sph_core::parallel` helper, with ` (AVX2)`; every other name loses its generic arguments.
fn loop_name(name: &str) -> String {
    const WIDE: &str = "sph_core::wide::with_avx2_fma::<";
    let Some(inner) = name.strip_prefix(WIDE) else {
        return without_generics(name);
    };
    // The last type argument is the loop's closure, e.g.
    // `sph_core::parallel::gather<T, sph_tl::…::acceleration<…>::{closure#0}>::{closure#0}`:
    // descend through the helpers to the closure they were given.
    let mut body = generic_args(inner).last().copied().unwrap_or(inner);
    while body.starts_with("sph_core::parallel::") {
        let Some(open) = body.find('<') else { break };
        match generic_args(&body[open + 1..]).last() {
            Some(last) => body = last,
            None => break,
        }
    }
    format!("{} (AVX2)", without_generics(body))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    sph_benchmarks::check_flags(
        &args,
        &["--sph", "--build", "--end"],
        "usage: instructions [--sph PATH] [--build NAME] [--end SECONDS]",
    );
    let exe = std::env::current_exe().expect("own path");
    let root = exe
        .ancestors()
        .find(|p| p.join("Cargo.lock").exists())
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."));
    let sph = flag(&args, "--sph").map_or_else(|| exe.with_file_name("sph"), PathBuf::from);
    let build = flag(&args, "--build").unwrap_or_else(|| sph_benchmarks::build_name(&root));
    let end: f64 = match flag(&args, "--end").map(|v| v.parse::<f64>()) {
        None => 0.02,
        Some(Ok(e)) if e > 0.0 && e.is_finite() => e,
        Some(_) => {
            eprintln!("error: --end: simulated seconds, a number > 0");
            std::process::exit(2);
        }
    };
    if !sph.exists() {
        eprintln!(
            "error: {} not found: build it first (cargo build --release -p sph-cases --bin sph)",
            sph.display()
        );
        std::process::exit(2);
    }
    if Command::new("valgrind").arg("--version").output().is_err() {
        println!("notice: valgrind is not installed; no instruction counts measured");
        return;
    }
    let scratch = std::env::temp_dir().join(format!("sph-instructions-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch directory");
    let mut rows = Vec::new();
    for scene in scenes().into_iter().filter(|s| s.group == "anchors") {
        let full = end_time(&scene.args).expect("an anchor scene sets its end_time");
        // The monitor's 200 samples of the full run, at the same spacing in the shortened one.
        let (end_key, monitor_key) = (
            format!("end_time={end}"),
            format!("monitor_interval={}", full / 200.0),
        );
        let (out, summary) = (scratch.join("cachegrind.out"), scratch.join("summary.json"));
        let status = Command::new("valgrind")
            .args(["--tool=cachegrind", "--cache-sim=no"])
            .arg(format!("--cachegrind-out-file={}", out.display()))
            .arg(&sph)
            .arg("run")
            .args(&scene.args)
            .args(["--set", &end_key, "--set", &monitor_key])
            .args(["--no-output", "--threads", "1", "--summary"])
            .arg(&summary)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .expect("run valgrind");
        if !status.success() {
            eprintln!("error: {} failed under valgrind ({status})", scene.label);
            std::process::exit(1);
        }
        let (total, per_function) = read_cachegrind(&out);
        let figures: Value =
            serde_json::from_str(&std::fs::read_to_string(&summary).expect("summary"))
                .expect("summary JSON");
        // UL counts its force evaluations as acoustic steps.
        let (particles, steps) = (
            figures["particles"].clone(),
            match &figures["acoustic_steps"] {
                Value::Null => figures["steps"].clone(),
                n => n.clone(),
            },
        );
        let per_particle_step = total as f64
            / (particles.as_f64().unwrap_or(f64::NAN) * steps.as_f64().unwrap_or(f64::NAN));
        let mut top: Vec<(String, u64)> = per_function.into_iter().collect();
        top.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
        top.truncate(TOP_FUNCTIONS);
        let command = format!(
            "valgrind --tool=cachegrind --cache-sim=no sph run {} --set {end_key} --set \
             {monitor_key} --no-output --threads 1",
            scene.args.join(" ")
        );
        eprintln!(
            "{} (first {end} s): {total} instructions, {per_particle_step:.0} per particle-step",
            scene.label
        );
        rows.push(json!({
            "label": scene.label,
            "build": build,
            "end_time": end,
            "command": command,
            "particles": particles,
            "steps": steps,
            "instructions": total,
            "per_particle_step": per_particle_step,
            "top_functions": top
                .iter()
                .map(|(name, n)| json!({ "function": name, "instructions": n }))
                .collect::<Vec<_>>(),
        }));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let path = root
        .join("benchmarks")
        .join("results")
        .join("instructions.json");
    // A row is replaced only by the same scene, build and end time.
    let key = |r: &Value| format!("{}|{}|{}", r["label"], r["build"], r["end_time"]);
    let mut all: Vec<Value> = std::fs::read_to_string(&path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|v| v.get("rows").and_then(Value::as_array).cloned())
        .unwrap_or_default();
    let fresh: Vec<String> = rows.iter().map(key).collect();
    all.retain(|r| !fresh.contains(&key(r)));
    all.extend(rows);
    let doc = json!({
        "generated_by": "cargo run --release -p sph-benchmarks --bin instructions",
        "rows": all,
    });
    std::fs::create_dir_all(path.parent().unwrap()).expect("results directory");
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).expect("write results");
    println!("wrote {}", path.display());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cachegrind_counts_add_up_per_function() {
        let text = "events: Ir\nfl=a.c\nfn=f\n1 10\n2 5\nfn=g::{{closure}}\n7 3\n\
                    fl=b.c\nfn=f\n4 100\nsummary: 118\n";
        let (total, per) = parse_cachegrind(text);
        assert_eq!(total, 118);
        assert_eq!(per["f"], 115);
        assert_eq!(per["g"], 3);
        assert_eq!(per.values().sum::<u64>(), total);
    }

    #[test]
    fn an_avx2_loop_is_named_after_its_closure() {
        let wide = "sph_core::wide::with_avx2_fma::<(), sph_core::parallel::gather<\
                    glam::f64::dvec3::DVec3, sph_tl::hourglass_free::acceleration<\
                    sph_core::dim::D3, sph_tl::reference_pairs::StoredRows<sph_core::dim::D3>>\
                    ::{closure#0}>::{closure#0}::{closure#0}>";
        assert_eq!(
            loop_name(wide),
            "sph_tl::hourglass_free::acceleration (AVX2)"
        );
        let through_fold = "sph_core::wide::with_avx2_fma::<f64, sph_core::parallel::map_tasks<\
                            f64, sph_core::parallel::fold_chunks<f64, sph_core::parallel::\
                            max_over<sph_core::diagnostics::max_norm_where<sph_core::dim::D3>\
                            ::{closure#0}>::{closure#0}>::{closure#0}>::{closure#1}::{closure#0}>";
        assert_eq!(
            loop_name(through_fold),
            "sph_core::diagnostics::max_norm_where (AVX2)"
        );
        let method = "<sph_tl::solver::TlSolver<sph_core::dim::D3, sph_materials::model::\
                      MaterialModel> as sph_core::solver::Solver<sph_core::dim::D3>>::energies";
        assert_eq!(
            loop_name(method),
            "<sph_tl::solver::TlSolver as sph_core::solver::Solver>::energies"
        );
        assert_eq!(
            loop_name("sph_core::pairs::PairSymmetry::new"),
            "sph_core::pairs::PairSymmetry::new"
        );
        assert_eq!(loop_name("g::{{closure}}"), "g");
    }

    #[test]
    fn the_end_time_is_the_last_one_set() {
        assert_eq!(
            end_time(&["x", "--set", "end_time=1", "--set", "end_time=0.5"]),
            Some(0.5)
        );
        assert_eq!(end_time(&["x"]), None);
    }
}
