//! What each optional feature costs (`validate tradeoff --only features`, the "model only what a
//! scene requires" table of docs/tradeoffs.md).
//!
//! Each row runs one scene twice as a user runs it ([`crate::cost`]: 2 threads, CPU seconds of
//! the `sph` process), once with the feature off and once on, everything else equal, each
//! [`REPEATS`] times (the median is reported, with the spread). Both variants take the same
//! steps (the features do not change the motion, or the row says how), so the ratio of CPU
//! seconds is the ratio of the per-step costs.

use crate::cost::{run_or_load_writing, CostedRun};
use std::fmt::Write as _;

/// Runs per variant (median and spread reported).
pub const REPEATS: usize = 3;

/// Threads of these runs: one, so CPU seconds are the work done (on two, the CPU time of
/// serial parts counts twice while the idle worker spins, which inflates features that run
/// serially, such as the monitor).
pub const THREADS: usize = 1;

/// One on/off comparison.
struct Feature {
    /// Scene label in the table.
    scene: &'static str,
    case: &'static str,
    method: &'static str,
    /// Assignments common to both variants.
    base: &'static [&'static str],
    /// What is switched.
    feature: &'static str,
    /// Assignments of the off and on variants.
    off: &'static [&'static str],
    on: &'static [&'static str],
    /// Whether the on variant writes its results (snapshots, probes) instead of `--no-output`.
    on_writes: bool,
    /// What the on variant adds, for the reader.
    note: &'static str,
}

fn features() -> Vec<Feature> {
    const PLATE_UL: &[&str] = &["end_time=0.2"];
    const PLATE_TL: &[&str] = &["end_time=0.5"];
    const COLUMN: &[&str] = &["end_time=0.1"];
    // One monitor sample: in a run of 200 sub-steps, 200 samples would dominate the cost.
    const PLATE3D: &[&str] = &["end_time=0.001", "monitor_interval=0.001"];
    let f = |scene, case, method, base, feature, off, on, on_writes, note| Feature {
        scene,
        case,
        method,
        base,
        feature,
        off,
        on,
        on_writes,
        note,
    };
    vec![
        f("2D plate", "oscillating-plate-2d", "ul-enog", PLATE_UL, "results written",
          &[], &[], true,
          "51 HDF5 snapshots and the probes; ENOG then also integrates its output-only shear stress"),
        f("2D plate", "oscillating-plate-2d", "ul-enog", PLATE_UL, "energy budget",
          &["energy_budget=false"], &[], false,
          "the dissipated/artificial parts of every pair force and the works, per sub-step"),
        f("2D plate", "oscillating-plate-2d", "ul-enog", PLATE_UL, "kernel data refreshed every sub-step",
          &["refresh_kernel_data=false"], &[], false,
          "e, r, W′ recomputed from the current positions (off changes the motion: the plate softens, docs/methods.md)"),
        f("2D plate", "oscillating-plate-2d", "ul-enog", PLATE_UL, "disorder/energy monitor",
          &["monitor_interval=0.2"], &[], false,
          "200 samples of the disorder indicator and the energies instead of 1"),
        f("2D plate", "oscillating-plate-2d", "tl-hf", PLATE_TL, "results written",
          &[], &[], true, "51 HDF5 snapshots and the probes"),
        f("2D plate", "oscillating-plate-2d", "tl", PLATE_TL, "Kelvin–Voigt damping",
          &["damping=false"], &[], false,
          "the viscous stress of TL eq 23–24 (changes the motion: the damped plate)"),
        f("2D plate", "oscillating-plate-2d", "tl-hf", PLATE_TL, "Kelvin–Voigt damping",
          &["damping=false"], &[], false,
          "the viscous stress of TL eq 23–24, the fourth term of the TL paper's HF Kirchhoff stress"),
        f("2D plate", "oscillating-plate-2d", "tl-hf", PLATE_TL, "disorder/energy monitor",
          &["monitor_interval=0.5"], &[], false,
          "200 samples of the disorder indicator and the energies instead of 1"),
        f("2D plate", "oscillating-plate-2d", "tl-hf", PLATE_TL, "probe every step",
          &[], &["probe_interval=0"], false,
          "the tip probe sampled every step instead of every 0.5 ms"),
        f("3D twisting column", "twisting-column-3d", "tl-hf", COLUMN, "results written",
          &[], &[], true, "51 HDF5 snapshots and the probes"),
        f("3D twisting column", "twisting-column-3d", "tl-hf", COLUMN, "Kelvin–Voigt damping",
          &["damping=false"], &[], false, "the viscous stress of TL eq 23–24 (changes the motion)"),
        f("3D twisting column", "twisting-column-3d", "tl-hf", COLUMN, "disorder/energy monitor",
          &["monitor_interval=0.1"], &[], false,
          "200 samples of the disorder indicator and the energies instead of 1"),
        f("3D plate (43,200 particles)", "oscillating-plate-3d", "ul-enog", PLATE3D, "results written",
          &[], &[], true,
          "51 HDF5 snapshots and the probes; ENOG then also integrates its output-only shear stress"),
        f("3D plate (43,200 particles)", "oscillating-plate-3d", "ul-enog", PLATE3D, "energy budget",
          &["energy_budget=false"], &[], false,
          "the dissipated/artificial parts of every pair force and the works, per sub-step"),
        f("3D plate (43,200 particles)", "oscillating-plate-3d", "ul-enog", PLATE3D,
          "kernel data refreshed every sub-step", &["refresh_kernel_data=false"], &[], false,
          "e, r, W′ recomputed from the current positions (off changes the motion)"),
    ]
}

/// The assignments and the run id of one variant's `k`-th repeat.
fn variant(f: &Feature, on: bool, k: usize) -> (String, Vec<String>, bool) {
    let extra = if on { f.on } else { f.off };
    let set: Vec<String> = f.base.iter().chain(extra).map(|s| s.to_string()).collect();
    let writes = on && f.on_writes;
    let tag: String = set
        .iter()
        .map(|s| s.replace(['=', '.'], "_"))
        .collect::<Vec<_>>()
        .join("-");
    let id = format!(
        "feature-{}-{}-{tag}-{}-t{THREADS}-r{k}",
        f.case,
        f.method,
        if writes { "out" } else { "noout" }
    );
    (id, set, writes)
}

/// Runs (or loads) every variant of every row.
pub fn run_all(force: bool) -> Result<(), String> {
    for f in features() {
        for k in 1..=REPEATS {
            for on in [false, true] {
                let (id, set, writes) = variant(&f, on, k);
                run_or_load_writing(&id, f.case, f.method, &set, writes, THREADS, force)?;
            }
        }
    }
    Ok(())
}

/// The stored repeats of one variant (all of them, or `None`).
fn repeats(f: &Feature, on: bool) -> Option<Vec<CostedRun>> {
    (1..=REPEATS)
        .map(|k| crate::cost::load(&variant(f, on, k).0))
        .collect()
}

/// Median and (min, max) of CPU seconds.
fn median_spread(runs: &[CostedRun]) -> (f64, f64, f64) {
    let mut c: Vec<f64> = runs.iter().map(|r| r.cpu_seconds).collect();
    c.sort_by(f64::total_cmp);
    (c[c.len() / 2], c[0], c[c.len() - 1])
}

/// Steps of a run: acoustic sub-steps for UL (the force evaluations), steps otherwise.
fn steps(r: &CostedRun) -> Option<f64> {
    r.num("acoustic_steps").or_else(|| r.num("steps"))
}

/// The report section (empty when no row has all its runs).
pub fn section(md: &mut String) -> bool {
    let rows: Vec<(Feature, Vec<CostedRun>, Vec<CostedRun>)> = features()
        .into_iter()
        .filter_map(|f| {
            let off = repeats(&f, false)?;
            let on = repeats(&f, true)?;
            Some((f, off, on))
        })
        .collect();
    if rows.is_empty() {
        return false;
    }
    writeln!(
        md,
        "## Model only what a scene requires: what each feature costs\n"
    )
    .unwrap();
    writeln!(
        md,
        "Every optional piece of work runs only when the scene or the user asks for it: contact \
         search only between bodies of a multi-body scene (a one-body scene builds no contact \
         list), ENOG's output-only shear stress only when results are written, damping, the \
         energy budget, the monitor and the probes only when on. The table measures what each \
         costs when it is on: the same scene run with the feature off and on (everything else \
         equal, `--threads {}`: CPU seconds are then the work done), CPU seconds of the `sph` \
         process, median of {REPEATS} runs \
         (range in brackets), and the extra cost of the on variant. Both variants take the same \
         steps unless the step count differs in the table (a feature that changes the motion \
         says so). Timings were taken while other work may have run on the machine: \
         differences below ~5 % are within the noise.\n",
        THREADS
    )
    .unwrap();
    writeln!(
        md,
        "| scene | method | feature | off: CPU s | on: CPU s | steps off / on | µs per step off / on | extra | what \"on\" does | commands (off; on) |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
    for (f, off, on) in &rows {
        let (m_off, lo_off, hi_off) = median_spread(off);
        let (m_on, lo_on, hi_on) = median_spread(on);
        let (s_off, s_on) = (steps(&off[0]), steps(&on[0]));
        let per =
            |m: f64, s: Option<f64>| s.map_or("–".into(), |s| format!("{:.1}", 1e6 * m / s));
        let fmt_steps = |s: Option<f64>| s.map_or("–".into(), |s| format!("{s:.0}"));
        // A variant that fails is not a cost but a finding: say which and why.
        let failure = [("off", off), ("on", on)].iter().find_map(|(v, runs)| {
            runs.iter()
                .find(|r| r.exit_code != 0)
                .map(|r| format!("{v} variant failed: {}; ", r.status()))
        });
        writeln!(
            md,
            "| {} | {} | {} | {:.2} [{:.2}–{:.2}] | {:.2} [{:.2}–{:.2}] | {} / {} | {} / {} | {}{:+.0} % | {} | `{}`; `{}` |",
            f.scene,
            f.method,
            f.feature,
            m_off,
            lo_off,
            hi_off,
            m_on,
            lo_on,
            hi_on,
            fmt_steps(s_off),
            fmt_steps(s_on),
            per(m_off, s_off),
            per(m_on, s_on),
            failure.as_deref().unwrap_or(""),
            100.0 * (m_on / m_off - 1.0),
            f.note,
            off[0].command,
            on[0].command,
        )
        .unwrap();
    }
    writeln!(md).unwrap();
    true
}
