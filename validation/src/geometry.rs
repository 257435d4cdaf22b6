//! Geometry: body-fitted particles of meshes against the shapes they tessellate. A sphere, a
//! torus and a cube, generated here as triangle meshes at several tessellations, filled at
//! several resolutions with the relaxation off and on and the count match off and on
//! (`sph_geometry::fit`): the particles' total volume against the analytic one, the surface layer's distance from depth dp/2 and the
//! spread of the kernel-sum volumes. Stored as `validation/results/geometry.json`.

use crate::store::results_dir;
use serde_json::{json, Value};
use sph_core::glam::DVec3;
use sph_geometry::fit::{fit, FitOptions, DEFAULT_RELAX_STEPS};
use sph_geometry::mesh::{MeshSolid, TriMesh};
use std::f64::consts::PI;
use std::fmt::Write as _;

/// Particles across the smallest feature (a sphere's diameter, the torus's tube diameter, the
/// cube's side).
pub const ACROSS: [usize; 3] = [10, 20, 30];

const FILE: &str = "geometry.json";

/// A shape: its name, analytic volume, smallest feature and meshes of increasing
/// tessellation (with the number of segments that names each).
type TestShape = (&'static str, f64, f64, Vec<(usize, TriMesh)>);

fn shapes() -> Vec<TestShape> {
    let (big, r) = (1.0, 0.4);
    vec![
        (
            "sphere",
            4.0 / 3.0 * PI,
            2.0,
            [32, 64, 128]
                .iter()
                .map(|&n| (n, TriMesh::uv_sphere(DVec3::ZERO, 1.0, n)))
                .collect(),
        ),
        (
            "torus",
            2.0 * PI * PI * big * r * r,
            2.0 * r,
            [32, 64, 128]
                .iter()
                .map(|&n| (n, TriMesh::torus(DVec3::ZERO, big, r, 2 * n, n)))
                .collect(),
        ),
        (
            "cube",
            1.0,
            1.0,
            vec![(1, TriMesh::cuboid(DVec3::splat(-0.5), DVec3::splat(0.5)))],
        ),
    ]
}

/// Fills every shape (the finest tessellation at every resolution, relaxation off and on; every
/// tessellation at 20 across with the relaxation on) and stores the figures; reuses them unless
/// `force`.
pub fn run_all(force: bool) -> Result<(), String> {
    let path = results_dir().join(FILE);
    if path.is_file() && !force {
        println!("geometry: stored ({})", path.display());
        return Ok(());
    }
    let mut rows = Vec::new();
    for (name, exact, feature, meshes) in shapes() {
        let finest = meshes.len() - 1;
        for (k, (segments, mesh)) in meshes.into_iter().enumerate() {
            let solid = MeshSolid::new(mesh, name).map_err(|e| e.to_string())?;
            for &across in &ACROSS {
                if k != finest && across != 20 {
                    continue;
                }
                let dp = feature / across as f64;
                // The lattice fill as it is, relaxed, and relaxed after the count match (the
                // default); coarser tessellations with the default only.
                for (steps, count) in [
                    (0, false),
                    (DEFAULT_RELAX_STEPS, false),
                    (DEFAULT_RELAX_STEPS, true),
                ] {
                    if k != finest && !(steps > 0 && count) {
                        continue;
                    }
                    let (_, r) = fit(
                        &solid,
                        dp,
                        &FitOptions {
                            relax_steps: steps,
                            match_count: count,
                            ..FitOptions::default()
                        },
                    )
                    .map_err(|e| e.to_string())?;
                    println!(
                        "geometry: {name} ({segments} segments) at {across} across, {steps} steps, count match {count}: {} particles, volume error {:+.3} %",
                        r.particles,
                        100.0 * (r.volume / exact - 1.0)
                    );
                    rows.push(json!({
                        "shape": name,
                        "segments": segments,
                        "triangles": solid.mesh().triangles.len(),
                        "across": across,
                        "dp": dp,
                        "relax_steps": steps,
                        "match_count": count,
                        "lattice_particles": r.lattice_particles,
                        "particles": r.particles,
                        "volume": r.volume,
                        "mesh_volume": r.mesh_volume,
                        "exact_volume": exact,
                        "surface_distance_rms": r.surface_distance_rms,
                        "surface_distance_max": r.surface_distance_max,
                        "volume_spread": r.volume_spread,
                    }));
                }
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
    println!("geometry: stored {}", path.display());
    Ok(())
}

/// The "Geometry" section of docs/validation.md from the stored figures.
pub fn report(md: &mut String) -> Result<(), String> {
    writeln!(md, "## Geometry: body-fitted particles of meshes\n").unwrap();
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
    writeln!(
        md,
        "A sphere (radius 1), a torus (R = 1, r = 0.4) and a unit cube, generated as triangle \
         meshes (UV sphere of n segments and n/2 rings; torus of 2n × n quads; the cube's 12 \
         triangles), filled by `sph_geometry::fit` at `across` particles over the smallest \
         feature (diameter, tube diameter, side): the lattice fill (0 steps, count `lattice`), \
         the lattice fill relaxed onto the surface ({DEFAULT_RELAX_STEPS} steps, the scene \
         files' default), and the default fit: the count first brought to the mesh's volume \
         (count `matched`, `FitOptions::match_count`: `N = round(V_mesh / dp³)` by removing \
         outer-layer particles spread over the surface, or adding some inside it, every \
         particle of volume dp³), then relaxed. \
         Volume error: the particles' total `N dp³` against the analytic volume (the mesh's own \
         volume, an inscribed polyhedron, is below it by the tessellation error in the next \
         column, which a matched count reproduces to half a particle). \
         Surface distance: of the particles less than dp below the surface, from \
         depth dp/2 (in dp). Volume spread: relative standard deviation of `1/(Σ W + Q)` (the \
         kernel sum completed beyond the surface). Regenerated by `validate geometry` (stored \
         in `validation/results/{FILE}`).\n"
    )
    .unwrap();
    writeln!(
        md,
        "| shape | segments | across | steps | count | particles | volume error | mesh volume error | surface distance rms / max (dp) | volume spread |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
    let rows = stored["rows"].as_array().cloned().unwrap_or_default();
    for r in &rows {
        let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:+.2} % | {:+.2} % | {:.3} / {:.3} | {:.4} |",
            r["shape"].as_str().unwrap_or("?"),
            r["segments"],
            r["across"],
            r["relax_steps"],
            if r["match_count"].as_bool() == Some(true) {
                "matched"
            } else {
                "lattice"
            },
            r["particles"],
            100.0 * (f("volume") / f("exact_volume") - 1.0),
            100.0 * (f("mesh_volume") / f("exact_volume") - 1.0),
            f("surface_distance_rms"),
            f("surface_distance_max"),
            f("volume_spread"),
        )
        .unwrap();
    }
    writeln!(md).unwrap();
    Ok(())
}
