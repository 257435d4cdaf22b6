//! The `sph` command end to end: bad input exits with status 2 and one line naming the problem
//! (nothing written); a short run writes the HDF5 file, its sidecar and the JSON summary.

use std::path::PathBuf;
use std::process::Command;

fn sph(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(args)
        .output()
        .expect("run sph");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn list_names_every_case_with_its_methods() {
    let (code, out, _) = sph(&["list"]);
    assert_eq!(code, 0);
    for case in [
        "oscillating-plate-2d",
        "bending-column-3d",
        "twisting-column-3d",
    ] {
        assert!(out.contains(case), "{out}");
    }
    assert!(out.contains("tl-hf"));
}

#[test]
fn bad_input_exits_2_with_one_line_and_writes_nothing() {
    let dir = scratch("bad");
    let out = dir.join("o");
    let o = out.to_str().unwrap();
    let toml = dir.join("bad.toml");
    std::fs::write(&toml, "nu = = 0.3\n").unwrap();
    let t = toml.to_str().unwrap();
    let cases: [(&[&str], &str); 9] = [
        (
            &["run", "oscillating-plate-2d", "--compress=10", "--out", o],
            "invalid --compress = 10: a deflate level, 1 (fastest) to 9",
        ),
        (
            &["run", "oscillating-plate-2d", "--compress", "--no-output"],
            "--no-output writes none",
        ),
        (
            &["run", "no-such-case", "--out", o],
            "unknown case `no-such-case`",
        ),
        (
            &[
                "run",
                "oscillating-plate-2d",
                "--method",
                "ul-x",
                "--out",
                o,
            ],
            "does not run method `ul-x`",
        ),
        (
            &[
                "run",
                "oscillating-plate-2d",
                "--set",
                "poisson=0.3",
                "--out",
                o,
            ],
            "no parameter `poisson`",
        ),
        (
            &["run", "oscillating-plate-2d", "--set", "nu=0.5", "--out", o],
            "invalid nu = 0.5",
        ),
        (
            &[
                "run",
                "oscillating-plate-2d",
                "--set",
                "resolution=ten",
                "--out",
                o,
            ],
            "invalid resolution = ten",
        ),
        (
            &["run", "oscillating-plate-2d", "--set", "nu", "--out", o],
            "key=value",
        ),
        (
            &["run", "oscillating-plate-2d", "--config", t, "--out", o],
            "malformed TOML",
        ),
    ];
    for (args, expect) in cases {
        let (code, stdout, stderr) = sph(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stdout.is_empty(), "{stdout}");
    }
    assert!(!out.exists(), "bad input must not create output");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_short_run_writes_results_and_summary() {
    let dir = scratch("run");
    let summary = dir.join("s.json");
    let toml = dir.join("plate.toml");
    std::fs::write(
        &toml,
        "case = \"oscillating-plate-2d\"\nmethod = \"tl\"\nresolution = 4\n",
    )
    .unwrap();
    let (code, stdout, stderr) = sph(&[
        "run",
        "oscillating-plate-2d",
        "--config",
        toml.to_str().unwrap(),
        "--set",
        "end_time=0.01",
        "--set",
        "snapshot_interval=0.005",
        "--out",
        dir.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("particle_steps_per_second"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    for key in [
        "case",
        "method",
        "particles",
        "steps",
        "wall_seconds",
        "particle_steps_per_second",
        "max_disorder",
        "energy_drift",
        "period_theory",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}: {s}");
    }
    assert_eq!(s["method"], "tl");
    assert_eq!(s["status"], "completed");
    let h5 = dir.join("oscillating-plate-2d-tl.h5");
    let file = sph_output::read_file(&h5).unwrap();
    // Snapshots at t = 0, 0.005, 0.01.
    assert_eq!(file.snapshots.len(), 3);
    assert!((file.snapshots[2].time - 0.01).abs() < 1e-12);
    assert!(file.probes.contains_key("tip"));
    assert_eq!(file.summary["case"], "oscillating-plate-2d");
    assert_eq!(file.meta["params"]["resolution"], 4);
    assert!(dir.join("oscillating-plate-2d-tl.xmf").exists());
    // No temporary or lock file is left behind.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".lock"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 15: a run on the default schedule writes 51 frames (the library's default too), each
/// with the particle ids as integers; `--compress` changes the storage, not the values.
#[test]
fn a_default_run_writes_51_frames_with_ids_compressed_or_not() {
    let dir = scratch("frames");
    let d = dir.to_str().unwrap();
    let mut files = Vec::new();
    for (sub, extra) in [("plain", None), ("packed", Some("--compress=9"))] {
        let out = format!("{d}/{sub}");
        let mut args = vec![
            "run",
            "oscillating-plate-2d",
            "--method",
            "tl-hf",
            "--set",
            "resolution=4",
            "--set",
            "end_time=0.005",
            "--out",
            &out,
        ];
        args.extend(extra);
        let (code, _, stderr) = sph(&args);
        assert_eq!(code, 0, "{stderr}");
        files.push(dir.join(sub).join("oscillating-plate-2d-tl-hf.h5"));
    }
    let (plain, packed) = (
        sph_output::read_file(&files[0]).unwrap(),
        sph_output::read_file(&files[1]).unwrap(),
    );
    assert_eq!(plain.snapshots.len(), 51);
    assert_eq!(plain.snapshots, packed.snapshots);
    let n = plain.meta["particles"].as_u64().unwrap();
    for s in &plain.snapshots {
        match &s.dataset("id").expect("id").data {
            sph_output::DatasetData::U64 { values, .. } => {
                assert_eq!(values, &(0..n).collect::<Vec<u64>>(), "{}", s.name)
            }
            other => panic!("{}: id is not integer: {other:?}", s.name),
        }
    }
    let size = |p: &PathBuf| std::fs::metadata(p).unwrap().len();
    assert!(size(&files[1]) < size(&files[0]));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The impact cases (UL paper §6.4–6.6 and the Hertz verification) stop bad input before any
/// work with one line naming the key and its allowed range: overlapping bodies, a spacing
/// coarser than a third of the thinnest part, a non-positive speed, an out-of-range resolution.
#[test]
fn impact_cases_reject_bad_input_naming_the_key() {
    let dir = scratch("impact-bad");
    let out = dir.join("o");
    let o = out.to_str().unwrap();
    let cases: [(&str, &str, &str); 9] = [
        (
            "colliding-balls-3d",
            "centre_distance=0.07",
            "invalid centre_distance = 0.07",
        ),
        ("colliding-balls-3d", "dp=0.004", "invalid dp = 0.004"),
        (
            "colliding-balls-3d",
            "v0=0",
            "invalid v0 = 0: allowed range is v0 > 0",
        ),
        (
            "colliding-balls-3d",
            "inner_radius=0.05",
            "invalid inner_radius = 0.05",
        ),
        (
            "ball-plate-2d",
            "ball_distance=0.05",
            "invalid ball_distance = 0.05",
        ),
        ("ball-plate-2d", "dp=0.01", "invalid dp = 0.01"),
        ("ball-plate-3d", "v0=-0.1", "invalid v0 = -0.1"),
        ("hertz-impact-3d", "resolution=2", "invalid resolution = 2"),
        ("hertz-impact-3d", "target=floor", "invalid target = floor"),
    ];
    for (case, set, expect) in cases {
        let (code, stdout, stderr) = sph(&["run", case, "--set", set, "--out", o]);
        assert_eq!(code, 2, "{case} {set}: {stderr}");
        assert!(stderr.contains(expect), "{case} {set}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{case} {set}: {stderr}");
        assert!(stdout.is_empty(), "{stdout}");
    }
    assert!(!out.exists(), "bad input must not create output");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A coarse Hertz impact (R/dp = 4, ENOG) runs end to end: the spheres touch and rebound, the
/// contact force is written to `/series`, momentum is conserved to round-off (1e-12 of Σ m|v|,
/// the bound of the UL momentum tests) and the energy budget with the exact works closes to
/// 1e-2 of the initial energy (measured 7e-6; printed).
#[test]
fn a_coarse_hertz_impact_rebounds_and_records_the_contact_force() {
    let dir = scratch("hertz");
    let summary = dir.join("s.json");
    let (code, _, stderr) = sph(&[
        "run",
        "hertz-impact-3d",
        "--set",
        "resolution=4",
        "--out",
        dir.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let num = |k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k}: {s}"));
    println!(
        "R/dp = 4: t_c {} (theory {}), F {} ({}), e {}, momentum {}, residual (exact works) {}",
        num("contact_time"),
        num("contact_time_theory"),
        num("max_force"),
        num("max_force_theory"),
        num("restitution"),
        num("momentum_balance"),
        num("energy_residual_exact_work")
    );
    assert!(num("restitution") > 0.5 && num("restitution") < 1.0);
    assert!(num("contact_time") > 0.0);
    assert!(num("momentum_balance") < 1e-12);
    assert!(num("energy_residual_exact_work").abs() < 1e-2);
    let file = sph_output::read_file(dir.join("hertz-impact-3d-ul-enog.h5")).unwrap();
    let f = &file.series["contact_force_0"];
    assert!(
        f.columns["x"].iter().any(|&x| x < 0.0),
        "the left sphere is pushed back"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_run_without_a_terminal_logs_its_progress_to_stderr() {
    // stderr is a pipe here; a tiny interval makes every report a line.
    let (code, _, err) = sph(&[
        "run",
        "oscillating-plate-2d",
        "--set",
        "end_time=0.005",
        "--no-output",
        "--log-every",
        "1e-9",
    ]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("t = ")).collect();
    assert!(lines.len() >= 2, "{err}");
    assert!(lines.last().unwrap().contains("(100.0 %)"), "{err}");
    assert!(lines[0].contains("particle-steps/s"), "{err}");
    // And none by default for a run this short.
    let (code, _, err) = sph(&[
        "run",
        "oscillating-plate-2d",
        "--set",
        "end_time=0.005",
        "--no-output",
    ]);
    assert_eq!(code, 0);
    assert!(!err.contains("t = "), "{err}");
}

#[test]
fn every_case_template_reads_back_as_its_config() {
    let dir = scratch("templates");
    let (_, list, _) = sph(&["list"]);
    let mut n = 0;
    for case in list.lines().filter_map(|l| l.split_whitespace().next()) {
        let (code, text, err) = sph(&["list", "--toml", case]);
        assert_eq!(code, 0, "{case}: {err}");
        assert!(text.contains(&format!("case = \"{case}\"")), "{text}");
        let file = dir.join(format!("{case}.toml"));
        std::fs::write(&file, &text).unwrap();
        // The template is the defaults: a dry run with it checks and estimates the case (with a
        // memory limit of its own: the default, 80 % of what is free now, depends on what else
        // runs on the machine, and stent-3d's defaults plan ~16 GiB).
        let (code, _, err) = sph(&[
            "run",
            case,
            "--config",
            file.to_str().unwrap(),
            "--dry-run",
            "--max-memory",
            "1000",
        ]);
        assert_eq!(code, 0, "{case}: {err}");
        n += 1;
    }
    assert!(n >= 13, "{n} cases");
    // A bad value in a parameter file names the file, the line and the key.
    std::fs::write(dir.join("bad.toml"), "\n\nnu = 0.7\n").unwrap();
    let (code, _, err) = sph(&[
        "run",
        "punching-strip-2d",
        "--config",
        dir.join("bad.toml").to_str().unwrap(),
        "--dry-run",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.toml:3:") && err.contains("nu"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_scene_file_runs_and_refuses_case_options() {
    let dir = scratch("scene");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/discs.toml"
    );
    let out = dir.join("o");
    let (code, text, err) = sph(&["run", scene, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("discs-ul-enog.h5"), "{text}");
    assert!(out.join("discs-ul-enog.h5").exists());
    let (code, _, err) = sph(&["run", scene, "--config", "x.toml"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--config reads a case's parameter file"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 42: `--set KEY=VALUE` overrides a scene file's key by its dotted path or a
/// parameter, `--method` its method (the results are named after it), the overrides are in
/// the results' meta; a bad override is one line naming it; a case's parameter file given
/// as a scene says how to run it; `--format vtu` writes the frames and their collection,
/// `--log FILE` the command, the progress and the figures.
#[test]
fn scene_files_take_overrides_formats_and_a_log() {
    let dir = scratch("scene-set");
    let ring = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/pressurised_ring.toml"
    );
    let out = dir.join("o");
    let o = out.to_str().unwrap();
    let log = dir.join("run.log");
    let args = [
        "run",
        ring,
        "--method",
        "tl",
        "--set",
        "settle=1",
        "--set",
        "load_time=5e-4",
        "--set",
        "material.nu=0.25",
        "--set",
        "body.ring.dp=1.5e-3",
        "--out",
        o,
        "--format",
        "vtu",
        "--log",
        log.to_str().unwrap(),
        "--log-every",
        "0",
    ];
    let (code, text, err) = sph(&args);
    assert_eq!(code, 0, "{err}");
    let h5 = out.join("pressurised-ring-tl.h5");
    assert!(text.contains("pressurised-ring-tl.h5"), "{text}");
    let meta = sph_output::read_file(&h5).unwrap().meta;
    let set: Vec<&str> = meta["overrides"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(
        set,
        [
            "method=tl",
            "settle=1",
            "load_time=5e-4",
            "material.nu=0.25",
            "body.ring.dp=1.5e-3"
        ]
    );
    // 51 frames and their collection.
    assert!(out.join("pressurised-ring-tl_000050.vtu").is_file());
    let pvd = std::fs::read_to_string(out.join("pressurised-ring-tl.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 51);
    assert!(text.contains("pressurised-ring-tl.pvd"), "{text}");
    // The log: the command, the progress at the end, the figures.
    let logged = std::fs::read_to_string(&log).unwrap();
    assert!(logged.contains("--method tl"), "{logged}");
    assert!(logged.contains("t = 5.000000e-4"), "{logged}");
    assert!(
        logged.contains("status") && logged.contains("completed"),
        "{logged}"
    );
    // Bad overrides and formats: one line, exit status 2, nothing written.
    for (args, words) in [
        (
            vec!["--set", "material.nu=0.7"],
            "material.nu (from --set material.nu=0.7)",
        ),
        (vec!["--set", "body.slab.dp=1e-3"], "no body named `slab`"),
        (vec!["--set", "dp"], "expected KEY=VALUE"),
        (
            vec!["--set", "spacing=2"],
            "`spacing` is neither a key of the scene",
        ),
        (
            vec!["--method", "ul-enog"],
            "relaxation is for the TL methods, not ul-enog",
        ),
        (vec!["--format", "vtk"], "invalid --format = vtk"),
        (
            vec!["--format", "vtu", "--no-output"],
            "--no-output writes none",
        ),
        (vec!["--log", ring], "an input of this run"),
    ] {
        let bad = dir.join("bad");
        let mut all = vec!["run", ring, "--out", bad.to_str().unwrap()];
        all.extend(args);
        let (code, _, err) = sph(&all);
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(words), "{all:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!bad.exists(), "{all:?} wrote {}", bad.display());
    }
    // A parameter file of a case, given as a scene file.
    let params = dir.join("plate.toml");
    let (_, template, _) = sph(&["list", "--toml", "oscillating-plate-2d"]);
    std::fs::write(&params, template).unwrap();
    let (code, _, err) = sph(&["run", params.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("sph run oscillating-plate-2d --config"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
