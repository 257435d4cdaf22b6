//! The speed–accuracy trade and the stability limits (`validate tradeoff`, docs/tradeoffs.md).
//!
//! **Pareto fronts.** Every method that can run a scene, at several resolutions, each run costed
//! as a user runs it ([`crate::cost`]: 2 threads, no output, CPU seconds and peak memory of the
//! `sph` process, and the machine-independent work `pair_visits` = neighbour pairs visited by
//! the force evaluations). The error of each run against a reference that does not depend on
//! that run: a closed form where one exists, otherwise an independent finite-element solution (stated per
//! scene).
//!
//! **Stability map.** A severity parameter swept per scene and method; each cell is ordered
//! (completed, largest disorder indicator ≤ [`DISORDER_LIMIT`]), disordered, failed (with the
//! reason) or rejected (the input is outside the parameter's allowed range).

use crate::cost::{run_or_load, CostedRun};
use crate::plot;
use std::fmt::Write as _;
use std::path::Path;

/// What to run.
#[derive(Clone, Debug)]
pub struct Selection {
    /// Coarse resolutions and a reduced map only (minutes).
    pub quick: bool,
    /// Re-run stored runs.
    pub force: bool,
    /// Only the scenes and sweeps whose key starts with this (e.g. `plate`, `homog`, `rings`).
    pub only: Option<String>,
}

/// Largest disorder indicator of a run still called ordered. From the stored validation runs
/// and their pictures (docs/validation.md): TL-HF's plate at v_f = 0.15 (H/dp 10, frame clamp)
/// peaks at 0.16 and UL-ENOG's colliding rings at 0.04–0.06, both visibly ordered; TL-GM's
/// plate at 1.20, OAS's rings at 0.31–1.8 (zigzag) and OG's at 1.6–2.6 (fracture) are visibly
/// disordered.
pub const DISORDER_LIMIT: f64 = 0.25;

/// A sweep's run may take this many times the steps its dry run estimates (`steps_estimate`:
/// the end time over the stable step of the initial state; for UL the acoustic steps), key
/// `max_steps`: one that needs more has a mean step below a tenth of that step, a time step
/// collapsing towards the solvers' own floor (10⁻³ of the acoustic step at rest, which would
/// cost up to a thousand times a normal run before it stops), and counts as failed (time-step
/// collapse).
pub const STEP_LIMIT_FACTOR: f64 = 10.0;

/// `set` without the step limit the sweeps add (`max_steps=…`), for comparing a stored run's
/// settings with the sweep's.
fn without_step_limit(set: &[String]) -> Vec<String> {
    set.iter()
        .filter(|s| !s.starts_with("max_steps="))
        .cloned()
        .collect()
}

pub mod advice_data;
mod catalogue;
mod estimates;
mod example;
pub mod regression;
mod report;

use catalogue::{scenes, sweeps, Line, Measure, Scene, Sweep};
pub use report::report;

fn fmt_value(v: f64) -> String {
    let s = format!("{v}");
    s.trim_end_matches(".0").to_string()
}

fn scene_run_id(scene: &Scene, line: &Line, res: f64) -> String {
    format!(
        "pareto-{}-{}-{}{}",
        scene.key,
        line.label.replace(' ', "-"),
        scene.resolution_key,
        fmt_value(res)
    )
}

fn scene_set(scene: &Scene, line: &Line, res: f64) -> Vec<String> {
    scene
        .fixed
        .iter()
        .chain(line.extra)
        .map(|s| s.to_string())
        .chain(std::iter::once(format!(
            "{}={}",
            scene.resolution_key,
            fmt_value(res)
        )))
        .collect()
}

/// Whether the `--quick` runs of `sweep` differ from its full runs (then they are stored apart).
fn has_quick_settings(sweep: &Sweep, quick: bool) -> bool {
    quick && !sweep.quick_fixed.is_empty()
}

fn sweep_run_id(sweep: &Sweep, method: &str, value: f64, quick: bool) -> String {
    let suffix = if has_quick_settings(sweep, quick) {
        "-quick"
    } else {
        ""
    };
    format!("map-{}-{method}-{}{suffix}", sweep.key, fmt_value(value))
}

fn sweep_set(sweep: &Sweep, value: f64, quick: bool) -> Vec<String> {
    let extra: &[&str] = if quick { sweep.quick_fixed } else { &[] };
    sweep
        .fixed
        .iter()
        .chain(extra)
        .map(|s| s.to_string())
        .chain(std::iter::once(format!(
            "{}={}",
            sweep.parameter,
            fmt_value(value)
        )))
        .collect()
}

/// Makes (or reuses) every run of the selection.
pub fn run_all(sel: Selection) -> Result<(), String> {
    let wanted = |key: &str| {
        sel.only
            .as_ref()
            .is_none_or(|o| key.starts_with(o.as_str()))
    };
    for scene in scenes().into_iter().filter(|s| wanted(s.key)) {
        let res = if sel.quick { scene.quick } else { scene.full };
        for l in &scene.lines {
            for &r in res {
                run_or_load(
                    &scene_run_id(&scene, l, r),
                    scene.case,
                    l.method,
                    &scene_set(&scene, l, r),
                    sel.force,
                )?;
            }
        }
    }
    if !sel.quick && wanted("example") {
        example::run_all(sel.force)?;
    }
    for sweep in sweeps().into_iter().filter(|s| wanted(s.key)) {
        let values = if sel.quick { sweep.quick } else { sweep.full };
        for m in sweep.methods {
            // Values run in increasing severity: once a method has failed, its harsher values
            // are not made (stored ones are still read); the map marks them as skipped.
            let mut failed_at = None;
            for &v in values {
                let id = sweep_run_id(&sweep, m, v, sel.quick);
                if let Some(at) = failed_at
                    .as_ref()
                    .filter(|_| crate::cost::load(&id).is_none())
                {
                    if !crate::store::plan_only() && !crate::store::filtered_out(&id) {
                        println!("{id}: not made, {m} failed at the milder {at}");
                    }
                    continue;
                }
                let mut set = sweep_set(&sweep, v, sel.quick);
                // The step limit: a multiple of the steps the run's dry run estimates.
                let limit = crate::cost::estimated_steps(sweep.case, m, &set);
                set.extend(limit.map(|n| format!("max_steps={}", (STEP_LIMIT_FACTOR * n).ceil())));
                let run = run_or_load(&id, sweep.case, m, &set, sel.force)?;
                let made = !run.command.is_empty();
                if made && matches!(outcome(&run), Outcome::Failed) && failed_at.is_none() {
                    failed_at = Some(format!("{} = {}", sweep.parameter, fmt_value(v)));
                }
            }
        }
    }
    if wanted("features") {
        if crate::store::plan_only() {
            println!("features\tvalidate tradeoff --only features (timed, median of three)");
        } else if sel.quick {
            println!(
                "features: the feature-cost table is timed (median of three at one thread); \
                 not part of --quick (`validate tradeoff --only features` makes it)"
            );
        } else {
            crate::features::run_all(sel.force)?;
        }
    }
    Ok(())
}

/// A point of a Pareto plot.
#[derive(Clone)]
struct Point {
    line: String,
    res: f64,
    cpu: f64,
    wall: f64,
    work: f64,
    rss: f64,
    error: Option<f64>,
    /// The run's largest disorder indicator (`max_disorder` of its summary).
    disorder: Option<f64>,
    /// The run's `amplitude` (oscillation scenes), shown where no period was measured.
    amplitude: Option<f64>,
    status: String,
    command: String,
}

/// Indices of the points on the Pareto front (no other point is both cheaper and more
/// accurate).
fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (c, e) = points[i];
            !points
                .iter()
                .enumerate()
                .any(|(j, &(cj, ej))| j != i && cj <= c && ej <= e && (cj < c || ej < e))
        })
        .collect()
}

/// The value a run is judged by: the measured quantity (extrapolated scenes) or the signed
/// relative error.
/// The run's relative error under `m` (for [`Measure::FiniteElement`] against the FE period of
/// `method`'s own small-strain law).
fn value_of(r: &CostedRun, m: Measure, method: &str) -> Option<f64> {
    match m {
        Measure::FiniteElement {
            num,
            clamp,
            thickness,
            nu,
        } => {
            let reference =
                crate::fem_plate::period(crate::fem_plate::law_of(method), clamp, thickness, nu)?;
            Some(r.num(num)? / reference - 1.0)
        }
        Measure::ClosedForm { num, den } => Some(r.num(num)? / r.num(den)? - 1.0),
        Measure::Error { key } => r.num(key),
    }
}

/// The summary key a measure reads from a run.
fn measured_key(m: Measure) -> &'static str {
    match m {
        Measure::FiniteElement { num, .. } | Measure::ClosedForm { num, .. } => num,
        Measure::Error { key } => key,
    }
}

fn spacing(scene: &Scene, res: f64) -> f64 {
    if scene.resolution_key == "dp" {
        res
    } else {
        1.0 / res
    }
}

/// Every stored run of `scene` (each line at each resolution of either list, its settings
/// those of the scene), line by line, coarse to fine within a line as listed.
fn stored_runs(scene: &Scene) -> Vec<(&Line, f64, CostedRun)> {
    let mut res: Vec<f64> = scene.quick.iter().chain(scene.full).copied().collect();
    res.sort_by(f64::total_cmp);
    res.dedup();
    scene
        .lines
        .iter()
        .flat_map(|l| res.iter().map(move |&r| (l, r)))
        .filter_map(|(l, r)| {
            let run = crate::cost::load(&scene_run_id(scene, l, r))?;
            (run.set == scene_set(scene, l, r)).then_some((l, r, run))
        })
        .collect()
}

/// The refinement value of a spacing (the inverse of [`spacing`]).
fn spacing_inverse(scene: &Scene, h: f64) -> f64 {
    if scene.resolution_key == "dp" {
        h
    } else {
        1.0 / h
    }
}

fn short(status: &str) -> String {
    let s: String = status.chars().take(90).collect();
    s.replace('|', "/")
}

/// A cell of the stability map.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Outcome {
    /// Completed, disorder within the limit.
    Ordered,
    /// Completed, disorder above the limit.
    Disordered,
    /// Stopped during the run.
    Failed,
    /// Input refused before the run.
    Rejected,
}

/// Classifies a run (see [`DISORDER_LIMIT`]).
pub fn outcome(run: &CostedRun) -> Outcome {
    let status = run.status();
    if status.starts_with("rejected") {
        Outcome::Rejected
    } else if status != "completed" {
        Outcome::Failed
    } else if run.num("max_disorder").is_some_and(|d| d <= DISORDER_LIMIT) {
        Outcome::Ordered
    } else {
        Outcome::Disordered
    }
}

/// One sentence on a method's runs of a sweep (in increasing severity, rejected values left
/// out): up to which value it stays ordered, where it first becomes disordered and where it
/// first fails, and why.
fn usability_sentence(parameter: &str, runs: &[(f64, &CostedRun)]) -> String {
    let at = |v: f64| format!("{parameter} = {}", fmt_value(v));
    let disorder = |r: &CostedRun| {
        r.num("max_disorder")
            .map_or("–".into(), |d| format!("{d:.2}"))
    };
    let Some(&(mildest, _)) = runs.first() else {
        return ": not run yet".into();
    };
    let first = |o: fn(&Outcome) -> bool| runs.iter().position(|(_, r)| o(&outcome(r)));
    let disordered = first(|o| matches!(o, Outcome::Disordered));
    let failed = first(|o| matches!(o, Outcome::Failed));
    let fails = |k: usize| {
        format!(
            "fails at {} ({})",
            at(runs[k].0),
            failure_reason(&runs[k].1.status())
        )
    };
    let first_bad = disordered.into_iter().chain(failed).min().unwrap_or(0);
    let mildest_note = |k: usize| {
        if k == 0 {
            ", already at the mildest value run"
        } else {
            ""
        }
    };
    let bad = match (disordered, failed) {
        (None, None) => {
            return format!(
                "stays ordered over the values run ({} to {})",
                fmt_value(mildest),
                fmt_value(runs[runs.len() - 1].0)
            )
        }
        (Some(d), Some(f)) if d < f => format!(
            "becomes disordered at {} (max disorder {}){}, and {}",
            at(runs[d].0),
            disorder(runs[d].1),
            mildest_note(d),
            fails(f)
        ),
        (Some(d), None) => format!(
            "becomes disordered at {} (max disorder {}){}",
            at(runs[d].0),
            disorder(runs[d].1),
            mildest_note(d)
        ),
        (_, Some(f)) => format!("{}{}", fails(f), mildest_note(f)),
    };
    if first_bad == 0 {
        bad
    } else {
        format!("is usable up to {}; it {bad}", at(runs[first_bad - 1].0))
    }
}

/// The reason a failed run stopped, in a few words.
fn failure_reason(status: &str) -> &'static str {
    let s = status.to_lowercase();
    if s.contains("step limit") {
        "time-step collapse: more steps than the limit"
    } else if s.contains("time step") || s.contains("collapse") {
        "time-step collapse"
    } else if s.contains("non-finite") || s.contains("nan") || s.contains("infinite") {
        "non-finite state"
    } else if s.contains("neighbour") {
        "lost neighbours"
    } else if s.contains("j ≤ 0") || s.contains("invert") || s.contains("j <= 0") {
        "inverted particles"
    } else if s.contains("rejected") {
        "rejected input"
    } else {
        "other (see the table)"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let pts = [(1.0, 0.1), (2.0, 0.05), (3.0, 0.08), (0.5, 0.2), (2.0, 0.2)];
        assert_eq!(pareto_front(&pts), vec![0, 1, 3]);
    }
}
