//! `sph run` under `mpirun` (feature `mpi`; run by crates/sph-cases/mpi-ci.sh): the results of a
//! TL-HF bending column on 2 and 3 ranks equal the single-rank run's bit for bit (every
//! snapshot field, the probe), and methods that do not run distributed are refused.
#![cfg(feature = "mpi")]

use std::path::Path;
use std::process::Command;

fn mpirun(ranks: usize, args: &[&str]) -> std::process::Output {
    // OpenMPI refuses root without the first, and 3 ranks on 2 cores without the second;
    // SPH_MPIRUN_FLAGS replaces them (e.g. empty for MPICH).
    let flags = std::env::var("SPH_MPIRUN_FLAGS")
        .unwrap_or_else(|_| "--allow-run-as-root --oversubscribe".into());
    let mut c = Command::new("mpirun");
    c.args(flags.split_whitespace());
    c.args(["-n", &ranks.to_string(), env!("CARGO_BIN_EXE_sph")])
        .args(args)
        .output()
        .expect("mpirun starts")
}

fn column(ranks: usize, out: &Path) -> sph_output::FileContents {
    let o = mpirun(
        ranks,
        &[
            "run",
            "bending-column-3d",
            "--method",
            "tl-hf",
            "--set",
            "resolution=4",
            "--set",
            "end_time=0.02",
            "--threads",
            "1",
            "--log-every",
            "0",
            "--out",
            out.to_str().expect("utf-8 path"),
        ],
    );
    assert!(
        o.status.success(),
        "{ranks} ranks: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    sph_output::read_file(out.join("bending-column-3d-tl-hf.h5")).expect("results")
}

#[test]
fn two_and_three_ranks_write_the_single_rank_results_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("sph-mpi-test-{}", std::process::id()));
    let one = column(1, &dir.join("1"));
    assert_eq!(one.snapshots.len(), 51);
    for ranks in [2, 3] {
        let many = column(ranks, &dir.join(ranks.to_string()));
        assert_eq!(many.summary.get("ranks"), Some(&ranks.into()));
        assert_eq!(many.snapshots.len(), one.snapshots.len());
        for (a, b) in one.snapshots.iter().zip(&many.snapshots) {
            assert_eq!((a.time, a.step), (b.time, b.step));
            for d in &a.datasets {
                let e = b.dataset(&d.name).expect("same fields");
                assert!(
                    d.data == e.data,
                    "{ranks} ranks: {} at t = {}",
                    d.name,
                    a.time
                );
            }
        }
        let (p, q) = (&one.probes["S"], &many.probes["S"]);
        assert!(p.positions == q.positions && p.velocities == q.velocities);
        // Energies are sums over the ranks: equal to round-off.
        let e = |f: &sph_output::FileContents| f.summary["energy_drift"].as_f64();
        let (x, y) = (e(&one).expect("drift"), e(&many).expect("drift"));
        assert!((x - y).abs() <= 1e-9 * x.abs(), "energy drift {x} vs {y}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn methods_that_do_not_run_distributed_are_refused_before_any_work() {
    let o = mpirun(
        2,
        &[
            "run",
            "oscillating-plate-2d",
            "--method",
            "ul-enog",
            "--no-output",
        ],
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("does not run distributed"), "{err}");
    let o = mpirun(
        2,
        &[
            "run",
            "bending-column-3d",
            "--set",
            "resolution=4",
            "--checkpoint-every",
            "0.01",
            "--no-output",
        ],
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("checkpoints"), "{err}");
}
