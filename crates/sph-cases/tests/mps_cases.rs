//! The MPS paper's cases at a tiny resolution for a few steps without output: each reports its
//! figures, and what physics fixes at that size is asserted (symmetry, conservation, the sign
//! and order of a response). The validated figures themselves are re-checked at their stored
//! sizes by validation/tests/regression.rs.

use sph_cases::{find_case, RunOptions};

fn run(
    case: &str,
    method: &str,
    set: &[&str],
    keys: &[&str],
) -> serde_json::Map<String, serde_json::Value> {
    let c = find_case(case).unwrap();
    let mut p = c.params();
    for a in set {
        p.apply_assignment(a).unwrap();
    }
    let (record, summary) = c.run(method, &p, &RunOptions::default()).unwrap();
    assert!(record.failure.is_none(), "{case}: {:?}", record.failure);
    assert!(record.steps > 0);
    for k in keys {
        assert!(
            summary.contains_key(*k),
            "{case} {method}: no `{k}` in {:?}",
            summary.keys().collect::<Vec<_>>()
        );
    }
    summary
}

#[test]
fn pressurised_ring_runs() {
    let s = run(
        "pressurised-ring-2d",
        "mps",
        &["dp=0.5", "end_time=0.01", "pressure=1000"],
        &[
            "inner_radius_max",
            "inner_radius_final",
            "outer_radius_final",
            "inner_displacement_theory",
            "outer_displacement_theory",
            "limit_pressure_incompressible",
            "max_disorder",
        ],
    );
    let n = |k: &str| s[k].as_f64().unwrap();
    // An internal pressure pushes both surfaces out, the inner further (Lamé: u ∝ a²/r for an
    // incompressible wall), and keeps the ring round (the load and the polar layers are
    // symmetric: ovality from the layers' discrete angles only, measured 1 % of the inner
    // displacement; allowed 5 %).
    assert!(n("inner_displacement_final") > n("outer_displacement_final"));
    assert!(n("outer_displacement_final") > 0.0);
    assert!(n("inner_ovality_max") < 0.05 * n("inner_displacement_final"));
}

#[test]
fn slab_tension_runs() {
    let s = run(
        "slab-tension-2d",
        "mps",
        &["resolution=4", "end_time=2e-4"],
        &["final_length", "middle_strain_uniformity", "max_disorder"],
    );
    // Pulled, the middle stretches: volume ratios above 1 and a positive mean strain.
    assert!(s["middle_jacobian_min"].as_f64().unwrap() >= 1.0);
    assert!(s["middle_strain_mean"].as_f64().unwrap() > 0.0);
}

#[test]
fn colliding_rings_run_with_and_without_contact() {
    for (flag, expect) in [("contact=true", true), ("contact=false", false)] {
        let s = run(
            "colliding-rings-2d",
            "mps",
            &["dp=0.005", "gap=0.012", "end_time=1e-3", flag],
            &[
                "front_separation_min",
                "interpenetration_max",
                "left_velocity_final",
                "contact",
            ],
        );
        assert_eq!(s["contact"], serde_json::json!(expect));
        // Before the rings meet (1 ms, 0.4 mm of a 12 mm gap): free flight, each ring at its
        // speed, no net momentum (the rings are mirror images), energy kept to round-off.
        let v0 = s["v0_m_per_s"].as_f64().unwrap();
        assert!((s["left_velocity_final"].as_f64().unwrap() - v0).abs() < 1e-9 * v0);
        assert!((s["right_velocity_final"].as_f64().unwrap() + v0).abs() < 1e-9 * v0);
        assert!(s["momentum_x_final"].as_f64().unwrap().abs() < 1e-12);
        assert!(s["energy_drift"].as_f64().unwrap().abs() < 1e-12);
    }
    let c = find_case("colliding-rings-2d").unwrap();
    let mut p = c.params();
    p.apply_assignment("gap=0.001").unwrap();
    assert!(
        c.run("mps", &p, &RunOptions::default()).is_err(),
        "gap < r_e must be refused"
    );
}

#[test]
fn cantilever_plate_runs_with_mps_and_tl_hf() {
    for m in ["mps", "tl-hf"] {
        let s = run(
            "cantilever-plate-2d",
            m,
            &[
                "resolution=3",
                "length=0.2",
                "thickness=0.02",
                "base_length=0.04",
                "end_time=2e-3",
            ],
            &[
                "amplitude",
                "amplitude_dimensionless",
                "period_dimensionless_paper",
                "period_dimensionless_theory",
                "amplitude_dimensionless_theory",
            ],
        );
        assert!(s.contains_key("period"), "{m}");
    }
}

#[test]
fn static_cantilever_runs() {
    let s = run(
        "static-cantilever-2d",
        "mps",
        &["resolution=4", "length=0.16", "end_time=2e-3"],
        &[
            "tip_deflection",
            "tip_deflection_theory",
            "tip_deflection_error",
            "deflection_w",
        ],
    );
    // 2 ms into a load applied at once: the tip has started down the load's way, far from the
    // static deflection (the full run takes 2 s; its figure is in the regression tests).
    let (w, theory) = (
        s["tip_deflection"].as_f64().unwrap(),
        s["tip_deflection_theory"].as_f64().unwrap(),
    );
    assert!(w > 0.0 && w < 0.1 * theory, "{w} of {theory}");
}
