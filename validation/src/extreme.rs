//! Validation of the extreme TL scenes (TL paper §4.2, §4.3, §4.6): the punching strip, the
//! pulling strip and cylinder, and the stent — against the plane-strain closed form
//! (homogeneous compression and tension), an independent finite-element reference
//! (`validation/fem/`, scikit-fem) and the paper's qualitative findings.

mod fem;
mod report;

pub use report::report;

use crate::frames::frame_projected;
use crate::plot::{line_plot, particle_frames, Frame, Series};
use crate::store::{fmt_opt, load, pct, rel, run_or_load, run_or_load_then, status, StoredRun};
use serde_json::{Map, Value};
use sph_cases::CaseError;
use std::fmt::Write as _;
use std::path::Path;

/// The TL methods, the paper's first.
pub const METHODS: [&str; 3] = ["tl-hf", "tl", "tl-gm"];
/// Resolutions (H/dp) of the homogeneous compression check.
pub const HOMOG_RES: [u32; 4] = [20, 30, 45, 60];
/// Compressions of the homogeneous check.
pub const HOMOG_C: [f64; 2] = [0.2, 0.3];
/// Resolutions (L/dp) of the roller-grip tension check (stretch 2).
pub const ROLLER_RES: [u32; 3] = [20, 30, 45];
/// Resolutions (H/dp) of the punching strip with the paper's punches.
pub const PUNCH_RES: [u32; 3] = [30, 45, 60];
/// Resolutions (L/dp) and stretches of the clamped pulling strip against the FE reference.
pub const PULL_RES: [u32; 3] = [20, 30, 45];
/// Stretches compared with the FE reference.
pub const PULL_STRETCH: [f64; 3] = [1.5, 2.0, 3.0];
/// The paper's large stretches of the strip ("500 %", "1000 %": 12 and 22 mm from 2 mm).
pub const STRIP_LARGE: [f64; 2] = [6.0, 11.0];
/// The paper's large stretches of the cylinder ("240 %", "480 %").
pub const CYLINDER_LARGE: [f64; 2] = [3.4, 5.8];
/// Wide punches (3 × the strip width) for the homogeneous check.
const WIDE_PUNCH: &str = "punch_width=0.027";

fn homog_id(m: &str, c: f64, r: u32) -> String {
    format!("ext-homog-{m}-c{c}-r{r}")
}
/// The TL-HF homogeneous compression with another ζ (eq 27–28's correction).
fn homog_zeta_id(zeta: f64, r: u32) -> String {
    format!("ext-homog-tl-hf-c0.2-r{r}-zeta{zeta}")
}
/// The ζ of the HF study beside the default 1.07, and its resolutions.
const HOMOG_ZETA: [f64; 2] = [1.0, 1.04];
const HOMOG_ZETA_RES: [u32; 2] = [30, 60];
fn roller_id(m: &str, r: u32) -> String {
    format!("ext-roller-{m}-r{r}")
}
fn punch_id(m: &str, r: u32) -> String {
    format!("ext-punch-{m}-r{r}")
}
fn punch_sym_id(m: &str, c: f64, r: u32) -> String {
    format!("ext-punchsym-{m}-c{c}-r{r}")
}
/// The centre-held punching to 50 % with the punch edges rounded by r = 50 µm (the FE
/// reference's first radius, now a check: about dp/2 at H/dp = 30).
fn punch_round_id(m: &str, r: u32) -> String {
    format!("ext-punchround-{m}-r{r}")
}
/// The centre-held punching to 50 % with the punch edges rounded as the FE reference's:
/// r = 0.15 mm, half the punch thickness.
fn punch_fe_corner_id(m: &str, r: u32) -> String {
    format!("ext-punchround150-{m}-r{r}")
}
/// The FE reference's punch corner radius (validation/fem/punching.py, `CORNER_RADIUS`).
const FE_CORNER_RADIUS: &str = "punch_corner_radius=1.5e-4";
/// The smaller radius run beside it (validation/fem/punching.py, `SMALL_CORNER_RADIUS`).
const SMALL_CORNER_RADIUS: &str = "punch_corner_radius=5e-5";
fn pull_fem_id(m: &str, s: f64, r: u32) -> String {
    format!("ext-pullfem-{m}-s{s}-r{r}")
}
fn pull_large_id(m: &str, s: f64) -> String {
    format!("ext-pull-{m}-s{s}")
}
fn cylinder_id(m: &str, s: f64) -> String {
    format!("ext-cyl-{m}-s{s}")
}
fn stent_id(loading: &str) -> String {
    format!("ext-stent-{loading}")
}
/// The punching runs of the quasi-static check at the halved speeds (m/s, run id); the 2 m/s
/// run is the centre-held punching run at 50 %.
const QUASI_PUNCH_SLOWER: [(f64, &str); 3] = [
    (1.0, "ext-quasi-punch-v1"),
    (0.5, "ext-quasi-punch-v0.5"),
    (0.25, "ext-quasi-punch-v0.25"),
];
/// The same at 30 % compression, where the centre-held strip has one (mirror-symmetric)
/// equilibrium; the 2 m/s run is the centre-held punching run at 30 %.
const QUASI_PUNCH30_SLOWER: [(f64, &str); 3] = [
    (1.0, "ext-quasi-punch30-v1"),
    (0.5, "ext-quasi-punch30-v0.5"),
    (0.25, "ext-quasi-punch30-v0.25"),
];
const QUASI_PULL: &str = "ext-quasi-pull-v1";

/// Which runs to do.
#[derive(Clone, Copy, Debug)]
pub struct Selection {
    /// Re-run even when stored.
    pub force: bool,
    /// Skip the long runs (strip to 1000 %, cylinder, stent; tens of minutes each).
    pub short: bool,
}

/// A picture callback for [`run_or_load_then`] that draws the frames nearest to `times`,
/// projected on `axes` and filtered by `keep`, coloured by von Mises stress.
#[allow(clippy::too_many_arguments)]
fn pictures<'a>(
    png: std::path::PathBuf,
    title: String,
    times: &'a dyn Fn(&sph_output::FileContents) -> Vec<(f64, String)>,
    axes: (usize, usize),
    keep: &'a (dyn Fn([f64; 3]) -> bool + Sync),
    columns: usize,
    dp: f64,
) -> impl Fn(&sph_output::FileContents) -> Result<Map<String, Value>, String> + 'a {
    move |c| {
        let frames: Vec<Frame> = times(c)
            .into_iter()
            .filter_map(|(t, label)| frame_projected(c, t, &label, axes, "von_mises", keep))
            .collect();
        let vmax = crate::frames::p99_value(&frames);
        particle_frames(&png, &title, &frames, columns, vmax, dp)?;
        Ok(Map::new())
    }
}

/// The snapshot times at which the top punch had travelled `fractions` of its final travel,
/// from the file's `/series/punch_top`, labelled by the compression.
fn compression_times(c: &sph_output::FileContents, fractions: &[f64]) -> Vec<(f64, String)> {
    let Some(s) = c.series.get("punch_top") else {
        return Vec::new();
    };
    let d = &s.columns["displacement"];
    let last = d.last().copied().unwrap_or(0.0);
    let h = 3e-3;
    fractions
        .iter()
        .map(|&f| {
            let k = d.iter().position(|&x| x >= f * last - 1e-15).unwrap_or(0);
            (s.times[k], format!("compression {:.0} %", 200.0 * d[k] / h))
        })
        .collect()
}

/// Runs (or loads) every run of the selection, cheapest first.
pub fn run_all(sel: Selection, fig_dir: &Path) -> Result<(), CaseError> {
    let f = sel.force;
    let set = |v: &[String]| v.to_vec();
    for m in METHODS {
        for c in HOMOG_C {
            for r in HOMOG_RES {
                run_or_load(
                    &homog_id(m, c, r),
                    "punching-strip-2d",
                    m,
                    &set(&[
                        WIDE_PUNCH.into(),
                        format!("compression={c}"),
                        format!("resolution={r}"),
                    ]),
                    f,
                )?;
            }
        }
        if m == "tl-hf" {
            for zeta in HOMOG_ZETA {
                for r in HOMOG_ZETA_RES {
                    run_or_load(
                        &homog_zeta_id(zeta, r),
                        "punching-strip-2d",
                        m,
                        &set(&[
                            WIDE_PUNCH.into(),
                            "compression=0.2".into(),
                            format!("resolution={r}"),
                            format!("zeta={zeta}"),
                        ]),
                        f,
                    )?;
                }
            }
        }
        for r in ROLLER_RES {
            run_or_load(
                &roller_id(m, r),
                "pulling-strip-2d",
                m,
                &set(&[
                    "grip=roller".into(),
                    "stretch=2".into(),
                    format!("resolution={r}"),
                ]),
                f,
            )?;
        }
    }
    for m in METHODS {
        for s in PULL_STRETCH {
            for r in PULL_RES {
                run_or_load(
                    &pull_fem_id(m, s, r),
                    "pulling-strip-2d",
                    m,
                    &set(&[format!("stretch={s}"), format!("resolution={r}")]),
                    f,
                )?;
            }
        }
    }
    // The paper's punching strip (free, as specified) with pictures at 0, 25 and 50 %, and with
    // the centre held (the symmetric branch the FE reference computes).
    for m in METHODS {
        for r in PUNCH_RES {
            let png = fig_dir.join(format!("ext_punch_{m}_r{r}.png"));
            let times = |c: &sph_output::FileContents| compression_times(c, &[0.0, 0.5, 1.0]);
            let keep = |_: [f64; 3]| true;
            let dp = 3e-3 / r as f64;
            let after = pictures(
                png,
                format!("punching strip, {m}, H/dp = {r} (von Mises, Pa)"),
                &times,
                (0, 1),
                &keep,
                1,
                dp,
            );
            run_or_load_then(
                &punch_id(m, r),
                "punching-strip-2d",
                m,
                &set(&[
                    format!("resolution={r}"),
                    "snapshot_interval=1.25e-5".into(),
                ]),
                f,
                &after,
            )?;
            for c in [0.5, 0.3] {
                run_or_load(
                    &punch_sym_id(m, c, r),
                    "punching-strip-2d",
                    m,
                    &set(&[
                        format!("resolution={r}"),
                        format!("compression={c}"),
                        "hold_centre=true".into(),
                    ]),
                    f,
                )?;
            }
            for (id, corner) in [
                (punch_fe_corner_id(m, r), FE_CORNER_RADIUS),
                (punch_round_id(m, r), SMALL_CORNER_RADIUS),
            ] {
                run_or_load(
                    &id,
                    "punching-strip-2d",
                    m,
                    &set(&[
                        format!("resolution={r}"),
                        "compression=0.5".into(),
                        "hold_centre=true".into(),
                        corner.into(),
                    ]),
                    f,
                )?;
            }
        }
    }
    // Quasi-static check: the same runs at half the speed.
    for (compression, slower) in [(0.5, QUASI_PUNCH_SLOWER), (0.3, QUASI_PUNCH30_SLOWER)] {
        for (speed, id) in slower {
            run_or_load(
                id,
                "punching-strip-2d",
                "tl-hf",
                &set(&[
                    "resolution=30".into(),
                    format!("compression={compression}"),
                    "hold_centre=true".into(),
                    format!("punch_speed={speed}"),
                ]),
                f,
            )?;
        }
    }
    run_or_load(
        QUASI_PULL,
        "pulling-strip-2d",
        "tl-hf",
        &set(&[
            "stretch=2".into(),
            "resolution=30".into(),
            "pull_speed=1".into(),
        ]),
        f,
    )?;
    let large_strip: &[f64] = if sel.short {
        &STRIP_LARGE[..1]
    } else {
        &STRIP_LARGE
    };
    for &s in large_strip {
        for m in METHODS {
            let png = fig_dir.join(format!("ext_pull_{m}_s{s}.png"));
            let times = |c: &sph_output::FileContents| {
                let t = c.snapshots.last().map_or(0.0, |x| x.time);
                vec![(t, "final".to_string())]
            };
            let keep = |_: [f64; 3]| true;
            let after = pictures(
                png,
                format!("pulling strip, {m}, stretch {s} (von Mises, Pa)"),
                &times,
                (0, 1),
                &keep,
                1,
                2e-3 / 30.0,
            );
            run_or_load_then(
                &pull_large_id(m, s),
                "pulling-strip-2d",
                m,
                &set(&[format!("stretch={s}")]),
                f,
                &after,
            )?;
        }
    }
    if sel.short {
        return Ok(());
    }
    for s in CYLINDER_LARGE {
        for m in METHODS {
            let png = fig_dir.join(format!("ext_cyl_{m}_s{s}.png"));
            let times = |c: &sph_output::FileContents| {
                let t = c.snapshots.last().map_or(0.0, |x| x.time);
                vec![(t, "final, cut |y| < dp/2".to_string())]
            };
            let keep = |p: [f64; 3]| p[1].abs() < 0.5e-4;
            let after = pictures(
                png,
                format!("pulling cylinder, {m}, stretch {s}, mid-plane cut (von Mises, Pa)"),
                &times,
                (0, 2),
                &keep,
                1,
                1e-4,
            );
            run_or_load_then(
                &cylinder_id(m, s),
                "pulling-cylinder-3d",
                m,
                &set(&[format!("stretch={s}")]),
                f,
                &after,
            )?;
        }
    }
    for loading in ["point-forces", "punches"] {
        let png = fig_dir.join(format!("ext_stent_{loading}.png"));
        let times = |_: &sph_output::FileContents| {
            vec![
                (0.18e-3, "0.18 ms".to_string()),
                (0.34e-3, "0.34 ms".to_string()),
            ]
        };
        // Side view of the front half (x > 0), so struts do not hide each other.
        let keep = |p: [f64; 3]| p[0] > 0.0;
        let after = pictures(
            png,
            format!("stent, {loading}, TL-HF, side view of the x > 0 half (von Mises, Pa)"),
            &times,
            (2, 1),
            &keep,
            2,
            0.1e-3 / 3.0,
        );
        run_or_load_then(
            &stent_id(loading),
            "stent-3d",
            "tl-hf",
            &set(&[format!("loading={loading}")]),
            f,
            &after,
        )?;
    }
    Ok(())
}

/// A summary number of a stored run.
fn num(id: &str, key: &str) -> Option<f64> {
    load(id)?.num(key)
}

/// A stored run's force curve: `(x, force)` pairs (`x` = compression or stretch).
fn curve(r: &StoredRun, x_name: &str) -> Vec<(f64, f64)> {
    let Some(c) = r.summary.get("force_curve") else {
        return Vec::new();
    };
    let arr = |k: &str| -> Vec<Option<f64>> {
        c.get(k)
            .and_then(Value::as_array)
            .map(|a| a.iter().map(Value::as_f64).collect())
            .unwrap_or_default()
    };
    arr(x_name)
        .into_iter()
        .zip(arr("force"))
        .filter_map(|(x, f)| Some((x?, f?)))
        .collect()
}

/// Linear interpolation of a monotone-in-x curve at `x` (None outside).
fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    points.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        (x0 <= x && x <= x1 && x1 > x0).then(|| y0 + (y1 - y0) * (x - x0) / (x1 - x0))
    })
}
