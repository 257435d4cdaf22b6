//! The whole-run tables of docs/performance.md: `benchmarks/results/case-timings.json` by
//! group, the anchor rows beside the recorded SPHinXsys reference
//! (`benchmarks/results/sphinxsys-reference.json`) and beside SPHinXsys timed in the same rounds
//! (`benchmarks/results/anchors-interleaved.json`).

use super::read_results;
use std::fmt::Write as _;
use std::path::Path;

/// One SPHinXsys wall time of an anchor row.
struct Reference {
    /// The label prefix of our row.
    case: String,
    threads: usize,
    /// Where it was measured ([`sph_benchmarks::machine`]).
    machine: String,
    /// Median wall seconds.
    wall: f64,
}

/// The SPHinXsys wall times of the anchor rows, each with the machine it was measured on
/// (`benchmarks/results/sphinxsys-reference.json`), and its `how` lines (how each was made).
fn sphinxsys_reference(root: &Path) -> (Vec<Reference>, Vec<String>) {
    let Some(doc) = read_results(root, "sphinxsys-reference.json") else {
        return (Vec::new(), Vec::new());
    };
    let rows = doc["rows"]
        .as_array()
        .map(|rows| {
            rows.iter()
                .filter_map(|r| {
                    Some(Reference {
                        case: r["case"].as_str()?.to_string(),
                        threads: r["threads"].as_u64()? as usize,
                        machine: r["machine"].as_str()?.to_string(),
                        wall: r["wall_seconds"]["median"].as_f64()?,
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    let how = doc["how"]
        .as_array()
        .map(|h| {
            h.iter()
                .filter_map(|x| x.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    (rows, how)
}

/// The anchor rows timed in rounds of SPHinXsys and ours (`case-timings --sphinxsys`,
/// `benchmarks/results/anchors-interleaved.json`), if any.
fn interleaved_anchors(md: &mut String, root: &Path) {
    let Some(doc) = read_results(root, "anchors-interleaved.json") else {
        return;
    };
    let rows = doc["rows"].as_array().cloned().unwrap_or_default();
    if rows.is_empty() {
        return;
    }
    writeln!(
        md,
        "#### The anchor rows and SPHinXsys in the same rounds\n\n\
         From `benchmarks/results/anchors-interleaved.json` (`cargo run --release -p \
         sph-benchmarks --bin case-timings -- --sphinxsys DIR`; how to build the SPHinXsys \
         side: `benchmarks/sphinxsys/README.md`). Each round runs the SPHinXsys test and then \
         ours, whole-process wall time; the ratio of a round is SPHinXsys / ours, and the \
         median of the rounds is given with their range. Both sides of a ratio see the machine \
         as it is at that moment, which absolute times from different days do not; but on a \
         loaded machine the two programs need not slow down alike (on 2026-12-03 our \
         two-thread runs lost more to the load than SPHinXsys's), so the quiet-window table \
         above stays the measurement of record.\n"
    )
    .unwrap();
    writeln!(
        md,
        "| scene | machine | date | build | threads | rounds | SPHinXsys (s) | ours (s) | ratio | range |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
    let f = |v: &serde_json::Value, k: &str, q: &str| {
        v[k][q].as_f64().map_or("–".into(), |x| format!("{x:.2}"))
    };
    for r in &rows {
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {}–{} |",
            r["label"].as_str().unwrap_or("?"),
            short_machine(&row_machine(r)),
            r["date"].as_str().unwrap_or("?"),
            r["build"].as_str().unwrap_or("?"),
            r["threads"],
            r["rounds"].as_array().map_or(0, Vec::len),
            f(r, "sphinxsys_wall_seconds", "median"),
            f(r, "wall_seconds", "median"),
            f(r, "ratio", "median"),
            f(r, "ratio", "min"),
            f(r, "ratio", "max"),
        )
        .unwrap();
    }
    writeln!(md).unwrap();
}

/// The machine a results row was measured on (rows from before the field: [`sph_benchmarks::EARLIER_MACHINE`]).
pub(crate) fn row_machine(r: &serde_json::Value) -> String {
    r["machine"]
        .as_str()
        .unwrap_or(sph_benchmarks::EARLIER_MACHINE)
        .to_string()
}

/// A machine's short name for a table column ("Intel Xeon", "AMD EPYC").
pub(crate) fn short_machine(m: &str) -> String {
    m.split(',')
        .next()
        .unwrap_or(m)
        .replace("(R)", "")
        .replace(" Processor", "")
        .replace(" CPU", "")
        .trim()
        .to_string()
}

pub(crate) fn case_timings_section(md: &mut String, root: &Path) {
    let Some(doc) = read_results(root, "case-timings.json") else {
        writeln!(
            md,
            "## Whole runs\n\nNot measured yet: `cargo run --release -p sph-benchmarks --bin case-timings`.\n"
        )
        .unwrap();
        return;
    };
    let rows = doc["rows"].as_array().cloned().unwrap_or_default();
    let (references, how) = sphinxsys_reference(root);
    let f = |v: &serde_json::Value, k: &str| v[k]["median"].as_f64();
    let spread = |v: &serde_json::Value, k: &str| match (v[k]["min"].as_f64(), v[k]["max"].as_f64())
    {
        (Some(a), Some(b)) => format!("{a:.2}–{b:.2}"),
        _ => "–".into(),
    };
    writeln!(md, "## Whole runs through `sph run`\n").unwrap();
    writeln!(
        md,
        "Generated from `benchmarks/results/case-timings.json` (`cargo run --release -p \
         sph-benchmarks --bin case-timings`): each scene run as a user runs it (`sph run … \
         --no-output --threads N`, unpinned), median of the repeats with the range; user and \
         system CPU time and peak resident memory (RSS) of the process, the latter also per \
         particle (– for rows measured before the memory column existed). Each row is the \
         build of the day it was measured: the AMD EPYC rows predate the smaller pair records \
         and the cross-block refresh above (the UL rows gained 5–8 % in 2D from them on Intel \
         Xeon), the Intel Xeon rows include them.\n"
    )
    .unwrap();
    for (group, title) in [
        (
            "anchors",
            "Anchor cases beside SPHinXsys (ratio = SPHinXsys wall / ours, both on the row's \
             machine; how each SPHinXsys time was made is listed below the table)",
        ),
        ("extreme", "Extreme TL scenes"),
        (
            "impacts",
            "UL impacts in 3D (steps: advection steps; particle-steps/s: acoustic sub-steps, \
             from the run's summary)",
        ),
        (
            "memory",
            "Memory of 3D TL-HF above 1e5 particles: the reference pair data stored (default) \
             or recomputed at every force pass (key `pair_data`; both give the same bits). \
             Target: ≤ 1 KiB per particle",
        ),
    ] {
        let rows: Vec<&serde_json::Value> = rows.iter().filter(|r| r["group"] == group).collect();
        if rows.is_empty() {
            continue;
        }
        writeln!(md, "### {title}\n").unwrap();
        writeln!(
            md,
            "| scene | machine | threads | particles | steps | wall (s) | range | user (s) | system (s) | sys/user | particle-steps/s | peak RSS (MB) | KiB/particle | SPHinXsys (s) | ratio |"
        )
        .unwrap();
        writeln!(
            md,
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        )
        .unwrap();
        for r in rows {
            let label = r["label"].as_str().unwrap_or("?");
            let threads = r["threads"].as_u64().unwrap_or(0) as usize;
            let wall = f(r, "wall_seconds");
            let (user, sys) = (f(r, "user_seconds"), f(r, "system_seconds"));
            let rss = f(r, "peak_rss_bytes");
            let machine = row_machine(r);
            let reference = references
                .iter()
                .find(|x| {
                    label.starts_with(&x.case) && x.threads == threads && x.machine == machine
                })
                .map(|x| x.wall);
            let opt = |x: Option<f64>, d: usize| x.map_or("–".into(), |v| format!("{v:.d$}"));
            let steps = r["acoustic_steps"]
                .as_u64()
                .or_else(|| r["steps"].as_u64())
                .map_or("–".into(), |s| s.to_string());
            writeln!(
                md,
                "| {label} | {} | {threads} | {} | {steps} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                short_machine(&machine),
                r["particles"],
                opt(wall, 2),
                spread(r, "wall_seconds"),
                opt(user, 2),
                opt(sys, 2),
                opt(user.zip(sys).map(|(u, s)| 100.0 * s / u), 1) + " %",
                r["particle_steps_per_second"]
                    .as_f64()
                    .map_or("–".into(), |v| format!("{v:.3e}")),
                opt(rss.map(|b| b / 1e6), 0),
                opt(
                    rss.zip(r["particles"].as_f64()).map(|(b, n)| b / n / 1024.0),
                    2
                ),
                opt(reference, 1),
                opt(reference.zip(wall).map(|(a, b)| a / b), 2),
            )
            .unwrap();
        }
        writeln!(md).unwrap();
        if group == "anchors" {
            for line in &how {
                writeln!(md, "- {line}").unwrap();
            }
            if !how.is_empty() {
                writeln!(md).unwrap();
            }
            writeln!(
                md,
                "The UL-ENOG plate comes twice. Our default recomputes the kernel data `e`, `r`, \
                 `W′` from the current positions in every acoustic sub-step (docs/methods.md: \
                 frozen over the advection step they soften the plate secularly, its period \
                 0.278 → 0.363 s over 10 s in docs/validation.md's long run), which costs \
                 1.33–1.49× the frozen sub-step in 2D and 1.72× in the 3D plate (the UL \
                 stepping table above). SPHinXsys's test \
                 updates them with the neighbour list only, once per advection step. The row \
                 \"kernel data frozen\" runs that same scheme (`--set \
                 refresh_kernel_data=false`), so its ratio compares the two implementations of \
                 one algorithm; the default row compares what a user of each gets without \
                 options, and is the row the performance target applies to.\n"
            )
            .unwrap();
            interleaved_anchors(md, root);
        }
    }
}
