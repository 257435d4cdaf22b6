//! Meshes and outlines in scene files: bodies, regions and booleans, the fitted layout, the
//! preview, and the one-line errors of every new key.

use sph_core::glam::DVec3;
use sph_geometry::mesh::TriMesh;
use sph_scene::Scene;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("sph-scene-geometry-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene(dir: &Path, text: &str) -> Result<Scene, String> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    Scene::from_file(&path).map_err(|e| e.to_string())
}

const HEAD3: &str = "name = \"m\"\ndimension = 3\nmethod = \"ul-enog\"\nend_time = 1e-4\n\
                     [material]\nlaw = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n";
const HEAD2: &str = "name = \"o\"\ndimension = 2\nmethod = \"tl-hf\"\nend_time = 1e-4\n\
                     [material]\nlaw = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n";

#[test]
fn a_mesh_body_is_fitted_and_a_mesh_region_holds_particles() {
    let dir = scratch("mesh");
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    // A ball of radius 5 (mm), a box region cut by a mesh.
    TriMesh::uv_sphere(DVec3::ZERO, 5.0, 32)
        .write_stl_binary(&dir.join("parts/ball.stl"))
        .unwrap();
    TriMesh::cuboid(
        DVec3::new(-10.0, -10.0, -10.0),
        DVec3::new(10.0, 10.0, -3.0),
    )
    .write_stl(&dir.join("parts/slab.stl"))
    .unwrap();
    let text = format!(
        "{HEAD3}[[body]]\nname = \"ball\"\ndp = 1e-3\nrelax_steps = 30\n\
         shape = {{ mesh = {{ file = \"parts/ball.stl\", scale = 1e-3, rotate = {{ axis = [1.0, 0.0, 0.0], degrees = 90.0 }}, translate = [0.0, 0.0, 0.01] }} }}\n\
         [[constraint]]\ntype = \"fixed\"\n\
         region = {{ intersection = [ {{ mesh = {{ file = \"parts/slab.stl\", scale = 1e-3, translate = [0.0, 0.0, 0.01] }} }}, {{ box = {{ min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }} }} ] }}\n"
    );
    let s = scene(&dir, &text).unwrap();
    let p = s.preview().unwrap();
    let b = &p.bodies[0];
    // 4/3 π 5³ = 523.6 particles of 1 mm³.
    assert!((b.volume / 1e-9 - 523.6).abs() < 0.06 * 523.6, "{b:?}");
    let mesh = b.mesh_volume.unwrap();
    assert!((mesh / 1e-9 - 523.6).abs() < 0.02 * 523.6, "{b:?}");
    // Scene files keep the fill's volumes (`FitOptions::match_volume` is off by default): the
    // factor is 1 and the raw fill N dp³ is the volume.
    assert_eq!(b.volume_scale, Some(1.0), "{b:?}");
    let raw = b.volume / b.volume_scale.unwrap();
    assert!(
        (raw / (b.particles as f64 * 1e-9) - 1.0).abs() < 1e-9,
        "{b:?}"
    );
    assert!(
        b.surface_distance_rms.unwrap() < 0.2 && b.volume_spread.unwrap() < 0.05,
        "{b:?}"
    );
    // Held: the particles below z = 10 mm − 3 mm.
    let held: Vec<usize> = (0..p.positions.len())
        .filter(|&i| p.constraint[i] == 1)
        .collect();
    assert!(!held.is_empty());
    assert!(held.iter().all(|&i| p.positions[i][2] < 0.007 + 1e-12));
    assert!(p.positions.iter().all(|x| (x[2] - 0.01).abs() < 0.005));
    // The same scene runs.
    let (record, _) = s.run(&Default::default()).unwrap();
    assert!(record.failure.is_none(), "{:?}", record.failure);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn an_outline_body_in_2d_with_the_lattice_or_fitted_layout() {
    let dir = scratch("outline");
    std::fs::write(dir.join("l.csv"), "0 0\n20 0\n20 5\n5 5\n5 20\n0 20\n").unwrap();
    let body = |extra: &str| {
        format!(
            "{HEAD2}[[body]]\nname = \"l\"\ndp = 1e-3\n{extra}shape = {{ outline = {{ file = \"l.csv\", scale = 1e-3 }} }}\n"
        )
    };
    let fitted = scene(&dir, &body("")).unwrap().preview().unwrap();
    let lattice = scene(&dir, &body("layout = \"lattice\"\n"))
        .unwrap()
        .preview()
        .unwrap();
    // The L: 20 × 5 + 5 × 15 = 175 cells, exactly, on a lattice through its corner.
    assert_eq!(lattice.bodies[0].particles, 175);
    assert_eq!(lattice.bodies[0].mesh_volume, None);
    assert_eq!(lattice.bodies[0].volume_scale, None);
    assert_eq!(fitted.bodies[0].particles, 175);
    assert!((fitted.bodies[0].mesh_volume.unwrap() - 175e-6).abs() < 1e-12);
    // Cells fill the L exactly: the factor is 1 (to round-off).
    assert!((fitted.bodies[0].volume_scale.unwrap() - 1.0).abs() < 1e-12);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_geometry_keys_give_one_line_naming_the_key() {
    let dir = scratch("bad");
    TriMesh::cuboid(DVec3::ZERO, DVec3::ONE)
        .write_stl(&dir.join("cube.stl"))
        .unwrap();
    std::fs::write(dir.join("bow.csv"), "0 0\n1 1\n1 0\n0 1\n").unwrap();
    let b3 = |shape: &str, extra: &str| {
        format!("{HEAD3}[[body]]\nname = \"b\"\ndp = 0.1\n{extra}shape = {shape}\n")
    };
    let b2 = |shape: &str| format!("{HEAD2}[[body]]\nname = \"b\"\ndp = 0.1\nshape = {shape}\n");
    for (text, needles) in [
        (b3("{ mesh = { file = \"none.stl\" } }", ""), vec!["body[0].shape.mesh.file", "none.stl"]),
        (b3("{ mesh = { file = \"cube.stl\", scale = -1.0 } }", ""), vec!["mesh.scale", "> 0"]),
        (b3("{ mesh = { file = \"cube.stl\", rotate = { axis = [0.0, 0.0, 0.0], degrees = 5.0 } } }", ""), vec!["rotate.axis"]),
        (b3("{ mesh = { file = \"cube.stl\", translate = [1.0, 2.0] } }", ""), vec!["translate"]),
        (b3("{ mesh = { file = \"cube.stl\", colour = 1 } }", ""), vec!["colour"]),
        (b3("{ mesh = { file = \"cube.stl\" } }", "layout = \"lattice\"\nrelax_steps = 3\n"), vec!["relax_steps", "fitted"]),
        (b3("{ box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] } }", "layout = \"fitted\"\n"), vec!["layout", "mesh"]),
        (b3("{ outline = { file = \"bow.csv\" } }", ""), vec!["outline", "2D"]),
        (b2("{ mesh = { file = \"cube.stl\" } }"), vec!["mesh", "3D"]),
        (b2("{ outline = { file = \"bow.csv\" } }"), vec!["bow.csv", "crosses itself"]),
        (b2("{ outline = { file = \"bow.csv\", rotate = { axis = [1.0, 0.0, 0.0], degrees = 5.0 } } }"), vec!["rotate.axis", "z"]),
    ] {
        let e = match scene(&dir, &text).and_then(|s| s.preview().map_err(|e| e.to_string())) {
            Ok(_) => panic!("accepted: {text}"),
            Err(e) => e,
        };
        assert_eq!(e.lines().count(), 1, "{e}");
        for n in needles {
            assert!(e.contains(n), "`{n}` not in: {e}");
        }
    }
    std::fs::remove_dir_all(dir).ok();
}
