//! `crates/sph-cases/data/tradeoffs.json`: the stored Pareto runs as `sph advise` carries them
//! (written by `validate report` beside docs/tradeoffs.md; a test checks it is current).

use super::*;
use sph_cases::advise::{StoredRun, StoredScene, TradeoffData};

/// The stored runs of `scene` (every line and resolution with a stored run, failed ones with
/// no error), as `sph advise` uses them.
pub(super) fn stored_scene(scene: &Scene) -> StoredScene {
    let mut res: Vec<f64> = scene.quick.iter().chain(scene.full).copied().collect();
    res.sort_by(f64::total_cmp);
    res.dedup();
    let (kind, dimension) =
        sph_cases::advise::class_of(scene.case).expect("every trade-off case has a class");
    let runs = scene
        .lines
        .iter()
        .flat_map(|l| res.iter().map(move |&r| (l, r)))
        .filter_map(|(l, r)| {
            let run = crate::cost::load(&scene_run_id(scene, l, r))?;
            (run.set == scene_set(scene, l, r)).then_some((l, r, run))
        })
        .map(|(l, r, run)| StoredRun {
            line: l.label.into(),
            method: l.method.into(),
            extra: l.extra.iter().map(|s| s.to_string()).collect(),
            resolution: r,
            error: (run.exit_code == 0)
                .then(|| value_of(&run, scene.measure, l.method))
                .flatten(),
            cpu_seconds: run.cpu_seconds,
            work: run.work(),
            particles: run.num("particles").unwrap_or(f64::NAN),
            steps: run.num("steps").unwrap_or(f64::NAN),
        })
        .collect();
    StoredScene {
        key: scene.key.into(),
        title: scene.title.into(),
        case: scene.case.into(),
        fixed: scene.fixed.iter().map(|s| s.to_string()).collect(),
        resolution_key: scene.resolution_key.into(),
        finer_is_larger: scene.resolution_key != "dp",
        dimension,
        kind: kind.into(),
        runs,
    }
}

/// The data of every scene with stored runs.
pub fn data() -> TradeoffData {
    TradeoffData {
        generated_by: "cargo run --release -p sph-validation --bin validate -- report".into(),
        scenes: scenes()
            .iter()
            .map(stored_scene)
            .filter(|s| !s.runs.is_empty())
            .collect(),
    }
}

/// The file's text (pretty JSON with a final newline).
pub fn text() -> String {
    serde_json::to_string_pretty(&data()).expect("serialises") + "\n"
}

/// Where the file lives.
pub fn path(root: &Path) -> std::path::PathBuf {
    root.join("crates/sph-cases/data/tradeoffs.json")
}
