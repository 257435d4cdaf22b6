//! Fills a triangle mesh with body-fitted particles and prints where the time and the memory
//! go: writing and reading the STL file, the repair and hierarchy (`MeshSolid::new`), the
//! lattice fill (winding numbers on every core), the count match (the fill's count brought to
//! the enclosed volume, `sph_geometry::count`), the relaxation and the report. Issue 41's
//! target: a 1e5-triangle mesh into 1e6 particles on 2 cores under 60 s, and under 1 KiB of
//! memory per particle beyond the particle set itself.
//!
//! ```text
//! cargo run --release -p sph-benchmarks --bin geometry-fill -- [TRIANGLES] [PARTICLES] [RELAX_STEPS]
//! ```
//! Defaults: 100000 triangles (a torus, R = 1, r = 0.4), 1000000 particles (dp chosen from the
//! torus's volume), 200 relaxation steps (the scene files' default). The last line is JSON.

use sph_core::glam::DVec3;
use sph_core::kernel::WendlandC2;
use sph_core::D3;
use sph_geometry::count::match_count;
use sph_geometry::fit::{lattice_points, relax, report, HalfSpaceIntegrals, RELAX_H_OVER_DP};
use sph_geometry::generate::{Lattice, ParticleSet, Shape};
use sph_geometry::mesh::{MeshSolid, Placement, TriMesh};
use std::time::Instant;

/// The peak resident memory of this process so far, bytes (Linux: `VmHWM`).
fn peak_rss() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

fn arg(k: usize, default: f64, what: &str) -> f64 {
    match std::env::args().nth(k) {
        None => default,
        Some(s) => match s.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => v,
            _ => {
                eprintln!("error: {what} must be a non-negative number, got {s:?}");
                std::process::exit(2);
            }
        },
    }
}

fn fail(e: sph_core::Error) -> ! {
    eprintln!("error: {e}");
    std::process::exit(1)
}

fn main() {
    let triangles = arg(1, 1e5, "TRIANGLES").max(100.0);
    let particles = arg(2, 1e6, "PARTICLES").max(1000.0);
    let steps = arg(3, 200.0, "RELAX_STEPS") as usize;
    // A torus of n × m quads, two triangles each, m ≈ n/3.
    let n = ((1.5 * triangles).sqrt()).round().max(6.0) as usize;
    let m = (triangles / (2.0 * n as f64)).round().max(3.0) as usize;
    let (big, r) = (1.0, 0.4);
    let mesh = TriMesh::torus(DVec3::ZERO, big, r, n, m);
    let volume = 2.0 * std::f64::consts::PI.powi(2) * big * r * r;
    let dp = (volume / particles).cbrt();
    println!(
        "torus: {} triangles, dp = {dp:.4e}, {} threads",
        mesh.triangles.len(),
        rayon::current_num_threads()
    );
    let dir = std::env::temp_dir().join(format!("sph-geometry-fill-{}", std::process::id()));
    std::fs::create_dir_all(&dir)
        .unwrap_or_else(|e| fail(sph_core::Error::Checkpoint(e.to_string())));
    let path = dir.join("torus.stl");
    let mut times = Vec::new();
    let t = Instant::now();
    mesh.write_stl_binary(&path).unwrap_or_else(|e| fail(e));
    times.push(("write STL", t.elapsed().as_secs_f64()));
    let t = Instant::now();
    let read = TriMesh::read(&path).unwrap_or_else(|e| fail(e));
    times.push(("read STL", t.elapsed().as_secs_f64()));
    std::fs::remove_dir_all(&dir).ok();
    let t = Instant::now();
    let solid =
        MeshSolid::new(read.placed(&Placement::default()), "torus.stl").unwrap_or_else(|e| fail(e));
    times.push(("repair + hierarchy", t.elapsed().as_secs_f64()));
    let rss_mesh = peak_rss();
    let t = Instant::now();
    let lattice = Lattice::<D3>::new(dp, solid.bounds().0).unwrap_or_else(|e| fail(e));
    let mut x = lattice_points(&lattice, &solid).unwrap_or_else(|e| fail(e));
    times.push(("lattice fill", t.elapsed().as_secs_f64()));
    let lattice_count = x.len();
    let t = Instant::now();
    let change = match_count(&mut x, &solid, &lattice).unwrap_or_else(|e| fail(e));
    times.push(("count match", t.elapsed().as_secs_f64()));
    let count = x.len();
    let t = Instant::now();
    let kernel = WendlandC2::<D3>::from_spacing(dp, RELAX_H_OVER_DP).unwrap_or_else(|e| fail(e));
    let tables = HalfSpaceIntegrals::new(&kernel);
    relax(&mut x, &solid, dp, &kernel, &tables, steps).unwrap_or_else(|e| fail(e));
    times.push(("relaxation", t.elapsed().as_secs_f64()));
    let t = Instant::now();
    let set = ParticleSet::from_parts(x, vec![dp.powi(3); count])
        .unwrap_or_else(|e| fail(e))
        .with_spacing(dp);
    let rep = report(&set, &solid, dp, &kernel, &tables, steps).unwrap_or_else(|e| fail(e));
    times.push(("report", t.elapsed().as_secs_f64()));
    let total: f64 = times.iter().map(|t| t.1).sum();
    for (what, s) in &times {
        println!("{what:<20} {s:>9.3} s  {:>5.1} %", 100.0 * s / total);
    }
    println!("{:<20} {total:>9.3} s", "total");
    // The set itself: position (24 B) and volume (8 B) and tag (4 B) per particle.
    let set_bytes = 36.0 * count as f64;
    let peak = peak_rss();
    let beyond = peak.map(|p| (p - set_bytes) / count as f64);
    println!(
        "{count} particles; peak memory {:.1} MiB (after the mesh: {:.1} MiB), {:.0} B per particle beyond the set",
        peak.unwrap_or(f64::NAN) / 1048576.0,
        rss_mesh.unwrap_or(f64::NAN) / 1048576.0,
        beyond.unwrap_or(f64::NAN)
    );
    println!("{rep:?}");
    let json = serde_json::json!({
        "triangles": solid.mesh().triangles.len(),
        "particles": count,
        "lattice_particles": lattice_count,
        "removed": change.removed,
        "added": change.added,
        "dp": dp,
        "relax_steps": steps,
        "threads": rayon::current_num_threads(),
        "seconds": times.iter().map(|(k, v)| (k.to_string(), serde_json::json!(v))).collect::<serde_json::Map<_, _>>(),
        "total_seconds": total,
        "peak_bytes": peak,
        "bytes_per_particle_beyond_set": beyond,
        "volume": rep.volume,
        "mesh_volume": rep.mesh_volume,
        "surface_distance_rms": rep.surface_distance_rms,
        "volume_spread": rep.volume_spread,
    });
    println!("{json}");
}
