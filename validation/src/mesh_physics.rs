//! Physics through a mesh: the breathing mode of an elastic sphere whose particles come from a
//! triangle mesh (`sph_geometry::fit`, relaxed and not), against the same sphere filled from the
//! exact primitive ([`HollowSphere::ball`] on the lattice) and against Lamb's closed form.
//!
//! The free sphere's fundamental radial mode (Lamb 1882; Love, *A Treatise on the Mathematical
//! Theory of Elasticity*, §195) has the displacement `u = A j₁(k r) r̂`, and the free surface
//! `σ_rr(R) = 0` gives the frequency equation in `ξ = k R = ω R / c_p`:
//!
//! `(λ + 2μ) j₀(ξ) − 4 μ j₁(ξ) / ξ = 0`  ([`breathing_root`]).
//!
//! Each run starts in that mode's velocity field, `v = v₀ j₁(k r)/j₁(k R) r̂`, at a strain
//! amplitude of 1e-4 (linear), and measures the period from the zero crossings of the radial
//! moment `Σ V (x − c)·v` (∝ cos ω t for the pure mode): the first and third crossings are
//! one period apart. Stored as `validation/results/geometry-physics.json`.

use crate::store::results_dir;
use serde_json::{json, Value};
use sph_core::glam::DVec3;
use sph_core::{Body, Solver, D3};
use sph_geometry::fit::{fit, FitOptions, DEFAULT_RELAX_STEPS};
use sph_geometry::generate::{HollowSphere, Lattice, ParticleSet};
use sph_geometry::mesh::{MeshSolid, TriMesh};
use sph_materials::{ElasticConstants, SaintVenantKirchhoff};
use sph_tl::{Shear, TlParams, TlSolver};
use std::f64::consts::PI;
use std::fmt::Write as _;

const FILE: &str = "geometry-physics.json";

/// The sphere: radius (m), Young's modulus (Pa), Poisson's ratio, density (kg/m³).
const RADIUS: f64 = 0.05;
const YOUNGS: f64 = 1e7;
const NU: f64 = 0.3;
const DENSITY: f64 = 1000.0;

/// Particles across the diameter.
pub const ACROSS: [usize; 3] = [10, 20, 30];

/// The spherical Bessel functions `j₀(x) = sin x / x` and `j₁(x) = sin x / x² − cos x / x`.
fn spherical_bessel_01(x: f64) -> (f64, f64) {
    if x.abs() < 1e-4 {
        return (1.0 - x * x / 6.0, x / 3.0 - x.powi(3) / 30.0);
    }
    let (s, c) = x.sin_cos();
    (s / x, s / (x * x) - c / x)
}

/// The first root `ξ = ω R / c_p` of the free sphere's breathing-mode frequency equation
/// `(λ + 2μ) j₀(ξ) − 4 μ j₁(ξ)/ξ = 0` (Lamb 1882), by bisection on `(0, π]` (where it lies:
/// the left side is positive near 0 and `−4μ j₁(π)/π < 0` at π).
pub fn breathing_root(nu: f64) -> f64 {
    // (λ + 2μ)/μ = 2(1 − ν)/(1 − 2ν).
    let p = 2.0 * (1.0 - nu) / (1.0 - 2.0 * nu);
    let f = |x: f64| {
        let (j0, j1) = spherical_bessel_01(x);
        p * j0 - 4.0 * j1 / x
    };
    let (mut a, mut b) = (1e-3, PI);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if f(a) * f(m) <= 0.0 {
            b = m;
        } else {
            a = m;
        }
    }
    0.5 * (a + b)
}

/// Lamb's breathing period `2π R / (ξ c_p)` of the sphere above.
pub fn breathing_period() -> f64 {
    let c = ElasticConstants::from_youngs(YOUNGS, NU, DENSITY).expect("valid constants");
    let cp = ((c.bulk_modulus + 4.0 / 3.0 * c.shear_modulus) / DENSITY).sqrt();
    2.0 * PI * RADIUS / (breathing_root(NU) * cp)
}

/// The sphere's particles: `"primitive"` (the lattice inside the exact ball), `"mesh"` (a UV
/// sphere of 128 segments fitted by default: count matched to its volume, relaxed) or
/// `"mesh-lattice"` (its lattice fill only).
fn particles(source: &str, across: usize) -> Result<ParticleSet<D3>, String> {
    let dp = 2.0 * RADIUS / across as f64;
    let lo = DVec3::splat(-RADIUS);
    match source {
        "primitive" => {
            let ball = HollowSphere::ball(DVec3::ZERO, RADIUS).map_err(|e| e.to_string())?;
            let lattice = Lattice::new(dp, lo).map_err(|e| e.to_string())?;
            ParticleSet::fill(&lattice, &ball).map_err(|e| e.to_string())
        }
        _ => {
            let mesh = TriMesh::uv_sphere(DVec3::ZERO, RADIUS, 128);
            let solid = MeshSolid::new(mesh, "sphere").map_err(|e| e.to_string())?;
            let relax_steps = if source == "mesh" {
                DEFAULT_RELAX_STEPS
            } else {
                0
            };
            let (set, _) = fit(
                &solid,
                dp,
                &FitOptions {
                    relax_steps,
                    // The lattice-only sphere is the lattice fill as it is.
                    match_count: source == "mesh",
                    ..FitOptions::default()
                },
            )
            .map_err(|e| e.to_string())?;
            Ok(set)
        }
    }
}

/// One run: the measured breathing period of `source` at `across` with TL (`hf`: TL-SPH-HF).
fn measure(source: &str, across: usize, hf: bool) -> Result<Value, String> {
    let shear = if hf {
        Shear::hourglass_free()
    } else {
        Shear::Original
    };
    measure_with(source, across, shear, TlParams::default())
}

/// The measured breathing period of `source` at `across` with any TL shear treatment and
/// numerical parameters: the row's `method` is the shear's name.
pub fn measure_with(
    source: &str,
    across: usize,
    shear: Shear,
    params: TlParams,
) -> Result<Value, String> {
    let set = particles(source, across)?;
    let n = set.len();
    let volumes = set.volumes().to_vec();
    let period = breathing_period();
    let omega = 2.0 * PI / period;
    let k = breathing_root(NU) / RADIUS;
    let v0 = 1e-4 * RADIUS * omega;
    let (_, j1_surface) = spherical_bessel_01(k * RADIUS);
    let body = Body::from(set).with_velocity(move |x: DVec3| {
        let r = x.length();
        if r < 1e-12 {
            return DVec3::ZERO;
        }
        x / r * (v0 * spherical_bessel_01(k * r).1 / j1_surface)
    });
    let law = SaintVenantKirchhoff::new(
        ElasticConstants::from_youngs(YOUNGS, NU, DENSITY).map_err(|e| e.to_string())?,
    );
    let mut s = TlSolver::<D3, _>::new(body, law, shear, params).map_err(|e| e.to_string())?;
    let total: f64 = volumes.iter().sum();
    let moment = |s: &TlSolver<D3, SaintVenantKirchhoff>| {
        let x = s.positions();
        let c = x
            .iter()
            .zip(&volumes)
            .fold(DVec3::ZERO, |a, (x, v)| a + *x * *v)
            / total;
        x.iter()
            .zip(s.velocities())
            .zip(&volumes)
            .map(|((x, v), w)| w * (*x - c).dot(*v))
            .sum::<f64>()
    };
    let mut crossings = Vec::new();
    let (mut t0, mut m0) = (s.time(), moment(&s));
    while crossings.len() < 3 && s.time() < 2.0 * period {
        s.step(f64::INFINITY).map_err(|e| e.to_string())?;
        let (t1, m1) = (s.time(), moment(&s));
        if m0 * m1 < 0.0 || (m1 == 0.0 && m0 != 0.0) {
            crossings.push(t0 + (t1 - t0) * m0 / (m0 - m1));
        }
        (t0, m0) = (t1, m1);
    }
    if crossings.len() < 3 {
        return Err(format!(
            "{source} at {across} across: fewer than three zero crossings of the radial moment in two periods"
        ));
    }
    // Crossings at T/4, 3T/4, 5T/4 for the pure mode: the first and third are a period apart.
    let measured = crossings[2] - crossings[0];
    Ok(json!({
        "source": source,
        "method": shear.method_name(),
        "across": across,
        "particles": n,
        "steps": s.step_count(),
        "period": measured,
        "period_theory": period,
        "first_crossing": crossings[0],
    }))
}

/// Runs every sphere (primitive, mesh relaxed, mesh lattice-only) at every resolution with TL
/// and TL-HF and stores the periods; reuses them unless `force`.
pub fn run_all(force: bool) -> Result<(), String> {
    let path = results_dir().join(FILE);
    if path.is_file() && !force {
        println!("geometry physics: stored ({})", path.display());
        return Ok(());
    }
    let mut rows = Vec::new();
    for hf in [true, false] {
        for &across in &ACROSS {
            for source in ["primitive", "mesh", "mesh-lattice"] {
                let row = measure(source, across, hf)?;
                println!(
                    "geometry physics: {} {source} at {across} across: period error {:+.3} % ({} particles)",
                    row["method"].as_str().unwrap_or("?"),
                    100.0 * (row["period"].as_f64().unwrap_or(f64::NAN) / breathing_period() - 1.0),
                    row["particles"],
                );
                rows.push(row);
            }
        }
    }
    std::fs::create_dir_all(results_dir()).map_err(|e| e.to_string())?;
    let text = serde_json::to_string_pretty(&json!({
        "command": "cargo run --release -p sph-validation --bin validate -- geometry",
        "rows": rows,
    }))
    .map_err(|e| e.to_string())?;
    std::fs::write(&path, text).map_err(|e| e.to_string())?;
    println!("geometry physics: stored {}", path.display());
    Ok(())
}

/// The "physics through a mesh" part of the Geometry section of docs/validation.md.
pub fn report(md: &mut String) -> Result<(), String> {
    writeln!(md, "### Physics through a mesh: the breathing sphere\n").unwrap();
    let path = results_dir().join(FILE);
    let Ok(text) = std::fs::read_to_string(&path) else {
        writeln!(
            md,
            "Not run yet: `cargo run --release -p sph-validation --bin validate -- geometry`.\n"
        )
        .unwrap();
        return Ok(());
    };
    let stored: Value = serde_json::from_str(&text).map_err(|e| format!("{FILE}: {e}"))?;
    let theory = breathing_period();
    writeln!(
        md,
        "An elastic sphere (R = {RADIUS} m, E = {YOUNGS:e} Pa, ν = {NU}, ρ = {DENSITY} kg/m³, \
         Saint-Venant–Kirchhoff at a strain amplitude of 1e-4) started in its breathing mode's \
         velocity field; the period from the zero crossings of `Σ V (x − c)·v`, against Lamb's \
         closed form `T = 2π R/(ξ c_p)` with `(λ + 2μ) j₀(ξ) = 4μ j₁(ξ)/ξ` (ξ = {:.5}, T = \
         {:.4e} s). The particles come from the exact ball on the lattice (`primitive`), from a \
         128-segment UV-sphere mesh fitted by default (`mesh`: its count brought to the mesh's \
         volume by removing outer-layer particles, then relaxed, {DEFAULT_RELAX_STEPS} steps) \
         and from the same mesh's lattice fill alone (`mesh-lattice`). The exact ball \
         and the mesh's lattice fill are the same particles when their columns agree (the \
         mesh's inside test against the exact one at every lattice point); the fitted mesh \
         differs from both only by its surface layer, thinned to the mesh's volume and moved \
         from the lattice's staircase onto \
         the sphere: `mesh − primitive` is what body fitting changes in the physics, and each \
         column's distance from Lamb is the method's error with that surface.\n",
        breathing_root(NU),
        theory
    )
    .unwrap();
    writeln!(
        md,
        "| method | across | particles (primitive / mesh / mesh-lattice) | period error primitive | mesh | mesh-lattice | mesh − primitive |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|").unwrap();
    let rows = stored["rows"].as_array().cloned().unwrap_or_default();
    let find = |m: &str, a: u64, s: &str| {
        rows.iter().find(|r| {
            r["method"].as_str() == Some(m)
                && r["across"].as_u64() == Some(a)
                && r["source"].as_str() == Some(s)
        })
    };
    for m in ["tl-hf", "tl"] {
        for &a in &ACROSS {
            let a = a as u64;
            let get = |s: &str| find(m, a, s);
            let (Some(p), Some(q), Some(l)) = (get("primitive"), get("mesh"), get("mesh-lattice"))
            else {
                continue;
            };
            let err = |r: &Value| 100.0 * (r["period"].as_f64().unwrap_or(f64::NAN) / theory - 1.0);
            let tp = p["period"].as_f64().unwrap_or(f64::NAN);
            let tq = q["period"].as_f64().unwrap_or(f64::NAN);
            writeln!(
                md,
                "| {m} | {a} | {} / {} / {} | {:+.2} % | {:+.2} % | {:+.2} % | {:+.2} % |",
                p["particles"],
                q["particles"],
                l["particles"],
                err(p),
                err(q),
                err(l),
                100.0 * (tq / tp - 1.0)
            )
            .unwrap();
        }
    }
    writeln!(md).unwrap();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambs_breathing_root_satisfies_the_free_surface_condition() {
        // ν = 1/4 (λ = μ): ξ/π ≈ 0.816 (Love §195's value for Poisson's ratio 1/4).
        let x = breathing_root(0.25);
        assert!((x / PI - 0.816).abs() < 1e-3, "{x}");
        // The root makes σ_rr vanish: (λ + 2μ) j₁' + 2λ j₁/x = 0 with j₁' = j₀ − 2 j₁/x.
        let (j0, j1) = spherical_bessel_01(x);
        let (lam, mu) = (1.0, 1.0);
        let srr = (lam + 2.0 * mu) * (j0 - 2.0 * j1 / x) + 2.0 * lam * j1 / x;
        assert!(srr.abs() < 1e-12, "{srr}");
    }
}
