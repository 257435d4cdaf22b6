//! Meshes and outlines: the readers, the inside test on damaged meshes, the one-line errors, and
//! the body-fitted fill with its report.

use sph_core::glam::{DVec2, DVec3};
use sph_core::{D2, D3};
use sph_geometry::fit::{fit, lattice_points, FitOptions};
use sph_geometry::generate::{Lattice, ParticleSet, Shape};
use sph_geometry::mesh::{MeshSolid, Placement, TriMesh};
use sph_geometry::outline::OutlineSolid;
use sph_geometry::Boundary;
use std::f64::consts::PI;
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-geometry-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A binary STL written byte by byte (80-byte header, count, 50 bytes per facet).
fn write_binary_stl(mesh: &TriMesh, path: &std::path::Path) {
    let mut b = vec![0u8; 80];
    b.extend((mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        b.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        for &i in t {
            let v = mesh.vertices[i as usize];
            for c in [v.x, v.y, v.z] {
                b.extend((c as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    std::fs::write(path, b).unwrap();
}

fn count(solid: &MeshSolid, dp: f64) -> usize {
    lattice_points(&Lattice::<D3>::new(dp, DVec3::splat(-1.0)).unwrap(), solid)
        .unwrap()
        .len()
}

#[test]
fn stl_ascii_binary_and_obj_read_the_same_solid() {
    let dir = scratch("readers");
    let sphere = TriMesh::uv_sphere(DVec3::ZERO, 0.8, 24);
    sphere.write_stl(&dir.join("a.stl")).unwrap();
    write_binary_stl(&sphere, &dir.join("b.STL"));
    // OBJ with quads (triangulated by the reader) and a comment: a cube.
    std::fs::write(
        dir.join("c.obj"),
        "# cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    )
    .unwrap();
    let p = Placement::default();
    let a = MeshSolid::read(&dir.join("a.stl"), &p).unwrap();
    let b = MeshSolid::read(&dir.join("b.STL"), &p).unwrap();
    let c = MeshSolid::read(&dir.join("c.obj"), &p).unwrap();
    assert_eq!(a.mesh().triangles.len(), sphere.triangles.len());
    assert_eq!(b.mesh().triangles.len(), sphere.triangles.len());
    // f32 storage: volumes agree to single precision.
    assert!((a.volume() - b.volume()).abs() < 1e-6 * a.volume());
    assert!((c.volume() - 1.0).abs() < 1e-12, "{}", c.volume());
    assert_eq!(c.mesh().triangles.len(), 12);
    assert_eq!(count(&a, 0.1), count(&b, 0.1));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn placement_scales_rotates_and_translates() {
    let dir = scratch("place");
    TriMesh::cuboid(DVec3::ZERO, DVec3::new(2.0, 1.0, 1.0))
        .write_stl(&dir.join("box.stl"))
        .unwrap();
    let p = Placement {
        scale: 0.5,
        axis: DVec3::Z,
        degrees: 90.0,
        translate: DVec3::new(10.0, 0.0, 0.0),
    };
    let s = MeshSolid::read(&dir.join("box.stl"), &p).unwrap();
    // (2 × 1 × 1) · ½ = 1 × ½ × ½, turned a quarter about z: x ∈ [−½, 0] + 10, y ∈ [0, 1].
    let (lo, hi) = s.bounds();
    assert!((lo - DVec3::new(9.5, 0.0, 0.0)).length() < 1e-12, "{lo}");
    assert!((hi - DVec3::new(10.0, 1.0, 0.5)).length() < 1e-12, "{hi}");
    assert!((s.volume() - 0.25).abs() < 1e-12);
    for bad in [
        Placement { scale: 0.0, ..p },
        Placement {
            axis: DVec3::ZERO,
            ..p
        },
        Placement {
            degrees: f64::NAN,
            ..p
        },
    ] {
        let e = MeshSolid::read(&dir.join("box.stl"), &bad)
            .unwrap_err()
            .to_string();
        assert!(e.contains("scale") || e.contains("rotate"), "{e}");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn winding_number_volume_and_distance_of_a_sphere() {
    let r = 1.0;
    let s = MeshSolid::new(TriMesh::uv_sphere(DVec3::ZERO, r, 64), "sphere").unwrap();
    // The inscribed polyhedron: volume below the sphere's by O(1/n²).
    let exact = 4.0 / 3.0 * PI;
    assert!(
        s.volume() < exact && s.volume() > 0.99 * exact,
        "{}",
        s.volume()
    );
    // The far field at first order (bvh.rs): within a few per cent; exact near the surface.
    for (x, w) in [
        (DVec3::ZERO, 1.0),
        (DVec3::new(0.5, 0.3, -0.2), 1.0),
        (DVec3::splat(2.0), 0.0),
    ] {
        assert!(
            (s.winding_number(x) - w).abs() < 0.05,
            "{x}: {}",
            s.winding_number(x)
        );
    }
    // Just inside and outside the pole: far from the threshold ½ either side.
    assert!(s.winding_number(DVec3::new(0.0, 0.0, 0.99)) > 0.9);
    assert!(s.winding_number(DVec3::new(0.0, 0.0, 1.01)) < 0.1);
    let (phi, n) = s.signed_distance(DVec3::new(0.0, 0.0, 0.5));
    assert!(
        (phi + 0.5).abs() < 2e-3 && (n - DVec3::Z).length() < 0.06,
        "{phi} {n}"
    );
    let (phi, n) = s.signed_distance(DVec3::new(3.0, 0.0, 0.0));
    assert!(
        (phi - 2.0).abs() < 2e-3 && (n - DVec3::X).length() < 1e-2,
        "{phi} {n}"
    );
}

#[test]
fn damaged_meshes_fill_like_the_intact_one() {
    let intact = TriMesh::uv_sphere(DVec3::ZERO, 0.9, 40);
    let dp = 0.1;
    let reference = count(&MeshSolid::new(intact.clone(), "intact").unwrap(), dp);
    assert!(reference > 2500, "{reference}");

    // A hole: two triangles missing.
    let mut hole = intact.clone();
    hole.triangles.drain(100..102);
    let s = MeshSolid::new(hole, "hole").unwrap();
    assert!(s.stats().boundary_edges >= 4, "{:?}", s.stats());
    assert_eq!(count(&s, dp), reference);

    // Every triangle turned over (inside out), and every third turned over.
    let mut flipped = intact.clone();
    flipped.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    let s = MeshSolid::new(flipped, "flipped").unwrap();
    assert_eq!(count(&s, dp), reference);
    let mut some = intact.clone();
    some.triangles
        .iter_mut()
        .step_by(3)
        .for_each(|t| t.swap(1, 2));
    let s = MeshSolid::new(some, "some-flipped").unwrap();
    assert!(s.stats().flipped > 0);
    assert_eq!(count(&s, dp), reference);

    // Duplicated faces, zero-area triangles, a non-manifold fin.
    let mut dup = intact.clone();
    let extra: Vec<[u32; 3]> = dup.triangles[..50].to_vec();
    dup.triangles.extend(extra);
    dup.triangles.push([3, 3, 7]);
    let v = dup.vertices.len() as u32;
    let (a, b) = (dup.vertices[5], dup.vertices[6]);
    dup.vertices.push((a + b) * 0.5); // collinear: zero area
    dup.triangles.push([5, 6, v]);
    dup.vertices.push(DVec3::new(3.0, 0.0, 0.0)); // a fin on an existing edge
    let t0 = dup.triangles[0];
    dup.triangles.push([t0[0], t0[1], v + 1]);
    let s = MeshSolid::new(dup, "dup").unwrap();
    let st = s.stats();
    assert_eq!((st.duplicates, st.degenerate), (50, 2), "{st:?}");
    assert!(st.non_manifold_edges >= 1, "{st:?}");
    assert_eq!(count(&s, dp), reference);
}

#[test]
fn what_cannot_be_filled_stops_with_one_line_naming_the_file() {
    let dir = scratch("bad");
    let sheet = TriMesh::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    sheet.write_stl(&dir.join("sheet.stl")).unwrap();
    std::fs::write(dir.join("empty.stl"), "solid x\nendsolid x\n").unwrap();
    std::fs::write(dir.join("junk.stl"), "this is not a mesh").unwrap();
    std::fs::write(dir.join("part.step"), "ISO-10303-21;").unwrap();
    let p = Placement::default();
    for (file, needle) in [
        ("sheet.stl", "2 triangles, 4 boundary edges"),
        ("empty.stl", "no triangle"),
        ("junk.stl", "junk.stl"),
        ("part.step", "allowed extensions are .stl and .obj"),
        ("missing.obj", "missing.obj"),
    ] {
        let e = MeshSolid::read(&dir.join(file), &p)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle) && e.contains(file), "{file}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    // A solid smaller than the spacing: no particle, an error naming the file.
    let tiny =
        MeshSolid::new(TriMesh::cuboid(DVec3::ZERO, DVec3::splat(0.01)), "tiny.stl").unwrap();
    let e = fit(&tiny, 0.1, &FitOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("tiny.stl") && e.contains("dp"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn outlines_from_text_and_svg_with_holes_and_crossings() {
    let dir = scratch("outline");
    // A square with a square hole (two loops, same orientation: even-odd makes the hole).
    std::fs::write(
        dir.join("frame.csv"),
        "x,y\n0,0\n4,0\n4,4\n0,4\n0,0\n\n1 1\n3 1\n3 3\n1 3\n",
    )
    .unwrap();
    let f = OutlineSolid::read(&dir.join("frame.csv"), &Placement::default()).unwrap();
    assert_eq!(f.loops().len(), 2);
    assert!((f.area() - 12.0).abs() < 1e-12);
    assert!(f.contains(DVec2::new(0.5, 0.5)) && !f.contains(DVec2::new(2.0, 2.0)));
    // SVG: y turned up, scaled by 1/10.
    std::fs::write(
        dir.join("tri.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg"><g><polygon points="0,0 10,0 0,10"/></g></svg>"#,
    )
    .unwrap();
    let place = Placement {
        scale: 0.1,
        ..Default::default()
    };
    let t = OutlineSolid::read(&dir.join("tri.svg"), &place).unwrap();
    assert!((t.area() - 0.5).abs() < 1e-12);
    assert!(t.contains(DVec2::new(0.2, -0.2)));
    // A bow tie crosses itself; a transform is refused; a 3D axis is refused.
    std::fs::write(dir.join("bow.txt"), "0 0\n1 1\n1 0\n0 1\n").unwrap();
    let e = OutlineSolid::read(&dir.join("bow.txt"), &Placement::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bow.txt") && e.contains("crosses itself (1 crossings"),
        "{e}"
    );
    std::fs::write(
        dir.join("moved.svg"),
        r#"<svg><g transform="scale(2)"><polygon points="0,0 1,0 0,1"/></g></svg>"#,
    )
    .unwrap();
    let e = OutlineSolid::read(&dir.join("moved.svg"), &Placement::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("transform"), "{e}");
    let tilted = Placement {
        axis: DVec3::X,
        degrees: 10.0,
        ..Default::default()
    };
    let e = OutlineSolid::read(&dir.join("frame.csv"), &tilted)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rotate.axis"), "{e}");
    std::fs::write(dir.join("two.csv"), "0 0\n1 1\n").unwrap();
    let e = OutlineSolid::read(&dir.join("two.csv"), &Placement::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("two.csv") && e.contains("2 distinct vertices"),
        "{e}"
    );
    std::fs::write(dir.join("text.csv"), "0 0\n1 x\n").unwrap();
    let e = OutlineSolid::read(&dir.join("text.csv"), &Placement::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("line 2"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_parallel_fill_is_the_sequential_fill() {
    let s = MeshSolid::new(TriMesh::torus(DVec3::ZERO, 1.0, 0.4, 32, 16), "torus").unwrap();
    let lattice = Lattice::<D3>::new(0.1, DVec3::splat(-1.4)).unwrap();
    let seq = ParticleSet::fill(&lattice, &s).unwrap();
    let par = lattice_points(&lattice, &s).unwrap();
    assert_eq!(seq.positions(), &par[..]);
}

#[test]
fn relaxation_fits_the_surface_layer_of_a_ball() {
    // A ball of radius 6 dp (12 particles across): relaxation brings the surface layer to
    // depth dp/2 and evens the volumes; with the lattice's count (N dp³) it also lowers the
    // largest distance. With the count matched to the volume (the default) the thinned
    // layer is still filling in after 100 steps: the rms and the spread improve as much, the
    // largest distance (a second-layer particle moving into a gap counts as surface once less
    // than dp deep) stays below dp/2.
    let dp = 1.0;
    let s = MeshSolid::new(TriMesh::uv_sphere(DVec3::ZERO, 6.0, 96), "ball").unwrap();
    for match_count in [false, true] {
        let (_, off) = fit(
            &s,
            dp,
            &FitOptions {
                relax_steps: 0,
                match_count,
                ..FitOptions::default()
            },
        )
        .unwrap();
        let (set, on) = fit(
            &s,
            dp,
            &FitOptions {
                relax_steps: 100,
                match_count,
                ..FitOptions::default()
            },
        )
        .unwrap();
        assert_eq!(off.particles, on.particles);
        assert_eq!(set.len(), on.particles);
        assert!((on.volume / on.mesh_volume - 1.0).abs() < 0.05, "{on:?}");
        if match_count {
            assert!((on.volume - on.mesh_volume).abs() <= 0.5, "{on:?}");
        }
        assert!(
            on.surface_distance_rms < 0.5 * off.surface_distance_rms,
            "{off:?} {on:?}"
        );
        if !match_count {
            assert!(
                on.surface_distance_max <= off.surface_distance_max,
                "{off:?} {on:?}"
            );
        }
        assert!(on.volume_spread < 0.5 * off.volume_spread, "{off:?} {on:?}");
        // Every particle stays inside.
        assert!(set.positions().iter().all(|&x| s.contains(x)));
    }
}

#[test]
fn relaxation_fits_a_2d_outline() {
    let n = 64;
    let disc: Vec<DVec2> = (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            DVec2::new(a.cos(), a.sin()) * 10.0
        })
        .collect();
    let s = OutlineSolid::new(vec![disc], "disc").unwrap();
    let (_, off) = fit::<D2>(
        &s,
        1.0,
        &FitOptions {
            relax_steps: 0,
            ..FitOptions::default()
        },
    )
    .unwrap();
    let (set, on) = fit::<D2>(
        &s,
        1.0,
        &FitOptions {
            relax_steps: 100,
            ..FitOptions::default()
        },
    )
    .unwrap();
    assert!(
        on.surface_distance_rms < 0.5 * off.surface_distance_rms,
        "{off:?} {on:?}"
    );
    assert!((on.volume / on.mesh_volume - 1.0).abs() < 0.05, "{on:?}");
    assert!(set.positions().iter().all(|&x| s.contains(x)));
}

#[test]
fn the_fit_and_its_report_do_not_depend_on_the_units() {
    // The same ball in metres and in millimetres: the same particles (scaled), the same
    // report in units of dp (a missing 1/dp³ once made the volume spread unit-dependent:
    // 0.039 against 0.226 unrelaxed). Round-off in the scaled vertices grows through the
    // relaxation's steps: 2 %.
    let fit_at = |scale: f64| {
        let ball = TriMesh::uv_sphere(DVec3::ZERO, 5.0, 32).placed(&Placement {
            scale,
            ..Default::default()
        });
        let s = MeshSolid::new(ball, "ball").unwrap();
        fit(
            &s,
            scale,
            &FitOptions {
                relax_steps: 20,
                ..FitOptions::default()
            },
        )
        .unwrap()
        .1
    };
    let (a, b) = (fit_at(1.0), fit_at(1e-3));
    assert_eq!(a.particles, b.particles);
    assert!((a.volume - b.volume * 1e9).abs() < 1e-9 * a.volume);
    for (x, y) in [
        (a.surface_distance_rms, b.surface_distance_rms),
        (a.volume_spread, b.volume_spread),
    ] {
        assert!((x - y).abs() < 0.02 * x, "{a:?} {b:?}");
    }
}

#[test]
fn matched_volume_makes_the_body_hold_the_enclosed_volume() {
    // A sphere at 20 particles across: the lattice fill's N dp³ (`match_count` off) misses the
    // enclosed volume by the cells the surface cuts (+0.94 %); with `match_volume` (an
    // option, off by default) every particle's volume, and with the density its mass, is scaled so the total
    // is the mesh's volume (to round-off in the sum: 1e-12), and the report keeps the raw N dp³.
    let s = MeshSolid::new(TriMesh::uv_sphere(DVec3::ZERO, 1.0, 64), "ball").unwrap();
    let dp = 0.1;
    let raw_options = FitOptions {
        relax_steps: 0,
        match_volume: false,
        match_count: false,
    };
    let (raw, r) = fit(&s, dp, &raw_options).unwrap();
    assert_eq!(r.volume_scale, 1.0);
    assert!(raw.volumes().iter().all(|&v| v == dp.powi(3)));
    assert!((r.volume - raw.total_volume()).abs() < 1e-12 * r.volume);
    // The miss is what the remedy is for (not round-off): more than 0.1 %.
    assert!((r.volume / r.mesh_volume - 1.0).abs() > 1e-3, "{r:?}");

    assert!(!FitOptions::default().match_volume, "off by default");
    let options = FitOptions {
        relax_steps: 0,
        match_volume: true,
        match_count: false,
    };
    let (set, m) = fit(&s, dp, &options).unwrap();
    assert_eq!(set.positions(), raw.positions());
    assert_eq!(m.volume, r.volume, "the report keeps the raw volume");
    assert!((m.volume_scale - m.mesh_volume / m.volume).abs() < 1e-15);
    assert!(
        (set.total_volume() / m.mesh_volume - 1.0).abs() < 1e-12,
        "{m:?}"
    );
    assert!((m.volume * m.volume_scale / m.mesh_volume - 1.0).abs() < 1e-12);
    let rho = 1000.0;
    let mass: f64 = set.masses(rho).iter().sum();
    assert!((mass / (rho * m.mesh_volume) - 1.0).abs() < 1e-12);
    // The spacing (kernel length) is still dp.
    assert_eq!(set.spacing(), Some(dp));
}

#[test]
fn matched_volume_leaves_a_cube_on_the_lattice_and_scales_an_outline() {
    // A cube whose faces are cell faces: N dp³ is its volume, the factor 1 (to round-off).
    let c = MeshSolid::new(TriMesh::cuboid(DVec3::ZERO, DVec3::splat(1.0)), "cube").unwrap();
    let (_, r) = fit(
        &c,
        0.1,
        &FitOptions {
            relax_steps: 0,
            match_volume: true,
            match_count: false,
        },
    )
    .unwrap();
    assert_eq!(r.particles, 1000);
    assert!((r.volume_scale - 1.0).abs() < 1e-12, "{r:?}");
    // A disc outline (2D): the area is matched.
    let n = 64;
    let disc: Vec<DVec2> = (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            DVec2::new(a.cos(), a.sin()) * 10.0
        })
        .collect();
    let s = OutlineSolid::new(vec![disc], "disc").unwrap();
    let (set, r) = fit::<D2>(
        &s,
        1.0,
        &FitOptions {
            relax_steps: 0,
            match_volume: true,
            match_count: false,
        },
    )
    .unwrap();
    assert!((r.volume / r.mesh_volume - 1.0).abs() > 1e-4, "{r:?}");
    assert!(
        (set.total_volume() / r.mesh_volume - 1.0).abs() < 1e-12,
        "{r:?}"
    );
}
