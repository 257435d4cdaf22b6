//! Issue 42: a pressure load from a scene file against its closed form. The thick ring of
//! `examples/scenes/pressurised_ring.toml` (inner radius a = 10 mm, outer b = 20 mm, linear
//! elastic E = 1 MPa, ν = 0.3, plane strain) under an internal pressure p = 1 kPa that rises
//! smoothly over 1 ms and is held, relaxed to equilibrium by the TL pairwise damping: the mean
//! radial displacement of the inner and outer layers against Lamé's
//! `u(r) = p a²/(b² − a²) ((1 − 2ν)(1 + ν) r + (1 + ν) b²/r)/E` at each particle's radius.

use sph_driver::RunOptions;
use sph_output::read_file;
use sph_scene::Scene;
use std::path::{Path, PathBuf};

fn ring_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/pressurised_ring.toml")
}

/// Lamé's plane-strain radial displacement of a thick cylinder under internal pressure.
fn lame(r: f64, p: f64, a: f64, b: f64, e: f64, nu: f64) -> f64 {
    p * a * a / (b * b - a * a) * ((1.0 - 2.0 * nu) * (1.0 + nu) * r + (1.0 + nu) * b * b / r) / e
}

/// The relative errors of the mean radial displacement of the inner and outer layers at the
/// end of the run, at spacing `dp`.
fn ring_errors(dp: f64) -> (f64, f64) {
    let dir = std::env::temp_dir().join(format!("sph-ring-{}-{dp}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Scene::from_file(ring_file())
        .unwrap()
        .set("dp", &dp.to_string())
        .unwrap();
    let options = RunOptions {
        output: Some(dir.join("ring")),
        ..RunOptions::default()
    };
    let (record, _) = scene.run(&options).unwrap();
    assert!(record.failure.is_none(), "{:?}", record.failure);
    let file = read_file(record.file.unwrap()).unwrap();
    let x0 = file.snapshots[0]
        .dataset("position")
        .unwrap()
        .as_f64()
        .unwrap();
    let x1 = file
        .snapshots
        .last()
        .unwrap()
        .dataset("position")
        .unwrap()
        .as_f64()
        .unwrap();
    let (a, b, p, e, nu) = (0.01, 0.02, 1e3, 1e6, 0.3);
    let (mut inner, mut outer) = ((0.0, 0.0), (0.0, 0.0));
    for k in 0..x0.len() / 3 {
        let r0 = x0[3 * k].hypot(x0[3 * k + 1]);
        let r1 = x1[3 * k].hypot(x1[3 * k + 1]);
        let layer = if r0 < a + dp {
            &mut inner
        } else if r0 > b - dp {
            &mut outer
        } else {
            continue;
        };
        layer.0 += r1 - r0;
        layer.1 += lame(r0, p, a, b, e, nu);
    }
    let _ = std::fs::remove_dir_all(&dir);
    (inner.0 / inner.1 - 1.0, outer.0 / outer.1 - 1.0)
}

/// Tolerance: 2 % at dp = 0.5 mm (20 layers through the wall), and the error smaller than at
/// dp = 1 mm. Measured (this test, 2 cores): inner +2.0 %, outer +3.4 % at dp = 1 mm; inner
/// −0.1 %, outer +1.3 % at dp = 0.5 mm. The error is the discretisation's, first order near
/// the free surfaces (the outer layer sits dp/2 inside r = b, its kernel support cut by the
/// surface), and halves with dp; on top of it the relaxation leaves ±0.2 % of breathing at
/// the end time, and the small-strain closed form differs from the large-strain solution by
/// O(p/E) = 0.1 %.
#[test]
fn a_pressurised_ring_from_a_scene_file_matches_lame() {
    let (coarse_in, coarse_out) = ring_errors(1e-3);
    let (fine_in, fine_out) = ring_errors(5e-4);
    println!(
        "dp = 1 mm: inner {coarse_in:+.4}, outer {coarse_out:+.4}; \
         dp = 0.5 mm: inner {fine_in:+.4}, outer {fine_out:+.4}"
    );
    assert!(fine_in.abs() < 0.02 && fine_out.abs() < 0.02);
    let (coarse, fine) = (
        coarse_in.abs().max(coarse_out.abs()),
        fine_in.abs().max(fine_out.abs()),
    );
    assert!(fine < coarse, "no convergence: {coarse} -> {fine}");
}
