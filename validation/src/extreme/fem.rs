//! The extreme scenes against the finite-element reference (`validation/fem/`): punching and
//! clamped pulling, with the force curves averaged over the corner saw-tooth as the FE values
//! are.

use super::*;

/// Half-width of the compression window over which a force curve is averaged (the FE
/// reference's `SMOOTHING_HALF_WIDTH`).
const FORCE_WINDOW: f64 = 0.05;

/// The value at `x` of the least-squares quadratic through the points within `half_width` of
/// it (one-sided at an end): the mean of a saw-toothed curve (particles or FE nodes slipping
/// round a punch corner), as the FE reference takes it. Falls back to [`interpolate`] with
/// fewer than four points.
fn smoothed_at(points: &[(f64, f64)], x: f64, half_width: f64) -> Option<f64> {
    let near: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| (p.0 - x).abs() <= half_width + 1e-12 && p.1.is_finite())
        .map(|&(px, py)| (px - x, py))
        .collect();
    if near.len() < 4 {
        return interpolate(points, x);
    }
    // Normal equations of y = a + b t + c t², scaled by the window for conditioning.
    let (mut m, mut r) = ([[0.0f64; 3]; 3], [0.0f64; 3]);
    for &(t, y) in &near {
        let u = t / half_width;
        let phi = [1.0, u, u * u];
        for i in 0..3 {
            r[i] += phi[i] * y;
            for j in 0..3 {
                m[i][j] += phi[i] * phi[j];
            }
        }
    }
    let a = glam::DMat3::from_cols_array_2d(&m).transpose();
    (a.determinant().abs() > 1e-12).then(|| (a.inverse() * glam::DVec3::from_array(r)).x)
}

/// The finite-element reference file (`validation/fem/`), if computed.
fn fem(name: &str) -> Option<Value> {
    let path = crate::store::results_dir().join(format!("fem-{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

/// The FE value of `quantity` for an entry whose parameters match `matches`, from the FE
/// reference file (`validation/fem/README.md`): the extrapolated value where the meshes
/// converge with an observed order of at least 1, else the finest mesh's (an order below 1 is
/// no asymptotic range; files written before that rule may still hold such an extrapolation).
pub(super) fn fem_value(
    file: &Value,
    matches: &dyn Fn(&Value) -> bool,
    quantity: &str,
) -> Option<f64> {
    let entries = file.get("entries")?.as_array()?;
    let e = entries
        .iter()
        .find(|e| e.get("params").is_some_and(matches))?;
    let q = e.get(quantity)?;
    let asymptotic = q
        .get("order")
        .and_then(Value::as_f64)
        .is_some_and(|p| p >= 1.0);
    q.get("extrapolated")
        .and_then(Value::as_f64)
        .filter(|_| asymptotic)
        .or_else(|| q.get("finest").and_then(Value::as_f64))
        .or_else(|| q.as_f64())
}

/// Whether parameter `key` (or its alias) of an FE entry equals `x`.
fn close(params: &Value, keys: &[&str], x: f64) -> bool {
    keys.iter()
        .find_map(|k| params.get(*k).and_then(Value::as_f64))
        .is_some_and(|a| (a - x).abs() < 1e-9 * x.abs().max(1.0))
}

/// The FE punching entry at compression `c` with the paper's punches.
fn punching_entry(c: f64) -> impl Fn(&Value) -> bool {
    move |p| close(p, &["compression", "c"], c) && close(p, &["punch_width"], 9e-3)
}

/// The FE pulling entry at `stretch` for a body of height/width `h_over_w`.
pub(super) fn pulling_entry(stretch: f64, h_over_w: f64) -> impl Fn(&Value) -> bool {
    move |p| {
        let aspect = p
            .get("H_p")
            .and_then(Value::as_f64)
            .zip(p.get("W_p").and_then(Value::as_f64))
            .map(|(h, w)| h / w);
        close(p, &["stretch"], stretch) && aspect.is_some_and(|a| (a - h_over_w).abs() < 1e-6)
    }
}

pub(super) fn fem_section(md: &mut String, fig_dir: &Path, rel_dir: &str) -> Result<(), String> {
    writeln!(
        md,
        "### Against finite elements: punching and clamped pulling\n"
    )
    .unwrap();
    let punching = fem("punching");
    let pulling = fem("pulling");
    if punching.is_none() && pulling.is_none() {
        writeln!(
            md,
            "The finite-element reference (`bash validation/fem/run.sh`) has not been computed \
             on this machine; the SPH side is below.\n"
        )
        .unwrap();
    } else {
        writeln!(
            md,
            "Plane-strain finite elements (scikit-fem, `validation/fem/`, with a mesh study: the \
             value is the extrapolated one where the meshes converge with an order of at least \
             1, else the finest mesh's). Punching: punches as wide as the strip, the SPH runs \
             with the strip's centre held in x (the FE solution's symmetric branch; see the next \
             section for the free runs). Target: within 5 % at the paper's resolution, \
             converging.\n\n\
             **Punch corners.** The FE punches have their corners rounded with r = 0.15 mm (half \
             the punch thickness), and so do the SPH runs compared with them (`edges r = 0.15 \
             mm`): the comparison. The paper's punches are sharp, and neither code resolves a \
             sharp corner. Node-to-surface contact hooks the FE strip on it (several \
             equilibria, README of `validation/fem/`); an SPH particle at a corner sharper than \
             about dp/2 takes a force that does not shrink with dp (the sharp rows below are \
             the same at H/dp 30, 45 and 60). The FE value at each compression is a quadratic \
             fit over ±0.05 of a load path recorded every 0.01: the mean of the saw-tooth that \
             FE nodes (and SPH particles) make as they slip round the corner one at a time. \
             The SPH forces are averaged over their force curves in the same way. An earlier \
             FE reference with r = 50 µm corners sampled that saw-tooth at single compressions. \
             Its extrapolation at 20 % had an observed order of 0.29, outside any asymptotic \
             range, and it moved the value by 6 %.\n"
        )
        .unwrap();
        if let Some(file) = &punching {
            // The FE's own corner checks (level 1, single samples on the coarse path).
            let check = |name: &str, key: &str, c: &str| {
                file.pointer(&format!("/checks/{name}/{key}/{c}/force"))
                    .and_then(Value::as_f64)
            };
            let small = check(
                "small_corner_radius",
                "relative_changes_small_vs_reference",
                "0.2",
            );
            let sharp = check("corner_radius", "relative_changes_sharp_vs_rounded", "0.2");
            let path = check("load_path", "relative_changes_coarse_vs_fine", "0.4");
            writeln!(
                md,
                "The FE's own corner checks, on level 1 with single samples at 20 % compression \
                 (upper bounds, taken on the saw-tooth): r = 50 µm instead of 0.15 mm changes \
                 the force by {}, sharp corners by {}. So part of the sharp SPH rows' excess \
                 is the corner itself, and the comparison needs the same rounded punches in both \
                 codes. At 40 and 50 % the FE answer depends on the load path (coarse steps \
                 instead of 0.01: {} at 40 %), because the strip has several equilibria there. \
                 The 5 % target is therefore read at 10–30 %.\n",
                pct(small),
                pct(sharp),
                pct(path),
            )
            .unwrap();
        }
    }
    // Punching force curve against compression, and the bulge at 30 %.
    writeln!(
        md,
        "| method | H/dp | force at 10 % | 20 % | 30 % | 40 % | 50 % | bulge at 30 % |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|").unwrap();
    let cs = [0.1, 0.2, 0.3, 0.4, 0.5];
    if let Some(file) = &punching {
        let mut row = "| FE | – ".to_string();
        for c in cs {
            let v = fem_value(file, &punching_entry(c), "force");
            write!(row, "| {} ", fmt_opt(v, 0)).unwrap();
        }
        let b = fem_value(file, &punching_entry(0.3), "bulge");
        writeln!(md, "{row}| {} |", fmt_opt(b, 4)).unwrap();
    }
    // The force at each compression of `cs`, with its difference from FE's.
    let force_cells = |pts: &[(f64, f64)]| {
        let mut cells = String::new();
        for c in cs {
            let v = smoothed_at(pts, c, FORCE_WINDOW);
            let ref_v = punching
                .as_ref()
                .and_then(|file| fem_value(file, &punching_entry(c), "force"));
            match ref_v {
                Some(_) => write!(cells, "| {} ({}) ", fmt_opt(v, 0), pct(rel(v, ref_v))),
                None => write!(cells, "| {} ", fmt_opt(v, 0)),
            }
            .unwrap();
        }
        cells
    };
    let mut plot = Vec::new();
    for m in METHODS {
        for r in PUNCH_RES {
            let Some(run) = load(&punch_sym_id(m, 0.5, r)) else {
                continue;
            };
            let pts = curve(&run, "compression");
            let mut row = format!("| {m}, sharp corners (the paper's) | {r} ");
            row.push_str(&force_cells(&pts));
            let b = num(&punch_sym_id(m, 0.3, r), "bulge");
            let ref_b = punching
                .as_ref()
                .and_then(|file| fem_value(file, &punching_entry(0.3), "bulge"));
            writeln!(md, "{row}| {} {} |", fmt_opt(b, 4), pct(rel(b, ref_b))).unwrap();
            if m == "tl-hf" && r == 30 {
                plot.push(Series {
                    label: format!("{m}, sharp, H/dp {r}"),
                    points: pts,
                    markers: false,
                });
            }
        }
    }
    // The same with the punch edges rounded: by the FE reference's radius (the comparison)
    // and by r = 50 µm (about dp/2 at H/dp 30).
    for (label, id_of) in [
        (
            "edges r = 0.15 mm",
            punch_fe_corner_id as fn(&str, u32) -> String,
        ),
        ("edges r = 50 µm", punch_round_id),
    ] {
        for m in METHODS {
            for r in PUNCH_RES {
                let Some(run) = load(&id_of(m, r)) else {
                    continue;
                };
                let pts = curve(&run, "compression");
                let mut row = format!("| {m}, {label} | {r} ");
                row.push_str(&force_cells(&pts));
                writeln!(md, "{row}| – |").unwrap();
                if label.contains("0.15") && (r == 30 || (m == "tl-hf" && r == 60)) {
                    plot.push(Series {
                        label: format!("{m}, r = 0.15 mm, H/dp {r}"),
                        points: pts,
                        markers: false,
                    });
                }
            }
        }
    }
    if let Some(file) = &punching {
        let pts: Vec<(f64, f64)> = cs
            .iter()
            .filter_map(|&c| Some((c, fem_value(file, &punching_entry(c), "force")?)))
            .collect();
        if !pts.is_empty() {
            plot.push(Series {
                label: "finite elements".into(),
                points: pts,
                markers: true,
            });
        }
    }
    writeln!(md).unwrap();
    if !plot.is_empty() {
        line_plot(
            &fig_dir.join("ext_punch_force.png"),
            "Punching strip: force per unit depth on a punch",
            "compression",
            "force (N/m)",
            &plot,
        )?;
        writeln!(md, "![punching force]({rel_dir}/ext_punch_force.png)\n").unwrap();
    }
    // Clamped pulling.
    writeln!(
        md,
        "Clamped grips (the paper's rows pulled at (0, ±v)); the FE body's height is the SPH \
         gauge between the grip rows, L − dp:\n"
    )
    .unwrap();
    writeln!(
        md,
        "| method | L/dp | stretch | force (N/m) | FE | err | neck width | FE | err | max disorder |"
    )
    .unwrap();
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
    for m in METHODS {
        for r in PULL_RES {
            for s in PULL_STRETCH {
                let Some(run) = load(&pull_fem_id(m, s, r)) else {
                    continue;
                };
                let matches = pulling_entry(s, 1.0 - 1.0 / r as f64);
                let ff = pulling
                    .as_ref()
                    .and_then(|p| fem_value(p, &matches, "force"));
                let fw = pulling
                    .as_ref()
                    .and_then(|p| fem_value(p, &matches, "neck_width"));
                let (f, w) = (run.num("reaction_force"), run.num("neck_width"));
                writeln!(
                    md,
                    "| {m} | {r} | {s} | {} | {} | {} | {} | {} | {} | {} |",
                    fmt_opt(f, 0),
                    fmt_opt(ff, 0),
                    pct(rel(f, ff)),
                    fmt_opt(w, 4),
                    fmt_opt(fw, 4),
                    pct(rel(w, fw)),
                    fmt_opt(run.num("max_disorder"), 3),
                )
                .unwrap();
            }
        }
    }
    writeln!(md).unwrap();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smoothed_force_is_the_quadratic_under_a_saw_tooth() {
        let f = |c: f64| 1e6 + 2e7 * c + 3e7 * c * c;
        // Exactly a quadratic: recovered to round-off.
        let pts: Vec<(f64, f64)> = (0..=100)
            .map(|k| (k as f64 * 0.005, f(k as f64 * 0.005)))
            .collect();
        for c in [0.1, 0.2, 0.5] {
            let v = smoothed_at(&pts, c, FORCE_WINDOW).unwrap();
            assert!((v / f(c) - 1.0).abs() < 1e-10, "{c}: {v} vs {}", f(c));
        }
        // With a ±3 % saw-tooth of period 0.02 on top: the fit lands within 0.5 % of the
        // quadratic, where a single sample can be 3 % off.
        let saw = |c: f64| 0.03 * (2.0 * ((c / 0.02).fract()) - 1.0);
        let jagged: Vec<(f64, f64)> = (0..=500)
            .map(|k| k as f64 * 0.001)
            .map(|c| (c, f(c) * (1.0 + saw(c))))
            .collect();
        for c in [0.1, 0.2, 0.3] {
            let v = smoothed_at(&jagged, c, FORCE_WINDOW).unwrap();
            assert!((v / f(c) - 1.0).abs() < 5e-3, "{c}: {v} vs {}", f(c));
        }
    }
}
