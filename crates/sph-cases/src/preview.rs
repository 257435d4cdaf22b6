//! `sph preview SCENE --out DIR [--summary FILE.json]`: a scene's bodies, regions and tools built
//! without running ([`sph_scene::Scene::preview`]), written as a run's first snapshot would be
//! (`DIR/<name>-preview.h5` and `.xmf`: `position`, `volume`, `id`, `body`, `constraint`), drawn
//! (`DIR/<name>-preview.png`: 2D the particles coloured by body, and by constraint; 3D two cuts
//! through the middle) and reported per body (`particles`, `volume`, `mesh_volume`,
//! `volume_scale`, `surface_distance_rms`, `surface_distance_max` in units of dp, `volume_spread`).
//!
//! The same rules as `sph run` ([`crate::preflight::RunFiles`]): every destination is checked
//! before anything is built, nothing is written outside `DIR` and the summary file, no input
//! (the scene, its meshes, outlines and particle files) is ever written over, and each file
//! appears complete or not at all (written beside and renamed).

use crate::error::CaseError;
use crate::preflight::{write_summary, RunFiles};
use serde_json::{json, Map, Value as Json};
use sph_output::{create_writer, Backend, Dataset};
use sph_scene::{Preview, Scene};
use std::path::{Path, PathBuf};

/// What `sph preview` wrote.
#[derive(Clone, Debug)]
pub struct PreviewFiles {
    /// The HDF5 file (its XDMF sidecar beside it).
    pub results: PathBuf,
    /// The picture.
    pub picture: PathBuf,
    /// The per-body report, as written to `--summary`.
    pub summary: Map<String, Json>,
}

/// Builds `scene` (read from `scene_file`), and writes its initial particles and picture to
/// `out` and the report to `summary` (if given).
///
/// # Errors
/// A destination refused (before anything is built), the scene's own errors, a write that
/// fails.
pub fn preview(
    scene: &Scene,
    scene_file: &Path,
    out: &Path,
    summary: Option<&Path>,
) -> Result<PreviewFiles, CaseError> {
    let base = out.join(format!("{}-preview", scene.name()));
    let picture = base.with_extension("png");
    let mut inputs = vec![("the scene".to_string(), scene_file.to_path_buf())];
    inputs.extend(
        scene
            .input_files()
            .into_iter()
            .map(|f| ("a file the scene reads".to_string(), f)),
    );
    RunFiles {
        results: Some(base.clone()),
        summary: summary.map(Path::to_path_buf),
        inputs: inputs.clone(),
        ..Default::default()
    }
    .check()?;
    // The picture: the same checks as the summary (a regular file or nothing, not an input).
    RunFiles {
        summary: Some(picture.clone()),
        inputs,
        ..Default::default()
    }
    .check()?;
    let p = scene
        .preview()
        .map_err(|e| CaseError::Config(e.to_string()))?;
    let report = report(scene, &p);
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let mut w = create_writer(&base, Backend::default())?;
    let mut meta = Map::new();
    meta.insert("case".into(), json!(scene.name()));
    meta.insert("method".into(), json!(scene.method()));
    meta.insert("preview".into(), json!(true));
    meta.insert("particles".into(), json!(p.positions.len()));
    meta.insert("dimension".into(), json!(p.dimension));
    meta.insert("scene".into(), json!(scene.resolved_text()));
    meta.insert("crate_version".into(), json!(env!("CARGO_PKG_VERSION")));
    w.write_meta(&meta)?;
    let n = p.positions.len();
    w.write_snapshot(
        0.0,
        0,
        &[
            Dataset::vectors("position", &p.positions),
            Dataset::scalars("volume", &p.volumes),
            Dataset::u64_scalars("id", &(0..n as u64).collect::<Vec<_>>()),
            Dataset::u64_scalars(
                "body",
                &p.body.iter().map(|&b| b as u64).collect::<Vec<_>>(),
            ),
            Dataset::u64_scalars(
                "constraint",
                &p.constraint.iter().map(|&c| c as u64).collect::<Vec<_>>(),
            ),
        ],
    )?;
    w.write_summary(&report)?;
    let results = w.finish()?;
    draw(scene, &p, &picture)?;
    if let Some(path) = summary {
        let text = serde_json::to_string_pretty(&Json::Object(report.clone())).expect("json");
        write_summary(path, &text)?;
    }
    Ok(PreviewFiles {
        results,
        picture,
        summary: report,
    })
}

/// The report: per body (by name) its figures, the tools, the particle count.
fn report(scene: &Scene, p: &Preview) -> Map<String, Json> {
    let bodies: Map<String, Json> = p
        .bodies
        .iter()
        .map(|b| {
            (
                b.name.clone(),
                json!({
                    "particles": b.particles,
                    "dp": b.dp,
                    "volume": b.volume,
                    "mesh_volume": b.mesh_volume,
                    "volume_scale": b.volume_scale,
                    "surface_distance_rms": b.surface_distance_rms,
                    "surface_distance_max": b.surface_distance_max,
                    "volume_spread": b.volume_spread,
                }),
            )
        })
        .collect();
    let mut m = Map::new();
    m.insert("scene".into(), json!(scene.name()));
    m.insert("status".into(), json!("ok"));
    m.insert("particles".into(), json!(p.positions.len()));
    m.insert("bodies".into(), Json::Object(bodies));
    m.insert("tools".into(), json!(p.tools));
    m
}

/// The picture, written beside and renamed into place.
fn draw(scene: &Scene, p: &Preview, path: &Path) -> Result<(), CaseError> {
    use sph_plot::Frame;
    let dp = p.bodies.iter().map(|b| b.dp).fold(f64::INFINITY, f64::min);
    let nb = p.bodies.len().max(1) as f64;
    let by_body = |i: usize| (p.body[i] as f64 + 1.0) / nb;
    let nc = p.constraint.iter().copied().max().unwrap_or(0).max(1) as f64;
    let frames: Vec<Frame> = if p.dimension == 2 {
        vec![
            Frame {
                title: "bodies".into(),
                points: (0..p.positions.len())
                    .map(|i| (p.positions[i][0], p.positions[i][1], by_body(i)))
                    .collect(),
            },
            Frame {
                title: "constraints (0: free)".into(),
                points: (0..p.positions.len())
                    .map(|i| {
                        let x = p.positions[i];
                        (x[0], x[1], p.constraint[i] as f64 / nc)
                    })
                    .collect(),
            },
        ]
    } else {
        // Cuts through the middle of the particles' bounds, one spacing thick.
        let mid = |k: usize| {
            let (lo, hi) = p
                .positions
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x[k]), b.max(x[k])));
            0.5 * (lo + hi)
        };
        let (zm, ym) = (mid(2), mid(1));
        vec![
            Frame {
                title: format!("cut z = {zm:.4e}, by body"),
                points: (0..p.positions.len())
                    .filter(|&i| (p.positions[i][2] - zm).abs() <= 0.5 * dp)
                    .map(|i| (p.positions[i][0], p.positions[i][1], by_body(i)))
                    .collect(),
            },
            Frame {
                title: format!("cut y = {ym:.4e} (x, z), by body"),
                points: (0..p.positions.len())
                    .filter(|&i| (p.positions[i][1] - ym).abs() <= 0.5 * dp)
                    .map(|i| (p.positions[i][0], p.positions[i][2], by_body(i)))
                    .collect(),
            },
        ]
    };
    // Drawn to a name of this process beside the destination (the encoder picks the format
    // by extension), then renamed into place: the picture is complete or absent.
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("preview.png");
    let tmp = path.with_file_name(format!(".{name}.{}.tmp.png", std::process::id()));
    let title = format!("{}: {} particles", scene.name(), p.positions.len());
    let drawn = sph_plot::particle_frames(&tmp, &title, &frames, 2, 1.0, dp)
        .map_err(CaseError::Config)
        .and_then(|_| std::fs::rename(&tmp, path).map_err(|e| io(path, e)));
    if drawn.is_err() {
        std::fs::remove_file(&tmp).ok();
    }
    drawn
}

fn io(path: &Path, e: std::io::Error) -> CaseError {
    CaseError::Io {
        path: path.display().to_string(),
        source: e,
    }
}
