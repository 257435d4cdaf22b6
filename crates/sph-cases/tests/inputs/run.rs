//! The `sph run` inputs of `docs/reliability.md`'s classes that `robustness.rs` runs and counts
//! (each table's rows: what is tried, the arguments, the words the refusal must contain).

/// `--summary` destinations that must be refused: (what, the argument, the expected words).
/// Paths are relative to the scratch directory, which holds `cfg.toml`, `fifo`, `link.json`
/// (→ `old.json`, an earlier summary), `notes.txt` and the directory `sub`.
pub const SUMMARY_REFUSED: &[(&str, &str, &str)] = &[
    ("a device", "/dev/full", "it is a device"),
    ("another device", "/dev/null", "it is a device"),
    ("a FIFO", "fifo", "it is a FIFO"),
    ("a symbolic link", "link.json", "it is a symbolic link"),
    (
        "the --config file",
        "cfg.toml",
        "an input of this run (--config)",
    ),
    (
        "the results file",
        "out/oscillating-plate-2d-tl.h5",
        "the results of this run",
    ),
    (
        "the sidecar",
        "out/oscillating-plate-2d-tl.xmf",
        "the results of this run",
    ),
    ("`.`", ".", "names a directory"),
    ("a trailing slash", "new/", "names a directory"),
    ("a directory", "sub", "names a directory"),
    (
        "a file that is no summary",
        "notes.txt",
        "is not an sph summary",
    ),
    (
        "an unwritable place",
        "/proc/sph-summary.json",
        "cannot write",
    ),
    (
        "below a regular file",
        "notes.txt/s.json",
        "is not a directory",
    ),
];

/// Result destinations that must be refused: (what, how the scratch directory is prepared,
/// the expected words). The run writes `out/oscillating-plate-2d-tl.{h5,xmf}`.
pub const RESULTS_REFUSED: &[(&str, &str, &str)] = &[
    ("--out is a file", "out-file", "is not a directory"),
    ("--out is unwritable", "out-proc", "cannot write"),
    (
        "the .h5 is not a results file",
        "h5-text",
        "not an sph-solids results file",
    ),
    ("the .h5 is a symbolic link", "h5-link", "symbolic link"),
    ("the .h5 is a FIFO", "h5-fifo", "a FIFO"),
    ("the .xmf is a directory", "xmf-dir", "a directory"),
];

/// Particle counts beyond the memory budget: (what, arguments, expected words).
pub const TOO_LARGE: &[(&str, &[&str], &str)] = &[
    (
        "ring, outer_radius = 1e300",
        &[
            "run",
            "pressurised-ring-2d",
            "--set",
            "dp=0.5",
            "--set",
            "outer_radius=1e300",
        ],
        "annulus_polar at dp = 0.5 would generate ≈ ∞ particles",
    ),
    (
        "ring, dp = 1e-6",
        &["run", "pressurised-ring-2d", "--set", "dp=1e-6"],
        "annulus_polar at dp = 1e-6 would generate",
    ),
    (
        "ring, outer_radius = 1e6",
        &["run", "pressurised-ring-2d", "--set", "outer_radius=1e6"],
        "annulus_polar",
    ),
    (
        "two rings, dp = 1e-7",
        &["run", "colliding-rings-2d", "--set", "dp=1e-7"],
        "annulus_polar at dp = 1e-7",
    ),
    (
        "column, resolution = 200 (46M particles) in 1 GiB",
        &[
            "run",
            "bending-column-3d",
            "--set",
            "resolution=200",
            "--max-memory",
            "1",
        ],
        "the lattice fill at dp = 0.005 would generate",
    ),
    (
        "UL 3D plate, resolution = 12 in 0.1 GiB",
        &[
            "run",
            "oscillating-plate-3d",
            "--set",
            "resolution=12",
            "--max-memory",
            "0.1",
        ],
        "more than the limit of 102 MiB (--max-memory 0.1)",
    ),
    (
        "--max-memory 0",
        &["run", "oscillating-plate-2d", "--max-memory", "0"],
        "invalid --max-memory = 0",
    ),
    (
        "--max-memory -1",
        &["run", "oscillating-plate-2d", "--max-memory=-1"],
        "invalid --max-memory = -1",
    ),
    (
        "--max-memory nan",
        &["run", "oscillating-plate-2d", "--max-memory", "nan"],
        "invalid --max-memory = NaN",
    ),
    (
        "--max-memory inf",
        &["run", "oscillating-plate-2d", "--max-memory", "inf"],
        "invalid --max-memory = inf",
    ),
];

/// Schedules, end times, threads and CFL numbers that must be refused before the run.
pub const BAD_SCHEDULES: &[(&str, &[&str], &str)] = &[
    (
        "snapshot_interval = 1e-300",
        &["--set", "snapshot_interval=1e-300"],
        "invalid snapshot_interval = 1e-300: gives 1.00e300 snapshots",
    ),
    (
        "snapshot_interval = 1e-9",
        &["--set", "snapshot_interval=1e-9"],
        "more than 100,000",
    ),
    (
        "monitor_interval = 1e-300",
        &["--set", "monitor_interval=1e-300"],
        "invalid monitor_interval = 1e-300",
    ),
    (
        "end_time = 1e300",
        &["--set", "end_time=1e300"],
        "no longer resolves the step",
    ),
    (
        "end_time = 1e8 (a year of steps)",
        &["--set", "end_time=1e8"],
        "pass --allow-long-run",
    ),
    ("--threads 0", &["--threads", "0"], "invalid --threads = 0"),
    (
        "--threads 1025",
        &["--threads", "1025"],
        "1 <= --threads <= 1024",
    ),
    (
        "--threads 100000",
        &["--threads", "100000"],
        "invalid --threads = 100000",
    ),
    (
        "ul_cfl_acoustic = 1",
        &["--method", "ul-enog", "--set", "ul_cfl_acoustic=1"],
        "0 < ul_cfl_acoustic < 1",
    ),
    (
        "ul_cfl_acoustic = 5",
        &["--method", "ul-enog", "--set", "ul_cfl_acoustic=5"],
        "0 < ul_cfl_acoustic < 1",
    ),
];

/// Inputs near those limits that are accepted (checked with `--dry-run`).
pub const GOOD_SCHEDULES: &[(&str, &[&str])] = &[
    (
        "end_time = 1e8 with --allow-long-run (and probes every 1e5 s)",
        &[
            "--set",
            "end_time=1e8",
            "--allow-long-run",
            "--set",
            "probe_interval=1e5",
        ],
    ),
    (
        "probe_interval = 1e-300 (at most a sample per step)",
        &["--set", "probe_interval=1e-300"],
    ),
    ("--threads 1024", &["--threads", "1024"]),
];

/// Values that were silently accepted.
pub const ABSURD_VALUES: &[(&str, &[&str], &str)] = &[
    (
        "density = 1e300",
        &["run", "oscillating-plate-2d", "--set", "density=1e300"],
        "invalid density = 1e300: allowed range is 0.001 <= density <= 1e6",
    ),
    (
        "youngs_modulus = 1e-300",
        &[
            "run",
            "static-cantilever-2d",
            "--set",
            "youngs_modulus=1e-300",
        ],
        "invalid youngs_modulus = 1e-300",
    ),
    (
        "bulk_modulus = 1e300",
        &["run", "colliding-rings-2d", "--set", "bulk_modulus=1e300"],
        "invalid bulk_modulus = 1e300",
    ),
    (
        "c1 = 1e-300",
        &["run", "pressurised-ring-2d", "--set", "c1=1e-300"],
        "invalid c1 = 1e-300",
    ),
    (
        "slab strip_width = 0.02, wider than half the slab",
        &[
            "run",
            "slab-tension-2d",
            "--set",
            "resolution=10",
            "--set",
            "strip_width=0.02",
        ],
        "strip_width < length/2 = 0.015",
    ),
    (
        "slab strip_width = 1e-6, narrower than half a spacing",
        &[
            "run",
            "slab-tension-2d",
            "--set",
            "resolution=10",
            "--set",
            "strip_width=1e-6",
        ],
        "dp/2 = 0.0005 < strip_width",
    ),
    (
        "--method tl-hf with the TOML's method = \"tl\"",
        &[
            "run",
            "oscillating-plate-2d",
            "--method",
            "tl-hf",
            "--config",
            "method.toml",
        ],
        "method = \"tl\" contradicts --method tl-hf",
    ),
];

/// Runs that blow up: (what, arguments after `run`, expected words).
pub const BLOW_UPS: &[(&str, &[&str], &str)] = &[
    (
        "TL (linear-elastic plate thrown at 50 c0)",
        &["oscillating-plate-2d", "--method", "tl", "--set", "vf=50"],
        "inverted (J = ",
    ),
    (
        "TL-HF (plate thrown at 50 c0)",
        &[
            "oscillating-plate-2d",
            "--method",
            "tl-hf",
            "--set",
            "vf=50",
        ],
        "inverted (J = ",
    ),
    (
        "UL-ENOG (plate thrown at 50 c0)",
        &[
            "oscillating-plate-2d",
            "--method",
            "ul-enog",
            "--set",
            "vf=50",
        ],
        "",
    ),
    (
        "MPS (slab strips pulled at 1e9 m/s²)",
        &["slab-tension-2d", "--set", "acceleration=1e9"],
        "inverted (J = ",
    ),
    (
        "a run that reaches its step limit (max_steps = 20)",
        &[
            "oscillating-plate-2d",
            "--method",
            "ul-enog",
            "--set",
            "max_steps=20",
        ],
        "the step limit max_steps = 20 was reached at time ",
    ),
];

/// The `sph` invocations whose stdout is closed before they write.
pub const CLOSED_PIPES: &[(&str, &[&str])] = &[
    ("sph list --verbose | head -1", &["list", "--verbose"]),
    ("sph list | head -1", &["list"]),
    (
        "sph run … --dry-run | head -1",
        &["run", "oscillating-plate-2d", "--dry-run"],
    ),
];

/// Malformed values for every key of every case: non-numbers, non-finite numbers and words
/// outside a choice.
pub fn malformed_inputs() -> Vec<(String, String, String)> {
    let mut v = Vec::new();
    for case in sph_cases::all_cases() {
        let p = case.params();
        for spec in p.specs() {
            let bad: &[&str] = match spec.default {
                sph_cases::Value::Float(_) => &["nan", "inf", "abc"],
                sph_cases::Value::Int(_) => &["2.5", "abc", "99999999999999999999"],
                sph_cases::Value::Bool(_) => &["maybe"],
                sph_cases::Value::Text(_) => &["nonsense"],
            };
            for b in bad {
                v.push((
                    case.info().name.to_string(),
                    spec.key.to_string(),
                    b.to_string(),
                ));
            }
        }
    }
    v
}

/// Extreme finite values for every numeric key of every case, each key with one method of
/// each family (TL, UL, MPS) it applies to (the variants of a family share their set-up code;
/// a key of one variant, such as `zeta` of tl-hf, is tried with that variant).
pub fn extreme_inputs() -> Vec<(String, String, String, String)> {
    let mut v = Vec::new();
    for case in sph_cases::all_cases() {
        let mut seen: Vec<(&str, &str)> = Vec::new();
        for &m in case.info().methods {
            let family = m.split('-').next().unwrap_or(m);
            let p = case.params_for(m);
            for spec in p.specs() {
                let numeric = matches!(
                    spec.default,
                    sph_cases::Value::Float(_) | sph_cases::Value::Int(_)
                );
                if !numeric || !spec.applies_to(m) || seen.contains(&(family, spec.key)) {
                    continue;
                }
                seen.push((family, spec.key));
                for x in ["1e300", "1e-300", "0", "-1"] {
                    v.push((
                        case.info().name.to_string(),
                        m.to_string(),
                        spec.key.to_string(),
                        x.to_string(),
                    ));
                }
            }
        }
    }
    v
}
