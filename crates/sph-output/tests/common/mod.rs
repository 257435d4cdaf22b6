//! Shared test content: the same run written through any backend.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use serde_json::{json, Map, Value};
use sph_output::{create_writer_with, Backend, Compression, Dataset, ResultWriter};

/// Particles per snapshot: enough that every per-particle dataset is over the 1 KiB from
/// which compressed writers chunk and deflate it.
pub const N: usize = 200;

pub fn meta() -> Map<String, Value> {
    json!({
        "case": "cantilever <beam> & \"friends\"",
        "dim": 2,
        "dx": 0.01,
        "offset": -3,
        "huge": u64::MAX,
        "parallel": true,
        "material": {"E": 2.0e11, "nu": 0.3},
        "tags": ["a", "b"],
        "nothing": null,
        "json": "a key named json",
    })
    .as_object()
    .unwrap()
    .clone()
}

pub fn summary() -> Map<String, Value> {
    json!({
        "status": "failed",
        "reason": "energy blew up at step 1200",
        "steps": 1200u64,
        "wall_time_s": 12.345678901234567,
        // serde_json's default parser reads this one 1 ulp off (a CI failure); the workspace
        // enables `float_roundtrip` so summaries read back exactly.
        "time_reached": 0.0022502095608844586,
        "ok": false,
    })
    .as_object()
    .unwrap()
    .clone()
}

/// Awkward but exact f64 values (sub-normals, negative zero, large exponents).
fn val(k: usize, i: usize, c: usize) -> f64 {
    let x = (k * 1000 + i * 10 + c) as f64;
    match (k + i + c) % 5 {
        0 => x * 0.1 + 1.0 / 3.0,
        1 => -x * 1e-300,
        2 => 5e-324 * x,
        3 => -0.0,
        _ => x.sqrt() * 1e200,
    }
}

pub fn snapshot(k: usize) -> (f64, u64, Vec<Dataset>) {
    let pos: Vec<[f64; 2]> = (0..N).map(|i| [val(k, i, 0), val(k, i, 1)]).collect();
    let vel: Vec<[f64; 3]> = (0..N)
        .map(|i| [val(k, i, 2), val(k, i, 3), val(k, i, 4)])
        .collect();
    let rho: Vec<f64> = (0..N).map(|i| val(k, i, 5)).collect();
    let stress: Vec<[[f64; 2]; 2]> = (0..N)
        .map(|i| [[val(k, i, 6), val(k, i, 7)], [val(k, i, 7), val(k, i, 8)]])
        .collect();
    let f: Vec<[[f64; 3]; 3]> = (0..N)
        .map(|i| {
            let mut m = [[0.0; 3]; 3];
            for (r, row) in m.iter_mut().enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    *v = val(k, i, 10 + 3 * r + c);
                }
            }
            m
        })
        .collect();
    // Ids beyond 2^63 (and no permutation of 0..N: the XDMF connectivity is inline).
    let ids: Vec<u64> = (0..N as u64)
        .map(|i| u64::MAX - (N as u64 - 1) + i)
        .collect();
    (
        0.25 * k as f64 + 1e-17,
        100 * k as u64 + 7,
        vec![
            Dataset::vectors_2d("position", &pos),
            Dataset::vectors("velocity", &vel),
            Dataset::scalars("density", &rho),
            Dataset::matrices_2d("stress", &stress),
            Dataset::matrices("deformation_gradient", &f),
            Dataset::u64_scalars("id", &ids),
            Dataset::f64("energy", vec![val(k, 0, 99)], vec![1]),
        ],
    )
}

pub fn probe(seed: usize, m: usize) -> (Vec<f64>, Vec<[f64; 3]>, Vec<[f64; 3]>) {
    (
        (0..m).map(|j| val(seed, j, 0)).collect(),
        (0..m)
            .map(|j| [val(seed, j, 1), val(seed, j, 2), val(seed, j, 3)])
            .collect(),
        (0..m)
            .map(|j| [val(seed, j, 4), val(seed, j, 5), val(seed, j, 6)])
            .collect(),
    )
}

pub const PROBES: [(&str, usize, usize); 2] = [("tip", 3, 11), ("mid point", 4, 5)];

/// Writes the standard content to `<base>.h5` and returns its path.
pub fn write_all(base: &Path, backend: Backend) -> PathBuf {
    write_all_with(base, backend, Compression::None)
}

/// [`write_all`] with a dataset compression.
pub fn write_all_with(base: &Path, backend: Backend, compression: Compression) -> PathBuf {
    let mut w: Box<dyn ResultWriter> =
        create_writer_with(base, backend, compression).expect("create writer");
    w.write_meta(&meta()).unwrap();
    for k in 0..3 {
        let (t, s, d) = snapshot(k);
        w.write_snapshot(t, s, &d).unwrap();
    }
    for (name, seed, m) in PROBES {
        let (t, p, v) = probe(seed, m);
        w.write_probe(name, &t, &p, &v).unwrap();
    }
    let (t, force) = series();
    w.write_series(
        "punch",
        &t,
        &[("force_y", &force), ("displacement", &t)],
        "a punch",
    )
    .unwrap();
    w.write_summary(&summary()).unwrap();
    w.finish().expect("finish")
}

/// The standard series: a reaction force over time.
pub fn series() -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = (0..7).map(|k| k as f64 * 0.125).collect();
    let f = t
        .iter()
        .map(|t| (3.0 * t).sin() * 1e3 + 1.0 / 3.0)
        .collect();
    (t, f)
}

/// Asserts `contents` is exactly the standard content, bit for bit.
pub fn check_contents(c: &sph_output::FileContents) {
    assert_eq!(c.meta, meta());
    assert_eq!(c.summary, summary());
    assert_eq!(c.snapshots.len(), 3);
    for (k, snap) in c.snapshots.iter().enumerate() {
        let (t, s, mut d) = snapshot(k);
        d.sort_by(|a, b| a.name.cmp(&b.name));
        assert_eq!(snap.name, format!("{k:06}"));
        assert_eq!(snap.time.to_bits(), t.to_bits());
        assert_eq!(snap.step, s);
        assert_eq!(snap.datasets.len(), d.len());
        for (got, want) in snap.datasets.iter().zip(&d) {
            assert_eq!(got.name, want.name);
            assert_eq!(got.shape(), want.shape(), "{}", want.name);
            match (&got.data, &want.data) {
                (
                    sph_output::DatasetData::F64 { values: g, .. },
                    sph_output::DatasetData::F64 { values: w, .. },
                ) => {
                    let gb: Vec<u64> = g.iter().map(|v| v.to_bits()).collect();
                    let wb: Vec<u64> = w.iter().map(|v| v.to_bits()).collect();
                    assert_eq!(gb, wb, "{} bits", want.name);
                }
                (g, w) => assert_eq!(g, w),
            }
        }
    }
    let (t, force) = series();
    let s = &c.series["punch"];
    assert_eq!(s.times, t);
    assert_eq!(s.columns["force_y"], force);
    assert_eq!(s.columns["displacement"], t);
    assert_eq!(s.columns.len(), 2);
    assert_eq!(c.probes.len(), 2);
    for (name, seed, m) in PROBES {
        let p = &c.probes[name];
        let (t, pos, vel) = probe(seed, m);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&p.times), bits(&t));
        assert_eq!(bits(p.positions.as_flattened()), bits(pos.as_flattened()));
        assert_eq!(bits(p.velocities.as_flattened()), bits(vel.as_flattened()));
    }
}

/// A fresh scratch directory under the target dir (no tempfile dependency).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("sph-output-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Temporary and lock files left in `dir` (a finished or refused writer leaves none).
pub fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".lock"))
        .collect()
}

/// A large, smooth snapshot (a rotating, stretching block of `n` particles): compressible like
/// a real run's, and with `[n, 3, 3]` matrices several chunks long (the last one partial).
pub fn smooth_snapshot(n: usize, t: f64) -> Vec<Dataset> {
    let side = (n as f64).cbrt().ceil() as usize;
    let x0: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let (a, b, c) = (i % side, (i / side) % side, i / (side * side));
            [a as f64 * 0.01, b as f64 * 0.01, c as f64 * 0.01]
        })
        .collect();
    let (s, c) = (t.sin(), t.cos());
    let f = [
        [c * (1.0 + t), -s, 0.0],
        [s, c, 0.0],
        [0.0, 0.0, 1.0 / (1.0 + t)],
    ];
    let pos: Vec<[f64; 3]> = x0
        .iter()
        .map(|x| std::array::from_fn(|r| (0..3).map(|k| f[r][k] * x[k]).sum()))
        .collect();
    let vel: Vec<[f64; 3]> = pos.iter().map(|p| [-p[1], p[0], 0.1 * p[2]]).collect();
    let vm: Vec<f64> = pos
        .iter()
        .map(|p| 1e6 * (p[0] * p[0] + p[1]).sqrt())
        .collect();
    let ids: Vec<u64> = (0..n as u64).rev().collect();
    vec![
        Dataset::vectors("position", &pos),
        Dataset::u64_scalars("id", &ids),
        Dataset::vectors("velocity", &vel),
        Dataset::scalars("von_mises", &vm),
        Dataset::matrices("deformation_gradient", &vec![f; n]),
    ]
}

/// Writes two [`smooth_snapshot`]s of `n` particles to `<base>.h5`.
pub fn write_smooth(base: &Path, backend: Backend, compression: Compression, n: usize) -> PathBuf {
    let mut w = create_writer_with(base, backend, compression).expect("create writer");
    for (k, t) in [0.0, 0.5].into_iter().enumerate() {
        w.write_snapshot(t, k as u64, &smooth_snapshot(n, t))
            .unwrap();
    }
    w.finish().expect("finish")
}

/// Whether `python3` can import all of `modules`.
pub fn python_has(modules: &[&str]) -> bool {
    std::process::Command::new("python3")
        .args(["-c", &format!("import {}", modules.join(", "))])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Runs `python3 tests/<script> args…` and asserts it succeeds, printing its output.
pub fn run_python_check(script: &str, args: &[&Path]) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(script);
    let out = std::process::Command::new("python3")
        .arg(&path)
        .args(args)
        .output()
        .expect("run python3");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(out.status.success(), "{script} failed:\n{text}");
}
