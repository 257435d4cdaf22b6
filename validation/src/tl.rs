//! TL validation: the oscillating plate against TL paper Tables 1 and 2 and theory, with the
//! clamp of the base measured both ways and a convergence series, the share of the 2D
//! deviatoric split in the HF-vs-TL difference, the disorder indicator at large amplitude with a
//! Ganzenmüller α sweep, and the twisting column at extreme Ω0.

mod report;
mod table2;

pub use report::report;

pub use table2::TABLE2;
use table2::{table2_section, thin_id, thin_set, TABLE2_CONVERGENCE, TABLE2_FINE_RES, TABLE2_RES};

use crate::plot::{line_plot, Series};
use crate::store::{cost_estimate, fmt_opt, load, pct, rel, run_or_load, status, StoredRun};
use sph_cases::CaseError;
use std::fmt::Write as _;
use std::path::Path;

/// TL paper Table 1 (L = 0.2, H = 0.02, TL-SPH-HF at H/dp = 40): (v_f, ν, T).
pub const TABLE1: &[(f64, f64, f64)] = &[
    (0.01, 0.22, 0.29439),
    (0.05, 0.22, 0.29428),
    (0.1, 0.22, 0.29373),
    (0.15, 0.22, 0.29374),
    (0.01, 0.30, 0.28197),
    (0.05, 0.30, 0.28166),
    (0.1, 0.30, 0.28096),
    (0.15, 0.30, 0.28126),
    (0.01, 0.40, 0.26534),
    (0.05, 0.40, 0.26473),
    (0.1, 0.40, 0.26382),
    (0.15, 0.40, 0.26656),
];

/// SPHinXsys's own 2D beam (`test_2d_oscillating_beam`, plain TL with B, h = 1.3 dp,
/// H/dp = 10, ν = 0.3975, v_f = 0.05, frame clamp): the mean period between the downward zero
/// crossings of its regression data (`BeamObserver_Position_ensemble_averaged_mean_variance.xml`,
/// samples every 0.01 s, linear interpolation): 0.27451, 0.27457, 0.27461 s.
pub const SPHINXSYS_BEAM_PERIOD: f64 = 0.27456;
/// Its largest |y| of the tip (same data).
pub const SPHINXSYS_BEAM_AMPLITUDE: f64 = 0.11298;

const METHODS: [&str; 3] = ["tl-hf", "tl", "tl-gm"];
const NUS: [f64; 3] = [0.22, 0.30, 0.40];
const VFS: [f64; 2] = [0.01, 0.05];
/// The clamps of the base (`clamp` key of the plate).
pub const CLAMPS: [&str; 2] = ["frame", "solid"];
/// The Ganzenmüller α of the sweep (TL paper: GM needs case-dependent tuning).
const GM_ALPHAS: [f64; 5] = [0.01, 0.03, 0.1, 0.2, 0.3];
fn paper_period(vf: f64, nu: f64) -> Option<f64> {
    TABLE1
        .iter()
        .find(|r| (r.0 - vf).abs() < 1e-12 && (r.1 - nu).abs() < 1e-12)
        .map(|r| r.2)
}

/// Stored id of a plate run. Runs made before the clamp key existed used the solid clamp and
/// keep their ids; frame runs add `-frame`.
fn plate_id(method: &str, nu: f64, vf: f64, res: u32, clamp: &str) -> String {
    let base = format!("tl-plate-{method}-nu{nu}-vf{vf}-r{res}");
    if clamp == "solid" {
        base
    } else {
        format!("{base}-{clamp}")
    }
}

fn plate_set(nu: f64, vf: f64, res: u32, clamp: &str) -> Vec<String> {
    vec![
        format!("nu={nu}"),
        format!("vf={vf}"),
        format!("resolution={res}"),
        "end_time=1.0".into(),
        format!("clamp={clamp}"),
    ]
}

/// SPHinXsys's beam set-up: plain TL, SVK, h = 1.3 dp, ν = 0.3975, v_f = 0.05, H/dp = 10.
fn sphinxsys_id(clamp: &str) -> String {
    format!("tl-sphinxsys-beam-{clamp}")
}

fn sphinxsys_set(clamp: &str) -> Vec<String> {
    vec![
        "nu=0.3975".into(),
        "vf=0.05".into(),
        "resolution=10".into(),
        "h_over_dp=1.3".into(),
        "end_time=1.0".into(),
        format!("clamp={clamp}"),
    ]
}

/// TL-HF with the isochoric split on the plane-strain embedding (`deviator = embedded-3d`,
/// d = 3): plane-strain Hooke at small strain, the law TL's SVK agrees with.
fn embedded_id(nu: f64, res: u32) -> String {
    format!("tl-plate-tl-hf-nu{nu}-vf0.05-r{res}-frame-embedded3d")
}

fn embedded_set(nu: f64, res: u32) -> Vec<String> {
    let mut s = plate_set(nu, 0.05, res, "frame");
    s.push("deviator=embedded-3d".into());
    s
}

fn disorder_id(method: &str, clamp: &str) -> String {
    if clamp == "solid" {
        format!("tl-disorder-{method}-vf0.15")
    } else {
        format!("tl-disorder-{method}-vf0.15-{clamp}")
    }
}

fn disorder_set(clamp: &str) -> Vec<String> {
    vec![
        "nu=0.3975".into(),
        "vf=0.15".into(),
        "resolution=10".into(),
        "end_time=1.0".into(),
        format!("clamp={clamp}"),
    ]
}

fn gm_id(alpha: f64) -> String {
    format!("tl-gm-alpha{alpha}-vf0.15-frame")
}

fn gm_set(alpha: f64) -> Vec<String> {
    let mut s = disorder_set("frame");
    s.push(format!("alpha={alpha}"));
    s
}

const TWISTS: [(f64, f64); 3] = [(105.0, 0.499), (300.0, 0.49), (400.0, 0.49)];

fn twist_id(method: &str, omega: f64) -> String {
    format!("tl-twist-{method}-omega{omega}")
}

fn twist_set(omega: f64, nu: f64) -> Vec<String> {
    vec![
        format!("omega0={omega}"),
        format!("nu={nu}"),
        "resolution=10".into(),
        "end_time=0.3".into(),
    ]
}

/// Which runs to do.
#[derive(Clone, Copy, Debug)]
pub struct Selection {
    /// Re-run even when stored.
    pub force: bool,
    /// Include H/dp = 20 runs (minutes each).
    pub medium: bool,
    /// Include the H/dp = 40 runs: Table 1 with TL-HF, every row (half an hour or more each on
    /// 2 cores).
    pub fine: bool,
    /// Include Table 2 (H = 0.01, TL-HF at H/dp = 20, 11 rows).
    pub table2: bool,
}

/// Runs (or loads) every TL validation run of the selection, cheapest first.
pub fn run_all(sel: Selection) -> Result<(), CaseError> {
    let f = sel.force;
    let plate = |m: &str, nu: f64, vf: f64, res: u32, clamp: &str| {
        run_or_load(
            &plate_id(m, nu, vf, res, clamp),
            "oscillating-plate-2d",
            m,
            &plate_set(nu, vf, res, clamp),
            f,
        )
        .map(|_| ())
    };
    // The clamp against SPHinXsys's own beam.
    for clamp in CLAMPS {
        run_or_load(
            &sphinxsys_id(clamp),
            "oscillating-plate-2d",
            "tl",
            &sphinxsys_set(clamp),
            f,
        )?;
    }
    let mut resolutions = vec![10];
    if sel.medium {
        resolutions.push(20);
    }
    for &res in &resolutions {
        // Table 1's rows with TL-HF, frame clamp; both clamps at ν = 0.4, v_f = 0.05.
        for &(vf, nu, _) in TABLE1 {
            plate("tl-hf", nu, vf, res, "frame")?;
        }
        plate("tl-hf", 0.4, 0.05, res, "solid")?;
        // The three methods on the ν × v_f grid.
        for nu in NUS {
            for vf in VFS {
                for m in ["tl", "tl-gm"] {
                    plate(m, nu, vf, res, "frame")?;
                }
            }
        }
        for nu in NUS {
            run_or_load(
                &embedded_id(nu, res),
                "oscillating-plate-2d",
                "tl-hf",
                &embedded_set(nu, res),
                f,
            )?;
        }
    }
    for m in METHODS {
        run_or_load(
            &disorder_id(m, "frame"),
            "oscillating-plate-2d",
            m,
            &disorder_set("frame"),
            f,
        )?;
    }
    // Plain TL with the linear elastic (SVK) law collapses under the compression of this case;
    // the same run with the neo-Hookean law separates the material's failure from the method's.
    let mut nh = disorder_set("frame");
    nh.push("material=neo-hookean".into());
    run_or_load(
        &disorder_id("tl-neo-hookean", "frame"),
        "oscillating-plate-2d",
        "tl",
        &nh,
        f,
    )?;
    for alpha in GM_ALPHAS {
        run_or_load(
            &gm_id(alpha),
            "oscillating-plate-2d",
            "tl-gm",
            &gm_set(alpha),
            f,
        )?;
    }
    for (omega, nu) in TWISTS {
        for m in ["tl-hf", "tl"] {
            run_or_load(
                &twist_id(m, omega),
                "twisting-column-3d",
                m,
                &twist_set(omega, nu),
                f,
            )?;
        }
    }
    if sel.table2 {
        let (nu, vf, res) = TABLE2_CONVERGENCE;
        for r in [res[0]].into_iter().chain(sel.fine.then_some(res[2])) {
            run_or_load(
                &thin_id(nu, vf, r),
                "oscillating-plate-2d",
                "tl-hf",
                &thin_set(nu, vf, r),
                f,
            )?;
        }
        for &(vf, nu, paper) in TABLE2 {
            if paper.is_some() {
                let fine = sel.fine.then_some(TABLE2_FINE_RES);
                for res in std::iter::once(TABLE2_RES).chain(fine) {
                    run_or_load(
                        &thin_id(nu, vf, res),
                        "oscillating-plate-2d",
                        "tl-hf",
                        &thin_set(nu, vf, res),
                        f,
                    )?;
                }
            }
        }
    }
    if sel.fine {
        // The clamp comparison first, then the rest of Table 1.
        for clamp in CLAMPS {
            plate("tl-hf", 0.4, 0.05, 40, clamp)?;
        }
        for &(vf, nu, _) in TABLE1 {
            plate("tl-hf", nu, vf, 40, "frame")?;
        }
    }
    Ok(())
}

fn period(r: &Option<StoredRun>) -> Option<f64> {
    r.as_ref().and_then(|r| r.num("period"))
}

/// The period, or why there is none (`–` when not run).
fn period_cell(r: &Option<StoredRun>) -> String {
    match r {
        None => "–".into(),
        Some(run) => match run.num("period") {
            Some(t) => format!("{t:.5}"),
            None if status(run) != "completed" => "stopped".into(),
            None => "no period".into(),
        },
    }
}
