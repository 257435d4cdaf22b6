//! What the `sph` command's end-to-end tests share: running it (with a hang guard), scratch
//! directories, a listing that proves nothing changed, and the shape of a refusal.
// Each test binary uses its own part.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How a run of `sph` ended.
pub struct Run {
    /// Exit status (`None`: ended by a signal).
    pub code: Option<i32>,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

/// Starts `sph args` in `dir` with the environment `env`, stdout and stderr piped.
pub fn spawn_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(args)
        .current_dir(dir)
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn sph")
}

/// Starts `sph args` in `dir`.
pub fn spawn(dir: &Path, args: &[&str]) -> Child {
    spawn_env(dir, args, &[])
}

/// Waits for `child` (two minutes at most: a hang guard, not a timing assertion) and collects
/// its output.
pub fn finish(mut child: Child) -> Run {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("sph hung (killed after 120 s)");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let out = child.wait_with_output().unwrap();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into(),
        stderr: String::from_utf8_lossy(&out.stderr).into(),
    }
}

/// Runs `sph args` in `dir` with the environment `env`.
pub fn sph_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    finish(spawn_env(dir, args, env))
}

/// Runs `sph args` in `dir`.
pub fn sph(dir: &Path, args: &[&str]) -> Run {
    sph_env(dir, args, &[])
}

/// A new, empty scratch directory `sph-<kind>-<name>-<pid>` in the temporary directory.
pub fn scratch(kind: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-{kind}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// What a directory holds (recursively): name → kind and, for regular files under 1 MiB, their
/// content; it never opens a FIFO or device, nor reads a large file.
pub fn listing(dir: &Path) -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return m;
    };
    for e in entries {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        let meta = std::fs::symlink_metadata(e.path()).unwrap();
        let t = meta.file_type();
        let what = if t.is_symlink() {
            format!("link {}", std::fs::read_link(e.path()).unwrap().display())
        } else if t.is_dir() {
            for (k, v) in listing(&e.path()) {
                m.insert(format!("{name}/{k}"), v);
            }
            "dir".into()
        } else if t.is_file() && meta.len() < 1 << 20 {
            format!("file {:?}", std::fs::read(e.path()).unwrap())
        } else if t.is_file() {
            format!("large file, {} bytes", meta.len())
        } else {
            "special".into()
        };
        m.insert(name, what);
    }
    m
}

/// Exit status 2, one line on stderr containing `needle`, nothing on stdout, no panic.
pub fn assert_refused(r: &Run, needle: &str, what: &str) {
    assert_eq!(r.code, Some(2), "{what}: {}", r.stderr);
    assert!(!r.stderr.contains("panicked"), "{what}: {}", r.stderr);
    assert_eq!(r.stderr.trim().lines().count(), 1, "{what}: {}", r.stderr);
    assert!(
        r.stderr.contains(needle),
        "{what}: `{needle}` not in {}",
        r.stderr
    );
    assert!(r.stdout.is_empty(), "{what}: {}", r.stdout);
}

/// A small TL plate run that takes a second or so (or, with a long end time, until stopped).
pub const PLATE: &[&str] = &[
    "run",
    "oscillating-plate-2d",
    "--method",
    "tl",
    "--set",
    "resolution=4",
];

/// `base` followed by `more`.
pub fn with<'a>(base: &[&'a str], more: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(more).copied().collect()
}
