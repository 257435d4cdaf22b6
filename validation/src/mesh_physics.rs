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
//!
//! And the Hertz impact of two elastic spheres with UL-ENOG (`hertz-impact-3d`, whose
//! validation is the `impacts` section) with the spheres body-fitted to a 128-segment UV-sphere
//! mesh (`layout = mesh`) against the same impact with the procedural spheres (`layers`, the
//! case's default, and `lattice`) and Hertz's closed form: contact time and peak force at
//! R/dp = 10, 15 and 20 ([`HERTZ_MESH_RES`]), stored as
//! `validation/results/hertz-ul-enog-r<R/dp>-k1-mesh.json` beside the primitive runs.

use crate::store::{load, results_dir, run_or_load_then, StoredRun};
use serde_json::{json, Map, Value};
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

/// The resolutions R/dp of the Hertz impact through a mesh (those of the case's own ENOG
/// validation but 30, whose 230,000 particles per run are `--fine` there).
pub const HERTZ_MESH_RES: [u32; 3] = [10, 15, 20];

/// A Hertz impact run with UL-ENOG at `res` with the contact scale 1, in `layout`: its stored
/// id and `--set` assignments (the primitive `layers` runs are the impacts section's own).
fn hertz_run(res: u32, layout: &str) -> (String, Vec<String>) {
    let mut set = vec![
        format!("resolution={res}"),
        "contact_stiffness=1".to_string(),
        "monitor_interval=2e-4".to_string(),
        "snapshot_interval=1e-3".to_string(),
    ];
    let suffix = match layout {
        "layers" => String::new(),
        other => {
            set.push(format!("layout={other}"));
            format!("-{other}")
        }
    };
    (format!("hertz-ul-enog-r{res}-k1{suffix}"), set)
}

/// The Hertz impact's sphere radius (m; the case's default).
const HERTZ_RADIUS: f64 = 0.05;

/// The outer layer of the left sphere over the Hertz contact patch: its particles within `dp`
/// of the surface (depth `R − |x − c|`) and within the contact radius `a` of the x axis on the
/// side facing the other sphere, where the contact acts. `a = √(R* δ_max)` with `R* = R/2` and
/// Hertz's largest approach `δ_max` of the case's defaults (Johnson 1985, §4.2, §11.4). Returns
/// the count against the ideal `π a²/dp²` of a square array of spacing dp, and the depths'
/// mean, RMS spread, smallest and largest (in dp; `½` for a layer at exactly dp/2).
fn contact_patch(left: impl Iterator<Item = DVec3>, dp: f64) -> Value {
    use sph_cases::cases::hertz_impact_3d::{hertz_impact, HertzTarget};
    let (r, rho) = (HERTZ_RADIUS, 1200.0);
    let m = rho * 4.0 / 3.0 * PI * r.powi(3);
    let delta = hertz_impact(HertzTarget::Sphere, r, m, 1e7, 0.4, 1.0).max_compression;
    let a = (0.5 * r * delta).sqrt();
    // The case's left sphere: its surface dp/4 left of x = 0 (gap dp/2 between the spheres).
    let centre = DVec3::new(-(r + 0.25 * dp), 0.0, 0.0);
    let left: Vec<DVec3> = left.collect();
    // Rigid overlap: both spheres moved toward each other until their surfaces touch, then by
    // δ/2 more each; the pairs closer than dp (those the contact density counts), the right
    // sphere being the mirror image of the left (as the case builds it).
    let pairs = |approach: f64| -> usize {
        let shift = 0.25 * dp + 0.5 * approach;
        let near: Vec<DVec3> = left
            .iter()
            .map(|x| *x + DVec3::X * shift)
            .filter(|x| x.x > -dp)
            .collect();
        near.iter()
            .map(|x| {
                near.iter()
                    .filter(|y| x.distance_squared(DVec3::new(-y.x, y.y, y.z)) < dp * dp)
                    .count()
            })
            .sum()
    };
    let (pairs_half, pairs_max) = (pairs(0.5 * delta), pairs(delta));
    let depths: Vec<f64> = left
        .iter()
        .filter_map(|&x| {
            let d = x - centre;
            let depth = (r - d.length()) / dp;
            (d.x > 0.0 && d.y.hypot(d.z) < a && depth < 1.0).then_some(depth)
        })
        .collect();
    let n = depths.len().max(1) as f64;
    let mean = depths.iter().sum::<f64>() / n;
    let rms = (depths.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n).sqrt();
    json!({
        "particles": depths.len(),
        "ideal": PI * a * a / (dp * dp),
        "depth_mean": mean,
        "depth_rms": rms,
        "depth_min": depths.iter().copied().fold(f64::INFINITY, f64::min),
        "depth_max": depths.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        "pairs_half_approach": pairs_half,
        "pairs_max_approach": pairs_max,
    })
}

/// [`contact_patch`] of a primitive layout's left sphere at `res` (`layers` or `lattice`),
/// built as the case builds it.
fn primitive_patch(layout: &str, res: u32) -> Option<Value> {
    let dp = HERTZ_RADIUS / res as f64;
    let centre = DVec3::new(-(HERTZ_RADIUS + 0.25 * dp), 0.0, 0.0);
    let set = match layout {
        "lattice" => sph_geometry::generate::hollow_sphere(centre, 0.0, HERTZ_RADIUS, dp),
        _ => sph_geometry::generate::hollow_sphere_polar(centre, 0.0, HERTZ_RADIUS, dp),
    }
    .ok()?;
    Some(contact_patch(set.positions().iter().copied(), dp))
}

/// Runs (or loads) the Hertz impacts with mesh-built spheres and their primitive twins.
fn run_hertz(force: bool) -> Result<(), String> {
    for res in HERTZ_MESH_RES {
        for layout in ["layers", "mesh"] {
            let (id, set) = hertz_run(res, layout);
            // Only the mesh runs are this section's to re-run; the primitive ones are the
            // impacts section's (re-run there).
            let dp = HERTZ_RADIUS / res as f64;
            let after = |c: &sph_output::FileContents| -> Result<Map<String, Value>, String> {
                if layout != "mesh" {
                    return Ok(Map::new());
                }
                // The initial positions: the first snapshot, the left sphere x < 0.
                let first = c.snapshots.first().ok_or("no snapshot")?;
                let x = first
                    .dataset("position")
                    .and_then(|d| d.as_f64())
                    .ok_or("no positions")?;
                let left = x
                    .chunks_exact(3)
                    .map(|p| DVec3::new(p[0], p[1], p[2]))
                    .filter(|p| p.x < 0.0);
                let mut m = Map::new();
                m.insert("contact_patch".into(), contact_patch(left, dp));
                Ok(m)
            };
            run_or_load_then(
                &id,
                "hertz-impact-3d",
                "ul-enog",
                &set,
                force && layout == "mesh",
                &after,
            )
            .map_err(|e| format!("{id}: {e}"))?;
        }
    }
    Ok(())
}

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
    run_breathing(force)?;
    run_hertz(force)
}

/// The breathing spheres of [`run_all`].
fn run_breathing(force: bool) -> Result<(), String> {
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

/// The "physics through a mesh" part of the Geometry section of docs/validation.md: the
/// breathing sphere, then the Hertz impact.
pub fn report(md: &mut String) -> Result<(), String> {
    report_breathing(md)?;
    report_hertz(md);
    Ok(())
}

/// The Hertz impact through a mesh: contact time and peak force of the mesh-built spheres
/// against the primitive ones and Hertz.
fn report_hertz(md: &mut String) {
    writeln!(md, "### Physics through a mesh: the Hertz impact\n").unwrap();
    let runs: Vec<(u32, &str, Option<StoredRun>)> = HERTZ_MESH_RES
        .iter()
        .flat_map(|&res| {
            ["layers", "lattice", "mesh"]
                .into_iter()
                .map(move |layout| (res, layout, load(&hertz_run(res, layout).0)))
        })
        .collect();
    if !runs.iter().any(|(_, l, r)| *l == "mesh" && r.is_some()) {
        writeln!(
            md,
            "Not run yet: `cargo run --release -p sph-validation --bin validate -- geometry`.\n"
        )
        .unwrap();
        return;
    }
    writeln!(
        md,
        "Two elastic spheres meeting head-on (`hertz-impact-3d` with UL-ENOG, κ = 1, its \
         defaults: R = 0.05 m, 1 m/s each, E = 1e7 Pa, ν = 0.4, ρ = 1200 kg/m³) with the \
         spheres built three ways: `layers` (the case's default: concentric layers on Fibonacci \
         lattices), `lattice` (cut from a cubic lattice: a staircase surface) and `mesh` \
         (`layout = mesh`: body-fitted to a 128-segment UV-sphere triangle mesh, \
         `sph_geometry::fit` with its default {DEFAULT_RELAX_STEPS} relaxation steps, the \
         right sphere the mirror image of the left, as for the others). Contact time `t_c` and \
         peak force `F_max` from the contact-force series, against Hertz's closed form for \
         each run's own mass (`m/m_exact`: the particles' total volume over 4πR³/3, from the \
         ratio of the run's Hertz time to the exact sphere's, `t_c ∝ m^(2/5)`), and the mesh \
         run against the `layers` one (`mesh − layers`). The commands are in each run's \
         stored JSON (`validation/results/hertz-ul-enog-r<R/dp>-k1[-lattice|-mesh].json`).\n"
    )
    .unwrap();
    let exact = {
        use sph_cases::cases::hertz_impact_3d::{hertz_impact, HertzTarget};
        let (r, rho) = (0.05f64, 1200.0);
        let m = rho * 4.0 / 3.0 * PI * r.powi(3);
        hertz_impact(HertzTarget::Sphere, r, m, 1e7, 0.4, 1.0)
    };
    writeln!(
        md,
        "Hertz with the exact mass: t_c = {:.4} ms, F_max = {:.1} N.\n",
        1e3 * exact.contact_time,
        exact.max_force
    )
    .unwrap();
    writeln!(
        md,
        "| R/dp | layout | particles per sphere | m/m_exact | t_c (ms) | t_c vs Hertz | F_max (N) | F_max vs Hertz | t_c mesh − layers | F_max mesh − layers | patch particles / ideal | patch depth mean ± RMS (min–max), dp | pairs < dp at δ_max/2, δ_max |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|---|").unwrap();
    let num = |r: &StoredRun, k: &str| r.num(k).unwrap_or(f64::NAN);
    for &res in &HERTZ_MESH_RES {
        let layers = runs
            .iter()
            .find(|(r, l, _)| *r == res && *l == "layers")
            .and_then(|x| x.2.as_ref());
        for (_, layout, run) in runs.iter().filter(|(r, _, _)| *r == res) {
            let Some(run) = run else { continue };
            let (tc, f) = (num(run, "contact_time"), num(run, "max_force"));
            let (tt, ft) = (
                num(run, "contact_time_theory"),
                num(run, "max_force_theory"),
            );
            let mass = (tt / exact.contact_time).powf(2.5);
            let (dt, df) = match (layers, *layout == "mesh") {
                (Some(p), true) => (
                    format!("{:+.2} %", 100.0 * (tc / num(p, "contact_time") - 1.0)),
                    format!("{:+.2} %", 100.0 * (f / num(p, "max_force") - 1.0)),
                ),
                _ => (String::new(), String::new()),
            };
            let patch = match *layout {
                "mesh" => run
                    .summary
                    .get("snapshots")
                    .and_then(|s| s.get("contact_patch"))
                    .cloned(),
                other => primitive_patch(other, res),
            };
            let dash = || "–".to_string();
            let patch = patch.map_or((dash(), dash(), dash()), |p| {
                let g = |k: &str| p[k].as_f64().unwrap_or(f64::NAN);
                (
                    format!("{} / {:.1}", p["particles"], g("ideal")),
                    format!(
                        "{:.3} ± {:.3} ({:.3}–{:.3})",
                        g("depth_mean"),
                        g("depth_rms"),
                        g("depth_min"),
                        g("depth_max")
                    ),
                    format!("{}, {}", p["pairs_half_approach"], p["pairs_max_approach"]),
                )
            });
            writeln!(
                md,
                "| {res} | {layout} | {} | {mass:.4} | {:.4} | {:+.2} % | {f:.1} | {:+.2} % | {dt} | {df} | {} | {} | {} |",
                run.summary
                    .get("sphere_particles")
                    .cloned()
                    .unwrap_or_default(),
                1e3 * tc,
                100.0 * (tc / tt - 1.0),
                100.0 * (f / ft - 1.0),
                patch.0,
                patch.1,
                patch.2,
            )
            .unwrap();
        }
    }
    writeln!(md).unwrap();
    // mesh − layers and lattice − layers on t_c, resolution by resolution.
    let diff = |res: u32, layout: &str| -> Option<f64> {
        let find = |l: &str| {
            runs.iter()
                .find(|(r, x, _)| *r == res && *x == l)
                .and_then(|x| x.2.as_ref())
                .and_then(|r| r.num("contact_time"))
        };
        Some(100.0 * (find(layout)? / find("layers")? - 1.0))
    };
    let list = |layout: &str| -> String {
        HERTZ_MESH_RES
            .iter()
            .filter_map(|&r| diff(r, layout).map(|d| format!("{d:+.1} % at {r}")))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // The share of the lattice − layers difference that relaxing the surface layer removes
    // (the mesh's fit starts from the lattice fill: the same interior).
    let removed: Vec<String> = HERTZ_MESH_RES
        .iter()
        .filter_map(|&r| {
            let (m, l) = (diff(r, "mesh")?, diff(r, "lattice")?);
            Some(format!("{:.0} % at {r}", 100.0 * (1.0 - m / l)))
        })
        .collect();
    // F_max at the finest resolution: mesh and lattice (one interior) against layers.
    let force = |l: &str| -> Option<f64> {
        let r = *HERTZ_MESH_RES.last()?;
        let x = runs.iter().find(|(res, x, _)| *res == r && *x == l)?;
        x.2.as_ref()?.num("max_force")
    };
    let forces = match (force("mesh"), force("lattice"), force("layers")) {
        (Some(m), Some(l), Some(y)) => format!(
            " At R/dp = {}, F_max of the mesh and lattice runs (one interior) differ by {:.1} %, \
             layers lies {:.1} % below the mesh run and {:.1} % below the lattice one: \
             consistent with that, not a proof; separating the two would take a run with \
             concentric shells inside and the fitted layer outside.",
            HERTZ_MESH_RES.last().copied().unwrap_or(0),
            100.0 * (m / l - 1.0).abs(),
            100.0 * (1.0 - y / m),
            100.0 * (1.0 - y / l)
        ),
        _ => String::new(),
    };
    writeln!(
        md,
        "The mesh-built spheres do not meet the 1 % asked of them against `layers` at these \
         resolutions: `t_c` mesh − layers is {}. The difference falls with dp (about first \
         order), and the mesh run is the closer to Hertz's `t_c` at every resolution. What it \
         is not, measured: the mesh's faceting (6·10⁻⁴ R at most, 0.6–1.2 % of dp here; \
         0.3 % of the contact radius a), the mass (each row is against Hertz for its own \
         mass), or the position of the surface: over the Hertz contact radius \
         `a = √(R δ_max/2)` = 0.21 R the fitted outer layer lies dp/2 deep (the patch depth \
         column), as the `layers` one does exactly. The pairs closer than dp when the \
         undeformed spheres overlap by δ_max/2 and δ_max (what the contact density starts \
         from, the last column) differ between the layouts, but not consistently in the \
         direction of `t_c`, so the contact layer alone does not explain it either. The \
         measured decomposition is against the lattice: the fit starts from the `lattice` fill \
         (the same interior; the count matched to the mesh's volume by removing or adding \
         particles in the surface layer) and moves only the particles near the surface, and \
         that removes {} of the lattice − layers difference ({}); the remaining {} lies \
         between a lattice-interior body with a relaxed surface and concentric shells, i.e. in \
         the arrangement of the particles inside and along the surface, which the contact \
         samples at a = 2–4 dp.{forces}\n",
        list("mesh"),
        removed.join(", "),
        list("lattice"),
        list("mesh")
    )
    .unwrap();
}

/// The breathing sphere's table.
fn report_breathing(md: &mut String) -> Result<(), String> {
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
