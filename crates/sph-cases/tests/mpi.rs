//! `sph run` under `mpirun` (feature `mpi`; run by crates/sph-cases/mpi-ci.sh): the results of a
//! TL-HF bending column and of the MPS cantilever plate on 2 and 3 ranks equal the single-rank
//! run's bit for bit (every snapshot field, the probes), and what does not run distributed is
//! refused.
#![cfg(feature = "mpi")]

use sph_output::FileContents;
use std::path::Path;
use std::process::Command;

fn mpirun(ranks: usize, args: &[&str]) -> std::process::Output {
    // OpenMPI refuses root without the first, and 3 ranks on 2 cores without the second;
    // SPH_MPIRUN_FLAGS replaces them (e.g. empty for MPICH).
    let flags = std::env::var("SPH_MPIRUN_FLAGS")
        .unwrap_or_else(|_| "--allow-run-as-root --oversubscribe".into());
    // One mpirun at a time: concurrent ones race to create OpenMPI's session directory.
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _guard = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut c = Command::new("mpirun");
    c.args(flags.split_whitespace());
    c.args(["-n", &ranks.to_string(), env!("CARGO_BIN_EXE_sph")])
        .args(args)
        .output()
        .expect("mpirun starts")
}

/// Runs `case` with `method` on `ranks` ranks into `out` and reads the results.
fn run(ranks: usize, case: &str, method: &str, sets: &[&str], out: &Path) -> FileContents {
    run_with(ranks, case, method, sets, out, false)
}

/// [`run`], with per-rank output (`--per-rank-output`, read back with `read_ranks`) or not.
fn run_with(
    ranks: usize,
    case: &str,
    method: &str,
    sets: &[&str],
    out: &Path,
    per_rank: bool,
) -> FileContents {
    let mut args = vec![
        "run",
        case,
        "--method",
        method,
        "--threads",
        "1",
        "--log-every",
        "0",
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    args.extend(["--out", out.to_str().expect("utf-8 path")]);
    if per_rank {
        args.push("--per-rank-output");
    }
    let o = mpirun(ranks, &args);
    assert!(
        o.status.success(),
        "{ranks} ranks: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    if per_rank {
        sph_output::read_ranks(&out.join(format!("{case}-{method}"))).expect("results")
    } else {
        sph_output::read_file(out.join(format!("{case}-{method}.h5"))).expect("results")
    }
}

/// Runs `case` on 1, 2 and 3 ranks (3 with per-rank output) and checks that every snapshot
/// field and every probe of the 2- and 3-rank runs equal the single-rank run's bit for bit, and the energy drift (a sum
/// over the ranks) to round-off.
fn same_results_on_1_2_3_ranks(case: &str, method: &str, sets: &[&str], snapshots: usize) {
    let dir = std::env::temp_dir().join(format!("sph-mpi-{case}-{}", std::process::id()));
    let one = run(1, case, method, sets, &dir.join("1"));
    assert_eq!(one.snapshots.len(), snapshots);
    for ranks in [2, 3] {
        // 3 ranks write per-rank files, read back as one body.
        let out = dir.join(ranks.to_string());
        let many = run_with(ranks, case, method, sets, &out, ranks == 3);
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
        assert_eq!(
            one.probes.keys().collect::<Vec<_>>(),
            many.probes.keys().collect::<Vec<_>>()
        );
        for (name, p) in &one.probes {
            let q = &many.probes[name];
            assert!(
                p.positions == q.positions && p.velocities == q.velocities,
                "probe {name}"
            );
        }
        let e = |f: &FileContents| f.summary["energy_drift"].as_f64();
        let (x, y) = (e(&one).expect("drift"), e(&many).expect("drift"));
        assert!((x - y).abs() <= 1e-9 * x.abs(), "energy drift {x} vs {y}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_tl_hf_bending_column_on_2_and_3_ranks_writes_the_single_rank_results() {
    same_results_on_1_2_3_ranks(
        "bending-column-3d",
        "tl-hf",
        &["resolution=4", "end_time=0.02"],
        51,
    );
}

#[test]
fn the_mps_cantilever_plate_on_2_and_3_ranks_writes_the_single_rank_results() {
    same_results_on_1_2_3_ranks(
        "cantilever-plate-2d",
        "mps",
        &["resolution=4", "end_time=0.01"],
        51,
    );
}

#[test]
fn a_two_rank_run_checkpoints_per_rank_and_resumes_on_two_ranks_bit_for_bit() {
    checkpoint_and_resume_on_two_ranks(false);
}

#[test]
fn a_two_rank_run_with_per_rank_output_resumes_bit_for_bit() {
    checkpoint_and_resume_on_two_ranks(true);
}

/// A 2-rank run with checkpoints, its results deleted, resumed on 2 ranks: the same results as
/// one rank's; on 3 ranks the resume is refused.
fn checkpoint_and_resume_on_two_ranks(per_rank: bool) {
    let dir = std::env::temp_dir().join(format!("sph-mpi-ckpt-{per_rank}-{}", std::process::id()));
    let sets = ["resolution=4", "end_time=0.02"];
    let one = run(1, "bending-column-3d", "tl-hf", &sets, &dir.join("1"));
    let out = dir.join("2");
    let mut args = vec![
        "run",
        "bending-column-3d",
        "--method",
        "tl-hf",
        "--set",
        sets[0],
        "--set",
        sets[1],
        "--threads",
        "1",
        "--log-every",
        "0",
        "--checkpoint-every",
        "0.007",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    if per_rank {
        args.push("--per-rank-output");
    }
    let o = mpirun(2, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ckpt = out.join("bending-column-3d-tl-hf.ckpt");
    assert!(ckpt.exists() && out.join("bending-column-3d-tl-hf.ckpt.rank1").exists());
    std::fs::remove_file(out.join("bending-column-3d-tl-hf.h5")).expect("results");
    if per_rank {
        for r in 0..2 {
            let f = out.join(format!("bending-column-3d-tl-hf.rank{r}.h5"));
            std::fs::remove_file(f).expect("rank results");
        }
    }
    let resume = |ranks: usize| {
        mpirun(
            ranks,
            &["resume", ckpt.to_str().expect("utf-8"), "--log-every", "0"],
        )
    };
    let o = resume(2);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let base = out.join("bending-column-3d-tl-hf");
    let resumed = if per_rank {
        sph_output::read_ranks(&base)
    } else {
        sph_output::read_file(sph_output::h5_path(&base))
    }
    .expect("resumed results");
    assert_eq!(resumed.snapshots.len(), one.snapshots.len());
    for (a, b) in one.snapshots.iter().zip(&resumed.snapshots) {
        for d in &a.datasets {
            assert!(
                b.dataset(&d.name).is_some_and(|e| d.data == e.data),
                "{}",
                d.name
            );
        }
    }
    assert!(one.probes["S"].positions == resumed.probes["S"].positions);
    // Another rank count is refused with a message naming the ranks.
    let o = resume(3);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("as many ranks"), "{err}");
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
}
