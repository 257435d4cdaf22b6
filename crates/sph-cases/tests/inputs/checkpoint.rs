//! The checkpoint inputs that must be refused, shared by `checkpoint.rs` (which runs them) and
//! `robustness.rs` (which counts them in `docs/reliability.md`).

/// Damaged checkpoints for `sph resume`: (what, the damage, the expected words). Damages:
/// `missing`, `half` (the first half), `header` (the first 20 bytes), `flip` (one bit in the
/// middle), `reserved` (one bit of the header's 4 reserved bytes), `version` (format version
/// 99), `foreign` (a TOML file), `other-run` (the run description of another resolution,
/// re-checksummed).
pub const BAD_CHECKPOINTS: &[(&str, &str, &str)] = &[
    ("a missing checkpoint", "missing", "cannot read it"),
    ("a truncated checkpoint", "half", "truncated"),
    ("a checkpoint cut inside its header", "header", "truncated"),
    ("a flipped bit", "flip", "checksum"),
    (
        "a flipped bit in the header's reserved bytes",
        "reserved",
        "reserved bytes 12-15 are not zero",
    ),
    (
        "another format version",
        "version",
        "format version 99; this sph",
    ),
    (
        "a file that is no checkpoint",
        "foreign",
        "not an sph checkpoint",
    ),
    (
        "the state of another case's run",
        "other-run",
        "written by another run",
    ),
];

/// `--checkpoint-every` / `--checkpoint` arguments `sph run` must refuse before the run:
/// (what, the arguments, the expected words). The scratch directory holds `cfg.toml` (the
/// `--config`), `notes.txt` and the directory `sub`; the results go to
/// `out/oscillating-plate-2d-tl-hf.h5`, the summary to `s.json`.
pub const CHECKPOINT_REFUSED: &[(&str, &[&str], &str)] = &[
    (
        "interval 0",
        &["--checkpoint-every", "0"],
        "invalid --checkpoint-every = 0",
    ),
    (
        "a negative interval",
        &["--checkpoint-every=-1"],
        "invalid --checkpoint-every",
    ),
    (
        "interval nan",
        &["--checkpoint-every", "nan"],
        "invalid --checkpoint-every",
    ),
    (
        "an unknown unit",
        &["--checkpoint-every", "5 minutes"],
        "invalid --checkpoint-every",
    ),
    (
        "--checkpoint without an interval",
        &["--checkpoint", "c.ckpt"],
        "needs --checkpoint-every",
    ),
    (
        "the --config file",
        &["--checkpoint-every", "0.001", "--checkpoint", "cfg.toml"],
        "--config",
    ),
    (
        "the results file",
        &[
            "--checkpoint-every",
            "0.001",
            "--checkpoint",
            "out/oscillating-plate-2d-tl-hf.h5",
        ],
        "(--out)",
    ),
    (
        "the summary file",
        &["--checkpoint-every", "0.001", "--checkpoint", "s.json"],
        "is the --summary file",
    ),
    (
        "a directory",
        &["--checkpoint-every", "0.001", "--checkpoint", "sub"],
        "names a directory",
    ),
    (
        "a file that is no checkpoint",
        &["--checkpoint-every", "0.001", "--checkpoint", "notes.txt"],
        "is not an sph checkpoint",
    ),
    (
        "snapshots the checkpoints would carry beyond the memory limit",
        &[
            "--set",
            "snapshot_interval=1e-7",
            "--max-memory",
            "0.05",
            "--checkpoint-every",
            "0.001",
        ],
        "the checkpoints carry the 20,002 snapshots",
    ),
    (
        "a device",
        &["--checkpoint-every", "0.001", "--checkpoint", "/dev/null"],
        "it is a device",
    ),
];
