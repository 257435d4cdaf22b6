//! The folding strip (`folding-strip`): a free strip whose halves are thrown shut about its
//! midpoint, coarse (3 particles through the thickness, 270 particles) so the file runs in
//! seconds. With self-contact the ends' faces stop short of each other (measured: TL 0.552 dp,
//! TL-HF 0.743 dp); without it they pass through (0.0001 dp); no external force acts, so
//! momentum is conserved to round-off (measured 8e-17 M v_tip) and, with TL, the energy
//! `K + W + U_c` (the contact force is −∇U_c) to the time integrator's error (measured
//! 7.9e-4 E0; TL-HF's Laplacian shear is no gradient of W and loses 40 % here). docs/validation.md
//! ("Contact and friction") shows the strip at three resolutions.

use sph_cases::{find_case, RunOptions};

fn run(method: &str, set: &[&str]) -> serde_json::Map<String, serde_json::Value> {
    let c = find_case("folding-strip").unwrap();
    let mut p = c.params_for(method);
    for a in ["resolution=3"].iter().chain(set) {
        p.apply_assignment(a).unwrap();
    }
    let (record, summary) = c.run(method, &p, &RunOptions::default()).unwrap();
    assert!(record.failure.is_none(), "{method}: {:?}", record.failure);
    eprintln!("{method} {set:?}: {summary:?}");
    summary
}

fn f(s: &serde_json::Map<String, serde_json::Value>, key: &str) -> f64 {
    s[key].as_f64().unwrap_or(f64::NAN)
}

#[test]
fn self_contact_keeps_the_folded_faces_apart_and_the_budgets_closed() {
    let on = run("tl", &[]);
    let off = run("tl", &["self_contact=false"]);
    assert_eq!(on["self_contact"], true);
    assert_eq!(off["self_contact"], false);
    let (gap_on, gap_off) = (f(&on, "smallest_gap"), f(&off, "smallest_gap"));
    assert!(
        gap_on > 0.4,
        "interpenetration with self-contact: {gap_on} dp"
    );
    assert!(
        gap_off < 0.2,
        "without self-contact the faces should pass: {gap_off} dp"
    );
    assert!(f(&on, "contact_pairs_max") > 0.0 && f(&off, "contact_pairs_max") == 0.0);
    assert!(f(&on, "contact_energy_peak") > 0.0);
    for s in [&on, &off] {
        assert!(f(s, "momentum_error") < 1e-12, "{s:?}");
    }
    // The budget with the contact energy: the Verlet step's error at this resolution.
    assert!(f(&on, "energy_error") < 2e-3, "{on:?}");
}

#[test]
fn tl_hf_folds_with_self_contact_and_keeps_momentum() {
    let s = run("tl-hf", &[]);
    assert!(f(&s, "smallest_gap") > 0.4, "{s:?}");
    assert!(f(&s, "momentum_error") < 1e-12, "{s:?}");
    // Not a budget (TL-HF's shear is no gradient of W): a guard against a change (0.40).
    assert!(f(&s, "energy_error") < 0.5, "{s:?}");
}

#[test]
fn an_odd_count_along_the_strip_is_one_error_naming_the_key() {
    let c = find_case("folding-strip").unwrap();
    let mut p = c.params_for("tl");
    p.apply_assignment("aspect=20.5").unwrap();
    p.apply_assignment("resolution=3").unwrap();
    let e = c
        .run("tl", &p, &RunOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("aspect") && e.lines().count() == 1, "{e}");
}
