//! Shared set-up for the throughput benchmarks and the generator of `docs/performance.md`.
//!
//! Every criterion benchmark of the workspace lives in `benches/`; each describes itself here
//! (its group name, resolutions and methods, e.g. [`TL_BENCH_GROUP`]) so that the `perf-report`
//! binary can find its results under `target/criterion/` and render them as a table without
//! anyone copying numbers by hand.
#![deny(missing_docs)]

use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub mod scenes;

/// The neighbour-search benchmark: a jittered 3D lattice of `per_axis³` particles.
#[derive(Clone, Copy, Debug)]
pub struct NeighborBench {
    /// Criterion group name.
    pub group: &'static str,
    /// Lattice points per axis (47³ = 103,823 particles).
    pub per_axis: usize,
    /// Smoothing length in units of the spacing (cut-off 2h).
    pub h_over_dp: f64,
    /// Uniform random displacement, in units of dp, applied to every lattice point.
    pub jitter: f64,
}

/// The neighbour-search benchmark's parameters.
pub const NEIGHBOR_BENCH: NeighborBench = NeighborBench {
    group: "neighbor-search-3d",
    per_axis: 47,
    h_over_dp: 1.3,
    jitter: 0.1,
};

/// The TL step benchmark: the bending column (TL paper Table 3) at these H/dp.
pub const TL_BENCH_GROUP: &str = "tl-step-bending-column";
/// Resolutions of the TL benchmark (1,296 / 10,368 / 82,944 column particles).
pub const TL_BENCH_RESOLUTIONS: [i64; 3] = [6, 12, 24];
/// Methods of the TL benchmark.
pub const TL_BENCH_METHODS: [&str; 3] = ["tl", "tl-hf", "tl-gm"];

/// The MPS step benchmark: the MPS paper's cantilever plate, MPS beside TL-HF.
pub const MPS_BENCH_GROUP: &str = "mps-step-cantilever-plate";
/// Resolutions (H/dp) of the MPS benchmark.
pub const MPS_BENCH_RESOLUTIONS: [i64; 3] = [5, 10, 20];

/// A `n³` lattice of spacing `1/n` with every point displaced by up to `±jitter·dp` per axis
/// (deterministic SplitMix64 stream), so that distances are not all ties. Returns the points and dp.
pub fn jittered_lattice_3d(n: usize, jitter: f64) -> (Vec<DVec3>, f64) {
    let dp = 1.0 / n as f64;
    let mut rng = SplitMix64(0x5eed);
    let mut out = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let base = DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * dp;
                let d = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0;
                out.push(base + d * jitter * dp);
            }
        }
    }
    (out, dp)
}

/// A rayon pool of exactly `threads` threads (benchmarks run each variant inside `install`).
pub fn thread_pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("rayon thread pool")
}

/// SplitMix64: a tiny deterministic generator for benchmark inputs.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A criterion point estimate with its confidence interval, in nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
pub struct Estimate {
    /// Point estimate.
    pub point_estimate: f64,
    /// Confidence interval.
    pub confidence_interval: Interval,
}

/// Criterion's confidence interval.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
pub struct Interval {
    /// Lower bound.
    pub lower_bound: f64,
    /// Upper bound.
    pub upper_bound: f64,
}

#[derive(Deserialize)]
struct Estimates {
    mean: Estimate,
}

/// Criterion's sanitised directory name for a group, function or parameter.
fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '/' | '\\' | '?' | '"' | '<' | '>' | '|' | ':' | '*' => '_',
            c => c,
        })
        .collect()
}

/// The mean time per iteration (ns) of one criterion benchmark, if it has been run.
pub fn read_mean(
    criterion_dir: &Path,
    group: &str,
    function: &str,
    param: &str,
) -> Option<Estimate> {
    let path: PathBuf = criterion_dir
        .join(sanitize(group))
        .join(sanitize(function))
        .join(sanitize(param))
        .join("new")
        .join("estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let e: Estimates = serde_json::from_str(&text).ok()?;
    Some(e.mean)
}

/// One benchmark's mean as recorded: criterion's estimate and the machine it was measured on.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
pub struct Recorded {
    /// Criterion's mean.
    #[serde(flatten)]
    pub estimate: Estimate,
    /// [`machine`] of the measurement; entries recorded before the field have
    /// [`EARLIER_MACHINE`].
    #[serde(default = "earlier_machine")]
    pub machine: String,
}

fn earlier_machine() -> String {
    EARLIER_MACHINE.to_string()
}

/// The committed record of criterion means, `benchmarks/results/criterion.json`, so that
/// `perf-report` regenerates every table after `target/` has been cleaned. A benchmark's mean
/// comes from criterion's own results when they are present (the latest measurement on this
/// machine: `target/` does not move between machines) and is recorded with [`machine`];
/// otherwise from the record, with the machine recorded there.
#[derive(Debug, Default)]
pub struct BenchRecord {
    entries: BTreeMap<String, Recorded>,
}

impl BenchRecord {
    /// The record at `path` (empty if there is none yet).
    pub fn load(path: &Path) -> Self {
        let entries = std::fs::read_to_string(path)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_default();
        Self { entries }
    }

    /// The mean of one benchmark and its machine: criterion's result under `criterion_dir` if
    /// present (then recorded with this machine), else the recorded one.
    pub fn mean(
        &mut self,
        criterion_dir: &Path,
        group: &str,
        function: &str,
        param: &str,
    ) -> Option<Recorded> {
        let key = format!("{group}/{function}/{param}");
        if let Some(estimate) = read_mean(criterion_dir, group, function, param) {
            let recorded = Recorded {
                estimate,
                machine: machine(),
            };
            self.entries.insert(key, recorded.clone());
            return Some(recorded);
        }
        self.entries.get(&key).cloned()
    }

    /// Writes the record to `path` (a temporary file, then a rename).
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        let tmp = path.with_extension("json.tmp");
        let text = serde_json::to_string_pretty(&self.entries).map_err(std::io::Error::other)?;
        std::fs::write(&tmp, text + "\n")?;
        std::fs::rename(&tmp, path)
    }
}

/// The machine timings are taken on: the CPU model of `/proc/cpuinfo` and the hardware thread
/// count, e.g. "Intel(R) Xeon(R) Processor, 2 hardware threads". Recorded with every timing,
/// because a ratio of two wall times means something only when both were taken on the same
/// machine. See [`machine_from`].
pub fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    machine_from(&cpuinfo, cores)
}

/// [`machine`] from the text of `/proc/cpuinfo` and the thread count. A virtual machine may name
/// its CPU without a generation ("AMD EPYC", "Intel(R) Xeon(R) Processor"); such a name (one
/// without a digit) gets the CPU family and model numbers too, because two machines of that
/// name can differ by half in speed (SPHinXsys's TL plate on one thread: 21.3 s on the AMD
/// EPYC the performance issue was filed on, 11.2 s on an AMD EPYC of family 26 on
/// 2026-12-03).
///
/// # Example
/// ```
/// let info = "model name\t: AMD EPYC\ncpu family\t: 26\nmodel\t\t: 2\n";
/// assert_eq!(
///     sph_benchmarks::machine_from(info, 2),
///     "AMD EPYC family 26 model 2, 2 hardware threads"
/// );
/// ```
pub fn machine_from(cpuinfo: &str, cores: usize) -> String {
    let field = |key: &str| {
        cpuinfo
            .lines()
            .find(|l| l.split(':').next().map(str::trim) == Some(key))
            .and_then(|l| l.split(':').nth(1))
            .map(|s| s.trim().to_string())
    };
    let mut cpu = field("model name").unwrap_or_else(|| "unknown CPU".into());
    if !cpu.chars().any(|c| c.is_ascii_digit()) {
        if let (Some(family), Some(model)) = (field("cpu family"), field("model")) {
            cpu = format!("{cpu} family {family} model {model}");
        }
    }
    format!("{cpu}, {cores} hardware threads")
}

/// Checks a benchmark binary's arguments: each must be one of `flags`, each followed by its
/// value. `--help` or `-h` prints `usage` and exits; anything else is an error naming the
/// argument and the flags allowed (exit status 2), before any work.
pub fn check_flags(args: &[String], flags: &[&str], usage: &str) {
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{usage}");
        std::process::exit(0);
    }
    if let Err(message) = flags_error(args, flags) {
        eprintln!("error: {message}\n{usage}");
        std::process::exit(2);
    }
}

/// The error of [`check_flags`], if any.
fn flags_error(args: &[String], flags: &[&str]) -> Result<(), String> {
    let mut rest = args.iter();
    while let Some(a) = rest.next() {
        if !flags.contains(&a.as_str()) {
            return Err(format!(
                "unknown argument {a:?}: the flags are {}",
                flags.join(", ")
            ));
        }
        if rest.next().is_none() {
            return Err(format!("{a} needs a value"));
        }
    }
    Ok(())
}

/// The commit of the checkout at `root`, `+changes` appended when its tracked files differ
/// from it ("unknown" outside a git checkout): the build a timing or a count was made with.
pub fn build_name(root: &Path) -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .current_dir(root)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let commit = git(&["rev-parse", "--short", "HEAD"]).unwrap_or_else(|| "unknown".into());
    let dirty =
        git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    if dirty {
        format!("{commit}+changes")
    } else {
        commit
    }
}

/// Today's date in UTC, `YYYY-MM-DD` (the civil date of the Unix day number, H. Hinnant's
/// `civil_from_days`).
pub fn utc_date() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    civil_date((secs / 86_400) as i64)
}

/// The civil date of day `days` after 1970-01-01.
fn civil_date(days: i64) -> String {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// Where timings recorded before they carried their machine were taken: docs/performance.md
/// of that time names it ("Machine: AMD EPYC, 2 hardware threads").
pub const EARLIER_MACHINE: &str = "AMD EPYC, 2 hardware threads";

#[cfg(test)]
mod tests {
    #[test]
    fn flags_are_checked() {
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let flags = ["--sph", "--end"];
        assert!(super::flags_error(&args(&[]), &flags).is_ok());
        assert!(super::flags_error(&args(&["--end", "0.1", "--sph", "x"]), &flags).is_ok());
        let e = super::flags_error(&args(&["--ends", "0.1"]), &flags).unwrap_err();
        assert!(
            e.contains("\"--ends\"") && e.contains("--sph, --end"),
            "{e}"
        );
        let e = super::flags_error(&args(&["--end"]), &flags).unwrap_err();
        assert!(e.contains("--end needs a value"), "{e}");
        assert!(super::flags_error(&args(&["0.1"]), &flags).is_err());
    }

    use super::*;

    #[test]
    fn civil_dates_of_known_days() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_790), "2026-12-03");
        assert_eq!(civil_date(-1), "1969-12-31");
    }

    #[test]
    fn lattice_has_the_requested_size_and_stays_in_its_cells() {
        let (p, dp) = jittered_lattice_3d(5, 0.1);
        assert_eq!(p.len(), 125);
        // Jitter ±0.1 dp keeps every point inside its own lattice cell.
        for (n, x) in p.iter().enumerate() {
            let cell = ((x / dp).floor()).as_uvec3();
            assert_eq!(
                cell.x as usize + 5 * (cell.y as usize + 5 * cell.z as usize),
                n
            );
        }
    }

    #[test]
    fn reads_criterion_estimates() {
        let dir = std::env::temp_dir().join(format!("sph-bench-read-{}", std::process::id()));
        let leaf = dir.join("g_x").join("f").join("1-thread").join("new");
        std::fs::create_dir_all(&leaf).unwrap();
        std::fs::write(
            leaf.join("estimates.json"),
            r#"{"mean":{"confidence_interval":{"confidence_level":0.95,"lower_bound":1.0,"upper_bound":3.0},"point_estimate":2.0,"standard_error":0.1}}"#,
        )
        .unwrap();
        let e = read_mean(&dir, "g/x", "f", "1-thread").unwrap();
        assert_eq!(e.point_estimate, 2.0);
        assert!(read_mean(&dir, "g/x", "f", "2-thread").is_none());
        // The record keeps what criterion measured after its results are gone.
        let record_path = dir.join("record.json");
        let mut record = BenchRecord::load(&record_path);
        let recorded = Recorded {
            estimate: e,
            machine: machine(),
        };
        assert_eq!(
            record.mean(&dir, "g/x", "f", "1-thread"),
            Some(recorded.clone())
        );
        record.save(&record_path).unwrap();
        std::fs::remove_dir_all(dir.join("g_x")).unwrap();
        let mut again = BenchRecord::load(&record_path);
        assert_eq!(again.mean(&dir, "g/x", "f", "1-thread"), Some(recorded));
        assert_eq!(again.mean(&dir, "g/x", "f", "2-thread"), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn entries_recorded_before_the_machine_field_name_the_earlier_machine() {
        let dir = std::env::temp_dir().join(format!("sph-bench-old-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let record_path = dir.join("record.json");
        std::fs::write(
            &record_path,
            r#"{"g/f/1": {"point_estimate": 5.0, "confidence_interval": {"lower_bound": 4.0, "upper_bound": 6.0}}}"#,
        )
        .unwrap();
        let got = BenchRecord::load(&record_path)
            .mean(&dir, "g", "f", "1")
            .unwrap();
        assert_eq!(got.estimate.point_estimate, 5.0);
        assert_eq!(got.machine, EARLIER_MACHINE);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
