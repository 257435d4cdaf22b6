//! docs/tradeoffs.md, "Error estimates": `sph converge`'s estimator
//! ([`sph_driver::convergence::estimate`]) calibrated on the stored ladders of the Pareto
//! scenes, whose true error is known (a closed form, finite elements, Hertz, Timoshenko).
//!
//! Every window of three and of four consecutive stored resolutions of a method is a ladder as
//! `sph converge` would see it after that many levels; its estimate of the finest level's error
//! is compared with that level's true error against the scene's reference, and with its error
//! against the method's own limit (its finest stored run, at least one level finer than the
//! window), which separates the discretisation error the estimator measures from a model bias
//! (a method converging to another value) that no refinement study can see.

use super::*;
use sph_cases::convergence::{estimate_with, Estimate, Factors, Sample};

/// One ladder of the calibration.
struct Ladder {
    scene: &'static str,
    line: &'static str,
    /// The window's resolutions.
    levels: Vec<f64>,
    estimate: Estimate,
    /// The finest level's error against the reference, relative to the level's value.
    true_error: f64,
    /// Its error against the method's finest stored run (beyond the window), if there is one.
    self_error: Option<f64>,
}

/// The ladders of every scene's stored runs, estimated with `factors`.
fn ladders(factors: &Factors) -> Vec<Ladder> {
    let mut out = Vec::new();
    for scene in scenes() {
        let runs = stored_runs(&scene);
        for line in &scene.lines {
            // (spacing, value relative to the reference = 1 + signed error), coarse to fine.
            let mut pts: Vec<(f64, f64, f64)> = runs
                .iter()
                .filter(|(l, _, run)| l.label == line.label && run.exit_code == 0)
                .filter_map(|(_, r, run)| {
                    let e = value_of(run, scene.measure, line.method)?;
                    e.is_finite().then_some((spacing(&scene, *r), 1.0 + e, *r))
                })
                .collect();
            pts.sort_by(|a, b| b.0.total_cmp(&a.0));
            let finest = pts.last().copied();
            for n in [3, 4] {
                for w in pts.windows(n) {
                    let samples: Vec<Sample> = w
                        .iter()
                        .map(|p| Sample {
                            spacing: p.0,
                            value: p.1,
                        })
                        .collect();
                    let Ok(e) = estimate_with(&samples, factors) else {
                        continue;
                    };
                    let f = w[n - 1].1;
                    let beyond = finest.filter(|q| q.0 < w[n - 1].0);
                    out.push(Ladder {
                        scene: scene.key,
                        line: line.label,
                        levels: w.iter().map(|p| p.2).collect(),
                        true_error: (f - 1.0).abs() / f.abs(),
                        self_error: beyond.map(|q| (f - q.1).abs() / f.abs()),
                        estimate: e,
                    });
                }
            }
        }
    }
    out
}

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// A ladder whose fitted limit lies off the reference by more than its own estimate: its
/// method converges to another value (a model bias).
fn biased(l: &Ladder) -> bool {
    (l.estimate.value - 1.0).abs() > l.estimate.error_estimate
}

/// `k of n (p %)`, or `–` for none.
fn share(k: usize, of: usize) -> String {
    if of == 0 {
        "–".to_string()
    } else {
        format!("{k} of {of} ({:.0} %)", 100.0 * k as f64 / of as f64)
    }
}

/// The coverage row of `ladders` with `n` levels.
fn coverage_row(md: &mut String, label: &str, all: &[Ladder], n: usize) {
    let set: Vec<&Ladder> = all.iter().filter(|l| l.levels.len() == n).collect();
    let asym: Vec<&Ladder> = set
        .iter()
        .copied()
        .filter(|l| l.estimate.asymptotic)
        .collect();
    let within = |l: &Ladder| l.true_error <= l.estimate.error_estimate;
    let tight = |l: &Ladder| within(l) && l.estimate.error_estimate <= 3.0 * l.true_error;
    let fair: Vec<&Ladder> = asym.iter().copied().filter(|l| !biased(l)).collect();
    let with_self: Vec<&Ladder> = asym
        .iter()
        .copied()
        .filter(|l| l.self_error.is_some())
        .collect();
    let self_within = with_self
        .iter()
        .filter(|l| l.self_error.is_some_and(|s| s <= l.estimate.error_estimate))
        .count();
    writeln!(
        md,
        "| {label} | {n} | {} | {} | {} | {} | {} | {} | {} |",
        set.len(),
        asym.len(),
        share(asym.iter().filter(|l| within(l)).count(), asym.len()),
        share(fair.iter().filter(|l| tight(l)).count(), fair.len()),
        share(self_within, with_self.len()),
        share(set.iter().filter(|l| within(l)).count(), set.len()),
        set.len() - asym.len()
    )
    .unwrap();
}

/// Writes the section; false if no ladder is stored.
pub(super) fn section(md: &mut String) -> bool {
    let all = ladders(&Factors::CONVERGE);
    if all.is_empty() {
        return false;
    }
    let cfd = ladders(&Factors::CFD_PRACTICE);
    writeln!(md, "## Error estimates\n").unwrap();
    writeln!(
        md,
        "`sph converge` estimates the error of its finest run from the ladder of resolutions it \
         ran (the procedure, in `sph_driver::convergence`: a least-squares fit \
         `f(h) = f₀ + α hᵖ` over the levels as Eça & Hoekstra 2014 do, with a safety factor \
         of {v} when the ladder is verified asymptotic — monotone, an observed order in \
         [0.95, 2.05), and from four levels on, the finest three agreeing with the whole \
         ladder's order within {a:.0} % — and {u} otherwise; oscillating values never meet a \
         tolerance; a ladder of more than four levels is estimated from its finest four). Here it is calibrated on the stored runs of the scenes above, whose true \
         errors are known: every window of 3 and of 4 consecutive stored resolutions of a \
         method is a ladder as `sph converge` sees it after that many levels. *Estimate* is \
         its estimate of the finest level's error; *true* that level's error against the \
         scene's reference; *self* its error against the method's own finest stored run (a \
         finer level outside the window). A ladder can only estimate the discretisation error \
         (*self*, as far as the finest run is converged), never a model bias, the distance \
         between the method's limit and the physical reference (*limit*: the fitted `f₀` \
         against the reference); a verified ladder whose limit lies off the reference by more \
         than its estimate is *biased*. The factors were chosen on these ladders: the row \
         *CFD practice* shows the grid convergence index's usual 1.25 (verified) and 30 % \
         (order agreement) on the same ladders.\n",
        v = Factors::CONVERGE.verified,
        u = Factors::CONVERGE.unverified,
        a = 100.0 * Factors::CONVERGE.order_agreement,
    )
    .unwrap();
    writeln!(
        md,
        "| factors | levels | ladders | verified asymptotic | true error within the estimate \
         | the same, biased ladders aside, estimate ≤ 3 × true | self error within the \
         estimate | all ladders: true error within the estimate | flagged not asymptotic \
         |\n|---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    for n in [3, 4] {
        coverage_row(md, "`sph converge`", &all, n);
    }
    for n in [3, 4] {
        coverage_row(md, "CFD practice", &cfd, n);
    }
    let mut names: Vec<String> = Vec::new();
    for l in all.iter().filter(|l| l.estimate.asymptotic && biased(l)) {
        let key = format!("{} {}", l.scene, l.line);
        if !names.iter().any(|b| b.starts_with(&key)) {
            names.push(format!(
                "{key} (limit {:+.2} %)",
                100.0 * (l.estimate.value - 1.0)
            ));
        }
    }
    writeln!(
        md,
        "\nThe biased ladders: {}. Their methods converge to another value than the reference: \
         these are the accuracy gaps of the methods (docs/validation.md and the scenes above \
         discuss them), not of the estimate, which refinement cannot reveal; a user must add \
         such a bias, measured on the nearest validated scene, to the estimate of their own \
         run. With three levels no ladder is verified (the order cannot be cross-checked), \
         and the estimate takes the factor {u}.\n",
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        },
        u = Factors::CONVERGE.unverified,
    )
    .unwrap();
    writeln!(
        md,
        "<details><summary>Every ladder ({})</summary>\n\n| scene | method | resolutions | \
         order | asymptotic | estimate | true | self | limit vs reference |\n|---|---|---|---|---|---|---|---|---|",
        all.len()
    )
    .unwrap();
    for l in &all {
        let levels: Vec<String> = l.levels.iter().map(|r| format!("{r}")).collect();
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:+.2} % |",
            l.scene,
            l.line,
            levels.join(", "),
            l.estimate
                .order
                .map_or("–".to_string(), |p| format!("{p:.2}")),
            if l.estimate.asymptotic { "yes" } else { "no" },
            pct(l.estimate.error_estimate),
            pct(l.true_error),
            l.self_error.map_or("–".to_string(), pct),
            100.0 * (l.estimate.value - 1.0)
        )
        .unwrap();
    }
    writeln!(md, "\n</details>\n").unwrap();
    super::example::section(md);
    true
}
