//! Issue 43: `hertz-impact-3d` with the TL methods — two TL-HF elastic spheres in head-on
//! impact (each sphere its own TL body, meeting through TL's contact at its default κ = 2),
//! and one on a fixed TL wall, at a coarse resolution so the file runs in seconds in a dev
//! build; the resolution study against Hertz is docs/validation.md ("Hertz impact").
//!
//! Measured here (release and dev builds give the same numbers; R/dp = 5, 1038 particles,
//! 400 steps): t_c 6.974 ms against Hertz's 6.413 ms (+8.7 %), F_max 317.6 N against 360.7 N
//! (−12.0 %), restitution 0.975, energy change −4.9 %, |total momentum| 1.5e-14 m v.

use sph_cases::{find_case, RunOptions};

type Summary = serde_json::Map<String, serde_json::Value>;

fn run(method: &str, set: &[&str]) -> Summary {
    let c = find_case("hertz-impact-3d").unwrap();
    let mut p = c.params_for(method);
    for a in set {
        p.apply_assignment(a).unwrap();
    }
    p.check_method(method).unwrap();
    let (record, summary) = c.run(method, &p, &RunOptions::default()).unwrap();
    assert!(record.failure.is_none(), "{method}: {:?}", record.failure);
    summary
}

fn f(s: &Summary, key: &str) -> f64 {
    s[key].as_f64().unwrap_or(f64::NAN)
}

fn error(s: &Summary, key: &str) -> f64 {
    f(s, key) / f(s, &format!("{key}_theory")) - 1.0
}

/// Two TL-HF spheres at R/dp = 5. The contact happens and ends (a finite contact time, a
/// positive peak force, the spheres rebound: restitution 0.975 measured, > 0.9 asked). The
/// pair forces of TL's contact are equal and opposite bit for bit and the spheres' own forces
/// sum to zero, so the total momentum stays zero to round-off (measured 1.5e-14 of one sphere's
/// m v; 1e-10 asked). Against Hertz: t_c +8.7 % and F_max −12.0 % measured at this resolution
/// (at R/dp = 10: +6.6 % and −1.0 %, docs/validation.md), asked within [+4 %, +13 %] and
/// [−17 %, −7 %]: ±4–5 points around the measured error, so that a change of the contact law
/// or of the layout that moves the result by a quarter of Hertz's 5 % band or more fails here.
/// The energy lost in the impact (kinetic + strain + contact at the end, −4.9 % measured) is
/// a loss, and under 8 %.
#[test]
fn two_tl_hf_spheres_rebound_near_hertz() {
    let s = run("tl-hf", &["resolution=5"]);
    assert_eq!(f(&s, "sphere_particles"), 519.0, "{s:?}");
    assert!(f(&s, "contact_time") > 0.0, "{s:?}");
    assert!(f(&s, "max_force") > 0.0, "{s:?}");
    let e = f(&s, "restitution");
    assert!(e > 0.9 && e <= 1.0, "restitution {e}");
    assert!(f(&s, "momentum_change") < 1e-10, "{s:?}");
    let (t, force) = (error(&s, "contact_time"), error(&s, "max_force"));
    assert!((0.04..0.13).contains(&t), "t_c error {t}");
    assert!((-0.17..-0.07).contains(&force), "F_max error {force}");
    let de = f(&s, "energy_change");
    assert!((-0.08..0.0).contains(&de), "energy change {de}");
}

/// One TL-HF sphere on the fixed TL wall (a lattice slab, every particle fixed) at R/dp = 5
/// (627 particles, 600 steps): the sphere hits and rebounds (restitution measured 0.960, > 0.9
/// asked; no momentum check: the wall takes momentum, the summary says null), and the contact
/// lasts longer than Hertz's (measured +38.6 %, +23.1 % at R/dp = 10: the contact layer's
/// penetration is a larger share of the wall's half approach, as for UL, docs/validation.md),
/// asked within [+28 %, +48 %].
#[test]
fn a_tl_hf_sphere_rebounds_from_the_fixed_tl_wall() {
    let s = run("tl-hf", &["resolution=5", "target=wall"]);
    assert!(s["momentum_change"].is_null(), "{s:?}");
    let e = f(&s, "restitution");
    assert!(e > 0.9 && e <= 1.0, "restitution {e}");
    let t = error(&s, "contact_time");
    assert!((0.28..0.48).contains(&t), "t_c error {t}");
}

/// The keys: TL methods get TL's contact scale κ = 2 by default, UL methods 1, and an
/// explicit `contact_stiffness` holds for either; each family's numerical keys are refused
/// with the other family's methods in one line naming the key, before any work.
#[test]
fn tl_and_ul_keys_are_accepted_or_refused_by_method() {
    let c = find_case("hertz-impact-3d").unwrap();
    for m in ["tl-hf", "tl", "tl-gm"] {
        assert!(c.info().methods.contains(&m), "{m}");
        assert_eq!(c.params_for(m).f64("contact_stiffness"), 2.0, "{m}");
    }
    assert_eq!(c.params_for("ul-enog").f64("contact_stiffness"), 1.0);
    let check = |method: &str, key: &str| {
        let mut p = c.params_for(method);
        p.apply_assignment(key).unwrap();
        p.check_method(method)
    };
    for ok in [
        "contact_stiffness=1.5",
        "zeta=1.1",
        "h_over_dp=1.3",
        "layout=lattice",
    ] {
        check("tl-hf", ok).unwrap();
    }
    check("ul-enog", "contact_stiffness=1.5").unwrap();
    for (method, key) in [
        ("tl-hf", "ul_zeta=3"),
        ("tl-hf", "energy_budget=false"),
        ("tl-hf", "stepping=single"),
        ("tl", "zeta=1.1"),
        ("ul-enog", "zeta=1.1"),
        ("ul-enog", "h_over_dp=1.3"),
    ] {
        let e = check(method, key).unwrap_err().to_string();
        let name = key.split('=').next().unwrap();
        assert!(e.contains(name) && !e.contains('\n'), "{method} {key}: {e}");
    }
}

/// The wall as a rigid half-space tool (`target = tool`), UL-ENOG and TL-HF at R/dp = 6
/// (899 particles). Without a contact layer the approach is the sphere's own, so the contact
/// time is close to Hertz's already at this resolution (measured: ENOG −0.16 %, TL-HF −3.9 %;
/// the particle wall at the same resolution: ENOG +33 %); asked within ±6 %. The peak force
/// (measured +3.8 %, +7.1 %) within ±12 %. The kinematic contact is inelastic for each particle
/// it stops: the sphere rebounds slower than from the particle wall (measured 0.952 and 0.937
/// against 0.987 there), asked in (0.85, 1); the energy it takes (kinetic + stored at the end,
/// − 1: measured −9.3 % ENOG, −12.1 % TL-HF) is a loss under 20 %. UL's energy budget closes
/// with the tool (residual measured 3.0e-5 of the initial energy, asked 1e-3; before the tools'
/// work was rebooked on the velocities the particles keep it was +176 %), and its momentum
/// balance counts the tool's impulse as a support's reaction (3.9e-15 of the sphere's m v;
/// before, the tool's push was missing from it: 1.95). `contact_stiffness`
/// has nothing to scale at the tool and is refused off its default.
#[test]
fn a_sphere_on_a_rigid_tool_wall_meets_hertz_without_a_contact_layer() {
    for method in ["ul-enog", "tl-hf"] {
        let s = run(method, &["resolution=6", "target=tool"]);
        let (t, force) = (error(&s, "contact_time"), error(&s, "max_force"));
        assert!(t.abs() < 0.06, "{method}: t_c error {t}");
        assert!(force.abs() < 0.12, "{method}: F_max error {force}");
        let e = f(&s, "restitution");
        assert!(e > 0.85 && e < 1.0, "{method}: restitution {e}");
        let de = f(&s, "energy_change");
        assert!((-0.2..0.0).contains(&de), "{method}: energy change {de}");
        if method == "ul-enog" {
            let r = f(&s, "energy_residual");
            assert!(r.abs() < 1e-3, "{method}: budget residual {r}");
            // The tool's impulse counted as a support's reaction: measured 3.9e-15.
            let p = f(&s, "momentum_balance");
            assert!(p < 1e-10, "{method}: momentum balance {p}");
        }
    }
    let c = find_case("hertz-impact-3d").unwrap();
    let mut p = c.params_for("ul-enog");
    p.apply_assignment("target=tool").unwrap();
    p.apply_assignment("contact_stiffness=2").unwrap();
    let err = c
        .run("ul-enog", &p, &RunOptions::default())
        .expect_err("κ refused with the tool");
    assert!(err.to_string().contains("contact_stiffness"), "{err}");
}
