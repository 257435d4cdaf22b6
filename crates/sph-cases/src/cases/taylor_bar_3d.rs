//! The Taylor bar (Taylor 1948): an elastic–plastic cylinder hitting a rigid, frictionless wall
//! flat-on, shortening and spreading into a mushroom at the struck end.
//!
//! A solid cylinder of `radius` R and `length` L, its axis on z, stands on the wall `z = 0` and
//! moves at `velocity` toward it (−z). The wall is a rigid frictionless half-space tool
//! ([`sph_core::tool`], named `wall`, the UL tools' contact offset `dp/2`). The body is built
//! from concentric rings stacked in slices ([`tube_polar`]) with `dp = R/resolution`
//! (`resolution` counts particles across the **radius**); the methods are those that carry a
//! plastic law: UL's `ul-gnog` (default), `ul-og`, `ul-oas` (hypoelastic radial return;
//! `ul-enog` refuses one) and TL's `tl`, `tl-gm` (finite-strain exponential-map return on a
//! Hencky law, `sph_tl::solver::plastic`; `tl-hf` refuses one). TL keeps no energy budget:
//! its `energy_balance` is `null`, `kinetic_energy_final` and `elastic_energy_final` are its
//! kinetic and Hencky energies.
//!
//! TL against UL at the test resolution (R/dp = 3, 840 particles, the reference set-up,
//! `tests/taylor.rs`): L_f = 28.31 mm (tl), 28.33 mm (tl-gm), 27.19 mm (ul-og): TL is 4.1 %
//! and 4.2 % longer; R_f = 3.85, 3.80, 4.49 mm; plastic work 0.80, 0.90, 0.67 of KE0.
//!
//! **TL does not yet carry this case beyond the coarsest resolutions** (measured, release,
//! `sph run taylor-bar-3d --method M --set resolution=R --threads 2 --no-output --summary
//! s.json`): at R/dp = 4 it runs to 80 µs but its plastic work exceeds the initial kinetic
//! energy (1.25 KE0 tl, 1.33 KE0 tl-gm) and its largest ε̄p is 12.7 / 15.5 at the struck
//! face's rim (UL-OG's 0.63 at R/dp 3); at R/dp = 6 (tl) and 8 (tl, tl-gm) a particle inverts
//! or leaves the finite numbers between 23 and 33 µs and the run stops with that diagnostic
//! (`tl-gm` at 6 reaches the end with W_p 1.78 KE0 and ε̄p 83). So the rim's extreme shear
//! defeats plain TL's and GM's reference kernel; use the UL methods for impacts until that is
//! fixed.
//!
//! Material: UL's elastic constants (`youngs_modulus`, `nu`, `density`) with the plastic law
//! `law`: `johnson-cook` (default; `A`, `B`, `n`, `C`, `reference_strain_rate`, and with
//! `m > 0` thermal softening and adiabatic heating: `room_temperature`,
//! `melting_temperature`, `taylor_quinney`, `specific_heat`) or `j2` (`yield_stress`,
//! `hardening_modulus`, linear hardening). Setting a constant of the other law is an error.
//!
//! **Reference set-up** (the defaults): the 3D Taylor impact sample of the DynELA v4
//! documentation (O. Pantalé, 2020, *DynELA impact sample cases*, section "3D Taylor impact",
//! Table "Comparison of numerical results for the 3D Taylor impact test", repository
//! `pantale/DynELA-v.-4.0`, `Documentation/Samples-Impacts.tex`): a 42CrMo4 steel bar,
//! L = 32.4 mm, R = 3.2 mm, 287 m/s, frictionless rigid target, t = 80 µs; Johnson–Cook
//! E = 206.9 GPa, ν = 0.3, ρ = 7830 kg/m³, A = 806 MPa, B = 614 MPa, n = 0.168, C = 0.0089,
//! ε̇0 = 1/s, m = 1.1, T0 = 20 °C, Tm = 1540 °C, c_p = 460 J/(kg K), Taylor–Quinney 0.9. The
//! table gives Abaqus L_f = 26.55 mm and D_f = 11.22 mm (final diameter of the impact face;
//! DynELA's own 26.52 mm and 11.18 mm): `final_length_reference` = 26.55 mm and
//! `final_radius_reference` = 5.61 mm. They are reported only when every key that defines the
//! set-up (geometry, speed, end time, material) has its default, else `null`.
//!
//! Summary: `final_length` (axial extent of the particles plus one slice thickness: the
//! half-spacing surfaces at both ends), `final_radius` (largest distance of a particle from the
//! axis plus half a ring spacing: the mushroom's radius, at the struck face),
//! `final_length_reference`, `final_radius_reference`, their relative deviations
//! `final_length_error`, `final_radius_error`; `plastic_work` (Σ V q Δε̄p of every return, J),
//! `kinetic_energy_initial` (½ m v²), `kinetic_energy_final`, `elastic_energy_final`
//! (volumetric + shear stored energy), `energy_balance` (the budget's residual over the
//! initial kinetic energy: kinetic + elastic + plastic + Riemann dissipation + GNOG penalty −
//! wall work, each accumulated exactly), `max_plastic_strain`, `max_temperature` (K, with
//! thermal softening), `wall_impulse` (∫ F_z dt of the wall's reaction series, N s) and
//! `momentum_balance_wall` (|P_z(end) − P_z(0) + wall impulse| / |P_z(0)|: the momentum the bar
//! lost went into the wall).
//!
//! Measured (release build, one thread; `sph run taylor-bar-3d --method M --set resolution=R
//! --threads 1 --no-output --summary s.json`), the reference set-up, deviation of L_f and R_f
//! from 26.55 mm and 5.61 mm:
//!
//! | method | R/dp | particles | L_f (mm) | R_f (mm) | L_f dev. | R_f dev. | W_p/KE0 | budget residual/KE0 | momentum balance |
//! |---|---|---|---|---|---|---|---|---|---|
//! | ul-gnog | 4 | 2000 | 27.29 | 4.22 | +2.8 % | −24.8 % | 0.85 | +0.31 | 4.1e-2 |
//! | ul-gnog | 6 | 6893 | 27.13 | 4.35 | +2.2 % | −22.5 % | 0.87 | +0.26 | 2.5e-2 |
//! | ul-gnog | 8 | 16281 | 27.01 | 4.47 | +1.8 % | −20.4 % | 0.89 | +0.20 | 2.2e-2 |
//! | ul-og | 4 | 2000 | 27.09 | 4.63 | +2.0 % | −17.5 % | 0.72 | +0.097 | 2e-14 |
//! | ul-og | 6 | 6893 | 26.97 | 4.81 | +1.6 % | −14.3 % | 0.77 | +0.10 | 7e-14 |
//! | ul-og | 8 | 16281 | 26.87 | 4.96 | +1.2 % | −11.5 % | 0.81 | +0.10 | 2e-15 |
//!
//! The length converges toward the reference (within 3 % from R/dp = 4); the mushroom radius
//! is far short of it and converges slowly (OG −17.5 → −11.5 %, GNOG −24.8 → −20.4 %). Not
//! yet understood; suspects: the wall's velocity-projection contact takes 13–20 % of the
//! kinetic energy at R/dp = 3 (`tool_contact` in the budget; a rigid frictionless wall does no
//! work), the budget's positive residual (plastic + Riemann + wall works exceed the kinetic
//! energy lost), and GNOG's spin-rotated penalty, which does not conserve momentum here.

use crate::cases::tl_common::{material, run_tl, tl_params, TL_METHODS};
use crate::cases::ul_common::{run_ul, ul_params};
use crate::error::CaseError;
use crate::params::{Param, Params, Range, Value};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec3;
use serde_json::{json, Map, Value as Json};
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{Field, Solver, D3};
use sph_geometry::generate::tube_polar;
use sph_materials::plasticity::{IsotropicHardening, JohnsonCook, PlasticLaw, ThermalSoftening};
use sph_materials::{Material, MaterialKind};

/// The Taylor bar.
pub struct TaylorBar3d;

/// The methods that carry a plastic law: UL's nested ones and TL's `tl`, `tl-gm` (ENOG and
/// TL-HF are in the list so that they are refused with the solver's one-line reason rather
/// than as an unknown method).
pub const TAYLOR_METHODS: &[&str] = &[
    "ul-gnog", "ul-og", "ul-oas", "ul-enog", "tl", "tl-gm", "tl-hf",
];

/// Final length of the reference (m): Abaqus, DynELA v4 documentation (Pantalé 2020), Table
/// "Comparison of numerical results for the 3D Taylor impact test".
pub const FINAL_LENGTH_REFERENCE: f64 = 26.55e-3;
/// Final radius of the impact face of the reference (m): half of Abaqus' D_f = 11.22 mm,
/// same table.
pub const FINAL_RADIUS_REFERENCE: f64 = 0.5 * 11.22e-3;

/// The constants of the Johnson–Cook law (and of J2) as case keys.
const JC_KEYS: &[&str] = &[
    "A",
    "B",
    "n",
    "C",
    "reference_strain_rate",
    "m",
    "room_temperature",
    "melting_temperature",
    "taylor_quinney",
    "specific_heat",
];
const J2_KEYS: &[&str] = &["yield_stress", "hardening_modulus"];
/// Keys that define the reference set-up besides the law's constants.
const SETUP_KEYS: &[&str] = &[
    "length",
    "radius",
    "velocity",
    "end_time",
    "youngs_modulus",
    "nu",
    "density",
    "law",
];

impl Case for TaylorBar3d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "taylor-bar-3d",
            description: "elastic-plastic cylinder on a rigid wall (Taylor impact; J2 or \
                          Johnson-Cook) against a published final length and radius",
            methods: TAYLOR_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 32.4e-3, Range::Positive, "bar length L (m)"),
            Param::float("radius", 3.2e-3, Range::Positive, "bar radius R (m)"),
            Param::float(
                "velocity",
                287.0,
                Range::Positive,
                "impact speed toward the wall (m/s)",
            ),
            Param::int(
                "resolution",
                6,
                Range::Closed(2.0, 100.0),
                "particles across the radius, R/dp",
            ),
            Param::float(
                "end_time",
                80e-6,
                Range::Positive,
                "simulated time (s); the reference's 80 µs",
            ),
            Param::float("youngs_modulus", 206.9e9, Range::Positive, "E (Pa)"),
            Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float("density", 7830.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::choice(
                "law",
                "johnson-cook",
                &["johnson-cook", "j2"],
                "plastic law: johnson-cook (A, B, n, C, reference_strain_rate, m, …) or j2 \
                 (yield_stress, hardening_modulus)",
            ),
            Param::float("A", 806e6, Range::Positive, "johnson-cook: A (Pa)"),
            Param::float("B", 614e6, Range::NonNegative, "johnson-cook: B (Pa)"),
            Param::float("n", 0.168, Range::Positive, "johnson-cook: exponent n"),
            Param::float(
                "C",
                0.0089,
                Range::NonNegative,
                "johnson-cook: strain-rate coefficient C",
            ),
            Param::float(
                "reference_strain_rate",
                1.0,
                Range::Positive,
                "johnson-cook: reference plastic strain rate ε̇0 (1/s)",
            ),
            Param::float(
                "m",
                1.1,
                Range::NonNegative,
                "johnson-cook: thermal-softening exponent m (0: no thermal softening, no \
                 heating)",
            ),
            Param::float(
                "room_temperature",
                293.15,
                Range::Positive,
                "johnson-cook: room and initial temperature T0 (K)",
            ),
            Param::float(
                "melting_temperature",
                1813.15,
                Range::Positive,
                "johnson-cook: melting temperature Tm (K), > room_temperature",
            ),
            Param::float(
                "taylor_quinney",
                0.9,
                Range::Closed(0.0, 1.0),
                "johnson-cook: fraction of the plastic work turned into heat",
            ),
            Param::float(
                "specific_heat",
                460.0,
                Range::Positive,
                "johnson-cook: specific heat c_p (J/(kg K))",
            ),
            Param::float(
                "yield_stress",
                806e6,
                Range::Positive,
                "j2: initial yield stress σ0 (Pa)",
            ),
            Param::float(
                "hardening_modulus",
                614e6,
                Range::NonNegative,
                "j2: linear hardening modulus H (Pa)",
            ),
        ];
        specs.extend(crate::runner::output_params());
        // Both families' numerical keys (each marked with its methods); the output keys once.
        for param in ul_params().into_iter().chain(tl_params()) {
            if !specs.iter().any(|p| p.key == param.key) {
                specs.push(param);
            }
        }
        Params::new("taylor-bar-3d", specs)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (length, radius, v) = (p.f64("length"), p.f64("radius"), p.f64("velocity"));
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let law = plastic_law(p)?;
        let dp = radius / p.int("resolution") as f64;
        if length < 2.0 * dp {
            return Err(CaseError::InvalidValue {
                key: "length".into(),
                value: length.to_string(),
                allowed: format!("at least 2 dp = 2 radius/resolution = {}", 2.0 * dp),
            });
        }
        let mat = material(MaterialKind::LinearElastic, e, nu, rho)?;
        let constants = *Material::<D3>::constants(&mat);
        let set = tube_polar(DVec3::ZERO, DVec3::Z, 0.0, radius, length, dp)?;
        // The slice thickness and ring spacing tube_polar used (surfaces half of them out).
        let dz = length / (length / dp).round().max(1.0);
        let dr = radius / (radius / dp).round().max(1.0);
        let volumes = set.volumes().to_vec();
        let n = set.len();
        let body = sph_core::Body::<D3> {
            positions: set.positions().to_vec(),
            volumes: volumes.clone(),
            dp,
            velocities: vec![DVec3::new(0.0, 0.0, -v); n],
            densities: Vec::new(),
        };
        let wall = RigidTool::new(
            "wall",
            ToolShape::half_space(DVec3::ZERO, DVec3::Z)?,
            ToolMotion::fixed(),
        );
        let end = p.f64("end_time");
        let interval = match p.f64("probe_interval") {
            t if t > 0.0 => t,
            _ => end / 400.0,
        };
        let mass = rho * volumes.iter().sum::<f64>();
        let ke0 = 0.5 * mass * v * v;
        let p0 = mass * v;
        let reference = is_reference_setup(p);
        let thermal = matches!(law, PlasticLaw::JohnsonCook(jc) if jc.thermal.is_some());
        let summarise = move |s: &dyn Solver<D3>, _: &RunRecord| {
            let mut m = shape_summary(s, dz, dr);
            let (lf, rf) = (
                m.get("final_length").and_then(Json::as_f64),
                m.get("final_radius").and_then(Json::as_f64),
            );
            for (key, value, reference_value) in [
                ("final_length", lf, FINAL_LENGTH_REFERENCE),
                ("final_radius", rf, FINAL_RADIUS_REFERENCE),
            ] {
                let (r, err) = match (reference, value) {
                    (true, Some(x)) => (json!(reference_value), json!(x / reference_value - 1.0)),
                    (true, None) => (json!(reference_value), Json::Null),
                    _ => (Json::Null, Json::Null),
                };
                m.insert(format!("{key}_reference"), r);
                m.insert(format!("{key}_error"), err);
            }
            energy_summary(s, ke0, thermal, &mut m);
            momentum_summary(s, p0, &mut m);
            m.insert("particle_spacing".into(), json!(dp));
            m
        };
        if TL_METHODS.contains(&method) {
            return run_tl(
                "taylor-bar-3d",
                method,
                p,
                body,
                mat,
                |s| {
                    let s = s.with_plasticity(law)?.with_tools(vec![wall])?;
                    Ok(s.with_probes(Vec::new(), interval)?)
                },
                end,
                options,
                summarise,
            );
        }
        run_ul(
            "taylor-bar-3d",
            method,
            p,
            body,
            constants,
            |s| {
                let s = s.with_plasticity(law)?.with_tools(vec![wall])?;
                Ok(s.with_probes(Vec::new(), interval)?)
            },
            end,
            options,
            summarise,
        )
    }
}

/// The plastic law from the keys, refusing a constant of the other law.
fn plastic_law(p: &Params) -> Result<PlasticLaw, CaseError> {
    let johnson_cook = p.text("law") == "johnson-cook";
    let (own, other, other_law) = if johnson_cook {
        (JC_KEYS, J2_KEYS, "j2")
    } else {
        (J2_KEYS, JC_KEYS, "johnson-cook")
    };
    debug_assert!(!own.is_empty());
    if let Some(key) = other.iter().find(|k| !is_default(p, k)) {
        return Err(CaseError::InvalidValue {
            key: (*key).into(),
            value: p.f64(key).to_string(),
            allowed: format!(
                "its default with law = {}: it is a constant of law = {other_law}",
                p.text("law")
            ),
        });
    }
    let law = if johnson_cook {
        let m = p.f64("m");
        let thermal = (m > 0.0).then(|| ThermalSoftening {
            m,
            room_temperature: p.f64("room_temperature"),
            melting_temperature: p.f64("melting_temperature"),
            initial_temperature: p.f64("room_temperature"),
            taylor_quinney: p.f64("taylor_quinney"),
            specific_heat: p.f64("specific_heat"),
        });
        PlasticLaw::JohnsonCook(JohnsonCook {
            a: p.f64("A"),
            b: p.f64("B"),
            n: p.f64("n"),
            c: p.f64("C"),
            reference_strain_rate: p.f64("reference_strain_rate"),
            thermal,
        })
    } else {
        PlasticLaw::J2(IsotropicHardening::Linear {
            yield_stress: p.f64("yield_stress"),
            hardening_modulus: p.f64("hardening_modulus"),
        })
    };
    law.validate()?;
    Ok(law)
}

/// Whether `key` has its declared default.
fn is_default(p: &Params, key: &str) -> bool {
    match p.specs().iter().find(|s| s.key == key).map(|s| &s.default) {
        Some(Value::Float(d)) => p.f64(key) == *d,
        Some(d) => p.value(key) == Some(d),
        None => true,
    }
}

/// Whether the run is the reference set-up: every geometry, speed, time and material key at
/// its default (the law's own constants included).
fn is_reference_setup(p: &Params) -> bool {
    SETUP_KEYS
        .iter()
        .chain(JC_KEYS)
        .chain(J2_KEYS)
        .all(|k| is_default(p, k))
}

/// `final_length` and `final_radius` of the deformed bar (see the module docs).
fn shape_summary(s: &dyn Solver<D3>, dz: f64, dr: f64) -> Map<String, Json> {
    let mut m = Map::new();
    let x = s.positions();
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.z), hi.max(p.z))
        });
    let r = x.iter().map(|p| p.x.hypot(p.y)).fold(0.0f64, f64::max);
    m.insert("final_length".into(), finite_or_null(hi - lo + dz));
    m.insert("final_radius".into(), finite_or_null(r + 0.5 * dr));
    m
}

/// The energies at the end (see the module docs).
fn energy_summary(s: &dyn Solver<D3>, ke0: f64, thermal: bool, m: &mut Map<String, Json>) {
    m.insert("kinetic_energy_initial".into(), json!(ke0));
    let figures: std::collections::HashMap<&str, f64> = s.figures().into_iter().collect();
    let plastic = figures.get("plastic_work").copied().unwrap_or(f64::NAN);
    m.insert("plastic_work".into(), finite_or_null(plastic));
    match s.energy_budget() {
        Some(b) => {
            let get = |k: &str| b.get(k).unwrap_or(0.0);
            m.insert(
                "kinetic_energy_final".into(),
                finite_or_null(get("kinetic")),
            );
            m.insert(
                "elastic_energy_final".into(),
                finite_or_null(get("volumetric") + get("shear")),
            );
            m.insert("energy_balance".into(), finite_or_null(b.residual() / ke0));
        }
        // TL keeps no budget: the kinetic and (Hencky) elastic energies, no residual.
        None => {
            let (kinetic, elastic) = s.energies().unwrap_or((f64::NAN, f64::NAN));
            m.insert("kinetic_energy_final".into(), finite_or_null(kinetic));
            m.insert("elastic_energy_final".into(), finite_or_null(elastic));
            m.insert("energy_balance".into(), Json::Null);
        }
    }
    m.insert(
        "max_plastic_strain".into(),
        finite_or_null(field_max(s, "plastic_strain")),
    );
    if thermal {
        m.insert(
            "max_temperature".into(),
            finite_or_null(field_max(s, "temperature")),
        );
    }
}

/// The largest value of a scalar output field (NaN if the solver has none).
fn field_max(s: &dyn Solver<D3>, name: &str) -> f64 {
    match s.field(name) {
        Some(Field::Scalar(v)) => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        _ => f64::NAN,
    }
}

/// The wall's impulse from its reaction series and the bar's momentum balance with it.
fn momentum_summary(s: &dyn Solver<D3>, p0: f64, m: &mut Map<String, Json>) {
    let series = s.series();
    let impulse = series.iter().find(|x| x.name == "wall").and_then(|w| {
        let f = w.column("force_z")?;
        Some(
            w.time
                .windows(2)
                .zip(&f[1..])
                .map(|(t, f)| f * (t[1] - t[0]))
                .sum::<f64>(),
        )
    });
    let pz = s.momentum().map(|q| q.z);
    m.insert(
        "wall_impulse".into(),
        impulse.map_or(Json::Null, finite_or_null),
    );
    let balance = match (impulse, pz) {
        // P(0) = −p0 along z.
        (Some(j), Some(pz)) => finite_or_null((pz + p0 + j).abs() / p0),
        _ => Json::Null,
    };
    m.insert("momentum_balance_wall".into(), balance);
}
