//! `sph converge` on a user-style scene file: the ladders of docs/tradeoffs.md's "Error
//! estimates" that a user would run on `examples/scenes/pressurised_ring.toml`, with the
//! quantity's closed form beside the estimate.
//!
//! `validate tradeoff` (not `--quick`) runs each ladder through the `sph` binary (its levels in
//! `target/converge-examples/`, reused while their commands are unchanged) and stores the
//! report under `validation/results/tradeoff/converge-<key>.json`; the report section reads
//! the stored reports only.

use std::fmt::Write as _;
use std::path::PathBuf;

/// One ladder on an example scene.
pub(super) struct ExampleLadder {
    /// The stored report's name: `converge-<key>.json`.
    pub key: &'static str,
    /// The scene file, relative to the workspace root.
    pub file: &'static str,
    /// The method.
    pub method: &'static str,
    /// The quantity (`sph converge --quantity`).
    pub quantity: &'static str,
    /// `--tolerance`.
    pub tolerance: &'static str,
    /// `--start`, `--ratio`, `--levels`.
    pub start: &'static str,
    pub ratio: &'static str,
    pub levels: &'static str,
    /// The quantity's exact value and where it comes from.
    pub reference: (f64, &'static str),
}

/// Lamé's plane-strain radial displacement at the ring's mid-wall radius (the example's
/// parameters: a = 10 mm, b = 20 mm, p = 1 kPa, E = 1 MPa, ν = 0.3, r = 15 mm):
/// `u(r) = p a²/(b² − a²) ((1 − 2ν)(1 + ν) r + (1 + ν) b²/r)/E`.
fn lame_mid_wall() -> f64 {
    let (a, b, p, e, nu, r): (f64, f64, f64, f64, f64, f64) = (0.01, 0.02, 1e3, 1e6, 0.3, 0.015);
    p * a * a / (b * b - a * a) * ((1.0 - 2.0 * nu) * (1.0 + nu) * r + (1.0 + nu) * b * b / r) / e
}

/// The ladders: the ring's mid-wall displacement with the example's own method (TL-HF) and
/// with TL.
pub(super) fn ladders() -> Vec<ExampleLadder> {
    let ring = |method| ExampleLadder {
        key: if method == "tl" {
            "pressurised-ring-tl"
        } else {
            "pressurised-ring-tl-hf"
        },
        file: "examples/scenes/pressurised_ring.toml",
        method,
        quantity: "probe:mid:displacement.x:final",
        tolerance: "1%",
        start: "2e-3",
        ratio: "2",
        levels: "6",
        reference: (lame_mid_wall(), "Lamé"),
    };
    vec![ring("tl-hf"), ring("tl")]
}

impl ExampleLadder {
    fn args(&self) -> Vec<String> {
        [
            "converge",
            self.file,
            "--method",
            self.method,
            "--quantity",
            self.quantity,
            "--tolerance",
            self.tolerance,
            "--start",
            self.start,
            "--ratio",
            self.ratio,
            "--levels",
            self.levels,
            "--threads",
            "1",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    }

    /// The command as a user types it (from the workspace root).
    fn command(&self) -> String {
        format!("sph {}", self.args().join(" "))
    }

    fn stored_path(&self) -> PathBuf {
        crate::cost::dir().join(format!("converge-{}.json", self.key))
    }

    /// The stored report, if made by this ladder's command.
    fn stored(&self) -> Option<serde_json::Value> {
        let text = std::fs::read_to_string(self.stored_path()).ok()?;
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        (v["command"] == self.command().as_str()).then_some(v)
    }

    /// Runs the ladder unless its report is stored (or `force`), and stores the report.
    fn run(&self, force: bool) -> Result<(), String> {
        if !force && self.stored().is_some() {
            return Ok(());
        }
        if crate::store::plan_only() {
            println!("converge-{}\t{}", self.key, self.command());
            return Ok(());
        }
        if crate::store::filtered_out(&format!("converge-{}", self.key)) {
            return Ok(());
        }
        let root = crate::workspace_root();
        let store = root.join("target/converge-examples").join(self.key);
        let report = store.join("report.json");
        let mut args = self.args();
        args.extend([
            "--store".into(),
            store.display().to_string(),
            "--report".into(),
            report.display().to_string(),
        ]);
        eprintln!("running converge-{}: {}", self.key, self.command());
        let status = std::process::Command::new(crate::cost::sph_binary()?)
            .args(&args)
            .current_dir(&root)
            .status()
            .map_err(|e| format!("sph converge: {e}"))?;
        // 0: met; 1: not met (the report is written either way).
        if !matches!(status.code(), Some(0 | 1)) {
            return Err(format!("{}: {status}", self.command()));
        }
        let text =
            std::fs::read_to_string(&report).map_err(|e| format!("{}: {e}", report.display()))?;
        let mut v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", report.display()))?;
        v["command"] = self.command().into();
        std::fs::create_dir_all(crate::cost::dir()).map_err(|e| e.to_string())?;
        std::fs::write(
            self.stored_path(),
            serde_json::to_string_pretty(&v).expect("serialises") + "\n",
        )
        .map_err(|e| format!("{}: {e}", self.stored_path().display()))
    }
}

/// Runs every example ladder (see the module documentation).
pub(super) fn run_all(force: bool) -> Result<(), String> {
    for l in ladders() {
        l.run(force)?;
    }
    Ok(())
}

fn pct(x: f64) -> String {
    format!("{:+.2} %", 100.0 * x)
}

/// The subsection of "Error estimates"; false if no ladder is stored.
pub(super) fn section(md: &mut String) -> bool {
    let stored: Vec<(ExampleLadder, serde_json::Value)> = ladders()
        .into_iter()
        .filter_map(|l| l.stored().map(|v| (l, v)))
        .collect();
    if stored.is_empty() {
        return false;
    }
    writeln!(
        md,
        "### On a user's scene file\n\n`sph converge` run as a user would on \
         `examples/scenes/pressurised_ring.toml` (a thick ring under internal pressure, relaxed \
         to equilibrium; the quantity is the radial displacement at the mid-wall probe, whose \
         closed form is Lamé's), 1 thread, the levels halving the file's `dp` parameter. \
         *CPU s* is each level's CPU time; *vs {}* the level's distance to the closed form, \
         which the ladder does not know.\n",
        stored[0].0.reference.1
    )
    .unwrap();
    for (l, v) in &stored {
        let q = &v["quantities"][l.quantity];
        let exact = l.reference.0;
        writeln!(
            md,
            "`{}`\n\n| dp (m) | value | CPU s | vs {} |\n|---|---|---|---|",
            l.command(),
            l.reference.1
        )
        .unwrap();
        let runs = q["runs"].as_array().cloned().unwrap_or_default();
        let mut total = 0.0;
        for r in &runs {
            let (h, value, cpu) = (
                r["resolution"].as_f64().unwrap_or(f64::NAN),
                r["value"].as_f64().unwrap_or(f64::NAN),
                r["cpu_seconds"].as_f64().unwrap_or(f64::NAN),
            );
            total += cpu;
            writeln!(
                md,
                "| {h} | {value:.5e} | {cpu:.2} | {} |",
                pct(value / exact - 1.0)
            )
            .unwrap();
        }
        let value = q["value"].as_f64().unwrap_or(f64::NAN);
        let estimate = q["error_estimate"].as_f64().unwrap_or(f64::NAN);
        let finest = runs
            .last()
            .and_then(|r| r["value"].as_f64())
            .unwrap_or(f64::NAN);
        writeln!(
            md,
            "\n{}: estimated error of the finest level ±{:.2} % ({}{}); extrapolated value \
             {value:.5e} ({} against {}); the finest level is {} from the extrapolated value \
             and {} from {}. The ladder took {total:.1} CPU s{}.\n",
            l.method.to_uppercase(),
            100.0 * estimate,
            q["order"]
                .as_f64()
                .map_or("no order, ".to_string(), |p| format!("order {p:.2}, ")),
            if q["asymptotic"].as_bool() == Some(true) {
                "verified asymptotic".to_string()
            } else {
                format!(
                    "not asymptotic: {}",
                    q["warning"].as_str().unwrap_or("no reason given")
                )
            },
            pct(value / exact - 1.0),
            l.reference.1,
            pct(finest / value - 1.0),
            pct(finest / exact - 1.0),
            l.reference.1,
            if q["met"].as_bool() == Some(true) {
                format!("; {} met", l.tolerance)
            } else {
                format!(
                    "; {} not met ({})",
                    l.tolerance,
                    v["stopped"].as_str().unwrap_or("stopped")
                )
            },
        )
        .unwrap();
        let limit_bias = value / exact - 1.0;
        if limit_bias.abs() > estimate {
            writeln!(
                md,
                "The estimate covers the discretisation error only: {}'s limit on this scene lies \
                 {} from {}, more than the estimate, a bias of the method here that no ladder of \
                 its own runs can see (compare methods, or a case with a reference, to find one).\n",
                l.method.to_uppercase(),
                pct(limit_bias),
                l.reference.1
            )
            .unwrap();
        }
    }
    true
}

#[cfg(test)]
mod tests {
    /// The closed form the section compares with (the value the scene file's header states the
    /// formula for, at r = 15 mm).
    #[test]
    fn the_mid_wall_displacement_is_lames() {
        assert!((super::lame_mid_wall() - 1.415_555_6e-5).abs() < 1e-12);
    }
}
