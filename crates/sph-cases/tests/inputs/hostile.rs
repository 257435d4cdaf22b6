//! The inputs of issue 40's reproductions (round 2 of the hostile-input probe), shared by
//! `hostile.rs` (which runs them) and `robustness.rs` (which counts them in
//! `docs/reliability.md`).

/// A small TL scene with every kind of name: `{scene}`, `{body}`, `{constraint}`, `{tool}`,
/// `{probe}` are replaced by TOML strings, `{extra}` by more lines at the top level, `{numerics}`
/// and `{output}` by lines of those tables.
pub const NAMED_SCENE: &str = r#"name = {scene}
dimension = 2
method = "tl-hf"
end_time = 2e-4
{extra}
[material]
density = 1100.0
youngs_modulus = 1e7
nu = 0.45

[numerics]
{numerics}

[output]
{output}

[[body]]
name = {body}
dp = 1e-3
shape = { box = { min = [-0.01, 0.0], max = [0.01, 0.01] } }

[[constraint]]
type = "fixed"
name = {constraint}
region = { box = { min = [-1.0, -1.0], max = [1.0, 1e-3] } }

[[tool]]
name = {tool}
shape = { box = { min = [-0.005, 0.01], max = [0.005, 0.011] } }
direction = [0.0, -1.0]
speed = 1.0

[[probe]]
name = {probe}
at = [0.0, 0.01]
"#;

/// Edits of [`NAMED_SCENE`]: (text, its replacement), applied in order.
pub type Edits = &'static [(&'static str, &'static str)];

/// Scene names that are paths or not names at all: (what, the TOML string).
pub const BAD_SCENE_NAMES: &[(&str, &str)] = &[
    ("an absolute name", r#""/tmp/sph-hostile-absolute""#),
    ("a name climbing out of --out", r#""../../escaped""#),
    ("a name with a directory", r#""a/b""#),
    ("a newline", r#""new\nline""#),
    ("a tab", r#""a\tb""#),
    ("a NUL byte", r#""a\u0000b""#),
    ("a backslash", r#""a\\b""#),
    ("empty", r#""""#),
    ("`.`", r#"".""#),
    ("`..`", r#""..""#),
    ("300 bytes", "\"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\""),
];

/// Bad names of the other kinds: (the placeholder, the TOML string, the key the error names).
pub const BAD_PART_NAMES: &[(&str, &str, &str)] = &[
    ("body", r#""../b""#, "body[0].name"),
    ("body", r#""b\nc""#, "body[0].name"),
    ("constraint", r#""/abs""#, "constraint[0].name"),
    ("constraint", r#""""#, "constraint[0].name"),
    ("tool", r#""a/b""#, "tool[0].name"),
    ("tool", r#"".""#, "tool[0].name"),
    ("probe", r#""../p""#, "probe[0].name"),
    ("probe", r#""p\rq""#, "probe[0].name"),
];

/// Set-ups found only after the whole run before (rc 1, an orphan `.tmp`, no results), now
/// refused before any work: (what, the scene's edits (text, replacement), the expected words).
pub const LATE_REFUSALS: &[(&str, Edits, &str)] = &[
    (
        "two probes of one name",
        &[("{extra}", "[[probe]]\nname = \"tip\"\nat = [0.0, 0.005]\n")],
        "`tip` is the name of another probe",
    ),
    (
        "a field written twice",
        &[("{output}", "fields = [\"velocity\", \"velocity\"]")],
        "`velocity` (given twice)",
    ),
    (
        "a field the method lacks",
        &[("{output}", "fields = [\"velocity\", \"no-such-field\"]")],
        "`no-such-field`",
    ),
    (
        "a tool and a constraint of one name",
        &[("{tool}", "\"floor\"")],
        "also a constraint's name",
    ),
];

/// Scene values that ran to rc 0 before (`density = 1e300` …) and set-ups that failed only
/// mid-run or at step 0: (what, the scene's edits (text, replacement), the key the error names,
/// words of the message).
pub const SCENE_RANGES: &[(&str, Edits, &str, &str)] = &[
    (
        "density = 1e300",
        &[("density = 1100.0", "density = 1e300")],
        "material.density",
        "invalid density = 1e300: allowed range is 0.001 <= density <= 1e6",
    ),
    (
        "youngs_modulus = 1e-300",
        &[("youngs_modulus = 1e7", "youngs_modulus = 1e-300")],
        "material.youngs_modulus",
        "invalid youngs_modulus = 1e-300",
    ),
    (
        "[numerics] cfl = 10",
        &[("{numerics}", "cfl = 10")],
        "numerics.cfl",
        "0 < cfl < 1",
    ),
    (
        "[numerics] h_over_dp = 50",
        &[("{numerics}", "h_over_dp = 50")],
        "numerics.h_over_dp",
        "0.5 <= h_over_dp <= 3",
    ),
    (
        "a tool at speed = 1e300",
        &[("speed = 1.0", "speed = 1e300")],
        "tool[0].speed",
        "invalid speed of tool `punch` = 1e300",
    ),
    (
        "[numerics] zeta of tl-hf with tl",
        &[
            ("method = \"tl-hf\"", "method = \"tl\""),
            ("{numerics}", "zeta = 1.1"),
        ],
        "numerics",
        "`zeta` is not a key of method tl",
    ),
    (
        "a body of 2 particles (dp far larger than the body)",
        &[("dp = 1e-3", "dp = 0.015")],
        "body[0].dp",
        "a body needs at least 3 particles across",
    ),
    (
        "a very soft body under a punch",
        &[("youngs_modulus = 1e7", "youngs_modulus = 1e-3")],
        "tool[0].speed",
        "the body's sound speed c0",
    ),
];

/// `[numerics]` of the other families beyond their ranges: (what, method, the line, the words).
pub const FAMILY_RANGES: &[(&str, &str, &str, &str)] = &[
    (
        "UL cfl_acoustic = 10",
        "ul-enog",
        "cfl_acoustic = 10",
        "numerics.cfl_acoustic",
    ),
    (
        "MPS courant = 10",
        "mps",
        "courant = 10",
        "numerics.courant",
    ),
    (
        "epsilon of ul-oas with ul-enog",
        "ul-enog",
        "epsilon = 0.3",
        "`epsilon` is not a key of method ul-enog",
    ),
];

/// Case keys of another method, accepted without comment before: (what, arguments, words).
pub const OTHER_METHOD_KEYS: &[(&str, &[&str], &str)] = &[
    (
        "zeta (tl-hf) with tl",
        &["--method", "tl", "--set", "zeta=1.1"],
        "zeta is a key of tl-hf, not of tl",
    ),
    (
        "as_epsilon (ul-oas) with ul-enog",
        &["--method", "ul-enog", "--set", "as_epsilon=0.3"],
        "as_epsilon is a key of ul-oas, not of ul-enog",
    ),
    (
        "a TL key with a UL method",
        &["--method", "ul-og", "--set", "cfl=0.5"],
        "cfl is a key of tl-hf, tl, tl-gm, not of ul-og",
    ),
];

/// Output paths that reach an input through `..` and directories not created yet: (what, the
/// arguments beyond the run's, the expected words). The scratch directory holds `cfg.toml`,
/// `deep/cfg.toml` and a link `hop` to `deep/inner`.
pub const PATHS_THROUGH_DOTS: &[(&str, &[&str], &str)] = &[
    (
        "--summary through a directory not created yet",
        &["--config", "cfg.toml", "--summary", "./sub/../cfg.toml"],
        "--summary ./sub/../cfg.toml: is an input of this run (--config)",
    ),
    (
        "--summary through two of them",
        &["--config", "cfg.toml", "--summary", "a/b/../../cfg.toml"],
        "an input of this run (--config)",
    ),
    (
        "--checkpoint through a directory not created yet",
        &[
            "--config",
            "cfg.toml",
            "--checkpoint-every",
            "1",
            "--checkpoint",
            "new/../cfg.toml",
        ],
        "--checkpoint new/../cfg.toml: is",
    ),
    (
        "--summary through a link and `..` onto the --config",
        &["--config", "deep/cfg.toml", "--summary", "hop/../cfg.toml"],
        "an input of this run (--config)",
    ),
];

/// Arguments clap refused with its multi-line usage text before, now one line:
/// (what, the arguments).
pub const ARGUMENT_ERRORS: &[(&str, &[&str])] = &[
    (
        "--threads -1",
        &["run", "oscillating-plate-2d", "--threads", "-1"],
    ),
    (
        "--threads abc",
        &["run", "oscillating-plate-2d", "--threads", "abc"],
    ),
    (
        "--compress=-1",
        &["run", "oscillating-plate-2d", "--compress=-1"],
    ),
    (
        "an unknown flag",
        &["run", "oscillating-plate-2d", "--bogus"],
    ),
    (
        "a flag without its value",
        &["run", "oscillating-plate-2d", "--set"],
    ),
    ("no case", &["run"]),
    ("no subcommand", &[]),
    ("an unknown subcommand", &["frobnicate"]),
    ("--log-every x", &["resume", "c.ckpt", "--log-every", "x"]),
];

/// `RAYON_NUM_THREADS` values beyond the thread limit, or not a count.
pub const BAD_THREAD_VARIABLES: &[&str] = &["1500", "5000", "abc", "-1", "2.5"];

/// Inputs that are not regular files, or too large: (what, the kind of file, the argument
/// role). Kinds: `fifo`, `zero` (`/dev/zero`), `sparse` (a 2 GiB sparse file); roles:
/// `config`, `scene`, `particles`, `checkpoint`.
pub const NON_REGULAR_INPUTS: &[(&str, &str, &str, &str)] = &[
    ("a FIFO as --config", "fifo", "config", "it is a FIFO"),
    ("a FIFO as the scene file", "fifo", "scene", "it is a FIFO"),
    (
        "a FIFO as the particle file",
        "fifo",
        "particles",
        "it is a FIFO",
    ),
    (
        "a FIFO as the checkpoint",
        "fifo",
        "checkpoint",
        "it is a FIFO",
    ),
    ("/dev/zero as --config", "zero", "config", "it is a device"),
    (
        "/dev/zero as the scene file",
        "zero",
        "scene",
        "it is a device",
    ),
    (
        "/dev/zero as the particle file",
        "zero",
        "particles",
        "it is a device",
    ),
    (
        "/dev/zero as the checkpoint",
        "zero",
        "checkpoint",
        "it is a device",
    ),
    (
        "a 2 GiB file as --config",
        "sparse",
        "config",
        "more than the 16777216 an input of this kind may have",
    ),
    (
        "a 2 GiB file as the scene file",
        "sparse",
        "scene",
        "more than the 16777216",
    ),
    (
        "a 2 GiB file of one line as the particle file",
        "sparse",
        "particles",
        "line 1 is longer than 4096 bytes",
    ),
    (
        "a 2 GiB checkpoint beyond --max-memory",
        "sparse",
        "checkpoint",
        "exceed the memory limit",
    ),
];
