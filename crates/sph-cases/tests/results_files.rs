//! What results files hold: the whole summary a run reports, and the per-rank output of
//! distributed runs (`RunOptions::per_rank_output`, `sph run --per-rank-output`) on in-process
//! ranks (`sph_core::comm::ThreadRanks`): each rank writes only its own particles, and
//! `sph_output::read_ranks` gives back, bit for bit, the snapshots of the single-process run;
//! the XDMF file lists every rank's grid with its particle count.

use serde_json::Value;
use sph_cases::{find_case, RunOptions};
use sph_core::comm::{Communicator, ThreadRanks};
use sph_output::{read_file, read_ranks, FileContents};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const CASE: &str = "cantilever-plate-2d";
const METHOD: &str = "mps";

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sph-per-rank-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the small cantilever plate (MPS) on `ranks` in-process ranks (`None`: one process, no ranks).
fn run(ranks: Option<usize>, base: &Path, per_rank: bool) -> Vec<String> {
    run_case(
        CASE,
        METHOD,
        &["resolution=4", "end_time=0.005", "snapshots=4"],
        ranks,
        base,
        per_rank,
    )
}

/// Runs `case` with `method` and the assignments `set` on `ranks` in-process ranks, one
/// thread each.
fn run_case(
    case_name: &str,
    method: &str,
    set: &[&str],
    ranks: Option<usize>,
    base: &Path,
    per_rank: bool,
) -> Vec<String> {
    run_case_on(case_name, method, set, ranks, 1, base, per_rank)
}

/// [`run_case`] with `threads` threads per rank.
fn run_case_on(
    case_name: &str,
    method: &str,
    set: &[&str],
    ranks: Option<usize>,
    threads: usize,
    base: &Path,
    per_rank: bool,
) -> Vec<String> {
    let case = find_case(case_name).unwrap();
    let mut params = case.params_for(method);
    for s in set {
        params.apply_assignment(s).unwrap();
    }
    let go_here = |comm: Option<Arc<dyn Communicator>>| {
        let options = RunOptions {
            output: Some(base.to_path_buf()),
            ranks: comm,
            per_rank_output: per_rank,
            ..Default::default()
        };
        let (record, summary) = case.run(method, &params, &options).unwrap();
        assert!(record.failure.is_none(), "{:?}", record.failure);
        summary["status"].as_str().unwrap().to_string()
    };
    // Each rank in a pool of its own, as an MPI process has: the driver steps inside its
    // pool, and ranks sharing one pool of fewer threads would wait on each other for ever.
    let go = |comm: Option<Arc<dyn Communicator>>| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| go_here(comm))
    };
    match ranks {
        None => vec![go(None)],
        Some(n) => ThreadRanks::run(n, |c| go(Some(c))),
    }
}

fn assert_same_snapshots(one: &FileContents, many: &FileContents, what: &str) {
    assert_eq!(one.snapshots.len(), many.snapshots.len(), "{what}");
    for (a, b) in one.snapshots.iter().zip(&many.snapshots) {
        assert_eq!((a.time, a.step), (b.time, b.step), "{what}");
        let names = |s: &sph_output::Snapshot| {
            s.datasets
                .iter()
                .map(|d| d.name.clone())
                .collect::<Vec<_>>()
        };
        assert_eq!(names(a), names(b), "{what}");
        for (d, e) in a.datasets.iter().zip(&b.datasets) {
            assert!(d.data == e.data, "{what}: {} at t = {}", d.name, a.time);
        }
    }
    assert_eq!(one.probes, many.probes, "{what}: probes");
}

/// The `(file, rows)` of every rank grid of the first snapshot of an XDMF file.
fn grids_of_first_snapshot(xmf: &str) -> Vec<(String, usize)> {
    let first = xmf.split("CollectionType=\"Spatial\"").nth(1).unwrap();
    let first = first.split("</Grid>\n      </Grid>").next().unwrap();
    first
        .split("<Geometry GeometryType=\"XYZ\">")
        .skip(1)
        .map(|g| {
            let dims = g.split("Dimensions=\"").nth(1).unwrap();
            let rows = dims.split(' ').next().unwrap().parse().unwrap();
            let file = g.split("Format=\"HDF\">").nth(1).unwrap();
            (file.split(':').next().unwrap().to_string(), rows)
        })
        .collect()
}

/// Every `HDF` data item of the XDMF text names a dataset of a file in `dir` with the stated
/// dimensions.
fn every_data_item_resolves(xmf: &str, dir: &Path) {
    let mut files = std::collections::HashMap::new();
    let mut items = 0;
    for item in xmf.split("<DataItem ").skip(1) {
        let Some((head, rest)) = item.split_once('>') else {
            panic!("{item}")
        };
        if !head.contains("Format=\"HDF\"") {
            continue;
        }
        items += 1;
        let dims: Vec<usize> = head
            .split("Dimensions=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .split(' ')
            .map(|d| d.parse().unwrap())
            .collect();
        let reference = rest.split('<').next().unwrap();
        let (file, path) = reference.split_once(':').unwrap();
        let contents = files
            .entry(file.to_string())
            .or_insert_with(|| read_file(dir.join(file)).unwrap());
        let parts: Vec<&str> = path.trim_start_matches('/').split('/').collect();
        let [group, snapshot, name] = parts[..] else {
            panic!("{path}")
        };
        assert_eq!(group, "snapshots");
        let snap = contents.snapshots.iter().find(|s| s.name == snapshot);
        let data = snap
            .and_then(|s| s.dataset(name))
            .unwrap_or_else(|| panic!("{path}"));
        assert_eq!(data.shape(), &dims[..], "{reference}");
    }
    assert!(items > 0);
}

/// The same file through Python's XML parser and h5py (`tests/rank_xdmf_check.py`), when
/// `python3` with h5py is installed (CI's HDF5 step installs it where it can); a notice
/// otherwise.
fn python_reads_the_rank_xdmf(xmf: &Path, ranks: usize, particles: usize) {
    let has_h5py = std::process::Command::new("python3")
        .args(["-c", "import h5py"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_h5py {
        eprintln!("notice: python3 with h5py not available; the XDMF check by h5py is skipped");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rank_xdmf_check.py");
    let out = std::process::Command::new("python3")
        .arg(script)
        .arg(xmf)
        .args([ranks.to_string(), particles.to_string()])
        .output()
        .expect("python3 runs");
    print!("{}", String::from_utf8_lossy(&out.stdout));
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The TL cases build each rank's share of the neighbour data only (`TlSolver::for_ranks`);
/// the gathered results equal the single-process run's bit for bit.
#[test]
fn a_tl_case_on_ranks_writes_the_single_process_results() {
    let dir = scratch("tl");
    let set = [
        "resolution=4",
        "end_time=0.002",
        "snapshots=2",
        "pair_data=recomputed",
    ];
    run_case(
        "bending-column-3d",
        "tl-hf",
        &set,
        None,
        &dir.join("one/c"),
        false,
    );
    let one = read_file(dir.join("one/c.h5")).unwrap();
    assert_eq!(one.snapshots.len(), 3);
    for ranks in [2, 3] {
        let base = dir.join(format!("{ranks}/c"));
        let statuses = run_case(
            "bending-column-3d",
            "tl-hf",
            &set,
            Some(ranks),
            &base,
            false,
        );
        assert!(statuses.iter().all(|s| s == "completed"), "{statuses:?}");
        let many = read_file(dir.join(format!("{ranks}/c.h5"))).unwrap();
        assert_same_snapshots(&one, &many, &format!("tl-hf on {ranks} ranks"));
        assert_eq!(many.summary["ranks"], Value::from(ranks));
        assert_eq!(
            many.meta["guarded_particles"],
            one.meta["guarded_particles"]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Short runs of every method family above the 1,024 particles from which loops are split:
/// case, method and parameters.
const SPLIT_RUNS: [(&str, &str, &[&str]); 5] = [
    (
        "oscillating-plate-2d",
        "tl-hf",
        &["end_time=0.002", "snapshots=2"],
    ),
    (
        "oscillating-plate-2d",
        "tl-gm",
        &["end_time=0.002", "snapshots=2"],
    ),
    (
        "oscillating-plate-2d",
        "ul-enog",
        &["end_time=0.002", "snapshots=2"],
    ),
    (
        "colliding-rings-2d",
        "ul-og",
        &["end_time=0.0005", "snapshots=2", "contact=true"],
    ),
    (
        "cantilever-plate-2d",
        "mps",
        &["end_time=0.002", "snapshots=2", "stabilisation=0.5"],
    ),
];

/// The parallel loops of every method (`sph_core::team`: any thread may run any task) give
/// the one-thread results bit for bit on 2 and 3 threads: TL-HF and TL-GM, UL-ENOG, UL-OG with
/// contact between bodies, and the stabilised MPS (all above the 1,024 particles from which
/// loops are split).
#[test]
fn every_method_writes_the_same_results_on_one_two_and_three_threads() {
    let dir = scratch("threads");
    for (case, method, set) in SPLIT_RUNS {
        let file = |threads: usize| {
            let base = dir.join(format!("{case}-{method}-{threads}/c"));
            let status = run_case_on(case, method, set, None, threads, &base, false);
            assert_eq!(
                status,
                ["completed"],
                "{case} {method} on {threads} threads"
            );
            read_file(base.with_extension("h5")).unwrap()
        };
        let one = file(1);
        assert!(
            one.meta["particles"].as_f64().unwrap() > 1024.0,
            "{case}: too small to split"
        );
        for threads in [2, 3] {
            assert_same_snapshots(&one, &file(threads), &format!("{case} {method} {threads}"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The loops' AVX2 + FMA copy (`sph_core::wide`) gives the plain x86-64 results bit for bit,
/// for the runs of every method family above.
#[test]
fn every_method_writes_the_same_results_with_and_without_avx2() {
    if !sph_core::wide::cpu_has_avx2_fma() {
        eprintln!("notice: this CPU has no AVX2 + FMA; both runs use plain x86-64 code");
    }
    let dir = scratch("wide");
    for (case, method, set) in SPLIT_RUNS {
        let file = |wide: bool| {
            sph_core::wide::set_enabled(wide);
            let base = dir.join(format!("{case}-{method}-{wide}/c"));
            let status = run_case_on(case, method, set, None, 2, &base, false);
            sph_core::wide::set_enabled(true);
            assert_eq!(status, ["completed"], "{case} {method}, AVX2 {wide}");
            read_file(base.with_extension("h5")).unwrap()
        };
        let plain = file(false);
        assert_same_snapshots(&plain, &file(true), &format!("{case} {method} AVX2"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn per_rank_files_read_back_as_the_single_process_results() {
    let dir = scratch("same");
    run(None, &dir.join("one/c"), false);
    let one = read_file(dir.join("one/c.h5")).unwrap();
    assert_eq!(one.snapshots.len(), 5);
    for ranks in [1, 2, 3] {
        let base = dir.join(format!("{ranks}/c"));
        let statuses = run(Some(ranks), &base, true);
        assert!(statuses.iter().all(|s| s == "completed"), "{statuses:?}");
        let many = read_ranks(&base).unwrap();
        assert_same_snapshots(&one, &many, &format!("{ranks} ranks"));
        assert_eq!(many.summary["ranks"], Value::from(ranks));
        assert_eq!(many.summary["output"], "per rank");
        assert_eq!(many.summary["steps"], one.summary["steps"]);
        // The main file holds no snapshots; each rank's file only its own particles.
        assert!(read_file(dir.join(format!("{ranks}/c.h5")))
            .unwrap()
            .snapshots
            .is_empty());
        let n = one.snapshots[0].dataset("position").unwrap().shape()[0];
        let mut contiguous = true;
        let rows: Vec<usize> = (0..ranks)
            .map(|r| {
                let f = read_file(dir.join(format!("{ranks}/c.rank{r}.h5"))).unwrap();
                assert_eq!(f.meta["rank"], Value::from(r));
                assert_eq!(f.summary["status"], "completed");
                let g = f.snapshots[0].dataset("global_id").unwrap();
                if let sph_output::DatasetData::U64 { values, .. } = &g.data {
                    contiguous &= values.windows(2).all(|w| w[1] == w[0] + 1);
                }
                f.snapshots[0].dataset("position").unwrap().shape()[0]
            })
            .collect();
        assert_eq!(rows.iter().sum::<usize>(), n);
        if ranks > 1 {
            assert!(
                rows.iter().all(|&r| r < n),
                "{rows:?}: split between the ranks"
            );
            // Otherwise putting the ranks' rows one after the other would pass too.
            assert!(
                !contiguous,
                "{ranks} ranks: each owns a range of global ids"
            );
        }
        // The XDMF file shows the ranks' files as one body.
        let xmf = std::fs::read_to_string(dir.join(format!("{ranks}/c.xmf"))).unwrap();
        assert_eq!(xmf.matches("CollectionType=\"Spatial\"").count(), 5);
        let grids = grids_of_first_snapshot(&xmf);
        let expected: Vec<(String, usize)> = rows
            .iter()
            .enumerate()
            .map(|(r, &k)| (format!("c.rank{r}.h5"), k))
            .collect();
        assert_eq!(grids, expected);
        every_data_item_resolves(&xmf, &dir.join(ranks.to_string()));
        python_reads_the_rank_xdmf(&dir.join(format!("{ranks}/c.xmf")), ranks, n);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn per_rank_output_without_a_results_file_is_refused() {
    let case = find_case(CASE).unwrap();
    let params = case.params_for(METHOD);
    let options = RunOptions {
        per_rank_output: true,
        ..Default::default()
    };
    let e = case.run(METHOD, &params, &options).unwrap_err().to_string();
    assert!(e.contains("per_rank_output"), "{e}");
}

/// The results file's `/summary` holds every figure the run reports (before, UL's sub-step
/// counts, momentum balance and exact-work budget were added after the file was completed,
/// so a results file lacked what `sph run` printed).
#[test]
fn the_results_file_carries_the_whole_summary() {
    let dir = scratch("summary");
    for (case, method, sets) in [
        (
            "oscillating-plate-2d",
            "ul-enog",
            ["resolution=4", "end_time=0.01"],
        ),
        (
            "oscillating-plate-2d",
            "tl-hf",
            ["resolution=4", "end_time=0.01"],
        ),
    ] {
        let case_ = find_case(case).unwrap();
        let mut params = case_.params_for(method);
        for s in sets {
            params.apply_assignment(s).unwrap();
        }
        let base = dir.join(method);
        let options = RunOptions {
            output: Some(base.clone()),
            ..Default::default()
        };
        let (_, summary) = case_.run(method, &params, &options).unwrap();
        let file = read_file(sph_output::h5_path(&base)).unwrap().summary;
        for (key, value) in &summary {
            if key == "wall_seconds" {
                continue; // the total, taken after the file is completed
            }
            assert_eq!(file.get(key), Some(value), "{method}: {key}");
        }
        if method == "ul-enog" {
            for key in [
                "acoustic_steps",
                "momentum_balance",
                "energy_residual_exact_work",
            ] {
                assert!(file.contains_key(key), "{key}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
