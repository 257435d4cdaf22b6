//! The validated figures of docs/tradeoffs.md re-checked on their cheapest stored runs (every
//! scene and method whose cheapest run cost at most 4 CPU s as stored; the full ladders stay in
//! `validate tradeoff`): each re-run through the library must reproduce its stored value.
//!
//! Tolerance 1e-6 relative: the runs are deterministic for an input and thread count, and
//! neither the build profile nor the output schedule changes the arithmetic, but the thread
//! count (the stored runs used 2) may change a reduction's summation order in the last bits,
//! and the validated figures are quoted to 0.01 % at best: anything that moves one is a
//! change of 1e-4 or more.

use sph_validation::tradeoff::regression::checks;

#[test]
fn every_cheap_stored_trade_off_run_reproduces_its_value() {
    let checks = checks(4.0);
    // The 2D plate (six methods), the homogeneous compression (three), the MPS cantilever and
    // ring, and the Hertz impact (UL): a check per family at least.
    assert!(checks.len() >= 10, "{} checks", checks.len());
    for family in ["tl", "ul-", "mps"] {
        assert!(
            checks.iter().any(|c| c.method.starts_with(family)),
            "no check of {family}"
        );
    }
    // SPH_REGRESSION_ONLY=ID re-checks one stored run alone.
    let only = std::env::var("SPH_REGRESSION_ONLY").ok();
    let failures: Vec<String> = checks
        .iter()
        .filter(|c| only.as_ref().is_none_or(|id| *id == c.id))
        .filter_map(|c| {
            match c
                .rerun()
                .inspect(|(v, _)| eprintln!("{} {} = {v:e}", c.id, c.key))
            {
                Ok((value, error)) if (value / c.stored - 1.0).abs() <= 1e-6 => {
                    assert!((error - c.error).abs() <= 1e-6 * c.error.abs().max(1e-3));
                    None
                }
                Ok((value, error)) => Some(format!(
                    "{} ({} {} {}): {} = {value:e}, stored {:e} (error {:+.4} %, stored {:+.4} %)",
                    c.id,
                    c.case,
                    c.method,
                    c.set.join(" "),
                    c.key,
                    c.stored,
                    100.0 * error,
                    100.0 * c.error
                )),
                Err(e) => Some(e),
            }
        })
        .collect();
    assert!(
        failures.is_empty(),
        "a validated figure moved (re-run `validate tradeoff --force --only SCENE` and \
         regenerate the docs if the change is meant):\n{}",
        failures.join("\n")
    );
}

/// The cheapest stored runs of docs/validation.md (solver time at most 2.5 s as stored), each
/// re-run through the library: every physics figure of its summary reproduces (tolerance as
/// above), its status too.
#[test]
fn every_cheap_stored_validation_run_reproduces_its_summary() {
    use sph_validation::tradeoff::regression::{compare, validation_runs};
    let runs = validation_runs(2.5);
    assert!(runs.len() >= 4, "{} runs", runs.len());
    let only = std::env::var("SPH_REGRESSION_ONLY").ok();
    let mut moved = Vec::new();
    for r in runs
        .iter()
        .filter(|r| only.as_ref().is_none_or(|id| *id == r.id))
    {
        eprintln!("{}", r.id);
        match compare(r, 1e-6) {
            Ok(m) => moved.extend(m),
            Err(e) => moved.push(e),
        }
    }
    assert!(
        moved.is_empty(),
        "a validated figure moved (re-run its `validate` subcommand with --force and \
         regenerate the docs if the change is meant):\n{}",
        moved.join("\n")
    );
}
