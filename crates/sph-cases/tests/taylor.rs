//! The Taylor bar (`taylor-bar-3d`) at a coarse resolution (3 particles across the radius,
//! 840 particles per bar) over the reference's 80 µs, so the file runs in seconds in a dev
//! build: the physics every resolution must show. The comparison with the published final
//! length and radius at finer resolutions is in the case's docs.
//!
//! Measured here (R/dp = 3, release build, one thread, the reference set-up with the defaults:
//! mirror wall, `riemann = limited-no-jump`, `gnog_xi = 0.2`): see each test's docs.

use sph_cases::{find_case, RunOptions};

fn run(method: &str, set: &[&str]) -> serde_json::Map<String, serde_json::Value> {
    let c = find_case("taylor-bar-3d").unwrap();
    let mut p = c.params_for(method);
    for a in ["resolution=3"].iter().chain(set) {
        p.apply_assignment(a).unwrap();
    }
    let (record, summary) = c.run(method, &p, &RunOptions::default()).unwrap();
    assert!(record.failure.is_none(), "{method}: {:?}", record.failure);
    summary
}

fn f(s: &serde_json::Map<String, serde_json::Value>, key: &str) -> f64 {
    s[key].as_f64().unwrap_or(f64::NAN)
}

/// With the defaults (the bar and its mirror image, one body, so that the mid-plane is the
/// reference's wall that holds the face axially and lets it slide radially) the bar shortens
/// and spreads, plastic work takes most of the kinetic energy and the bar ends nearly at rest.
/// Measured (R/dp 3): L_f −2.0 % (GNOG), −2.8 % (OG), −5.4 % (OAS) from the reference's
/// 26.55 mm; R_f +0.2 %, +6.0 %, +22.6 % from its 5.61 mm; plastic work 1.17, 0.95, 1.71 of
/// KE0; budget residual +0.253 (GNOG: its spin-rotated penalty is not energy-conserving),
/// −0.003 (OG: every term exactly accumulated, no wall contact), +0.021 (OAS; its artificial
/// stress does work 1.47 times KE0 here, so its plastic work exceeds KE0 with the budget
/// closed); final kinetic energy ≤ 0.42 % of KE0; the bar and its image keep zero total
/// momentum to round-off (≤ 2.2e-15 of the bar's: a check of the symmetry, which holds
/// whether or not a method conserves momentum). Tolerances: GNOG's length and radius within
/// 5 % of the reference at this resolution (length within 1.5 %, radius within 4.4 % at R/dp
/// 4, 6 and 8);
/// OG and OAS, which have no hourglass control once the Riemann dissipation is limited,
/// spread wider than the reference (up to 30 %) with the length within 8 %; the budget closes
/// within 2 % (OG), 5 % (OAS), 35 % (GNOG).
#[test]
fn the_bar_shortens_spreads_and_dissipates_into_plastic_work() {
    let (l0, r0) = (32.4e-3, 3.2e-3);
    for (method, energy_tol) in [("ul-gnog", 0.35), ("ul-og", 0.02), ("ul-oas", 0.05)] {
        let s = run(method, &[]);
        let ke0 = f(&s, "kinetic_energy_initial");
        // ½ ρ π R² L v² of the reference bar (one bar, not bar and image).
        let theory = 0.5 * 7830.0 * std::f64::consts::PI * r0 * r0 * l0 * 287.0 * 287.0;
        assert!(
            (ke0 / theory - 1.0).abs() < 1e-9,
            "{method}: {ke0} vs {theory}"
        );
        let (le, re) = (f(&s, "final_length_error"), f(&s, "final_radius_error"));
        if method == "ul-gnog" {
            assert!(le.abs() < 0.05 && re.abs() < 0.05, "{method}: {s:?}");
        } else {
            assert!(le.abs() < 0.08 && re > 0.0 && re < 0.3, "{method}: {s:?}");
        }
        assert!(f(&s, "final_length") < 0.9 * l0, "{method}: {s:?}");
        assert!(f(&s, "final_radius") > 1.5 * r0, "{method}: {s:?}");
        assert!(f(&s, "plastic_work") > 0.8 * ke0, "{method}: {s:?}");
        assert!(
            f(&s, "kinetic_energy_final") < 0.02 * ke0,
            "{method}: {s:?}"
        );
        assert!(f(&s, "elastic_energy_final") >= 0.0, "{method}: {s:?}");
        assert!(
            f(&s, "energy_balance").abs() < energy_tol,
            "{method}: {s:?}"
        );
        // No tool: the wall does no work; the mid-plane passes the bar's momentum.
        assert_eq!(f(&s, "wall_work"), 0.0, "{method}");
        assert!(f(&s, "wall_impulse") < 0.0, "{method}: {s:?}");
        assert!(
            f(&s, "momentum_balance_wall") < 1e-12,
            "{method}: {}",
            f(&s, "momentum_balance_wall")
        );
        assert!(f(&s, "max_plastic_strain") > 0.5, "{method}: {s:?}");
        // Adiabatic heating from 293.15 K.
        assert!(f(&s, "max_temperature") > 500.0, "{method}: {s:?}");
        // The defaults are the reference set-up.
        assert_eq!(f(&s, "final_length_reference"), 26.55e-3);
        assert_eq!(f(&s, "final_radius_reference"), 5.61e-3);
    }
}

/// The old set-up — the wall a half-space tool, the UL family's Riemann default
/// (`sphinxsys-tests`, β = 1) — is kept as options. With the tool the momentum the bar loses
/// is the wall's impulse to round-off (OG: every pair force is antisymmetric; measured
/// 9.5e-16) and the tool takes energy (its contact work is negative). β = 1 shrinks the
/// mushroom: measured R_f 4.49 mm against 5.84 mm with the limiter (both with the tool), the
/// dissipative pressure ½ ρ0 c0 |u_ij| of separating pairs resisting the radial flow of the
/// struck end. Tolerance: β = 1's radius below 0.85 of the limiter's.
#[test]
fn the_tool_wall_conserves_momentum_and_full_riemann_dissipation_shrinks_the_mushroom() {
    let limited = run("ul-og", &["wall=tool"]);
    let full = run("ul-og", &["wall=tool", "riemann=sphinxsys-tests"]);
    for s in [&limited, &full] {
        assert!(f(s, "momentum_balance_wall") < 1e-9, "{s:?}");
        assert!(f(s, "wall_impulse") < 0.0, "{s:?}");
        assert!(f(s, "wall_work") < 0.0, "{s:?}");
        assert!(f(s, "riemann_dissipated") > 0.0, "{s:?}");
    }
    let (rl, rf) = (f(&limited, "final_radius"), f(&full, "final_radius"));
    assert!(rf < 0.85 * rl, "β = 1: {rf}, limiter: {rl}");
    assert!(
        f(&full, "riemann_dissipated") > 3.0 * f(&limited, "riemann_dissipated"),
        "{full:?}"
    );
}

/// Another set-up has no published reference; a J2 bar spreads too; a constant of the other
/// law and ENOG are one-line errors before any work.
#[test]
fn other_setups_have_no_reference_and_bad_input_is_refused() {
    let s = run("ul-og", &["law=j2", "end_time=2e-5"]);
    assert!(s["final_length_reference"].is_null(), "{s:?}");
    assert!(s["final_radius_reference"].is_null(), "{s:?}");
    assert!(f(&s, "plastic_work") > 0.0, "{s:?}");
    assert!(f(&s, "final_radius") > 3.2e-3, "{s:?}");
    let c = find_case("taylor-bar-3d").unwrap();
    for (method, set, expect) in [
        ("ul-og", "yield_stress=3e8", "yield_stress"),
        ("ul-enog", "law=j2", "ul-enog"),
        ("tl-hf", "law=j2", "tl-hf"),
    ] {
        let mut p = c.params_for(method);
        p.apply_assignment(set).unwrap();
        let e = c
            .run(method, &p, &RunOptions::default())
            .err()
            .unwrap_or_else(|| panic!("{method} {set} ran"))
            .to_string();
        assert!(e.contains(expect), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

/// TL (`tl`, `tl-gm`: the finite-strain exponential-map return on a Hencky law, the wall a
/// half-space tool) at the same resolution as UL. Measured (R/dp = 3, the reference set-up
/// with `wall = tool` and for UL-OG `riemann = sphinxsys-tests`, in which these were measured):
/// L_f = 28.31 mm (tl), 28.33 mm (tl-gm) against UL-OG's 27.19 mm (+4.1 %, +4.2 %); R_f =
/// 3.85, 3.80 mm against 4.49 mm; plastic work 0.80, 0.90 of KE0 (UL-OG 0.67); momentum lost
/// = wall impulse to 6e-16, 1e-15. Tolerances: the final length within 8 % of UL-OG's at this
/// resolution (the two families differ by 4 % here; their kernels live in different
/// configurations, so they agree only as both converge), the bar shortens by more than 10 %
/// and spreads by more than 10 %, plastic work above half of KE0, the bar nearly at rest.
#[test]
fn tl_bar_shortens_like_ul_og() {
    let (l0, r0) = (32.4e-3, 3.2e-3);
    // The set-up these were measured in: the tool wall, β = 1 for UL.
    let ul = run("ul-og", &["wall=tool", "riemann=sphinxsys-tests"]);
    let l_ul = f(&ul, "final_length");
    for method in ["tl", "tl-gm"] {
        let s = run(method, &["wall=tool"]);
        let (lf, rf) = (f(&s, "final_length"), f(&s, "final_radius"));
        let ke0 = f(&s, "kinetic_energy_initial");
        println!(
            "{method}: L_f {lf:.5e} (ul-og {l_ul:.5e}, {:+.2} %), R_f {rf:.5e}, W_p/KE0 {:.3}, \
             momentum balance {:.1e}",
            100.0 * (lf / l_ul - 1.0),
            f(&s, "plastic_work") / ke0,
            f(&s, "momentum_balance_wall")
        );
        assert!((lf / l_ul - 1.0).abs() < 0.08, "{method}: {s:?}");
        assert!(lf < 0.9 * l0 && rf > 1.1 * r0, "{method}: {s:?}");
        assert!(f(&s, "plastic_work") > 0.5 * ke0, "{method}: {s:?}");
        assert!(f(&s, "plastic_work") < ke0, "{method}: {s:?}");
        assert!(
            f(&s, "kinetic_energy_final") < 0.02 * ke0,
            "{method}: {s:?}"
        );
        assert!(f(&s, "momentum_balance_wall") < 1e-9, "{method}: {s:?}");
        assert!(f(&s, "max_temperature") > 350.0, "{method}: {s:?}");
        assert!(
            s["energy_balance"].is_null(),
            "{method}: TL keeps no budget"
        );
    }
}

/// The snapshots of a plastic run carry the equivalent plastic strain (`plastic_strain`) and,
/// with Johnson–Cook's adiabatic heating, `temperature`, for UL and TL (the output
/// field); the last snapshot's largest ε̄p is the summary's `max_plastic_strain`.
#[test]
fn plastic_runs_write_the_plastic_strain_field() {
    for method in ["ul-og", "tl"] {
        let dir =
            std::env::temp_dir().join(format!("sph-taylor-fields-{method}-{}", std::process::id()));
        let c = find_case("taylor-bar-3d").unwrap();
        let mut p = c.params_for(method);
        for a in ["resolution=2", "end_time=5e-6", "snapshots=1"] {
            p.apply_assignment(a).unwrap();
        }
        let options = RunOptions {
            output: Some(dir.join("bar")),
            ..Default::default()
        };
        let (record, summary) = c.run(method, &p, &options).unwrap();
        assert!(record.failure.is_none(), "{method}: {:?}", record.failure);
        let file = record.file.expect("a results file");
        let contents = sph_output::read_file(&file).unwrap();
        let last = contents.snapshots.last().unwrap();
        let eps = last
            .dataset("plastic_strain")
            .and_then(|d| d.as_f64())
            .unwrap_or_else(|| panic!("{method}: no plastic_strain in the snapshot"));
        assert!(last.dataset("temperature").is_some(), "{method}");
        let max = eps.iter().copied().fold(0.0, f64::max);
        assert!(max > 0.0, "{method}: the struck end yields");
        assert_eq!(max, f(&summary, "max_plastic_strain"), "{method}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
