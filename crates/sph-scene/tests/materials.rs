//! Issue 43, item 1: a material per body. `[[material]]` tables with a `name`, `material =
//! "NAME"` in a `[[body]]`; a single `[material]` keeps working. Bad references are one-line
//! errors naming the key before any work; two materials of the same constants give the bits of
//! one; the output carries each particle's body and material.

use glam::DVec2;
use sph_core::{Constraints, Loads, Solver, D2};
use sph_driver::{Run, RunOptions};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, MaterialModel, NeoHookean};
use sph_output::{read_file, FileContents};
use sph_scene::Scene;
use std::path::{Path, PathBuf};

/// Two 10 × 5 mm blocks 2 mm apart, meeting at 2 m/s each, `METHOD`, `MATERIALS` and each
/// body's `MATERIAL_L`/`MATERIAL_R` line to fill in.
const PAIR: &str = r#"dimension = 2
method = "METHOD"
end_time = 1.5e-3

MATERIALS

[output]
fields = ["velocity", "body", "material"]

[[body]]
name = "left"
dp = 1e-3
shape = { box = { min = [-0.011, 0.0], max = [-0.001, 0.005] } }
velocity = [2.0, 0.0]
MATERIAL_L

[[body]]
name = "right"
dp = 1e-3
shape = { box = { min = [0.001, 0.0], max = [0.011, 0.005] } }
velocity = [-2.0, 0.0]
MATERIAL_R
"#;

const ONE: &str = "[material]\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3";

/// Two named materials: `soft` as [`ONE`], `hard` with Young's modulus `e_hard`.
fn two(e_hard: &str) -> String {
    format!(
        "[[material]]\nname = \"soft\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n\n\
         [[material]]\nname = \"hard\"\ndensity = 1000.0\nyoungs_modulus = {e_hard}\nnu = 0.3"
    )
}

fn pair(method: &str, materials: &str, left: &str, right: &str) -> String {
    PAIR.replace("METHOD", method)
        .replace("MATERIALS", materials)
        .replace("MATERIAL_L", left)
        .replace("MATERIAL_R", right)
}

fn parse(text: &str) -> Scene {
    Scene::parse(text, "s.toml", Path::new("."), "s").unwrap()
}

/// The error of parsing, or else of running, `text`.
fn error(text: &str) -> String {
    match Scene::parse(text, "s.toml", Path::new("."), "s") {
        Err(e) => e.to_string(),
        Ok(s) => s
            .run(&RunOptions::default())
            .expect_err("should fail")
            .to_string(),
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-scene-mat-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn run(scene: &Scene, dir: &Path, name: &str) -> FileContents {
    let options = RunOptions {
        output: Some(dir.join(name)),
        ..RunOptions::default()
    };
    let (record, _) = scene.run(&options).unwrap();
    assert!(record.failure.is_none(), "{name}: {:?}", record.failure);
    read_file(record.file.unwrap()).unwrap()
}

/// The last snapshot's `field`, as bits.
fn last(c: &FileContents, field: &str) -> Vec<u64> {
    let s = c.snapshots.last().unwrap();
    let x = s.dataset(field).unwrap().as_f64().unwrap();
    x.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn bad_material_references_are_one_line_errors_naming_the_key() {
    let soft = "material = \"soft\"";
    let hard = "material = \"hard\"";
    let cases = [
        // An unknown name.
        (
            pair("ul-enog", &two("1e9"), soft, "material = \"steel\""),
            "body[1].material",
            "`steel`: no material of that name (the materials: `soft`, `hard`)",
        ),
        // A body without a material among several.
        (
            pair("ul-enog", &two("1e9"), soft, ""),
            "body[1].material",
            "required: the scene has several [[material]]",
        ),
        // A material no body uses.
        (
            pair("ul-enog", &two("1e9"), soft, soft),
            "material.hard",
            "no body uses material[1]",
        ),
        // Two materials of one name.
        (
            pair(
                "ul-enog",
                &two("1e9").replace("\"hard\"", "\"soft\""),
                soft,
                soft,
            ),
            "material[1].name",
            "`soft` is the name of another material",
        ),
        // A [[material]] without a name.
        (
            pair(
                "ul-enog",
                &two("1e9").replace("name = \"hard\"\n", ""),
                soft,
                soft,
            ),
            "material[1].name",
            "a [[material]] needs a name",
        ),
        // A name [material] does not have.
        (
            pair("ul-enog", ONE, soft, ""),
            "body[0].material",
            "`soft`: no material of that name (none has a name)",
        ),
        // A constant of a named material: its path is the one --set uses.
        (
            pair("ul-enog", &two("-1e9"), soft, hard),
            "material.hard.youngs_modulus",
            "",
        ),
        // TL runs its bodies with one material.
        (
            pair("tl-hf", &two("1e9"), soft, hard),
            "body[1]",
            "a TL method runs its bodies with one material",
        ),
    ];
    for (text, key, message) in cases {
        let e = error(&text);
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.contains(&format!(": {key}:")), "{key}: {e}");
        assert!(e.contains(message), "{message}: {e}");
    }
    // Both forms at once: the TOML parser's refusal, at the second.
    let both = pair("ul-enog", &format!("{ONE}\n\n{}", two("1e9")), soft, hard);
    let e = error(&both);
    assert!(
        !e.contains('\n') && e.contains(": material: give one [material]"),
        "{e}"
    );
    let both = pair("ul-enog", &format!("{}\n\n{ONE}", two("1e9")), soft, hard);
    let e = error(&both);
    assert!(
        !e.contains('\n') && e.contains(": material: give one [material]"),
        "{e}"
    );
}

#[test]
fn one_material_named_or_not_and_two_equal_materials_give_the_same_bits() {
    let dir = scratch("same");
    for method in ["ul-enog", "mps"] {
        let a = run(
            &parse(&pair(method, ONE, "", "")),
            &dir,
            &format!("{method}-one"),
        );
        // [material] named, chosen by name.
        let named = ONE.replace("[material]", "[material]\nname = \"soft\"");
        let b = run(
            &parse(&pair(method, &named, "material = \"soft\"", "")),
            &dir,
            &format!("{method}-named"),
        );
        // Two materials of the same constants: the per-particle material path.
        let c = run(
            &parse(&pair(
                method,
                &two("1e6"),
                "material = \"soft\"",
                "material = \"hard\"",
            )),
            &dir,
            &format!("{method}-two"),
        );
        let x = last(&a, "position");
        assert!(!x.is_empty());
        assert_eq!(x, last(&b, "position"), "{method}: named [material]");
        assert_eq!(x, last(&c, "position"), "{method}: two equal materials");
        assert_eq!(last(&a, "velocity"), last(&c, "velocity"), "{method}");
        // The output carries body and material ids, per particle in the output order.
        let body = c.snapshots[0].dataset("body").unwrap().as_f64().unwrap();
        let material = c.snapshots[0]
            .dataset("material")
            .unwrap()
            .as_f64()
            .unwrap();
        assert_eq!(body.len(), 100);
        assert_eq!(body, material, "{method}: body k has material k");
        assert_eq!(body.iter().filter(|&&b| b == 1.0).count(), 50, "{method}");
        let one = a.snapshots[0]
            .dataset("material")
            .unwrap()
            .as_f64()
            .unwrap();
        assert!(one.iter().all(|&m| m == 0.0));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_named_material_takes_overrides_by_its_name() {
    let text = pair(
        "ul-enog",
        &two("1e6"),
        "material = \"soft\"",
        "material = \"hard\"",
    );
    let dir = scratch("set");
    for method in ["ul-enog", "mps"] {
        let text = text.replace("ul-enog", method);
        let set = parse(&text)
            .set("material.hard.youngs_modulus", "1e8")
            .unwrap();
        // The same value written in the file (the second material's line).
        let k = text.rfind("youngs_modulus = 1e6").unwrap();
        let written = parse(&format!(
            "{}youngs_modulus = 1e8{}",
            &text[..k],
            &text[k + "youngs_modulus = 1e6".len()..]
        ));
        let a = run(&set, &dir, &format!("{method}-set"));
        let b = run(&written, &dir, &format!("{method}-written"));
        let c = run(&parse(&text), &dir, &format!("{method}-soft"));
        assert_eq!(last(&a, "position"), last(&b, "position"), "{method}");
        assert_ne!(last(&a, "position"), last(&c, "position"), "{method}");
        // A bad value through --set names the override.
        let e = parse(&text)
            .set("material.hard.nu", "0.7")
            .and_then(|s| s.run(&RunOptions::default()).map(|_| s))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("material.hard.nu") && e.contains("--set"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The body and material ids are written by default in a scene of several bodies, and not in a
/// scene of one (whose results files stay as they were).
#[test]
fn several_bodies_write_their_ids_by_default() {
    let dir = scratch("default");
    let no_fields = |text: String| {
        text.replace(
            "fields = [\"velocity\", \"body\", \"material\"]",
            "snapshot_interval = 0.0",
        )
    };
    for method in ["ul-enog", "mps"] {
        let two = run(
            &parse(&no_fields(pair(method, ONE, "", ""))),
            &dir,
            &format!("{method}-two"),
        );
        // The same without the right block.
        let full = no_fields(pair(method, ONE, "", ""));
        let one = &full[..full.find("[[body]]\nname = \"right\"").unwrap()];
        let one = run(&parse(one), &dir, &format!("{method}-one"));
        for field in ["body", "material"] {
            assert!(
                two.snapshots[0].dataset(field).is_some(),
                "{method} {field}"
            );
            assert!(
                one.snapshots[0].dataset(field).is_none(),
                "{method} {field}"
            );
        }
        assert!(one.snapshots[0].dataset("velocity").is_some(), "{method}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The two-material pair through the scene file and built with the library calls
/// (`with_materials`, `with_contact`) agree bit for bit, in UL-ENOG and MPS.
#[test]
fn two_materials_in_a_scene_and_in_rust_agree_bit_for_bit() {
    let dir = scratch("rust");
    let block = |min: [f64; 2], max: [f64; 2]| {
        let b = Aabb::<D2>::new(DVec2::from(min), DVec2::from(max)).unwrap();
        ParticleSet::fill(&Lattice::new(1e-3, DVec2::from(min)).unwrap(), &b).unwrap()
    };
    let mut set = block([-0.011, 0.0], [-0.001, 0.005]);
    let right = set.extend(&block([0.001, 0.0], [0.011, 0.005])).unwrap();
    let n = set.len();
    let body_of: Vec<u32> = (0..n).map(|i| u32::from(right.contains(&i))).collect();
    let velocities: Vec<DVec2> = (0..n)
        .map(|i| DVec2::new(if right.contains(&i) { -2.0 } else { 2.0 }, 0.0))
        .collect();
    let soft = ElasticConstants::from_youngs(1e6, 0.3, 1000.0).unwrap();
    let hard = ElasticConstants::from_youngs(1e8, 0.3, 1000.0).unwrap();
    let end = 1.5e-3;
    let rust = |solver: &mut dyn Solver<D2>, name: &str| {
        let (record, _) = Run::until(end)
            .write_to(dir.join(name))
            .fields(&["velocity", "body", "material"])
            .execute(solver)
            .unwrap();
        assert!(record.failure.is_none(), "{name}: {:?}", record.failure);
        read_file(record.file.unwrap()).unwrap()
    };
    for method in ["ul-enog", "mps"] {
        let text = pair(
            method,
            &two("1e8"),
            "material = \"soft\"",
            "material = \"hard\"",
        );
        let a = run(&parse(&text), &dir, &format!("{method}-scene"));
        let body = set
            .clone()
            .into_body(1e-3)
            .with_velocities(velocities.clone());
        let b = if method == "mps" {
            let laws = vec![
                MaterialModel::NeoHookean(NeoHookean::new(soft)),
                MaterialModel::NeoHookean(NeoHookean::new(hard)),
            ];
            let mut s =
                sph_mps::MpsSolver::with_materials(body, laws, body_of.clone(), Default::default())
                    .unwrap()
                    .with_constraints(Constraints::new())
                    .with_loads(Loads::new())
                    .with_contact(sph_mps::Contact::between(body_of.clone()))
                    .unwrap()
                    .with_tools(Vec::new())
                    .unwrap()
                    .with_probes(Vec::new(), 0.0)
                    .unwrap();
            rust(&mut s, "mps-rust")
        } else {
            let params = sph_ul::UlParams {
                track_shear_stress: true,
                ..Default::default()
            };
            let mut s = sph_ul::UlSolver::with_materials(
                body,
                vec![soft, hard],
                body_of.clone(),
                sph_ul::Shear::non_nested(),
                params,
            )
            .unwrap()
            .with_constraints(Constraints::new())
            .with_loads(Loads::new())
            .with_contact(body_of.clone())
            .unwrap()
            .with_tools(Vec::new())
            .unwrap()
            .with_probes(Vec::new(), 0.0)
            .unwrap();
            rust(&mut s, "ul-rust")
        };
        assert_eq!(
            a.snapshots.last().unwrap().step,
            b.snapshots.last().unwrap().step,
            "{method}: steps"
        );
        assert_eq!(last(&a, "position"), last(&b, "position"), "{method}");
        assert_eq!(last(&a, "material"), last(&b, "material"), "{method}");
        // And the stiff block changed the run: not the one-material bits.
        let c = run(
            &parse(&pair(method, ONE, "", "")),
            &dir,
            &format!("{method}-one"),
        );
        assert_ne!(last(&a, "position"), last(&c, "position"), "{method}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
