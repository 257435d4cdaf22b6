//! UL impacts (UL paper §6.4–6.6) and the Hertz contact verification ([`crate::hertz`]): runs
//! and report.
//!
//! - colliding hollow balls at 0.08 c0, ball–plate 2D at 0.02 / 0.06 / 0.12 c0 and ball–plate 3D
//!   at 0.12 c0, each for OG, OAS and ENOG: disorder over time, connected pieces and isolated
//!   particles (numerical fracture), stress roughness near the contact, momentum balance, energy
//!   budget, status; pictures of the mid-plane (3D) coloured by von Mises stress.

use crate::frames::{frame_at, frame_projected, p99_value, roughness_map, roughness_series};
use crate::plot::{line_plot, particle_frames, Frame, Series};
use crate::store::{fmt_opt, load, pct, run_or_load_then, status, StoredRun};
use serde_json::{Map, Value};
use sph_cases::CaseError;
use sph_output::FileContents;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const METHODS: [&str; 3] = ["ul-og", "ul-oas", "ul-enog"];

/// Which runs to do.
#[derive(Clone, Copy, Debug)]
pub struct Selection {
    /// Re-run even when stored.
    pub force: bool,
    /// Add the finest Hertz resolution (R/dp = 30, ENOG, κ = 1 and 2; ≈ 230,000 particles).
    pub fine: bool,
    /// Add the colliding balls at the paper's dp = 0.001 (ENOG, 310,000 particles, ≈ 6e8
    /// particle-steps). Ball–plate 3D at the paper's dp = 0.0025 (354,000 particles, ≈ 2.3e9
    /// particle-steps) is not run here; the report gives its command.
    pub paper: bool,
}

pub(crate) fn figures_dir() -> PathBuf {
    crate::workspace_root().join("docs").join("validation")
}

/// The mid-plane cut `|z| < dp` of a 3D snapshot in the x–y plane, coloured by von Mises stress.
pub(crate) fn mid_plane(c: &FileContents, t: f64, title: &str, dp: f64) -> Option<Frame> {
    frame_projected(c, t, title, (0, 1), "von_mises", |x| x[2].abs() < dp)
}

// ----------------------------------------------------------------------- impact scenes

/// One impact run: the scene, the method, the speed (units of c0) and the spacing.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Impact {
    scene: Scene,
    method: &'static str,
    v0: f64,
    dp: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scene {
    Balls,
    Plate2d,
    Plate3d,
}

impl Scene {
    fn case(self) -> &'static str {
        match self {
            Scene::Balls => "colliding-balls-3d",
            Scene::Plate2d => "ball-plate-2d",
            Scene::Plate3d => "ball-plate-3d",
        }
    }

    fn short(self) -> &'static str {
        match self {
            Scene::Balls => "balls",
            Scene::Plate2d => "bp2d",
            Scene::Plate3d => "bp3d",
        }
    }

    fn three_d(self) -> bool {
        self != Scene::Plate2d
    }

    /// The picture times: the paper's for the balls; impact, deepest, rebound for the plates.
    fn frames(self) -> &'static [f64] {
        match self {
            Scene::Balls => &[0.001, 0.003, 0.005, 0.007],
            Scene::Plate2d => &[0.005, 0.015, 0.03, 0.05],
            Scene::Plate3d => &[0.004, 0.008, 0.014, 0.02],
        }
    }

    /// Snapshot and monitor intervals.
    fn intervals(self) -> (f64, f64) {
        match self {
            Scene::Balls => (0.001, 1e-4),
            Scene::Plate2d => (0.005, 2.5e-4),
            Scene::Plate3d => (0.002, 2e-4),
        }
    }

    /// The stress-roughness regions in the picture plane: near the contact, far from it.
    fn near(self, x: f64, y: f64) -> bool {
        match self {
            Scene::Balls => x.abs() < 0.01 && y.abs() < 0.02,
            Scene::Plate2d | Scene::Plate3d => x.abs() < 0.05,
        }
    }

    fn far(self, x: f64, _y: f64) -> bool {
        match self {
            Scene::Balls => x.abs() > 0.07,
            Scene::Plate2d | Scene::Plate3d => x.abs() > 0.15,
        }
    }
}

impl Impact {
    fn id(&self) -> String {
        format!(
            "{}-{}-v{}-dp{}",
            self.scene.short(),
            self.method,
            self.v0,
            self.dp
        )
    }

    fn set(&self) -> Vec<String> {
        let (snap, monitor) = self.scene.intervals();
        vec![
            format!("v0={}", self.v0),
            format!("dp={}", self.dp),
            format!("snapshot_interval={snap}"),
            format!("monitor_interval={monitor}"),
        ]
    }

    fn png(&self) -> String {
        format!("impact_{}.png", self.id())
    }
}

/// Ball–plate 2D speeds (c0), the paper's.
const PLATE2D_SPEEDS: [f64; 3] = [0.02, 0.06, 0.12];
/// Coarse spacings of the 3D scenes run for every method (paper: 0.001 and 0.0025).
const BALLS_DP: f64 = 0.002;
const PLATE3D_DP: f64 = 0.005;

fn impact_runs(paper: bool) -> Vec<Impact> {
    let mut v = Vec::new();
    for method in METHODS {
        v.push(Impact {
            scene: Scene::Balls,
            method,
            v0: 0.08,
            dp: BALLS_DP,
        });
        for v0 in PLATE2D_SPEEDS {
            v.push(Impact {
                scene: Scene::Plate2d,
                method,
                v0,
                dp: 0.0025,
            });
        }
        v.push(Impact {
            scene: Scene::Plate3d,
            method,
            v0: 0.12,
            dp: PLATE3D_DP,
        });
    }
    if paper {
        v.push(Impact {
            scene: Scene::Balls,
            method: "ul-enog",
            v0: 0.08,
            dp: 0.001,
        });
    }
    v
}

/// Pictures (mid-plane cut |z| < dp for 3D) and the stress roughness of a fresh impact run.
fn impact_after(c: &FileContents, run: &Impact) -> Result<Map<String, Value>, String> {
    let (scene, dp) = (run.scene, run.dp);
    let at = |t: f64, title: &str| {
        if scene.three_d() {
            mid_plane(c, t, title, dp)
        } else {
            frame_at(c, t, title)
        }
    };
    let frames: Vec<Frame> = scene
        .frames()
        .iter()
        .filter_map(|&t| at(t, run.method))
        .collect();
    if !frames.is_empty() {
        let vmax = p99_value(&frames);
        let cut = if scene.three_d() {
            ", mid-plane |z| < dp"
        } else {
            ""
        };
        particle_frames(
            &figures_dir().join(run.png()),
            &format!(
                "{} {}, v0 = {} c0, dp = {}{cut} (von Mises, Pa)",
                scene.case(),
                run.method,
                run.v0,
                dp
            ),
            &frames,
            4,
            vmax,
            dp,
        )?;
    }
    let all: Vec<Frame> = c.snapshots.iter().filter_map(|s| at(s.time, "")).collect();
    Ok(roughness_map(
        c,
        &all,
        dp,
        &|x, y| scene.near(x, y),
        &|x, y| scene.far(x, y),
    ))
}

/// Runs (or loads) every impact validation run of the selection.
pub fn run_all(sel: Selection) -> Result<(), CaseError> {
    std::fs::create_dir_all(figures_dir()).map_err(|e| CaseError::Io {
        path: figures_dir().display().to_string(),
        source: e,
    })?;
    // Cheapest first: the 2D plate, Hertz, then the 3D scenes.
    let runs = impact_runs(sel.paper);
    for run in runs.iter().filter(|r| r.scene == Scene::Plate2d) {
        impact(run, sel.force)?;
    }
    crate::hertz::run_all(sel.fine, sel.force)?;
    for run in runs.iter().filter(|r| r.scene != Scene::Plate2d) {
        impact(run, sel.force)?;
    }
    Ok(())
}

fn impact(run: &Impact, force: bool) -> Result<StoredRun, CaseError> {
    run_or_load_then(
        &run.id(),
        run.scene.case(),
        run.method,
        &run.set(),
        force,
        &|c| impact_after(c, run),
    )
}

// --------------------------------------------------------------------------------- report

pub(crate) fn num(r: &Option<StoredRun>, key: &str) -> Option<f64> {
    r.as_ref().and_then(|r| r.num(key))
}

fn state(r: &Option<StoredRun>) -> String {
    match r {
        None => "not run".into(),
        Some(r) => {
            let s = status(r);
            if s == "completed" {
                s.into()
            } else {
                format!("{s} (t = {})", fmt_opt(r.num("time_reached"), 4))
            }
        }
    }
}

/// A number in engineering notation (`3.21e-4`), or `–`.
pub(crate) fn sci(x: Option<f64>) -> String {
    x.map_or("–".into(), |v| format!("{v:.2e}"))
}

/// The first monitor time at which `key` exceeds `level`.
fn first_above(r: &StoredRun, key: &str, level: f64) -> Option<f64> {
    r.monitor_series(key)
        .into_iter()
        .find(|p| p.1 > level)
        .map(|p| p.0)
}

/// Appends the impact sections to `md`, writing figures into `fig_dir` (linked as `rel/…`).
pub fn report(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    crate::hertz::report(md, fig_dir, rel_dir)?;
    report_impacts(md, fig_dir, rel_dir)?;
    Ok(())
}

fn report_impacts(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    let runs = impact_runs(true);
    if runs.iter().all(|r| load(&r.id()).is_none()) {
        return Ok(());
    }
    writeln!(
        md,
        "## UL: impacts — colliding balls, ball–plate 2D and 3D (UL paper §6.4–6.6)\n"
    )
    .unwrap();
    writeln!(
        md,
        "Scenes as in CASES.md 11–13 (`colliding-balls-3d`, `ball-plate-2d`, `ball-plate-3d`; \
         their module docs give every choice the paper leaves open: layered balls, plates \
         fixed over 0.01 at the ends/edges, end times 0.008 / 0.05 / 0.02 s). Bodies meet \
         through the UL contact (κ = 1); `allow_fracture` is on. Columns: `pieces` = the most \
         connected pieces of the neighbour graph at a monitor sample (2 = ball(s) and plate \
         intact; numerical fracture adds pieces) and the first time there were more than at \
         the start; `isolated` = the most particles without any neighbour at a rebuild; \
         disorder = the accumulated disorder indicator (max over the particles, its largest \
         value over time, and the time it first exceeds 0.3); roughness = the 99th percentile \
         of |σ_vM,i − mean of its neighbours| over the particles near the contact (balls: \
         |x| < 0.01, |y| < 0.02; plates: |x| < 0.05) and far from it (balls |x| > 0.07; plates \
         |x| > 0.15), over the largest 99th-percentile von Mises stress of the run, largest \
         over the snapshots (3D: in the mid-plane |z| < dp); momentum = |Σ m v − Σ m v(0) + \
         supports' impulse| / Σ m|v(0)|; residual = the energy budget's at the end (estimate \
         / exact works, see below). `validate impacts` runs the 3D scenes for every method at \
         dp = {BALLS_DP} \
         (balls; the paper's 0.001 is 8× the particles) and dp = {PLATE3D_DP} (plate; the \
         paper's 0.0025 is 8× the particles, 2× the steps). The balls at the paper's \
         resolution are `validate impacts --paper` (ENOG: 310,000 particles, ≈ 6e8 \
         particle-steps); ball–plate 3D at the paper's resolution (354,000 particles, ≈ 2.3e9 \
         particle-steps: ≈ 1.3 h at the ≈ 5e5 particle-steps/s of the dp = {PLATE3D_DP} runs \
         in the table, more if memory traffic slows the larger run) was not run: its command \
         is below. Runtimes on the shared 2-core machine, which ran other work at the same \
         time (the OG balls row is an older run, made under heavier load).\n"
    )
    .unwrap();
    writeln!(
        md,
        "| scene | v0/c0 | dp | method | status | pieces (first break) | isolated | max disorder (> 0.3 at) | roughness near / far | momentum | residual est. / exact | particles | wall s | particle-steps/s |"
    )
    .unwrap();
    writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    let mut order = runs.clone();
    order.sort_by(|a, b| {
        (
            a.scene as u8,
            (a.v0 * 1e3) as u64,
            (1e6 / a.dp) as u64,
            a.method,
        )
            .cmp(&(
                b.scene as u8,
                (b.v0 * 1e3) as u64,
                (1e6 / b.dp) as u64,
                b.method,
            ))
    });
    for run in &order {
        let r = load(&run.id());
        let Some(stored) = &r else { continue };
        let rough = roughness_series(stored).map_or("–".into(), |(_, near, far)| {
            let peak = |v: &[Option<f64>]| v.iter().flatten().copied().fold(0.0, f64::max);
            format!("{:.3} / {:.3}", peak(&near), peak(&far))
        });
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} ({}) | {} | {} ({}) | {rough} | {} | {} / {} | {} | {} | {} |",
            run.scene.case(),
            run.v0,
            run.dp,
            run.method,
            state(&r),
            fmt_opt(num(&r, "pieces_max"), 0),
            fmt_opt(num(&r, "first_break_time"), 4),
            fmt_opt(num(&r, "isolated_max"), 0),
            fmt_opt(num(&r, "max_disorder"), 3),
            fmt_opt(first_above(stored, "disorder_max", 0.3), 4),
            sci(num(&r, "momentum_balance")),
            pct(num(&r, "energy_residual")),
            pct(num(&r, "energy_residual_exact_work")),
            fmt_opt(num(&r, "particles"), 0),
            fmt_opt(num(&r, "wall_seconds"), 0),
            sci(num(&r, "particle_steps_per_second")),
        )
        .unwrap();
    }
    writeln!(md).unwrap();
    report_claims(md);
    // Disorder over time per scene.
    for (scene, v0s) in [
        (Scene::Balls, vec![0.08]),
        (Scene::Plate2d, PLATE2D_SPEEDS.to_vec()),
        (Scene::Plate3d, vec![0.12]),
    ] {
        let mut series = Vec::new();
        for run in runs
            .iter()
            .filter(|r| r.scene == scene && v0s.contains(&r.v0))
        {
            if let Some(r) = load(&run.id()) {
                series.push(Series {
                    label: format!("{} {} c0 dp {}", run.method, run.v0, run.dp),
                    points: r.monitor_series("disorder_max"),
                    markers: false,
                });
            }
        }
        if series.is_empty() {
            continue;
        }
        let name = format!("impact_{}_disorder.png", scene.short());
        line_plot(
            &fig_dir.join(&name),
            &format!("{}: largest disorder indicator", scene.case()),
            "t (s)",
            "max e_i",
            &series,
        )?;
        writeln!(md, "![{} disorder]({rel_dir}/{name})\n", scene.case()).unwrap();
    }
    report_budget(md, fig_dir, rel_dir)?;
    writeln!(md, "### Pictures\n").unwrap();
    for run in &order {
        if fig_dir.join(run.png()).exists() {
            writeln!(md, "![{}]({rel_dir}/{})\n", run.id(), run.png()).unwrap();
        }
    }
    writeln!(
        md,
        "Commands (one run each; `validate impacts` runs and stores them all):\n"
    )
    .unwrap();
    for run in &order {
        if let Some(r) = load(&run.id()) {
            writeln!(md, "- `{}`", r.command).unwrap();
        }
    }
    for run in impact_runs(false)
        .iter()
        .filter(|r| load(&r.id()).is_none())
    {
        let sets: String = run.set().iter().map(|s| format!(" --set {s}")).collect();
        writeln!(
            md,
            "- not stored yet (`validate impacts` runs it; add `--dry-run` for its particle and \
             step estimate): `cargo run --release -p sph-cases --bin sph -- run {} --method {}{sets}`",
            run.scene.case(),
            run.method
        )
        .unwrap();
    }
    for (scene, dp) in [(Scene::Balls, 0.001), (Scene::Plate3d, 0.0025)] {
        let paper = Impact {
            scene,
            method: "ul-enog",
            v0: if scene == Scene::Balls { 0.08 } else { 0.12 },
            dp,
        };
        if load(&paper.id()).is_none() {
            writeln!(
                md,
                "- paper resolution, not run here: `cargo run --release -p sph-cases --bin sph -- run {} --method ul-enog --set dp={dp}` (and `--method ul-og`, `ul-oas`)",
                scene.case()
            )
            .unwrap();
        }
    }
    writeln!(md).unwrap();
    Ok(())
}

/// The paper's qualitative findings as numbers from the stored runs.
fn report_claims(md: &mut String) {
    let r = |scene, method, v0, dp| {
        load(
            &Impact {
                scene,
                method,
                v0,
                dp,
            }
            .id(),
        )
    };
    let mut lines = Vec::new();
    let enog: Vec<f64> = impact_runs(true)
        .iter()
        .filter(|x| x.method == "ul-enog")
        .filter_map(|x| load(&x.id()).and_then(|r| r.num("max_disorder")))
        .collect();
    let others: Vec<(String, f64)> = impact_runs(true)
        .iter()
        .filter(|x| x.method != "ul-enog")
        .filter_map(|x| {
            load(&x.id())
                .and_then(|r| r.num("max_disorder"))
                .map(|d| (format!("{} {} {} c0", x.scene.case(), x.method, x.v0), d))
        })
        .collect();
    if let Some(max) = enog.iter().copied().reduce(f64::max) {
        let below = others.iter().filter(|o| o.1 > max).count();
        lines.push(format!(
            "ENOG's largest disorder indicator over all its impact runs is {max:.3}; {below} of \
             the {} OG/OAS runs exceed it",
            others.len()
        ));
    }
    if let Some(o) = r(Scene::Plate2d, "ul-oas", 0.06, 0.0025) {
        lines.push(format!(
            "ball–plate 2D at 0.06 c0, OAS (paper: zigzag, tensile instability from t ≈ 0.012 s): \
             disorder first above 0.3 at t = {}, above 0.5 at {}, largest {}; pieces {} (first \
             break {})",
            fmt_opt(first_above(&o, "disorder_max", 0.3), 4),
            fmt_opt(first_above(&o, "disorder_max", 0.5), 4),
            fmt_opt(o.num("max_disorder"), 3),
            fmt_opt(o.num("pieces_max"), 0),
            fmt_opt(o.num("first_break_time"), 4),
        ));
    }
    if let Some(o) = r(Scene::Plate2d, "ul-og", 0.02, 0.0025) {
        lines.push(format!(
            "ball–plate 2D at 0.02 c0, OG (paper: zigzag and numerical fracture): pieces {} \
             (first break t = {}), largest disorder {}",
            fmt_opt(o.num("pieces_max"), 0),
            fmt_opt(o.num("first_break_time"), 4),
            fmt_opt(o.num("max_disorder"), 3),
        ));
    }
    if lines.is_empty() {
        return;
    }
    writeln!(md, "**The paper's findings as numbers:**\n").unwrap();
    for l in lines {
        writeln!(md, "- {l}.").unwrap();
    }
    writeln!(md).unwrap();
}

fn report_budget(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    writeln!(md, "### Energy budget of the UL runs\n").unwrap();
    writeln!(
        md,
        "`sph_ul::energy`: total = kinetic + volumetric (EOS potential) + shear + contact + \
         dissipated (work of the Riemann term's −½βρ0c0u part, accumulated per acoustic step) + \
         diffused (the volumetric energy the paper's pressure jump removes; zero with the \
         cases' scheme) − work of OAS's artificial stress − work of loads; residual = total − \
         total(0), relative to the initial energy. Exact: kinetic, volumetric (for the p̄ part \
         of the pressure and the motion part of continuity), the accumulated works (exact for \
         the position-Verlet step: ΔKE = Σ m a·v_mid Δt). Estimated: the shear energy \
         Σ V τ:τ/(4G) — exact for OG/OAS up to the hypoelastic V̇ τ:τ term, an estimate for ENOG \
         whose force is the accumulated A_s, not the divergence of the output stress (eq 26) — \
         and the contact energy Σ κ c0² m ρ_c²/(2ρ0²) (exact only for pairs closer than dp with \
         V = m/ρ0). The work of A_s and of the contact forces is also accumulated exactly; the \
         second residual column uses those instead of the estimates, so it measures only the \
         time integration and the hypoelastic term; their difference is the estimates' error. \
         Tests: `energy_budget_closes_on_a_free_oscillation`, \
         `contact_conserves_momentum_and_the_budget_closes` (sph-ul, `tests/energy.rs`). The \
         cost of the budget (one more vector sum in the force gather, one pass of dot products \
         per acoustic step): +12 % wall time on the 2D plate with ENOG, on one and on two \
         threads (quiet Intel Xeon, median of 5; earlier, under load: +7 % CPU time on the 2D \
         rings with ENOG, +2 % on the 3D balls with OG; commands in the doc of \
         `UlParams::energy_budget`); `energy_budget = false` turns it off.\n"
    )
    .unwrap();
    // The budget terms of one run over time.
    let pick = Impact {
        scene: Scene::Plate2d,
        method: "ul-enog",
        v0: 0.12,
        dp: 0.0025,
    };
    if let Some(r) = load(&pick.id()) {
        let e0 = r
            .summary
            .get("monitor")
            .and_then(|m| m.get("energy_budget"))
            .and_then(|b| b.get("initial_total"))
            .and_then(Value::as_f64)
            .unwrap_or(1.0);
        let series: Vec<Series> = [
            "kinetic",
            "volumetric",
            "shear",
            "shear_work",
            "contact",
            "dissipated",
            "residual",
        ]
        .iter()
        .map(|k| Series {
            label: k.to_string(),
            points: r
                .budget_series(k)
                .into_iter()
                .map(|(t, v)| (t, v / e0))
                .collect(),
            markers: false,
        })
        .filter(|s| !s.points.is_empty())
        .collect();
        if !series.is_empty() {
            line_plot(
                &fig_dir.join("impact_budget_bp2d_enog_0.12.png"),
                "ball–plate 2D, ENOG, 0.12 c0: energy budget / E0",
                "t (s)",
                "E / E0",
                &series,
            )?;
            writeln!(
                md,
                "ENOG's accumulated shear acceleration does work that no stored energy holds: \
                 in the 2D ball–plate impact at 0.12 c0 the exact work of A_s at the end is \
                 {} of E0 (`shear_work` = energy stored by it; negative = it gave out more \
                 than it took up), while the estimate from the output stress is {}; the \
                 residual with the exact works is {}.\n",
                pct(r.num("shear_work_final")),
                pct(r.budget_series("shear").last().map(|p| p.1 / e0)),
                pct(r.num("energy_residual_exact_work")),
            )
            .unwrap();
            writeln!(
                md,
                "![budget]({rel_dir}/impact_budget_bp2d_enog_0.12.png)\n"
            )
            .unwrap();
        }
    }
    Ok(())
}
