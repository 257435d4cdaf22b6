//! Dual-criteria vs single-criterion time stepping of UL-ENOG (UL paper §5, Tables 2 and 4), in
//! the same run — dual with the kernel data refreshed every acoustic sub-step (the default),
//! dual with them frozen over the advection step (docs/methods.md's scheme) and single: the 2D oscillating plate at H/dp = 10, 20, 30 (v_f = 0.05) and the simply
//! supported 3D plate, mode (2, 2) as Table 4, at H/dp = 3 (and 5 with `--fine`), each to a fixed end time with both
//! schemes. Writes `benchmarks/results/ul-stepping.json`, which `perf-report` turns into the
//! table of `docs/performance.md`.
//!
//! ```text
//! cargo run --release -p sph-benchmarks --bin ul-stepping [-- --fine] [--end-2d T] [--end-3d T]
//! ```
//! The paper ran to t = 1 (2D); the ratio is what is compared, so the default end times are
//! shorter (0.1 s in 2D, a quarter of the first period, where the plate moves fastest; 0.01 s in
//! 3D) to keep the single-stepping runs within minutes on 2 cores.

use serde_json::{json, Value};
use sph_cases::{find_case, RunOptions};

fn run(case: &str, sets: &[String]) -> Result<Value, String> {
    let c = find_case(case).map_err(|e| e.to_string())?;
    let mut p = c.params_for("ul-enog");
    for s in sets {
        p.apply_assignment(s).map_err(|e| e.to_string())?;
    }
    let options = RunOptions {
        output: None,
        ..Default::default()
    };
    let (record, summary) = c.run("ul-enog", &p, &options).map_err(|e| e.to_string())?;
    if let Some(f) = &record.failure {
        return Err(format!("{case} {sets:?}: {f}"));
    }
    let pick = |k: &str| summary.get(k).cloned().unwrap_or(Value::Null);
    Ok(json!({
        "particles": record.particles,
        "solver_seconds": record.solver_seconds,
        "wall_seconds": record.wall_seconds,
        "acoustic_steps": pick("acoustic_steps"),
        "advection_steps": pick("advection_steps"),
        "neighbour_rebuilds": pick("neighbour_rebuilds"),
        "particle_steps_per_second": pick("particle_steps_per_second"),
    }))
}

const USAGE: &str = "usage: ul-stepping [--fine] [--end-2d SECONDS] [--end-3d SECONDS] \
                     (defaults: 0.1 s in 2D, 0.01 s in 3D)";

/// The run's choices from the command line: `(fine, end time 2D, end time 3D)`; an unknown
/// flag, a missing value or an end time that is not a positive finite number is an error
/// naming it.
fn parse_args(args: &[String]) -> Result<(bool, f64, f64), String> {
    let (mut fine, mut end2d, mut end3d) = (false, 0.1, 0.01);
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        let end = match flag.as_str() {
            "--fine" => {
                fine = true;
                continue;
            }
            "--end-2d" => &mut end2d,
            "--end-3d" => &mut end3d,
            other => {
                return Err(format!(
                    "unknown argument {other:?}: the flags are --fine, --end-2d, --end-3d"
                ))
            }
        };
        let value = rest.next().ok_or_else(|| format!("{flag} needs a value"))?;
        *end = value
            .parse::<f64>()
            .ok()
            .filter(|t| t.is_finite() && *t > 0.0)
            .ok_or_else(|| format!("{flag} must be a positive number of seconds, got {value:?}"))?;
    }
    Ok((fine, end2d, end3d))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{USAGE}");
        return;
    }
    let (fine, end2d, end3d) = parse_args(&args).unwrap_or_else(|message| {
        eprintln!("error: {message}\n{USAGE}");
        std::process::exit(2);
    });
    let mut scenes: Vec<(String, &str, Vec<String>)> = [10, 20, 30]
        .iter()
        .map(|r| {
            (
                format!("2D plate H/dp {r}"),
                "oscillating-plate-2d",
                vec![format!("resolution={r}"), format!("end_time={end2d}")],
            )
        })
        .collect();
    let mut res3d = vec![3];
    if fine {
        res3d.push(5);
    }
    for r in res3d {
        scenes.push((
            format!("3D plate H/dp {r}"),
            "oscillating-plate-3d",
            vec![
                format!("resolution={r}"),
                "mode_m=2".into(),
                "mode_n=2".into(),
                format!("end_time={end3d}"),
            ],
        ));
    }
    let threads = rayon::current_num_threads();
    let mut rows = Vec::new();
    for (name, case, sets) in scenes {
        let mut row = json!({
            "machine": sph_benchmarks::machine(),
            "scene": name,
            "case": case,
            "set": sets,
            "threads": threads,
        });
        for (scheme, extra) in [
            ("dual", &["stepping=dual"][..]),
            (
                "dual_frozen",
                &["stepping=dual", "refresh_kernel_data=false"][..],
            ),
            ("single", &["stepping=single"][..]),
        ] {
            let mut s = sets.clone();
            s.extend(extra.iter().map(|e| e.to_string()));
            eprintln!("{name}: {scheme} …");
            match run(case, &s) {
                Ok(v) => row[scheme] = v,
                Err(e) => {
                    eprintln!("error: {e}");
                    std::process::exit(1);
                }
            }
        }
        rows.push(row);
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("results");
    std::fs::create_dir_all(&dir).expect("create benchmarks/results");
    let path = dir.join("ul-stepping.json");
    let tmp = path.with_extension("json.tmp");
    std::fs::write(
        &tmp,
        serde_json::to_string_pretty(&rows).expect("serialises"),
    )
    .expect("write results");
    std::fs::rename(&tmp, &path).expect("rename results");
    println!("wrote {}", path.display());
}

#[cfg(test)]
mod tests {
    use super::parse_args;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn defaults_flags_and_errors() {
        assert_eq!(parse_args(&[]), Ok((false, 0.1, 0.01)));
        assert_eq!(
            parse_args(&args(&["--end-3d", "0.02", "--fine", "--end-2d", "1"])),
            Ok((true, 1.0, 0.02))
        );
        for (bad, names) in [
            (&["--end-2d", "abc"][..], "--end-2d"),
            (&["--end-3d", "-1"][..], "--end-3d"),
            (&["--end-2d", "inf"][..], "--end-2d"),
            (&["--end-2d"][..], "--end-2d needs a value"),
            (&["--fin"][..], "\"--fin\""),
        ] {
            let e = parse_args(&args(bad)).unwrap_err();
            assert!(e.contains(names), "{bad:?}: {e}");
        }
    }
}
