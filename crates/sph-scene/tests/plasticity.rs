//! Plastic materials in scene files: `law = "j2"` / `"johnson-cook"` with their keys in
//! `[material]`; the file and the same run built with the library agree bit for bit (positions
//! and the `plastic_strain` field); the methods that cannot carry a plastic law, and keys of
//! another law, are one-line errors before any work.

use glam::DVec2;
use sph_core::{Constraint, Constraints, D2};
use sph_driver::{Run, RunOptions};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::plasticity::{IsotropicHardening, PlasticLaw};
use sph_materials::ElasticConstants;
use sph_materials::LinearElastic;
use sph_scene::Scene;
use sph_tl::{TlParams, TlSolver};
use sph_ul::{Shear, UlParams, UlSolver};
use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/plastic_impact.toml")
}

#[test]
fn plastic_scene_file_and_the_library_agree_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("sph-scene-plastic-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Scene::from_file(example()).unwrap();
    let options = RunOptions {
        output: Some(dir.join("file")),
        ..RunOptions::default()
    };
    let (file_record, summary) = scene.run(&options).unwrap();
    assert_eq!(summary["status"], "completed");

    let dp = 0.5e-3;
    let bar = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.02, 0.005)).unwrap();
    let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &bar).unwrap();
    let (clamp, n) = (set.select(|x| x.x <= 0.001), set.len());
    let mut body = set.into_body(dp);
    body.velocities = vec![DVec2::new(-100.0, 0.0); n];
    let c = ElasticConstants::from_youngs(200e9, 0.3, 7850.0).unwrap();
    let law = PlasticLaw::J2(IsotropicHardening::Linear {
        yield_stress: 250e6,
        hardening_modulus: 2e9,
    });
    let mut clamps = Constraints::new();
    clamps
        .push(Constraint::Fixed { particles: clamp }, n)
        .unwrap();
    let params = UlParams {
        track_shear_stress: true,
        ..UlParams::default()
    };
    let mut solver = UlSolver::new(body, c, Shear::Original, params)
        .unwrap()
        .with_plasticity(law)
        .unwrap()
        .with_constraints(clamps)
        .with_tools(Vec::new())
        .unwrap()
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let (record, _) = Run::until(1e-5)
        .write_to(dir.join("rust"))
        .execute(&mut solver)
        .unwrap();
    assert_eq!(record.steps, file_record.steps);
    let a = sph_output::read_file(file_record.file.unwrap()).unwrap();
    let b = sph_output::read_file(record.file.unwrap()).unwrap();
    let last = |c: &sph_output::FileContents, name: &str| -> Vec<u64> {
        let snap = c.snapshots.last().unwrap();
        snap.dataset(name)
            .unwrap_or_else(|| panic!("no {name}"))
            .as_f64()
            .unwrap()
            .iter()
            .map(|x| x.to_bits())
            .collect()
    };
    assert_eq!(last(&a, "position"), last(&b, "position"));
    let eps = last(&a, "plastic_strain");
    assert_eq!(eps, last(&b, "plastic_strain"));
    let max = eps.iter().map(|&x| f64::from_bits(x)).fold(0.0, f64::max);
    println!("max plastic strain {max:.4e}");
    assert!(max > 1e-3, "the root must yield: max ε̄p = {max}");
    let _ = std::fs::remove_dir_all(&dir);
}

fn err(text: &str) -> String {
    match Scene::parse(text, "s.toml", Path::new("."), "s") {
        Err(e) => e.to_string(),
        Ok(s) => s
            .run(&RunOptions::default())
            .expect_err("should fail")
            .to_string(),
    }
}

fn scene(method: &str, material: &str) -> String {
    format!(
        "dimension = 2\nmethod = \"{method}\"\nend_time = 1e-6\n\n[material]\ndensity = 7850.0\n\
         youngs_modulus = 200e9\nnu = 0.3\n{material}\n[[body]]\nname = \"b\"\ndp = 1e-3\n\
         shape = {{ box = {{ min = [0.0, 0.0], max = [0.01, 0.005] }} }}\n"
    )
}

#[test]
fn plastic_law_errors_name_the_key_in_one_line() {
    let j2 = "law = \"j2\"\nyield_stress = 250e6\nhardening_modulus = 1e9\n";
    let one_line = |e: &str| e.lines().count() == 1;
    // Methods that cannot carry it.
    for method in ["tl-hf", "mps", "ul-enog"] {
        let e = err(&scene(method, j2));
        assert!(
            e.contains("material.law")
                && e.contains("ul-og, ul-oas, ul-gnog, tl, tl-gm")
                && one_line(&e),
            "{method}: {e}"
        );
    }
    assert!(err(&scene("ul-enog", j2)).contains("Laplacian"));
    assert!(err(&scene("tl-hf", j2)).contains("elastic deviator"));
    let cases = [
        ("law = \"j2\"\n", "material.yield_stress"),
        (
            "law = \"j2\"\nyield_stress = -1.0\n",
            "material.yield_stress",
        ),
        (
            "law = \"j2\"\nyield_stress = 1e8\nhardening_modulus = -1.0\n",
            "material.hardening_modulus",
        ),
        (
            "law = \"j2\"\nyield_stress = 1e8\nsaturation_stress = 2e8\n",
            "material.saturation_exponent",
        ),
        ("law = \"j2\"\nyield_stress = 1e8\nA = 1e8\n", "material.A"),
        (
            "law = \"neo-hookean\"\nyield_stress = 1e8\n",
            "material.yield_stress",
        ),
        (
            "law = \"johnson-cook\"\nA = 90e6\nB = 292e6\n",
            "material.n",
        ),
        (
            "law = \"johnson-cook\"\nA = 90e6\nB = 292e6\nn = 0.31\nyield_stress = 1e8\n",
            "material.yield_stress",
        ),
        (
            "law = \"johnson-cook\"\nA = 90e6\nB = 292e6\nn = 0.31\nm = 1.09\n",
            "material.room_temperature",
        ),
        (
            "law = \"johnson-cook\"\nA = 90e6\nB = 292e6\nn = 0.31\nreference_strain_rate = 0.0\n",
            "material.reference_strain_rate",
        ),
        ("law = \"plastic\"\n", "j2, johnson-cook"),
    ];
    for (material, key) in cases {
        let e = err(&scene("ul-og", material));
        println!("{e}");
        assert!(e.contains(key) && one_line(&e), "{material}: {e}");
    }
}

#[test]
fn johnson_cook_scene_runs_with_ul_oas() {
    let jc = "law = \"johnson-cook\"\nA = 90e6\nB = 292e6\nn = 0.31\nC = 0.025\nm = 1.09\n\
              room_temperature = 294.0\nmelting_temperature = 1356.0\nspecific_heat = 383.0\n";
    let text = scene("ul-oas", jc).replace(
        "shape = {",
        "velocity = [50.0, 0.0]\nshape = {",
    ) + "\n[[constraint]]\ntype = \"fixed\"\nregion = { box = { min = [0.009, -1.0], max = [1.0, 1.0] } }\n";
    let s = Scene::parse(&text, "s.toml", Path::new("."), "s").unwrap();
    let (record, summary) = s.run(&RunOptions::default()).unwrap();
    assert!(
        record.failure.is_none() && summary["status"] == "completed",
        "{summary:?}"
    );
}

#[test]
fn the_example_runs_with_ul_gnog_and_xi_is_checked() {
    let scene = Scene::from_file(example())
        .unwrap()
        .set("method", "ul-gnog")
        .unwrap()
        .set("end_time", "2e-6")
        .unwrap();
    let (record, summary) = scene.run(&RunOptions::default()).unwrap();
    assert!(
        record.failure.is_none() && summary["status"] == "completed",
        "{summary:?}"
    );
    let text = std::fs::read_to_string(example()).unwrap();
    let e = err(&format!(
        "{}\n[numerics]\nxi = -1.0\n",
        text.replace("\"ul-og\"", "\"ul-gnog\"")
    ));
    assert!(e.contains("xi") && e.lines().count() == 1, "{e}");
    // ξ is GNOG's alone.
    let e = err(&format!("{text}\n[numerics]\nxi = 2.0\n"));
    assert!(e.contains("xi"), "{e}");
}

/// The example with `tl` and `tl-gm` (the finite-strain return on a Hencky law): the scene file
/// and the same run built with the library agree bit for bit, and the root yields.
#[test]
fn the_example_runs_with_tl_and_agrees_with_the_library() {
    for method in ["tl", "tl-gm"] {
        let dir =
            std::env::temp_dir().join(format!("sph-scene-plastic-{method}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let scene = Scene::from_file(example())
            .unwrap()
            .set("method", method)
            .unwrap();
        let options = RunOptions {
            output: Some(dir.join("file")),
            ..RunOptions::default()
        };
        let (file_record, summary) = scene.run(&options).unwrap();
        assert_eq!(summary["status"], "completed", "{summary:?}");

        let dp = 0.5e-3;
        let bar = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.02, 0.005)).unwrap();
        let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &bar).unwrap();
        let (clamp, n) = (set.select(|x| x.x <= 0.001), set.len());
        let mut body = set.into_body(dp);
        body.velocities = vec![DVec2::new(-100.0, 0.0); n];
        let c = ElasticConstants::from_youngs(200e9, 0.3, 7850.0).unwrap();
        let law = PlasticLaw::J2(IsotropicHardening::Linear {
            yield_stress: 250e6,
            hardening_modulus: 2e9,
        });
        let mut clamps = Constraints::new();
        clamps
            .push(Constraint::Fixed { particles: clamp }, n)
            .unwrap();
        let shear = match method {
            "tl" => sph_tl::Shear::Original,
            _ => sph_tl::Shear::ganzenmuller(),
        };
        let mut solver = TlSolver::new(body, LinearElastic::new(c), shear, TlParams::default())
            .unwrap()
            .with_plasticity(law)
            .unwrap()
            .with_constraints(clamps)
            .with_tools(Vec::new())
            .unwrap()
            .with_probes(Vec::new(), 0.0)
            .unwrap();
        let (record, _) = Run::until(1e-5)
            .write_to(dir.join("rust"))
            .execute(&mut solver)
            .unwrap();
        assert_eq!(record.steps, file_record.steps);
        let a = sph_output::read_file(file_record.file.unwrap()).unwrap();
        let b = sph_output::read_file(record.file.unwrap()).unwrap();
        let last = |c: &sph_output::FileContents, name: &str| -> Vec<u64> {
            let snap = c.snapshots.last().unwrap();
            snap.dataset(name)
                .unwrap_or_else(|| panic!("no {name}"))
                .as_f64()
                .unwrap()
                .iter()
                .map(|x| x.to_bits())
                .collect()
        };
        assert_eq!(last(&a, "position"), last(&b, "position"));
        let eps = last(&a, "plastic_strain");
        assert_eq!(eps, last(&b, "plastic_strain"));
        let max = eps.iter().map(|&x| f64::from_bits(x)).fold(0.0, f64::max);
        println!("{method}: max plastic strain {max:.4e}");
        assert!(max > 1e-3, "the root must yield: max ε̄p = {max}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
