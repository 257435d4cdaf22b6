//! `sph converge` end to end on a small ladder of the TL plate (H/dp 4, 6, 9; seconds): the
//! report's interface, the reuse of stored levels, resuming an interrupted ladder, and bad input
//! as one line; `sph advise` on the same case. The estimator itself is tested in
//! `sph_driver::convergence`, the advice against every stored scene in the validation crate.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-converge-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn sph(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sph")
}

/// The plate's ladder: three levels, the period to 50 % (met from the third level on).
const LADDER: &[&str] = &[
    "converge",
    "oscillating-plate-2d",
    "--method",
    "tl",
    "--quantity",
    "period",
    "--quantity",
    "probe:tip:position.y:min",
    "--tolerance",
    "50%",
    "--set",
    "end_time=0.6",
    "--levels",
    "3",
    "--threads",
    "1",
];

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The report holds, per quantity, `value`, `error_estimate`, `order`, `asymptotic`, `met` and
/// `runs` (`resolution`, `value`, `cpu_seconds`), with an HDF5 file and a PNG beside it; a
/// second ladder reuses every stored level and gives the same report.
#[test]
fn a_ladder_reports_its_estimates_and_reuses_its_levels() {
    let dir = scratch("report");
    let out = sph(&dir, LADDER);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert_eq!(err.matches("level: sph run").count(), 3, "{err}");
    let store = dir.join("out/converge-oscillating-plate-2d");
    let report = json(&store.join("report.json"));
    assert_eq!(report["case"], "oscillating-plate-2d");
    assert_eq!(report["method"], "tl");
    assert_eq!(report["tolerance"], 0.5);
    for q in ["period", "probe:tip:position.y:min"] {
        let r = &report["quantities"][q];
        for key in ["value", "error_estimate", "asymptotic", "met"] {
            assert!(!r[key].is_null(), "{q}: {key} in {r}");
        }
        assert!(r.get("order").is_some(), "{q}");
        let runs = r["runs"].as_array().unwrap();
        let res: Vec<f64> = runs
            .iter()
            .map(|x| x["resolution"].as_f64().unwrap())
            .collect();
        assert_eq!(res, [4.0, 6.0, 9.0]);
        assert!(runs
            .iter()
            .all(|x| x["cpu_seconds"].as_f64().unwrap() > 0.0));
        assert!(runs.iter().all(|x| x["value"].as_f64().is_some()));
    }
    let period = &report["quantities"]["period"];
    assert!(period["met"].as_bool().unwrap(), "{period}");
    // The TL plate's period falls with resolution towards the FE period (docs/tradeoffs.md).
    let v = period["value"].as_f64().unwrap();
    assert!((0.25..0.29).contains(&v), "{v}");
    let h5 = std::fs::read(store.join("report.h5")).unwrap();
    assert_eq!(&h5[..8], b"\x89HDF\r\n\x1a\n");
    let png = std::fs::read(store.join("report.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // Again: every level from the store, the same estimates.
    let again = sph(&dir, LADDER);
    assert_eq!(again.status.code(), Some(0));
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(!err.contains("level: "), "nothing runs again: {err}");
    assert_eq!(
        String::from_utf8_lossy(&again.stdout)
            .matches("(stored)")
            .count(),
        3
    );
    assert_eq!(
        json(&store.join("report.json"))["quantities"],
        report["quantities"]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A ladder interrupted (SIGINT to its process group, as Ctrl-C sends it) stops with the
/// level's status; the same command continues from the stored levels.
#[test]
#[cfg(unix)]
fn an_interrupted_ladder_resumes_from_its_stored_levels() {
    use std::os::unix::process::CommandExt;
    let dir = scratch("resume");
    let mut args = LADDER.to_vec();
    // A longer third level, to interrupt it.
    let long = ["--set", "snapshot_interval=0.01"];
    args.extend_from_slice(&long);
    let child = Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(&args)
        .current_dir(&dir)
        .process_group(0)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let store = dir.join("out/converge-oscillating-plate-2d");
    let first = store.join("oscillating-plate-2d-tl-resolution4.json");
    let t = Instant::now();
    while !first.exists() {
        assert!(t.elapsed() < Duration::from_secs(120), "never ran a level");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(200));
    // SIGINT to the ladder's own process group only (its pgid is its pid).
    let pgid = child.id() as libc::pid_t;
    assert!(pgid > 1);
    // SAFETY: kill(2) with a negative pid signals that process group, nothing else.
    assert_eq!(unsafe { libc::kill(-pgid, libc::SIGINT) }, 0);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        err.contains("run the same command again to continue"),
        "{err}"
    );
    let again = sph(&dir, &args);
    assert_eq!(
        again.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(String::from_utf8_lossy(&again.stdout).contains("(stored)"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Bad input is one line naming it: an unknown quantity, a tolerance out of range, a budget
/// too small for two levels (before any run), the resolution key set by hand, an unknown
/// method; a quantity that is not finite in a run names the quantity and the level.
#[test]
fn bad_input_is_one_line_naming_it() {
    let dir = scratch("bad");
    let base = ["converge", "oscillating-plate-2d", "--method", "tl"];
    let cases: [(&[&str], &str, i32); 6] = [
        (
            &[
                "--quantity",
                "periodd",
                "--tolerance",
                "1%",
                "--set",
                "end_time=0.05",
            ],
            "invalid --quantity periodd: not in the run's summary; its numbers:",
            2,
        ),
        (
            &["--quantity", "period", "--tolerance", "0"],
            "invalid --tolerance = 0",
            2,
        ),
        (
            &[
                "--quantity",
                "period",
                "--tolerance",
                "1%",
                "--budget",
                "0.001s",
            ],
            "too small for two levels",
            2,
        ),
        (
            &[
                "--quantity",
                "period",
                "--tolerance",
                "1%",
                "--set",
                "resolution=20",
            ],
            "--set resolution=20: the ladder sets resolution",
            2,
        ),
        (
            &[
                "--quantity",
                "period",
                "--tolerance",
                "1%",
                "--method",
                "ul-zz",
            ],
            "does not run method `ul-zz`",
            2,
        ),
        (
            // Too short a run to measure a period: null in the summary.
            &[
                "--quantity",
                "period",
                "--tolerance",
                "1%",
                "--set",
                "end_time=0.01",
            ],
            "quantity period is NaN at resolution 4, not a finite number",
            1,
        ),
    ];
    for (args, needle, code) in cases {
        let mut a = base.to_vec();
        if args.contains(&"--method") {
            a.truncate(2);
        }
        a.extend_from_slice(args);
        let out = sph(&dir, &a);
        let err = String::from_utf8_lossy(&out.stderr);
        let errors: Vec<&str> = err.lines().filter(|l| !l.starts_with("level: ")).collect();
        assert_eq!(out.status.code(), Some(code), "{needle}: {err}");
        assert_eq!(errors.len(), 1, "{needle}: {err}");
        assert!(errors[0].contains(needle), "`{needle}` not in {err}");
    }
    // The budget was refused before any level ran.
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sph advise` names the stored scene, its confidence and the cheapest stored run within the
/// tolerance (the plate's at 3 %: TL at H/dp 20, docs/tradeoffs.md), as text and JSON; bad
/// input is one line.
#[test]
fn advise_suggests_the_cheapest_stored_run() {
    let dir = scratch("advise");
    let out = sph(
        &dir,
        &[
            "advise",
            "oscillating-plate-2d",
            "--tolerance",
            "3%",
            "--set",
            "end_time=0.6",
            "--summary",
            "a.json",
        ],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("high confidence"), "{text}");
    assert!(text.contains("--method tl --set resolution=20"), "{text}");
    let a = json(&dir.join("a.json"));
    assert_eq!(a["scene"], "plate2d");
    assert_eq!(a["confidence"], "high");
    assert_eq!(a["run"]["method"], "tl");
    assert_eq!(a["run"]["resolution"], 20.0);
    let p = a["predicted_cpu_seconds"].as_f64().unwrap();
    let stored = a["run"]["cpu_seconds"].as_f64().unwrap();
    assert!((p / stored - 1.0).abs() < 0.05, "{p} vs {stored}");
    for (args, needle) in [
        (
            vec!["advise", "oscillating-plate-2d", "--tolerance", "0"],
            "invalid --tolerance",
        ),
        (
            vec!["advise", "no-case", "--tolerance", "1%"],
            "unknown case",
        ),
        (
            vec![
                "advise",
                "oscillating-plate-2d",
                "--tolerance",
                "1%",
                "--set",
                "nu=2",
            ],
            "invalid nu = 2",
        ),
    ] {
        let out = sph(&dir, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A beam under gravity whose spacing is its parameter `dp` (4 particles across its 16 mm).
const BEAM: &str = r#"name = "beam"
dimension = 2
method = "tl"
end_time = 2e-3

[parameters]
dp = 4e-3

[material]
law = "saint-venant-kirchhoff"
density = 1000.0
youngs_modulus = 2e6
nu = 0.3

[output]
probe_interval = 1e-4

[[body]]
name = "beam"
dp = "${dp}"
shape = { box = { min = [-0.016, -0.008], max = [0.08, 0.008] } }

[[constraint]]
type = "fixed"
region = { box = { min = [-1.0, -1.0], max = [0.0, 1.0] } }

[[load]]
type = "gravity"
acceleration = [0.0, -9.81]

[[probe]]
name = "tip"
at = [0.08, 0.0]
fields = ["displacement"]
"#;

/// A scene whose bodies take their spacing from a `[parameters]` entry `dp` is refined through
/// that parameter (one `--set dp=…` per level, every `${dp}` following), and a probe's sampled
/// field is a quantity (`probe:NAME:FIELD.COMPONENT:STAT`).
#[test]
fn a_scene_refines_through_its_dp_parameter_and_reads_a_probe_field() {
    let dir = scratch("scene");
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    let out = sph(
        &dir,
        &[
            "converge",
            "beam.toml",
            "--quantity",
            "probe:tip:displacement.y:final",
            "--start",
            "4e-3",
            "--ratio",
            "2",
            "--levels",
            "2",
            "--tolerance",
            "50%",
            "--threads",
            "1",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert_eq!(err.matches("--set dp=").count(), 2, "{err}");
    assert!(!err.contains("body[0].dp"), "{err}");
    let report = json(&dir.join("out/converge-beam/report.json"));
    let runs = report["quantities"]["probe:tip:displacement.y:final"]["runs"]
        .as_array()
        .unwrap()
        .clone();
    let res: Vec<f64> = runs
        .iter()
        .map(|r| r["resolution"].as_f64().unwrap())
        .collect();
    assert_eq!(res, [4e-3, 2e-3]);
    // The tip sags under gravity.
    assert!(
        runs.iter().all(|r| r["value"].as_f64().unwrap() < 0.0),
        "{runs:?}"
    );
    // A field the probe does not sample is named with the ones it does.
    let bad = sph(
        &dir,
        &[
            "converge",
            "beam.toml",
            "--quantity",
            "probe:tip:von_mises:max",
            "--tolerance",
            "50%",
            "--start",
            "4e-3",
            "--levels",
            "2",
            "--threads",
            "1",
        ],
    );
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_ne!(bad.status.code(), Some(0), "{err}");
    assert!(
        err.contains("samples no such field") && err.contains("displacement"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sph advise` on a scene file: the kind read from what it holds (a beam left to swing under
/// gravity: vibration), its thinnest body measured from its particles (16 mm), the nearest
/// stored scene (the 2D plate, medium confidence) and the spacing that gives the beam the
/// suggested run's particles across (TL at H/dp 20 for 3 %: dp = 16 mm / 20), through the
/// file's parameter `dp`; a method the scene cannot take is one line.
#[test]
fn advise_on_a_scene_file_sizes_its_spacing_from_its_thinnest_body() {
    let dir = scratch("advise-scene");
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    let out = sph(
        &dir,
        &[
            "advise",
            "beam.toml",
            "--tolerance",
            "3%",
            "--summary",
            "a.json",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("a vibration problem"), "{text}");
    assert!(text.contains("--method tl --set dp=0.0008"), "{text}");
    let a = json(&dir.join("a.json"));
    assert_eq!(a["scene"], "plate2d");
    assert_eq!(a["confidence"], "medium");
    assert_eq!(a["kind"], "vibration");
    let t = a["bodies"][0]["thickness"].as_f64().unwrap();
    assert!((t - 0.016).abs() < 1e-12, "{t}");
    assert_eq!(a["particles_across"], 20.0);
    assert_eq!(a["set"][0], "dp=0.0008");
    assert!(a["predicted_cpu_seconds"].as_f64().unwrap() > 0.0);
    // Every method takes a beam under gravity.
    assert_eq!(
        a["methods"].as_array().unwrap().len(),
        sph_scene::METHODS.len(),
        "{}",
        a["methods"]
    );
    let out = sph(
        &dir,
        &[
            "advise",
            "beam.toml",
            "--tolerance",
            "3%",
            "--method",
            "fem",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("--method fem: allowed values are"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
