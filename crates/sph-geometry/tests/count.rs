//! The fill whose count holds the enclosed volume (`sph_geometry::count`): `N dp^d` within half
//! a particle's volume of the mesh's volume, the surplus taken from the outer layer spread over
//! the surface, a deficit added inside, and the same particles at any thread count.

use sph_core::glam::{DVec2, DVec3};
use sph_core::{D2, D3};
use sph_geometry::count::{match_count, volume_count};
use sph_geometry::fit::{fit, lattice_points, FitOptions};
use sph_geometry::generate::{Lattice, Shape};
use sph_geometry::mesh::{MeshSolid, TriMesh};
use sph_geometry::outline::OutlineSolid;
use sph_geometry::Boundary;
use std::f64::consts::PI;

fn in_pool<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Checks a count-matched fit of `s` at `dp` (no relaxation, so the particles left are
/// lattice points): `|N dp³ − V| ≤ dp³/2` (the count is `round(V / dp³)`: this is the
/// rounding, nothing looser), only surface-layer particles removed, and the removed ones
/// spread: no two closer than half the spacing an even spread over the layer would give.
fn check_removal(s: &MeshSolid, dp: f64, lo: DVec3) {
    let v = dp.powi(3);
    let lattice = Lattice::<D3>::new(dp, lo).unwrap();
    let full = lattice_points(&lattice, s).unwrap();
    let options = FitOptions {
        relax_steps: 0,
        ..FitOptions::default()
    };
    let (set, r) = fit(s, dp, &options).unwrap();
    assert_eq!(r.lattice_particles, full.len());
    assert_eq!(r.particles, volume_count::<D3>(s.volume(), dp));
    assert!(
        (r.particles as f64 * v - s.volume()).abs() <= 0.5 * v,
        "{r:?}"
    );
    // The lattice overshoots on these convex-ish surfaces by more than rounding.
    let removed_count = full.len() - set.len();
    assert!(removed_count as f64 > 0.002 * full.len() as f64, "{r:?}");
    let kept: std::collections::HashSet<[u64; 3]> = set
        .positions()
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect();
    let removed: Vec<DVec3> = full
        .iter()
        .copied()
        .filter(|p| !kept.contains(&p.to_array().map(f64::to_bits)))
        .collect();
    assert_eq!(
        removed.len(),
        removed_count,
        "kept particles are lattice points"
    );
    let layer = full
        .iter()
        .filter(|&&p| s.signed_distance(p).0 > -dp)
        .count();
    for p in &removed {
        let phi = s.signed_distance(*p).0;
        assert!(phi > -dp && phi < 0.0, "removed at depth {phi}");
    }
    // An even spread of k points over the layer's area (≈ layer dp²) is a spacing of
    // √(layer dp² / k); allow half of it between the closest two.
    let even = (layer as f64 * dp * dp / removed.len() as f64).sqrt();
    let closest = removed
        .iter()
        .enumerate()
        .flat_map(|(a, p)| removed[a + 1..].iter().map(move |q| (*p - *q).length()))
        .fold(f64::INFINITY, f64::min);
    assert!(
        closest > 0.5 * even,
        "closest removed pair {closest:.3} against an even spacing {even:.3}"
    );
}

#[test]
fn a_sphere_at_20_across_holds_the_mesh_volume() {
    let s = MeshSolid::new(TriMesh::uv_sphere(DVec3::ZERO, 1.0, 64), "ball").unwrap();
    check_removal(&s, 0.1, s.bounds().0);
}

#[test]
fn a_torus_at_20_across_holds_the_mesh_volume() {
    let s = MeshSolid::new(TriMesh::torus(DVec3::ZERO, 1.0, 0.4, 64, 32), "torus").unwrap();
    check_removal(&s, 0.04, s.bounds().0);
}

#[test]
fn a_deficit_is_added_inside_the_surface() {
    // A box of 1.04 on a lattice of 0.1 from its corner: 10 cells a side (1000), while the
    // volume is 1124.9 cell volumes: 125 particles are added at depth dp/2 below the three
    // faces the surface cuts 0.01 beyond the lattice's last cells (not below the three faces
    // on cell faces, where the layer already sits at depth dp/2).
    let c = MeshSolid::new(TriMesh::cuboid(DVec3::ZERO, DVec3::splat(1.04)), "box").unwrap();
    let dp = 0.1;
    let (set, r) = fit(
        &c,
        dp,
        &FitOptions {
            relax_steps: 0,
            ..FitOptions::default()
        },
    )
    .unwrap();
    assert_eq!(r.lattice_particles, 1000);
    assert_eq!(r.particles, 1125);
    let added = &set.positions()[1000..];
    for p in added {
        let (phi, _) = c.signed_distance(*p);
        assert!((phi + 0.5 * dp).abs() < 1e-9, "added at depth {phi}");
    }
    // Spread over the three faces the lattice does not reach (x, y or z = 0.99): each gets at
    // least half its share (125/3), no two closer than half the even spacing √(3 / 125).
    let on = |k: usize| added.iter().filter(|p| (p[k] - 0.99).abs() < 1e-9).count();
    assert_eq!(on(0) + on(1) + on(2), 125);
    for k in 0..3 {
        assert!(on(k) > 20, "{} {} {}", on(0), on(1), on(2));
    }
    let closest = added
        .iter()
        .enumerate()
        .flat_map(|(a, p)| added[a + 1..].iter().map(move |q| (*p - *q).length()))
        .fold(f64::INFINITY, f64::min);
    assert!(closest > 0.5 * (3.0f64 / 125.0).sqrt(), "{closest}");
    // Relaxed, the layer spreads out and stays inside.
    let (set, r) = fit(
        &c,
        dp,
        &FitOptions {
            relax_steps: 30,
            ..FitOptions::default()
        },
    )
    .unwrap();
    assert_eq!(r.particles, 1125);
    assert!(set.positions().iter().all(|&p| c.contains(p)));
}

#[test]
fn an_outline_holds_its_area() {
    let n = 64;
    let disc: Vec<DVec2> = (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            DVec2::new(a.cos(), a.sin()) * 10.0
        })
        .collect();
    let s = OutlineSolid::new(vec![disc], "disc").unwrap();
    let (_, r) = fit::<D2>(&s, 1.0, &FitOptions::default()).unwrap();
    assert_ne!(r.lattice_particles, r.particles, "{r:?}");
    assert!((r.particles as f64 - s.volume()).abs() <= 0.5, "{r:?}");
}

#[test]
fn the_count_match_and_the_relaxation_do_not_depend_on_the_thread_count() {
    let s = MeshSolid::new(TriMesh::torus(DVec3::ZERO, 1.0, 0.4, 32, 16), "torus").unwrap();
    let run = || {
        let lattice = Lattice::<D3>::new(0.08, s.bounds().0).unwrap();
        let mut x = lattice_points(&lattice, &s).unwrap();
        let change = match_count(&mut x, &s, &lattice).unwrap();
        let (set, _) = fit(
            &s,
            0.08,
            &FitOptions {
                relax_steps: 15,
                ..FitOptions::default()
            },
        )
        .unwrap();
        (x, change, set.positions().to_vec())
    };
    let one = in_pool(1, run);
    let two = in_pool(2, run);
    assert!(one.1.removed > 0, "{:?}", one.1);
    assert_eq!(one, two);
}

/// A sphere whose enclosed volume reads as `volume` (a stand-in for a damaged file).
struct BadVolume(MeshSolid, f64);

impl Shape<D3> for BadVolume {
    fn contains(&self, x: DVec3) -> bool {
        self.0.contains(x)
    }
    fn bounds(&self) -> (DVec3, DVec3) {
        self.0.bounds()
    }
}

impl Boundary<D3> for BadVolume {
    fn signed_distance(&self, x: DVec3) -> (f64, DVec3) {
        self.0.signed_distance(x)
    }
    fn volume(&self) -> f64 {
        self.1
    }
    fn name(&self) -> &str {
        "bad.stl"
    }
}

#[test]
fn a_volume_that_cannot_be_matched_is_a_one_line_error() {
    let s = MeshSolid::new(TriMesh::uv_sphere(DVec3::ZERO, 1.0, 16), "ball").unwrap();
    for v in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        let bad = BadVolume(s.clone(), v);
        let e = fit(&bad, 0.25, &FitOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("bad.stl") && e.contains("enclosed volume") && !e.contains('\n'),
            "{e}"
        );
        // Without the count match the fill goes on.
        let options = FitOptions {
            match_count: false,
            relax_steps: 0,
            ..FitOptions::default()
        };
        assert!(fit(&bad, 0.25, &options).is_ok());
    }
}
