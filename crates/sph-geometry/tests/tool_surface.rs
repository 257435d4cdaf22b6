//! Meshes and outlines as rigid-tool surfaces (`ToolShape::Surface`): their signed distance and
//! normal against the exact primitives they approximate or equal.

use sph_core::glam::{DVec2, DVec3};
use sph_core::tool::{SignedDistance, ToolShape};
use sph_core::{D2, D3};
use sph_geometry::mesh::{MeshSolid, Placement, TriMesh};
use sph_geometry::outline::OutlineSolid;
use sph_geometry::FileSolid;
use std::f64::consts::PI;
use std::sync::Arc;

/// Deterministic points in `[-a, a]^3` (a low-discrepancy sequence).
fn points(count: usize, a: f64) -> Vec<DVec3> {
    (0..count)
        .map(|i| {
            let f = i as f64 + 0.5;
            let frac = |x: f64| x - x.floor();
            DVec3::new(
                frac(f * 0.754_877_666),
                frac(f * 0.569_840_291),
                frac(f * 0.362_247_927),
            ) * (2.0 * a)
                - DVec3::splat(a)
        })
        .collect()
}

/// A UV sphere of `n` segments has its vertices on the sphere and every triangle inside a
/// cell of `2π/n` by `2π/n` (longitude by colatitude) whose circumscribed circle has the
/// angular radius `α ≤ √2 π/n` (half the cell's diagonal at the equator, less toward the
/// poles): the surface lies between the radii `R cos α` and `R`, so the signed distance of the
/// mesh is within `R (1 − cos α)` of the sphere's. The normals, for points between `R/2` and
/// `3R/2` from the centre, are within the angle `2α` of the radial direction (the facet normal
/// is within `α`; the nearest facet of a point within `α` of its direction).
#[test]
fn a_uv_sphere_surface_is_the_ball_within_its_tessellation_error() {
    let (c, r) = (DVec3::new(0.1, -0.2, 0.3), 0.5);
    let ball = ToolShape::<D3>::ball(c, r).unwrap();
    for n in [32, 64, 128] {
        let solid = MeshSolid::new(TriMesh::uv_sphere(c, r, n), "sphere").unwrap();
        let tool = ToolShape::<D3>::surface(Arc::new(solid)).unwrap();
        let alpha = 2f64.sqrt() * PI / n as f64;
        let bound = r * (1.0 - alpha.cos());
        let mut worst = 0.0f64;
        let mut checked = 0;
        for x in points(3000, 1.6 * r) {
            let x = x + c;
            let ((d, nm), (e, ne)) = (tool.distance(x), ball.distance(x));
            worst = worst.max((d - e).abs());
            assert!(
                (d - e).abs() <= bound * (1.0 + 1e-9),
                "n {n} at {x}: {d} vs {e}"
            );
            let rho = (x - c).length();
            if (0.5 * r..=1.5 * r).contains(&rho) {
                assert!(
                    nm.dot(ne) >= (2.0 * alpha).cos(),
                    "n {n} at {x}: normal {nm} vs {ne}"
                );
                checked += 1;
            }
        }
        println!(
            "n {n}: worst {worst:.3e} = {:.3} R(1 − cos α), {:.3} R(1 − cos(π/n))",
            worst / bound,
            worst / (r * (1.0 - (PI / n as f64).cos()))
        );
        // The bound is reached (measured 0.993–0.997 of it): the circumcentres of the
        // equator's triangles; the edge midpoints' sag R (1 − cos(π/n)) is half of it.
        assert!(
            worst > 0.95 * bound,
            "n {n}: worst {worst} vs bound {bound}"
        );
        assert!(checked > 1000);
        let (lo, hi) = tool.bounds();
        assert!((lo - (c - DVec3::splat(r))).abs().max_element() < 1e-12);
        assert!((hi - (c + DVec3::splat(r))).abs().max_element() < 1e-12);
    }
}

/// A cube given as 12 triangles is the `Box` tool exactly: the same distance, in and out, and
/// the same normals (the face's inside and on faces; the direction from the closest edge or
/// corner point outside).
#[test]
fn a_cube_mesh_is_the_box_tool() {
    let (lo, hi) = (DVec3::new(-0.1, 0.0, 0.2), DVec3::new(0.3, 0.5, 0.4));
    let cube = MeshSolid::new(TriMesh::cuboid(lo, hi), "cube").unwrap();
    let mesh = ToolShape::<D3>::surface(Arc::new(cube)).unwrap();
    let exact = ToolShape::<D3>::cuboid(lo, hi).unwrap();
    assert_eq!(mesh.bounds(), exact.bounds());
    let centre = 0.5 * (lo + hi);
    let mut inside = 0;
    for x in points(4000, 0.6) {
        let x = x + centre;
        let ((d, n), (e, m)) = (mesh.distance(x), exact.distance(x));
        assert!((d - e).abs() < 1e-12, "{x}: {d} vs {e}");
        assert!((n - m).length() < 1e-9, "{x}: {n} vs {m}");
        inside += usize::from(e < 0.0);
    }
    assert!(inside > 50, "{inside} points inside");
}

/// A regular polygon of `n` sides as a 2D outline tool: within `R (1 − cos(π/n))` of the disc
/// (its vertices on the circle, its edges' midpoints at `R cos(π/n)`).
#[test]
fn a_polygon_outline_is_the_disc_within_its_tessellation_error() {
    let (c, r, n) = (DVec2::new(0.2, 0.1), 0.3, 96);
    let polygon: Vec<DVec2> = (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            c + r * DVec2::new(a.cos(), a.sin())
        })
        .collect();
    let outline = OutlineSolid::new(vec![polygon], "disc").unwrap();
    let tool = ToolShape::<D2>::surface(Arc::new(outline)).unwrap();
    let disc = ToolShape::<D2>::ball(c, r).unwrap();
    let bound = r * (1.0 - (PI / n as f64).cos());
    let mut worst = 0.0f64;
    for x in points(2000, 1.5 * r) {
        let x = x.truncate() + c;
        let ((d, _), (e, _)) = (tool.distance(x), disc.distance(x));
        worst = worst.max((d - e).abs());
        assert!((d - e).abs() <= bound * (1.0 + 1e-9), "{x}: {d} vs {e}");
    }
    assert!(worst > 0.5 * bound, "worst {worst} vs bound {bound}");
}

/// A file solid read from an STL file is a surface of the scene's dimension; in the wrong
/// dimension it is refused before any tool exists.
#[test]
fn a_mesh_file_becomes_a_tool_surface() {
    let dir = std::env::temp_dir().join(format!("sph-geometry-tool-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ball.stl");
    TriMesh::uv_sphere(DVec3::ZERO, 5.0, 48)
        .write_stl(&path)
        .unwrap();
    let place = Placement {
        scale: 1e-2,
        translate: DVec3::new(0.0, 0.0, 1.0),
        ..Placement::default()
    };
    let solid = FileSolid::<D3>::mesh(&path, &place).unwrap();
    let (d, n) = SignedDistance::<D3>::signed_distance(&solid, DVec3::new(0.0, 0.0, 1.1));
    assert!(
        (d - 0.05).abs() < 1e-12 && (n - DVec3::Z).length() < 1e-12,
        "{d} {n}"
    );
    let shape = solid.into_tool_shape().unwrap();
    assert!(shape.distance(DVec3::new(0.0, 0.0, 1.0)).0 < -0.049);
    assert!(FileSolid::<D2>::mesh(&path, &place).is_err());
    std::fs::remove_dir_all(&dir).ok();
}
