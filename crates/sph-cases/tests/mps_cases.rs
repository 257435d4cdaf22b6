//! Smoke tests of the MPS paper's cases: each runs at a tiny resolution for a few steps without
//! output and reports its figures.

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
    run(
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
}

#[test]
fn slab_tension_runs() {
    run(
        "slab-tension-2d",
        "mps",
        &["resolution=4", "end_time=2e-4"],
        &["final_length", "middle_strain_uniformity", "max_disorder"],
    );
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
    run(
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
}
