//! The Taylor bar (`taylor-bar-3d`) at a coarse resolution (3 particles across the radius,
//! 840 particles) over the reference's 80 µs, so the file runs in seconds in a dev build: the
//! physics every resolution must show. The comparison with the published final length and
//! radius is at finer resolutions (the case's docs).
//!
//! Measured here (R/dp = 3, the reference set-up): L_f/L0 = 0.847 (GNOG), 0.839 (OG), 0.838
//! (OAS); R_f/R0 = 1.31, 1.40, 1.43; plastic work 0.84, 0.67, 0.72 of the initial kinetic
//! energy; budget residual +0.33, +0.091, +0.081 of it; momentum lost to the wall's impulse
//! 4.4e-2 (GNOG), 5.7e-16 (OG), 3.8e-16 (OAS) of the initial momentum.

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

/// The bar shortens by more than 10 % and its struck end spreads by more than 20 % (both
/// measured ≥ 15 % and ≥ 31 %), plastic work takes more than half of the kinetic energy
/// (measured ≥ 0.67) and the bar ends nearly at rest (< 2 % of it kinetic). The budget closes
/// within 15 % of the initial kinetic energy for OG and OAS (measured 9 %, 8 %: the rest is
/// the residual of the discrete plastic and Riemann works) and within 40 % for GNOG (measured
/// 33 %; GNOG's spin-rotated penalty is neither energy- nor momentum-conserving at the foot).
/// The momentum the bar loses is the wall's impulse to round-off for OG and OAS (every pair
/// force is antisymmetric; measured 6e-16) and within 6 % for GNOG (measured 4.4 %, the
/// penalty's per-particle rotation).
#[test]
fn the_bar_shortens_spreads_and_dissipates_into_plastic_work() {
    let (l0, r0) = (32.4e-3, 3.2e-3);
    for (method, energy_tol, momentum_tol) in [
        ("ul-gnog", 0.4, 0.06),
        ("ul-og", 0.15, 1e-9),
        ("ul-oas", 0.15, 1e-9),
    ] {
        let s = run(method, &[]);
        let ke0 = f(&s, "kinetic_energy_initial");
        // ½ ρ π R² L v² of the reference bar.
        let theory = 0.5 * 7830.0 * std::f64::consts::PI * r0 * r0 * l0 * 287.0 * 287.0;
        assert!(
            (ke0 / theory - 1.0).abs() < 1e-9,
            "{method}: {ke0} vs {theory}"
        );
        assert!(f(&s, "final_length") < 0.9 * l0, "{method}: {s:?}");
        assert!(f(&s, "final_length") > 0.5 * l0, "{method}: {s:?}");
        assert!(f(&s, "final_radius") > 1.2 * r0, "{method}: {s:?}");
        assert!(f(&s, "plastic_work") > 0.5 * ke0, "{method}: {s:?}");
        assert!(
            f(&s, "kinetic_energy_final") < 0.02 * ke0,
            "{method}: {s:?}"
        );
        assert!(f(&s, "elastic_energy_final") >= 0.0, "{method}: {s:?}");
        assert!(
            f(&s, "energy_balance").abs() < energy_tol,
            "{method}: {s:?}"
        );
        assert!(f(&s, "wall_impulse") < 0.0, "{method}: {s:?}");
        assert!(
            f(&s, "momentum_balance_wall") < momentum_tol,
            "{method}: {}",
            f(&s, "momentum_balance_wall")
        );
        assert!(f(&s, "max_plastic_strain") > 0.3, "{method}: {s:?}");
        // Adiabatic heating from 293.15 K.
        assert!(f(&s, "max_temperature") > 350.0, "{method}: {s:?}");
        // The defaults are the reference set-up.
        assert_eq!(f(&s, "final_length_reference"), 26.55e-3);
        assert_eq!(f(&s, "final_radius_reference"), 5.61e-3);
    }
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
/// half-space tool) at the same resolution as UL. Measured (R/dp = 3, the reference set-up):
/// L_f = 28.31 mm (tl), 28.33 mm (tl-gm) against UL-OG's 27.19 mm (+4.1 %, +4.2 %); R_f =
/// 3.85, 3.80 mm against 4.49 mm; plastic work 0.80, 0.90 of KE0 (UL-OG 0.67); momentum lost
/// = wall impulse to 6e-16, 1e-15. Tolerances: the final length within 8 % of UL-OG's at this
/// resolution (the two families differ by 4 % here; their kernels live in different
/// configurations, so they agree only as both converge), the bar shortens by more than 10 %
/// and spreads by more than 10 %, plastic work above half of KE0, the bar nearly at rest.
#[test]
fn tl_bar_shortens_like_ul_og() {
    let (l0, r0) = (32.4e-3, 3.2e-3);
    let ul = run("ul-og", &[]);
    let l_ul = f(&ul, "final_length");
    for method in ["tl", "tl-gm"] {
        let s = run(method, &[]);
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
