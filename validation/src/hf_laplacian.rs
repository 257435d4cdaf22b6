//! TL-HF's Laplacian normalised per particle (`validate hf-laplacian`): the paper's constant
//! ζ = 1.07 against each particle's own ζ (`laplacian = normalised`,
//! `sph_tl::hourglass_free::normalised_zeta`) on three closed-form or independent references —
//! homogeneous compression of the punching strip (the analytic force), the plate against the
//! finite-element period, Lamb's breathing sphere in 3D — and the undamped plate that the
//! paper's form inverts.

use crate::mesh_physics::{breathing_period, measure_with};
use crate::store::{load, pct, rel, results_dir, run_or_load, StoredRun};
use serde_json::{json, Value};
use sph_cases::CaseError;
use sph_tl::{HfLaplacian, Shear, TlParams};
use std::fmt::Write as _;

/// The two forms compared, as the key `laplacian` spells them.
const FORMS: [&str; 2] = ["paper", "normalised"];

/// Homogeneous compression to 20 % (the strip as wide as the punches): resolutions.
const COMPRESSION: [u32; 3] = [20, 40, 80];

/// The plate (v_f 0.05, frame clamp, H = 0.02 m, ν = 0.3975: the case's defaults) to 0.6 s.
const PLATE: [u32; 2] = [10, 20];

/// The breathing sphere: particles across the diameter.
const SPHERE: [usize; 3] = [10, 20, 30];

/// The stored breathing-sphere rows.
const SPHERE_FILE: &str = "hf-laplacian-sphere.json";

fn compression_id(form: &str, res: u32) -> String {
    format!("hfl-compression-{form}-r{res}")
}

fn compression_set(form: &str, res: u32) -> Vec<String> {
    vec![
        "punch_width=0.027".into(),
        "compression=0.2".into(),
        format!("resolution={res}"),
        format!("laplacian={form}"),
    ]
}

fn plate_id(form: &str, res: u32) -> String {
    format!("hfl-plate-{form}-r{res}")
}

fn plate_set(form: &str, res: u32) -> Vec<String> {
    vec![
        "end_time=0.6".into(),
        format!("resolution={res}"),
        format!("laplacian={form}"),
    ]
}

fn undamped_id(form: &str) -> String {
    format!("hfl-plate-undamped-{form}")
}

fn undamped_set(form: &str) -> Vec<String> {
    vec![
        "end_time=0.5".into(),
        "damping=false".into(),
        format!("laplacian={form}"),
    ]
}

fn laplacian(form: &str) -> HfLaplacian {
    HfLaplacian::from_name(form).expect("a form's name")
}

/// Which runs `validate hf-laplacian` makes.
#[derive(Clone, Copy, Debug)]
pub struct Selection {
    /// Re-run stored runs.
    pub force: bool,
}

/// Makes (or loads) every run.
///
/// # Errors
/// A run that cannot be made.
pub fn run_all(sel: Selection) -> Result<(), CaseError> {
    for form in FORMS {
        for res in COMPRESSION {
            let set = compression_set(form, res);
            run_or_load(
                &compression_id(form, res),
                "punching-strip-2d",
                "tl-hf",
                &set,
                sel.force,
            )?;
        }
        for res in PLATE {
            let set = plate_set(form, res);
            run_or_load(
                &plate_id(form, res),
                "oscillating-plate-2d",
                "tl-hf",
                &set,
                sel.force,
            )?;
        }
        run_or_load(
            &undamped_id(form),
            "oscillating-plate-2d",
            "tl-hf",
            &undamped_set(form),
            sel.force,
        )?;
    }
    let path = results_dir().join(SPHERE_FILE);
    if path.is_file() && !sel.force {
        return Ok(());
    }
    let mut rows = Vec::new();
    for form in FORMS {
        let params = TlParams {
            hf_laplacian: laplacian(form),
            ..TlParams::default()
        };
        for across in SPHERE {
            let mut row = measure_with("primitive", across, Shear::hourglass_free(), params)
                .map_err(CaseError::Config)?;
            row["laplacian"] = json!(form);
            println!(
                "hf-laplacian: breathing sphere {form} at {across} across: period error {:+.3} %",
                100.0 * (row["period"].as_f64().unwrap_or(f64::NAN) / breathing_period() - 1.0)
            );
            rows.push(row);
        }
    }
    let text = serde_json::to_string_pretty(&json!({
        "command": "cargo run --release -p sph-validation --bin validate -- hf-laplacian",
        "rows": rows,
    }))
    .map_err(|e| CaseError::Config(e.to_string()))?;
    let io = |e: std::io::Error| CaseError::Io {
        path: path.display().to_string(),
        source: e,
    };
    std::fs::create_dir_all(results_dir()).map_err(io)?;
    std::fs::write(&path, text).map_err(io)?;
    Ok(())
}

fn num(r: &Option<StoredRun>, key: &str) -> Option<f64> {
    r.as_ref().and_then(|r| r.num(key))
}

fn status(r: &Option<StoredRun>) -> String {
    match r.as_ref().and_then(|r| r.summary.get("status")?.as_str()) {
        Some("completed") => "completed".into(),
        Some(s) => s.to_string(),
        None => "–".into(),
    }
}

/// The section of docs/validation.md, from the stored runs (nothing if none is stored).
///
/// # Errors
/// None today (the signature of the other reports).
pub fn report(md: &mut String) -> Result<(), String> {
    let compression: Vec<[Option<StoredRun>; 2]> = COMPRESSION
        .iter()
        .map(|&r| FORMS.map(|f| load(&compression_id(f, r))))
        .collect();
    let plate: Vec<[Option<StoredRun>; 2]> = PLATE
        .iter()
        .map(|&r| FORMS.map(|f| load(&plate_id(f, r))))
        .collect();
    let undamped = FORMS.map(|f| load(&undamped_id(f)));
    let sphere: Option<Value> = std::fs::read_to_string(results_dir().join(SPHERE_FILE))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let any = compression
        .iter()
        .chain(&plate)
        .flatten()
        .any(Option::is_some)
        || undamped.iter().any(Option::is_some)
        || sphere.is_some();
    if !any {
        return Ok(());
    }
    writeln!(md, "## TL-HF: the Laplacian normalised per particle\n").unwrap();
    writeln!(
        md,
        "TL-HF's shear is `ζ G ∇²x` (TL eq 27) with one ζ = 1.07 for every particle, and eq 28 \
         subtracts the same ζ's trace term so that the two cancel at rest. Applied to a \
         quadratic field, the discrete Laplacian returns `H : M_i` with `M_i = −Σ_j X_ij ⊗ \
         X_ij V_j W′/r⁰` (the identity in the continuum), so the ζ that makes it exact is \
         `d / tr M_i`: 1.033 (2D) and 1.006 (3D) for a particle with a full lattice \
         neighbourhood at h = 1.15 dp, 1.58 (2D) and 1.41 (3D) in the outer layer of a flat \
         face (`cargo test -p sph-tl --test normalised_laplacian -- --nocapture`). The paper's \
         1.07 is therefore 3.6 % (2D) / 6.4 % (3D) too stiff in the bulk and a quarter to a \
         third too soft in the surface layer, at every resolution: the TL-HF errors that did \
         not shrink with resolution. `laplacian = normalised` (key of every TL-HF case and \
         `[numerics]`) gives each particle its own `ζ_i` in both eq 27 (pairs carry `ζ_i g_i + \
         ζ_j g_j`) and eq 28: the cancellation at rest, the antisymmetric pair forces (momentum) \
         and the cost per pair are those of the paper's form; `ζ_i` is computed once from the \
         reference configuration. The paper's form stays the default (it reproduces the TL \
         paper's tables). Runs: `validate hf-laplacian`.\n"
    )
    .unwrap();
    if compression.iter().flatten().any(Option::is_some) {
        writeln!(
            md,
            "**Homogeneous compression** to 20 % (`punching-strip-2d` with the strip as wide as \
             the punches, neo-Hookean ν 0.45): the punch force against the analytic homogeneous \
             force (`theory_homogeneous_force`).\n\n\
             | resolution (particles across) | paper ζ: force error | normalised: force error |\n\
             |---|---|---|"
        )
        .unwrap();
        for (res, runs) in COMPRESSION.iter().zip(&compression) {
            let err = |r: &Option<StoredRun>| {
                pct(rel(
                    num(r, "reaction_force"),
                    num(r, "theory_homogeneous_force"),
                ))
            };
            writeln!(md, "| {res} | {} | {} |", err(&runs[0]), err(&runs[1])).unwrap();
        }
        writeln!(md).unwrap();
    }
    if plate.iter().flatten().any(Option::is_some) {
        let fe = crate::fem_plate::period("d2-split", "frame", 0.02, 0.3975);
        writeln!(
            md,
            "**The plate** (`oscillating-plate-2d`, v_f = 0.05, frame clamp, to 0.6 s) against \
             the finite-element period of its own law (d = 2 split, {} s, section \"TL-SPH: the \
             clamp of the oscillating plate\"):\n\n\
             | H/dp | paper ζ: period (s) | error vs FE | normalised: period (s) | error vs FE |\n\
             |---|---|---|---|---|",
            crate::store::fmt_opt(fe, 5)
        )
        .unwrap();
        for (res, runs) in PLATE.iter().zip(&plate) {
            let cells = |r: &Option<StoredRun>| {
                let p = num(r, "period");
                (crate::store::fmt_opt(p, 5), pct(rel(p, fe)))
            };
            let (a, b) = (cells(&runs[0]), cells(&runs[1]));
            writeln!(md, "| {res} | {} | {} | {} | {} |", a.0, a.1, b.0, b.1).unwrap();
        }
        writeln!(md).unwrap();
    }
    if undamped.iter().any(Option::is_some) {
        writeln!(
            md,
            "**Without the Kelvin–Voigt damping** (the plate at its default resolution, \
             `damping = false`, to 0.5 s): paper ζ: {}; normalised: {} (period error vs FE \
             {}).\n",
            status(&undamped[0]),
            status(&undamped[1]),
            pct(rel(
                num(&undamped[1], "period"),
                crate::fem_plate::period("d2-split", "frame", 0.02, 0.3975)
            )),
        )
        .unwrap();
    }
    if let Some(rows) = sphere.as_ref().and_then(|s| s["rows"].as_array()) {
        writeln!(
            md,
            "**Lamb's breathing sphere** (3D, the exact ball on the lattice, section \"Physics \
             through a mesh\"): period error against the closed form.\n\n\
             | particles across | paper ζ | normalised |\n|---|---|---|"
        )
        .unwrap();
        let theory = breathing_period();
        for across in SPHERE {
            let cell = |form: &str| {
                rows.iter()
                    .find(|r| r["across"] == across && r["laplacian"] == form)
                    .and_then(|r| r["period"].as_f64())
                    .map_or("–".into(), |p| {
                        format!("{:+.2} %", 100.0 * (p / theory - 1.0))
                    })
            };
            writeln!(
                md,
                "| {across} | {} | {} |",
                cell("paper"),
                cell("normalised")
            )
            .unwrap();
        }
        writeln!(md).unwrap();
    }
    writeln!(
        md,
        "The pressurised ring (`examples/scenes/pressurised_ring.toml`, Lamé's thick cylinder, \
         mid-wall radial displacement; `sph converge examples/scenes/pressurised_ring.toml \
         --method tl-hf [--set numerics.laplacian=normalised] --quantity \
         probe:mid:displacement.x:final --start 1e-3 --ratio 2 --levels 3 --tolerance 0.1%`): \
         the paper's ζ gives +2.27 / +0.24 / −1.28 % at dp = 1e-3 / 5e-4 / 2.5e-4 m, drifting \
         through the answer (observed order 0.42, not in the asymptotic range); the normalised Laplacian \
         −2.52 / −1.17 / −0.72 %, monotone (order 1.59, limit −0.50 % ± 0.68 %).\n"
    )
    .unwrap();
    Ok(())
}
