//! `sph preview`: a scene with a mesh and an outline built without running, its particles
//! written like a run's first snapshot, its picture and its per-body report; and the rules of
//! issue 40: nothing written outside `--out` and `--summary`, no input ever written over, bad
//! input one line and nothing written.

mod common;
use common::{assert_refused, listing, scratch, sph};
use std::path::Path;

/// A 2D outline scene in `dir`: an L of 20 × 5 + 5 × 15 cells at dp = 1 mm.
fn outline_scene(dir: &Path) {
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(
        dir.join("parts/l.csv"),
        "0 0\n20 0\n20 5\n5 5\n5 20\n0 20\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("l.toml"),
        "name = \"l\"\ndimension = 2\nmethod = \"tl-hf\"\nend_time = 1e-3\n\
         [material]\nlaw = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\n\
         [[body]]\nname = \"bracket\"\ndp = 1e-3\nrelax_steps = 50\n\
         shape = { outline = { file = \"parts/l.csv\", scale = 1e-3 } }\n\
         [[constraint]]\ntype = \"fixed\"\nregion = { box = { min = [-1.0, -1.0], max = [1.0, 1e-3] } }\n",
    )
    .unwrap();
}

#[test]
fn preview_writes_the_particles_the_picture_and_the_report() {
    let dir = scratch("preview", "ok");
    outline_scene(&dir);
    let r = sph(
        &dir,
        &[
            "preview",
            "l.toml",
            "--out",
            "out",
            "--summary",
            "out/l.json",
        ],
    );
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stdout.contains("bracket: 175 particles"), "{}", r.stdout);
    let results = sph_output::read_file(dir.join("out/l-preview.h5")).unwrap();
    let snap = &results.snapshots[0];
    for field in ["position", "volume", "id", "body", "constraint"] {
        assert!(snap.dataset(field).is_some(), "{field}");
    }
    assert_eq!(snap.dataset("position").unwrap().shape(), &[175, 3]);
    assert!(dir.join("out/l-preview.xmf").is_file());
    let png = std::fs::read(dir.join("out/l-preview.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/l.json")).unwrap()).unwrap();
    let b = &summary["bodies"]["bracket"];
    assert_eq!(b["particles"], 175);
    for key in [
        "volume",
        "mesh_volume",
        "volume_scale",
        "surface_distance_rms",
        "surface_distance_max",
        "volume_spread",
    ] {
        assert!(b[key].as_f64().is_some_and(f64::is_finite), "{key}: {b}");
    }
    assert!((b["mesh_volume"].as_f64().unwrap() - 175e-6).abs() < 1e-12);
    // Nothing else was written.
    let names: Vec<String> = listing(&dir).into_keys().collect();
    assert_eq!(
        names,
        [
            "l.toml",
            "out",
            "out/l-preview.h5",
            "out/l-preview.png",
            "out/l-preview.xmf",
            "out/l.json",
            "parts",
            "parts/l.csv"
        ]
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn preview_never_writes_over_its_inputs_and_refuses_bad_input_in_one_line() {
    let dir = scratch("preview", "refused");
    outline_scene(&dir);
    let before = listing(&dir);
    for (args, needle) in [
        (
            vec!["preview", "l.toml", "--out", "o", "--summary", "l.toml"],
            "l.toml",
        ),
        (
            vec![
                "preview",
                "l.toml",
                "--out",
                "o",
                "--summary",
                "parts/l.csv",
            ],
            "l.csv",
        ),
        (
            vec!["preview", "missing.toml", "--out", "o"],
            "missing.toml",
        ),
        (
            vec![
                "preview",
                "l.toml",
                "--out",
                "o",
                "--set",
                "body.bracket.dp=-1",
            ],
            "dp",
        ),
        (
            vec![
                "preview",
                "l.toml",
                "--out",
                "o",
                "--set",
                "body.bracket.relax_steps=-3",
            ],
            "relax_steps",
        ),
    ] {
        let r = sph(&dir, &args);
        assert_refused(&r, needle, &args.join(" "));
        assert_eq!(listing(&dir), before, "{args:?} wrote or changed a file");
    }
    // An outline that crosses itself: one line naming the file and the crossing.
    std::fs::write(dir.join("parts/l.csv"), "0 0\n1 1\n1 0\n0 1\n").unwrap();
    let before = listing(&dir);
    let r = sph(&dir, &["preview", "l.toml", "--out", "o"]);
    assert_refused(&r, "crosses itself", "a bow tie");
    assert_eq!(listing(&dir), before);
    std::fs::remove_dir_all(dir).ok();
}
