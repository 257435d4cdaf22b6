//! Scene files: the example scenes run; a scene through TOML gives bit-identical results to the
//! same scene built with the library; errors name the file, the line and the key.

use glam::DVec2;
use sph_core::relaxation::PairwiseDamping;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{Body, Constraint, Constraints, D2};
use sph_driver::{Run, RunOptions};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, NeoHookean};
use sph_scene::Scene;
use sph_tl::{Shear, TlParams, TlSolver};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes")
}

#[test]
fn every_example_scene_runs_to_completion() {
    let mut found = 0;
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let scene = Scene::from_file(&path).unwrap();
        let (record, summary) = scene.run(&RunOptions::default()).unwrap();
        assert!(
            record.failure.is_none(),
            "{}: {:?}",
            path.display(),
            record.failure
        );
        assert_eq!(summary["status"], "completed", "{}", path.display());
        found += 1;
    }
    assert!(found >= 4, "example scenes found: {found}");
}

/// `examples/scenes/squeeze.toml` built by hand with the library (the calls of
/// `examples/tl_squeeze.rs`): the final positions are bit for bit those of the file's run.
#[test]
fn a_scene_file_and_the_same_scene_in_rust_agree_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("sph-scene-identical-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Scene::from_file(scenes_dir().join("squeeze.toml")).unwrap();
    let options = RunOptions {
        output: Some(dir.join("file")),
        ..RunOptions::default()
    };
    let (file_record, _) = scene.run(&options).unwrap();

    let (dp, w, h) = (0.5e-3, 0.02, 0.01);
    let corner = DVec2::new(-w / 2.0, 0.0);
    let block = Aabb::<D2>::new(corner, DVec2::new(w / 2.0, h)).unwrap();
    let set = ParticleSet::fill(&Lattice::new(dp, corner).unwrap(), &block).unwrap();
    let (floor, n) = (set.select(|x| x.y < dp), set.len());
    let law = NeoHookean::new(ElasticConstants::from_youngs(1e7, 0.45, 1100.0).unwrap());
    let punch = ToolShape::cuboid(DVec2::new(-w / 4.0, h), DVec2::new(w / 4.0, h + 1e-3)).unwrap();
    let motion = ToolMotion::new(DVec2::new(0.0, -1.0), 1.0, 2e-4, 2e-3).unwrap();
    let mut grips = Constraints::new();
    grips
        .push_named("floor", Constraint::Fixed { particles: floor }, n)
        .unwrap();
    let params = TlParams {
        stretch_limited_dt: true,
        ..TlParams::default()
    };
    let relax = PairwiseDamping::new(PairwiseDamping::viscosity_for(1.0, 1100.0, 1e7, h)).unwrap();
    let mut solver = TlSolver::new(Body::from(set), law, Shear::hourglass_free(), params)
        .unwrap()
        .with_constraints(grips)
        .with_tools(vec![RigidTool::new("punch", punch, motion)])
        .unwrap()
        .with_relaxation(relax)
        .unwrap()
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let (record, _) = Run::until(2.625e-3)
        .write_to(dir.join("rust"))
        .execute(&mut solver)
        .unwrap();
    assert_eq!(record.steps, file_record.steps);
    let a = sph_output::read_file(file_record.file.unwrap()).unwrap();
    let b = sph_output::read_file(record.file.unwrap()).unwrap();
    assert_eq!(a.snapshots.len(), b.snapshots.len());
    let bits = |c: &sph_output::FileContents| -> Vec<u64> {
        let last = c.snapshots.last().unwrap();
        last.dataset("position")
            .unwrap()
            .as_f64()
            .unwrap()
            .iter()
            .map(|x| x.to_bits())
            .collect()
    };
    assert_eq!(bits(&a), bits(&b), "final positions differ");
    // The reaction series too.
    assert_eq!(
        a.series["punch"].columns["force_y"],
        b.series["punch"].columns["force_y"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn parse_err(text: &str) -> String {
    match Scene::parse(text, "s.toml", Path::new("."), "s") {
        Err(e) => e.to_string(),
        Ok(s) => s
            .run(&RunOptions::default())
            .expect_err("should fail")
            .to_string(),
    }
}

const BASE: &str = r#"dimension = 2
method = "tl-hf"
end_time = 1e-4

[material]
density = 1000.0
youngs_modulus = 1e6
nu = 0.3

[[body]]
name = "b"
dp = 1e-3
shape = { box = { min = [0.0, 0.0], max = [0.01, 0.005] } }
"#;

#[test]
fn errors_name_the_file_the_line_and_the_key() {
    // Unknown key: the TOML parser's line.
    let e = parse_err(&BASE.replace("dp = 1e-3", "dp = 1e-3\nspacing = 2"));
    assert!(e.starts_with("s.toml:13:"), "{e}");
    assert!(e.contains("spacing"), "{e}");
    // A bad value: the key's own line.
    let e = parse_err(&BASE.replace("dp = 1e-3", "dp = -1e-3"));
    assert!(e.starts_with("s.toml:12: body[0].dp:"), "{e}");
    let e = parse_err(&BASE.replace("nu = 0.3", "nu = 0.7"));
    assert!(e.starts_with("s.toml:8: material.nu:"), "{e}");
    let e = parse_err(&BASE.replace("\"tl-hf\"", "\"sph\""));
    assert!(
        e.contains("s.toml:2: method:") && e.contains("ul-enog"),
        "{e}"
    );
    let e = parse_err(&format!("{BASE}\n[numerics]\ncfl_acoustic = 0.3\n"));
    assert!(e.contains("numerics") && e.contains("cfl_acoustic"), "{e}");
    let e = parse_err(&format!("{BASE}\n[numerics]\npair_data = \"auto\"\n"));
    assert!(
        e.contains("numerics.pair_data") && e.contains("stored, recomputed"),
        "{e}"
    );
    let e = parse_err(&format!("{BASE}\n[numerics]\nlaplacian = \"exact\"\n"));
    assert!(
        e.contains("numerics.laplacian") && e.contains("paper, normalised"),
        "{e}"
    );
    // TL-HF's normalised Laplacian: another method's key, and a ζ it cannot honour.
    let e = parse_err(&format!(
        "{}\n[numerics]\nlaplacian = \"normalised\"\n",
        BASE.replace("\"tl-hf\"", "\"tl\"")
    ));
    assert!(e.contains("laplacian") && e.lines().count() == 1, "{e}");
    let e = parse_err(&format!(
        "{BASE}\n[numerics]\nlaplacian = \"normalised\"\nzeta = 1.0\n"
    ));
    assert!(e.contains("zeta") && e.contains("1.07"), "{e}");
    let ok = format!("{BASE}\n[numerics]\nlaplacian = \"normalised\"\n");
    let scene = Scene::parse(&ok, "s.toml", Path::new("."), "s").unwrap();
    let (record, summary) = scene.run(&RunOptions::default()).unwrap();
    assert!(record.failure.is_none() && summary["status"] == "completed");
    let e = parse_err(&BASE.replace("[0.0, 0.0]", "[0.0, 0.0, 0.0]"));
    assert!(
        e.contains("body[0].shape") && e.contains("expected 2"),
        "{e}"
    );
    // What a method cannot honour is an error.
    let tool =
        "\n[[tool]]\nname = \"t\"\nshape = { ball = { centre = [0.0, 0.1], radius = 0.01 } }\n";
    // Friction coefficients out of range: one line naming the key and the range, before any
    // work (every method takes tools).
    for method in ["tl-hf", "ul-enog", "mps"] {
        let base = BASE.replace("tl-hf", method);
        let e = parse_err(&format!("{base}{tool}friction_static = -0.1\n"));
        assert!(
            e.contains("tool[0].friction_static") && e.contains(">= 0") && e.lines().count() == 1,
            "{e}"
        );
        let e = parse_err(&format!(
            "{base}{tool}friction_static = 0.2\nfriction_kinetic = 0.3\n"
        ));
        assert!(
            e.contains("tool[0].friction_kinetic") && e.contains("<= friction_static"),
            "{e}"
        );
    }
    let second = "\n[[body]]\nname = \"c\"\ndp = 1e-3\nshape = { box = { min = [0.02, 0.0], max = [0.03, 0.005] } }\n";
    // A second TL body is its own reference configuration, in contact with the first (issue
    // 43): the scene runs.
    let two = Scene::parse(&format!("{BASE}{second}"), "s.toml", Path::new("."), "s").unwrap();
    let (record, _) = two.run(&RunOptions::default()).unwrap();
    assert!(record.failure.is_none(), "{:?}", record.failure);
    let region = "\n[[constraint]]\ntype = \"fixed\"\nregion = { box = { min = [5.0, 5.0], max = [6.0, 6.0] } }\n";
    let e = parse_err(&format!("{BASE}{region}"));
    assert!(
        e.contains("constraint[0].region") && e.contains("no particle"),
        "{e}"
    );
}
