//! The UL sections of docs/validation.md: Table 1 and its convergence, the long runs with
//! refreshed and frozen kernel data, Table 3 (the 3D plate) and the colliding rings.

use super::*;

/// Appends the UL sections to `md`, writing figures into `fig_dir` (linked as `rel/…`).
pub fn report(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    table1_section(md)?;
    convergence_section(md, fig_dir, rel_dir)?;
    long_run_section(md, fig_dir, rel_dir)?;
    plate3d_section(md)?;
    rings_section(md, fig_dir, rel_dir)?;
    Ok(())
}

/// A run's period to four digits, or its state when it has none.
fn cell(r: &Option<StoredRun>) -> String {
    match period(r) {
        Some(t) => format!("{t:.4}"),
        None => state(r),
    }
}

/// Table 1 of the 2D plate: ENOG and OAS against the paper and theory, the FE period, the runs not yet made, and the OAS variants.
fn table1_section(md: &mut String) -> Result<(), String> {
    writeln!(md, "## UL: 2D oscillating plate (UL paper §6.1, Table 1)\n").unwrap();
    writeln!(
        md,
        "Plate L = 0.2 m, H = 0.02 m (the TL scene: 0.06 m of strip inside a base with 4 layers \
         above, below and behind it), E = 2 MPa, ν = 0.3975, ρ = 1000, h = 1.3 dp, H/dp = 30, \
         dual-criteria stepping (kernel data refreshed every acoustic sub-step), Riemann solver \
         as SPHinXsys's tests (β = 1, no pressure jump in the continuity equation; see \
         docs/methods.md). The first period of the tip mid-point (t ≤ {PLATE_END} s, two \
         downward crossings). `frame` is the papers' clamp (the base's layers fixed, the \
         embedded strip free between them; the default, see the TL clamp section), `solid` the \
         earlier runs that fix the whole base. OAS (B): the velocity gradient with the \
         correction matrix (eq 26, key `ul_corrected_gradient`), which the notes of the earlier \
         runs suspected the paper used; OAS (eq 14): as printed, without B. **Target: within \
         1 % of the paper's periods.**\n"
    )
    .unwrap();
    writeln!(
        md,
        "| v_f | paper ENOG | ENOG frame | vs paper | ENOG solid | vs paper | paper OAS | OAS (B) frame | vs paper | OAS (eq 14) solid | vs paper | thin plate |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|").unwrap();
    for (vf, p_enog, p_oas) in TABLE1 {
        let ef = load(&plate_id("ul-enog", 30, vf, "frame"));
        let es = load(&plate_id("ul-enog", 30, vf, "solid"));
        let ob = load(&oas_corrected_id(30, vf));
        let os = load(&plate_id("ul-oas", 30, vf, "solid"));
        writeln!(
            md,
            "| {vf} | {p_enog} | {} | {} | {} | {} | {p_oas} | {} | {} | {} | {} | {TABLE1_THEORY} |",
            cell(&ef),
            pct(rel(period(&ef), Some(p_enog))),
            cell(&es),
            pct(rel(period(&es), Some(p_enog))),
            cell(&ob),
            pct(rel(period(&ob), Some(p_oas))),
            cell(&os),
            pct(rel(period(&os), Some(p_oas))),
        )
        .unwrap();
    }
    writeln!(md).unwrap();
    // Against the continuum: the FE period of the same plate for the UL methods' nearest
    // small-strain law (the d = 2 split; crate::fem_plate), at the smallest and largest v_f.
    if let Some(fe) = crate::fem_plate::period("d2-split", "frame", 0.02, 0.3975) {
        let (small, p_small, _) = TABLE1[0];
        let (large, p_large, _) = TABLE1[TABLE1.len() - 1];
        let ours = |vf: f64| period(&load(&plate_id("ul-enog", 30, vf, "frame")));
        writeln!(
            md,
            "**Against the continuum.** Plane-strain finite elements (`validation/fem/\
             plate_modes.py`) give the small-amplitude period of this plate and clamp as \
             {fe:.5} s for the UL solvers' nearest small-strain law (the d = 2 split: pressure \
             from K, a 2D-deviatoric shear stress; UL-ENOG's shear term is not exactly it). At \
             v_f = {small} our ENOG period at H/dp 30 is {} from it and the paper's {}; at \
             v_f = {large}, {} and {}. The period of both UL-SPH codes grows with the \
             amplitude by {} (ours) and {} (the paper's) between these two rows, while TL-HF's \
             changes by a fraction of a percent with the amplitude (TL Table 1 above, v_f \
             0.01 against 0.05; the finite elements are linear): the growth points to the UL \
             schemes' response to large deformation, not the plate's. It is why UL-ENOG sits +6 % \
             from the continuum in docs/tradeoffs.md, which runs v_f = 0.05.\n",
            pct(rel(ours(small), Some(fe))),
            pct(rel(Some(p_small), Some(fe))),
            pct(rel(ours(large), Some(fe))),
            pct(rel(Some(p_large), Some(fe))),
            pct(rel(ours(large), ours(small))),
            pct(rel(Some(p_large), Some(p_small))),
        )
        .unwrap();
    }
    // The OAS runs' distance from the paper's own OAS column (B, frame clamp).
    let fe = crate::fem_plate::period("d2-split", "frame", 0.02, 0.3975);
    let oas_offsets: Vec<f64> = TABLE1
        .iter()
        .filter_map(|&(vf, _, p_oas)| rel(period(&load(&oas_corrected_id(30, vf))), Some(p_oas)))
        .collect();
    let (lo, hi) = oas_offsets
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    writeln!(
        md,
        "**Where the paper's OAS column comes from.** The UL paper's own runs: its Table 1 \
         caption says the first period \"is recorded for both SPH-ENOG and SPH-OAS with L = 0.2, \
         H = 0.02 and H/dp = 30\", and the column changes with v_f (0.273 to 0.278), as a run \
         does and a quoted value would not. Gray, Monaghan & Swift (2001), cited in §6.1 as \
         \"[5]\" and the source of OAS's artificial-stress parameters, report one period for \
         their plate, T c0/L = 82 (as the MPS paper's table quotes it): 0.288 s with this \
         plate's c0 = 57.0 m/s, not 0.273 s. (Earlier versions of this report called the column \
         quoted from Gray et al. and did not hold it to the target; that reading was wrong.) So \
         the OAS column is held to 1 % like ENOG's, and our OAS runs {}: {} to {} from it with \
         B and the frame clamp, the paper's set-up as far as it states it. The paper gives no \
         more of its OAS set-up (ε, n of the artificial stress are Gray et al.'s; whether its \
         OAS used B is not said); at v_f = {} our OAS period lies {} from the finite \
         elements of this plate and the paper's {}, so the gap is in the OAS scheme's \
         small-amplitude stiffness, not in the plate.\n",
        if hi.abs().max(lo.abs()) <= 0.01 {
            "meet it"
        } else {
            "miss it"
        },
        pct(Some(lo)),
        pct(Some(hi)),
        TABLE1[0].0,
        pct(rel(period(&load(&oas_corrected_id(30, TABLE1[0].0))), fe)),
        pct(rel(Some(TABLE1[0].2), fe)),
    )
    .unwrap();
    let missing: Vec<String> = TABLE1
        .iter()
        .flat_map(|&(vf, _, _)| {
            [
                (
                    plate_id("ul-enog", 30, vf, "frame"),
                    format!("ENOG v_f = {vf}"),
                ),
                (oas_corrected_id(30, vf), format!("OAS (B) v_f = {vf}")),
            ]
        })
        .filter(|(id, _)| load(id).is_none())
        .map(|(_, what)| what)
        .collect();
    if !missing.is_empty() {
        let like: Vec<String> = TABLE1
            .iter()
            .flat_map(|&(vf, _, _)| {
                [
                    plate_id("ul-enog", 30, vf, "frame"),
                    plate_id("ul-enog", 30, vf, "solid"),
                    plate_id("ul-oas", 30, vf, "solid"),
                ]
            })
            .collect();
        let cost = cost_estimate(
            "oscillating-plate-2d",
            "ul-enog",
            &plate_set(30, 0.01, "frame"),
            &like,
        )
        .unwrap_or_else(|| "no estimate".into());
        writeln!(
            md,
            "Not run with the frame clamp yet: {}. `validate ul` makes them; one run (ENOG, \
             v_f = 0.01, `sph run … --dry-run`): {cost}.\n",
            missing.join(", ")
        )
        .unwrap();
    }
    let disorder =
        |r: &Option<StoredRun>| fmt_opt(r.as_ref().and_then(|r| r.num("max_disorder")), 3);
    let (of, ob) = (
        load(&plate_id("ul-oas", 30, 0.05, "frame")),
        load(&oas_corrected_id(30, 0.05)),
    );
    if of.is_some() || ob.is_some() {
        writeln!(
            md,
            "B and the clamp separated (OAS, v_f = 0.05, H/dp = 30, frame clamp): eq 14 without \
             B gives T = {} s (max disorder {}), with B T = {} s (max disorder {}).\n",
            fmt_opt(period(&of), 4),
            disorder(&of),
            fmt_opt(period(&ob), 4),
            disorder(&ob),
        )
        .unwrap();
    }
    let (b0, b1) = (load(&oas_b_id(false)), load(&oas_b_id(true)));
    if b0.is_some() || b1.is_some() {
        writeln!(
            md,
            "Earlier check at H/dp = 10 (v_f = 0.05, t ≤ 0.7 s, solid clamp): with B the OAS \
             plate is stiffer and more ordered, T = {} s and max disorder {}, against T = {} s \
             and {} without.\n",
            fmt_opt(period(&b1), 4),
            disorder(&b1),
            fmt_opt(period(&b0), 4),
            disorder(&b0),
        )
        .unwrap();
    }
    Ok(())
}

/// The convergence of the 2D plate with ENOG over H/dp.
fn convergence_section(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    writeln!(md, "### Convergence (ENOG, v_f = 0.05)\n").unwrap();
    writeln!(
        md,
        "| H/dp | particles | T frame | vs paper (0.279) | vs thin plate | T solid | vs paper | particle-steps/s (frame) |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|").unwrap();
    let mut series = Vec::new();
    for res in CONVERGENCE_RES {
        let r = load(&plate_id("ul-enog", res, 0.05, "frame"));
        let so = load(&plate_id("ul-enog", res, 0.05, "solid"));
        let t = period(&r);
        writeln!(
            md,
            "| {res} | {} | {} | {} | {} | {} | {} | {} |",
            fmt_opt(r.as_ref().and_then(|r| r.num("particles")), 0),
            t.map_or(state(&r), |t| format!("{t:.4}")),
            pct(rel(t, Some(0.279))),
            pct(rel(t, r.as_ref().and_then(|r| r.num("period_theory")))),
            cell(&so),
            pct(rel(period(&so), Some(0.279))),
            rate(&r),
        )
        .unwrap();
        for (run, clamp) in [(r, "frame"), (so, "solid")] {
            if let Some(run) = run {
                series.push(Series {
                    label: format!("H/dp = {res}, {clamp}"),
                    points: run.probe_series("tip", 1),
                    markers: false,
                });
            }
        }
    }
    writeln!(md).unwrap();
    if !series.is_empty() {
        line_plot(
            &fig_dir.join("ul_plate_convergence.png"),
            "UL-ENOG plate, v_f = 0.05: tip y",
            "t (s)",
            "y (m)",
            &series,
        )?;
        writeln!(
            md,
            "![ENOG convergence]({rel_dir}/ul_plate_convergence.png)\n"
        )
        .unwrap();
    }
    Ok(())
}

/// The 10 s run of the 2D plate: disorder and tip motion with refreshed and frozen kernel data.
fn long_run_section(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    writeln!(md, "### Long run (t = 10 s, H/dp = 10, v_f = 0.05)\n").unwrap();
    writeln!(
        md,
        "The UL disorder indicator is Ganzenmüller's error of the affine fit from the initial to \
         the current configuration over the current neighbours (accumulated; see \
         `UlSolver::disorder`). Amplitudes: the tip's largest |y| in the first and in the last \
         second; periods: between successive downward crossings, the first and the last one. \
         Dual-criteria stepping with the kernel data refreshed every acoustic sub-step (the \
         default); the last row freezes them over the advection step as docs/methods.md describes, \
         which softens the plate secularly (the paper ran its long run with single stepping, \
         which avoids that too). Solid clamp (runs made before the clamp key; the zigzag does \
         not depend on it). Energy: the budget's residual (kinetic + volumetric + shear + \
         dissipated − total at t = 0, relative to it; see the impacts section), with the \
         shear energy estimated from the output stress (for ENOG: eq 26, not the energy its \
         force derives from) / with the exactly accumulated work of ENOG's A_s; and the \
         energy dissipated by the Riemann term.\n"
    )
    .unwrap();
    writeln!(
        md,
        "| run | status | max disorder | disorder at end | amplitude t < 1 | amplitude t > 9 | first period | last period | residual est. / exact | dissipated |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
    let mut dis = Vec::new();
    let mut tips = Vec::new();
    for (method, frozen) in LONG_RUNS {
        let id = long_id(method, frozen);
        let label = if frozen {
            format!("{method}, frozen kernel data")
        } else {
            method.to_string()
        };
        let r = load(&id);
        let (amp0, amp1, last, periods) = match &r {
            Some(r) => {
                let y = r.probe_series("tip", 1);
                let amp = |lo: f64, hi: f64| {
                    y.iter()
                        .filter(|p| p.0 >= lo && p.0 < hi)
                        .map(|p| p.1.abs())
                        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
                };
                let d = r.monitor_series("disorder_max");
                (
                    amp(0.0, 1.0),
                    amp(9.0, 10.0 + 1e-9),
                    d.last().map(|p| p.1),
                    crossing_periods(&y),
                )
            }
            None => (None, None, None, Vec::new()),
        };
        writeln!(
            md,
            "| {label} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            state(&r),
            fmt_opt(r.as_ref().and_then(|r| r.num("max_disorder")), 3),
            fmt_opt(last, 3),
            fmt_opt(amp0, 4),
            fmt_opt(amp1, 4),
            fmt_opt(periods.first().copied(), 4),
            fmt_opt(periods.last().copied(), 4),
            residuals(&r),
            pct(dissipated(&r)),
        )
        .unwrap();
        if let Some(r) = r {
            dis.push(Series {
                label: label.clone(),
                points: r.monitor_series("disorder_max"),
                markers: false,
            });
            tips.push(Series {
                label,
                points: r.probe_series("tip", 1),
                markers: false,
            });
        }
    }
    writeln!(md).unwrap();
    if !dis.is_empty() {
        line_plot(
            &fig_dir.join("ul_long_disorder.png"),
            "2D plate, t = 10 s: largest disorder indicator",
            "t (s)",
            "max e_i",
            &dis,
        )?;
        line_plot(
            &fig_dir.join("ul_long_tip.png"),
            "2D plate, t = 10 s: tip y",
            "t (s)",
            "y (m)",
            &tips,
        )?;
        writeln!(md, "![long-run disorder]({rel_dir}/ul_long_disorder.png)\n").unwrap();
        writeln!(md, "![long-run tip]({rel_dir}/ul_long_tip.png)\n").unwrap();
        for (method, frozen) in LONG_RUNS {
            let name = format!("ul_long_{}.png", long_id(method, frozen));
            if fig_dir.join(&name).exists() {
                writeln!(md, "![{method} at the end]({rel_dir}/{name})\n").unwrap();
            }
        }
    }
    Ok(())
}

/// Table 3: the simply supported 3D plate against the paper and the analytical periods, and the finer runs.
fn plate3d_section(md: &mut String) -> Result<(), String> {
    writeln!(
        md,
        "## UL: simply supported 3D plate (UL paper §6.2, Table 3)\n"
    )
    .unwrap();
    writeln!(
        md,
        "Plate 0.4 × 0.4 × 0.01 m, E = 100 MPa, ν = 0.3, ρ = 1000, SPH-ENOG; supports: z held at \
         the mid-thickness particles of the four sides; v_z = sin(mπx/L) sin(nπy/W) m/s; the \
         first period of the observation point (t ≤ 2 T). Target: within 3 % of the paper. \
         Particle-steps/s count acoustic steps, each row on the machine and build of the day it \
         was run (two threads for the H/dp = 5 rows): the (1, 1) row at H/dp = 5 was run on a \
         later build with the smaller pair records and the cross-block refresh of \
         docs/performance.md, the other two before them.\n"
    )
    .unwrap();
    writeln!(
        md,
        "| (m, n) | H/dp | particles | paper | ours | vs paper | analytical | vs analytical | particle-steps/s |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|").unwrap();
    for (mode, paper, theory) in TABLE3 {
        for (k, res) in [3u32, 5].into_iter().enumerate() {
            let r = load(&plate3d_id(res, mode));
            if r.is_none() && res == 5 {
                continue;
            }
            let t = period(&r);
            writeln!(
                md,
                "| ({}, {}) | {res} | {} | {} | {} | {} | {theory} | {} | {} |",
                mode.0,
                mode.1,
                fmt_opt(r.as_ref().and_then(|r| r.num("particles")), 0),
                paper[k],
                t.map_or(state(&r), |t| format!("{t:.4}")),
                pct(rel(t, Some(paper[k]))),
                pct(rel(t, Some(theory))),
                rate(&r),
            )
            .unwrap();
        }
    }
    writeln!(md).unwrap();
    // Rates from the finest resolution with stored runs: a 200,000-particle run makes about
    // a third of the particle-steps per second of a 43,200-particle one (pair data beyond the
    // caches), so H/dp = 3 rates would promise a third of the time.
    let (like_res, like) = [5u32, 3]
        .into_iter()
        .map(|res| {
            let ids: Vec<String> = TABLE3
                .iter()
                .map(|t| plate3d_id(res, t.0))
                .filter(|id| load(id).is_some())
                .collect();
            (res, ids)
        })
        .find(|(_, ids)| !ids.is_empty())
        .unwrap_or((3, Vec::new()));
    let mut finer = Vec::new();
    for (mode, res) in [((1, 1), 5), ((2, 1), 5), ((2, 2), 5), ((2, 2), 9)] {
        if load(&plate3d_id(res, mode)).is_some() {
            continue;
        }
        let theory = TABLE3.iter().find(|t| t.0 == mode).map_or(0.0, |t| t.2);
        if let Some(cost) = cost_estimate(
            "oscillating-plate-3d",
            "ul-enog",
            &plate3d_set(res, mode, theory),
            &like,
        ) {
            finer.push(format!(
                "({}, {}) at H/dp = {res}: {cost} (`{}`)",
                mode.0,
                mode.1,
                command_for(
                    &plate3d_id(res, mode),
                    "oscillating-plate-3d",
                    "ul-enog",
                    &plate3d_set(res, mode, theory)
                )
            ));
        }
    }
    if !finer.is_empty() {
        writeln!(
            md,
            "Not run at the paper's finer resolutions (estimates from `sph run … --dry-run` and \
             the rates of the stored H/dp = {like_res} runs; `validate ul --fine` adds H/dp = 5 \
             for every mode):\n"
        )
        .unwrap();
        for f in finer {
            writeln!(md, "- {f}").unwrap();
        }
        writeln!(md).unwrap();
    }
    Ok(())
}

/// The colliding rubber rings at 0.06–0.08 c0 with OG, OAS and ENOG, with pictures.
fn rings_section(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    writeln!(
        md,
        "## UL: colliding rubber rings (UL paper §6.3, Fig. 12–14)\n"
    )
    .unwrap();
    writeln!(
        md,
        "Rings r = 0.03/0.04 m, centres 0.09 m apart, E = 10 MPa, ν = 0.4, ρ = 1200 \
         (c0 = 117.9 m/s), dp = 0.001 (4,398 particles), t ≤ 0.02 s. The rings are two bodies of \
         one UL solver meeting through docs/methods.md's contact pressure (`UlSolver::with_contact`; \
         momentum conserved to round-off, test `contact_between_bodies_conserves_momentum_and_\
         rebounds`). Disorder indicator as for the long run; `isolated` = the most particles \
         without any neighbour of their own body at a rebuild (numerical fracture); stress \
         roughness as in the MPS rings section, largest over the snapshots, in windows that move \
         with the rings (`frames::rings_roughness`: near = within 0.01 m of each ring's facing \
         extreme and |y| < 0.02 m, far = beyond 0.025 m from each ring's centre on its outer \
         side); `–` when a window held no particle in any snapshot. Energy: the closed budget \
         of the impacts section (kinetic + volumetric + shear + contact + dissipated − total \
         at t = 0, relative to it) with the shear and contact energies estimated / with the \
         exactly accumulated works of the shear and contact forces, and the share of the \
         initial energy the Riemann term dissipated. (Runs stored before the budget \
         existed showed a bare change of the estimated total, mostly the Riemann \
         dissipation.)\n"
    )
    .unwrap();
    writeln!(
        md,
        "| v0 / c0 | method | status | max disorder | p99 disorder at end | isolated | stress roughness near contact / far sides | residual est. / exact | dissipated |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|").unwrap();
    let mut ring_dis = Vec::new();
    let (mut worst_est, mut worst_exact) = (None::<f64>, None::<f64>);
    for v in RING_SPEEDS {
        for method in UL_METHODS {
            let r = load(&rings_id(method, v));
            let p99 = r
                .as_ref()
                .and_then(|r| r.monitor_series("disorder_p99").last().map(|p| p.1));
            let rough =
                r.as_ref()
                    .and_then(roughness_series)
                    .map_or("–".into(), |(_, near, far)| {
                        format!("{} / {}", fmt_opt(peak(&near), 3), fmt_opt(peak(&far), 3))
                    });
            writeln!(
                md,
                "| {v} | {method} | {} | {} | {} | {} | {rough} | {} | {} |",
                state(&r),
                fmt_opt(r.as_ref().and_then(|r| r.num("max_disorder")), 3),
                fmt_opt(p99, 3),
                fmt_opt(r.as_ref().and_then(|r| r.num("isolated_max")), 0),
                residuals(&r),
                pct(dissipated(&r)),
            )
            .unwrap();
            let num = |k: &str| r.as_ref().and_then(|r| r.num(k)).map(f64::abs);
            if let Some(e) = num("energy_residual") {
                worst_est = Some(worst_est.map_or(e, |w| w.max(e)));
            }
            if let Some(e) = num("energy_residual_exact_work") {
                worst_exact = Some(worst_exact.map_or(e, |w| w.max(e)));
            }
            if let (Some(r), true) = (&r, v == 0.06 || method != "ul-og") {
                ring_dis.push(Series {
                    label: format!("{method} {v} c0"),
                    points: r.monitor_series("disorder_max"),
                    markers: false,
                });
            }
        }
    }
    writeln!(md).unwrap();
    if let (Some(e), Some(x)) = (worst_est, worst_exact) {
        writeln!(
            md,
            "Largest |residual| over the runs with a budget: {} with the estimates, {} with the \
             exact works.\n",
            pct(Some(e)),
            pct(Some(x))
        )
        .unwrap();
    }
    if !ring_dis.is_empty() {
        line_plot(
            &fig_dir.join("ul_rings_disorder.png"),
            "Colliding rings: largest disorder indicator",
            "t (s)",
            "max e_i",
            &ring_dis,
        )?;
        writeln!(md, "![rings disorder]({rel_dir}/ul_rings_disorder.png)\n").unwrap();
    }
    for v in RING_SPEEDS {
        for method in UL_METHODS {
            let name = format!("ul_rings_{method}_v{v}.png");
            if fig_dir.join(&name).exists() {
                writeln!(md, "![{method} {v} c0]({rel_dir}/{name})\n").unwrap();
            }
        }
    }
    Ok(())
}
