//! Rigid tools shaped by a triangle mesh (3D) or an outline (2D): the same physics as the exact
//! primitive they approximate, within the tessellation's distance error, for every family that
//! takes tools (TL, UL, MPS); the one-line errors of the keys.

use sph_core::glam::{DVec2, DVec3};
use sph_driver::RunOptions;
use sph_geometry::mesh::TriMesh;
use sph_output::{read_file, FileContents};
use sph_scene::Scene;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-scene-tools-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `text` written as `dir/<name>.toml` and reads its results file.
fn run(dir: &Path, name: &str, text: &str) -> FileContents {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let scene = Scene::from_file(&path).unwrap();
    let options = RunOptions {
        output: Some(dir.join(name)),
        ..RunOptions::default()
    };
    let (record, _) = scene.run(&options).unwrap();
    assert!(record.failure.is_none(), "{name}: {:?}", record.failure);
    read_file(record.file.unwrap()).unwrap()
}

/// The punch's force component `axis` and its contact count, sample by sample.
fn punch(c: &FileContents, axis: &str) -> (Vec<f64>, Vec<f64>) {
    let s = &c.series["punch"];
    (s.columns[axis].clone(), s.columns["contacts"].clone())
}

/// The largest difference between two force histories relative to the largest force.
fn force_difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    let peak = a.iter().fold(0.0f64, |m, f| m.max(f.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    (diff / peak, peak)
}

const BLOCK3: &str = r#"dimension = 3
method = "tl-hf"
end_time = 2e-3

[material]
law = "neo-hookean"
density = 1000.0
youngs_modulus = 1e6
nu = 0.3

[output]
probe_interval = 1e-4

[[body]]
name = "block"
dp = 1e-3
shape = { box = { min = [-0.006, -0.006, -0.006], max = [0.006, 0.006, 0.0] } }

[[constraint]]
type = "fixed"
region = { box = { min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, -0.005] } }
"#;

/// A ball of radius 4 mm pressed 1.5 mm into a TL-HF block, given as the exact `ball` and as
/// UV-sphere STL files of 64 and 128 segments (drawn in millimetres, scaled and moved into
/// place by the placement keys). The mesh's surface lies inside the sphere by at most
/// `ε = R (1 − cos(√2 π/n))` (9.6 µm and 2.4 µm; `tool_surface.rs` in sph-geometry), second
/// order in `1/n`: the force histories must differ by an amount that falls with ε (by at least
/// 2.5× from 64 to 128 segments, where ε falls 4×) and, at 128 segments, by less than 1 % of
/// the peak force.
#[test]
fn an_stl_sphere_punch_indents_a_block_as_the_exact_ball_does() {
    let dir = scratch("ball3");
    let motion = "direction = [0.0, 0.0, -1.0]\nspeed = 1.0\nramp_time = 2e-4\ntravel = 1.6e-3\n";
    let exact = format!(
        "{BLOCK3}\n[[tool]]\nname = \"punch\"\nshape = {{ ball = {{ centre = [0.0, 0.0, 0.0041], radius = 0.004 }} }}\n{motion}"
    );
    let a = run(&dir, "exact", &exact);
    let (fa, ca) = punch(&a, "force_z");
    let mut differences = Vec::new();
    for n in [64, 128] {
        TriMesh::uv_sphere(DVec3::ZERO, 4.0, n)
            .write_stl_binary(&dir.join(format!("ball{n}.stl")))
            .unwrap();
        let mesh = format!(
            "{BLOCK3}\n[[tool]]\nname = \"punch\"\nshape = {{ mesh = {{ file = \"ball{n}.stl\", scale = 1e-3, translate = [0.0, 0.0, 0.0041] }} }}\n{motion}"
        );
        let b = run(&dir, &format!("mesh{n}"), &mesh);
        let (fb, cb) = punch(&b, "force_z");
        let (rel, peak) = force_difference(&fa, &fb);
        println!(
            "{n} segments: peak {peak} N, largest difference {rel:.2e} of it, contacts {} vs {}",
            ca.last().unwrap(),
            cb.last().unwrap()
        );
        assert!(peak > 1.0, "the punch pressed: {peak} N");
        differences.push(rel);
    }
    assert!(differences[1] < 1e-2, "{differences:?}");
    assert!(differences[1] < differences[0] / 2.5, "{differences:?}");
    std::fs::remove_dir_all(dir).ok();
}

/// In 2D every family that takes tools (TL-HF, UL-ENOG, MPS) takes an outline tool: a disc of
/// radius 4 mm given as a 256-gon, its edges within `ε = R (1 − cos(π/256)) = 0.3 µm` of the
/// circle, turning and pressed 1 mm into a strip; the forces of the outline and the exact disc
/// agree within 1 % of their peak (ε is 3·10⁻⁴ of the indentation).
#[test]
fn every_family_takes_an_outline_tool_as_the_exact_disc() {
    let dir = scratch("disc2");
    let n = 256;
    let mut csv = String::new();
    for k in 0..n {
        let a = 2.0 * PI * k as f64 / n as f64;
        let p = 4.0 * DVec2::new(a.cos(), a.sin());
        csv.push_str(&format!("{:.17}, {:.17}\n", p.x, p.y));
    }
    std::fs::write(dir.join("disc.csv"), csv).unwrap();
    for method in ["tl-hf", "ul-enog", "mps"] {
        let head = format!(
            "dimension = 2\nmethod = \"{method}\"\nend_time = 1.5e-3\n\n[material]\nlaw = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n\n[output]\nprobe_interval = 1e-4\n\n[[body]]\nname = \"strip\"\ndp = 0.5e-3\nshape = {{ box = {{ min = [-0.01, -0.004], max = [0.01, 0.0] }} }}\n\n[[constraint]]\ntype = \"fixed\"\nregion = {{ box = {{ min = [-1.0, -1.0], max = [1.0, -0.0035] }} }}\n"
        );
        let law = if method == "mps" {
            head.replace("neo-hookean", "saint-venant-kirchhoff")
        } else {
            head
        };
        let motion = "direction = [0.0, -1.0]\nspeed = 1.0\nramp_time = 2e-4\ntravel = 1.1e-3\nrotation = { centre = [0.0, 0.00405], angular_velocity = 50.0 }\n";
        let exact = format!(
            "{law}\n[[tool]]\nname = \"punch\"\nshape = {{ ball = {{ centre = [0.0, 0.00405], radius = 0.004 }} }}\n{motion}"
        );
        let outline = format!(
            "{law}\n[[tool]]\nname = \"punch\"\nshape = {{ outline = {{ file = \"disc.csv\", scale = 1e-3, translate = [0.0, 0.00405] }} }}\n{motion}"
        );
        let a = run(&dir, &format!("{method}-exact"), &exact);
        let b = run(&dir, &format!("{method}-outline"), &outline);
        let ((fa, _), (fb, cb)) = (punch(&a, "force_y"), punch(&b, "force_y"));
        let (rel, peak) = force_difference(&fa, &fb);
        println!("{method}: peak {peak} N/m, largest difference {rel:.2e} of it");
        assert!(peak > 1.0 && *cb.last().unwrap() > 0.0, "{method}: {peak}");
        assert!(rel < 1e-2, "{method}: {rel}");
    }
    std::fs::remove_dir_all(dir).ok();
}

/// Bad mesh and outline tools: one line naming the key, before any run.
#[test]
fn bad_mesh_tools_are_one_line_errors_naming_the_key() {
    let dir = scratch("bad");
    TriMesh::cuboid(DVec3::ZERO, DVec3::ONE)
        .write_stl(&dir.join("cube.stl"))
        .unwrap();
    // An open sheet (a cube with a missing face still has an inside: winding number 5/6).
    let mut open = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
    open.triangles.truncate(2);
    open.write_stl(&dir.join("open.stl")).unwrap();
    std::fs::write(dir.join("bow.csv"), "0 0\n1 1\n1 0\n0 1\n").unwrap();
    let tool = |dim: u32, shape: &str| {
        let (bmin, bmax) = if dim == 3 {
            ("[-1.0, -1.0, -1.0]", "[1.0, 1.0, 0.0]")
        } else {
            ("[-1.0, -1.0]", "[1.0, 0.0]")
        };
        format!(
            "dimension = {dim}\nmethod = \"tl-hf\"\nend_time = 1e-4\n[material]\nlaw = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n\
             [[body]]\nname = \"b\"\ndp = 0.25\nshape = {{ box = {{ min = {bmin}, max = {bmax} }} }}\n\
             [[tool]]\nname = \"punch\"\nshape = {shape}\n"
        )
    };
    for (text, needles) in [
        (tool(3, "{ mesh = { file = \"none.stl\" } }"), vec!["tool[0].shape.mesh.file", "none.stl"]),
        (tool(3, "{ mesh = { file = \"open.stl\" } }"), vec!["tool[0].shape.mesh.file", "encloses no volume"]),
        (tool(3, "{ mesh = { file = \"cube.stl\", scale = 0.0 } }"), vec!["tool[0].shape.mesh.scale", "> 0"]),
        (tool(3, "{ mesh = { file = \"cube.stl\", rotate = { axis = [0.0, 0.0, 0.0], degrees = 5.0 } } }"), vec!["tool[0].shape.mesh.rotate.axis"]),
        (tool(3, "{ mesh = { file = \"cube.stl\", translate = [1.0, 2.0] } }"), vec!["tool[0].shape.mesh.translate"]),
        (tool(3, "{ mesh = { file = \"cube.stl\", colour = 1 } }"), vec!["colour"]),
        (tool(3, "{ outline = { file = \"bow.csv\" } }"), vec!["tool[0].shape.outline.file", "2D"]),
        (tool(2, "{ mesh = { file = \"cube.stl\" } }"), vec!["tool[0].shape.mesh.file", "3D"]),
        (tool(2, "{ outline = { file = \"bow.csv\" } }"), vec!["bow.csv", "crosses itself"]),
        (tool(2, "{ outline = { file = \"bow.csv\", rotate = { axis = [1.0, 0.0, 0.0], degrees = 5.0 } } }"), vec!["tool[0].shape.outline.rotate.axis", "z"]),
    ] {
        let path = dir.join("s.toml");
        std::fs::write(&path, &text).unwrap();
        let e = match Scene::from_file(&path).and_then(|s| s.preview().map(|_| ())) {
            Ok(()) => panic!("accepted: {text}"),
            Err(e) => e.to_string(),
        };
        assert_eq!(e.lines().count(), 1, "{e}");
        for n in needles {
            assert!(e.contains(n), "`{n}` not in: {e}");
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

/// `examples/scenes/mesh_indenter.toml` (an OBJ punch shipped in the repository) builds, and
/// its punch presses the pad: a reaction opposing the motion, with particles in contact.
#[test]
fn the_mesh_indenter_example_builds_and_presses() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/mesh_indenter.toml");
    let scene = Scene::from_file(&path).unwrap();
    let preview = scene.preview().unwrap();
    assert_eq!(preview.tools, vec!["punch".to_string()]);
    let dir = scratch("example");
    let options = RunOptions {
        output: Some(dir.join("run")),
        ..RunOptions::default()
    };
    let (record, summary) = scene.run(&options).unwrap();
    assert!(record.failure.is_none(), "{:?}", record.failure);
    assert_eq!(summary["status"], "completed");
    let c = read_file(record.file.unwrap()).unwrap();
    let (force, contacts) = punch(&c, "force_z");
    let peak = force.iter().fold(0.0f64, |m, f| m.max(*f));
    println!(
        "peak {peak} N, contacts at the end {}",
        contacts.last().unwrap()
    );
    assert!(
        peak > 1.0 && *contacts.last().unwrap() >= 5.0,
        "{peak} {contacts:?}"
    );
    std::fs::remove_dir_all(dir).ok();
}
