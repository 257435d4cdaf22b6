//! `sph advise`'s data and suggestions against the stored trade-off runs: the data file the
//! `sph` command carries is what `validate report` writes from them, and for every scene and
//! tolerance of docs/tradeoffs.md the advice for the scene's own case is the cheapest stored run
//! meeting the tolerance (within 1.5x of its CPU time: the target; here exactly it).

use sph_cases::advise::{advise, stored, Confidence};
use sph_validation::tradeoff::advice_data;

/// `crates/sph-cases/data/tradeoffs.json` is current (regenerate with `validate report`).
#[test]
fn the_advice_data_is_what_the_report_writes() {
    let path = advice_data::path(&sph_validation::workspace_root());
    let committed = std::fs::read_to_string(&path).unwrap();
    assert!(
        committed == advice_data::text(),
        "{} is out of date: run `cargo run --release -p sph-validation --bin validate -- report`",
        path.display()
    );
}

#[test]
fn the_advice_for_each_stored_scene_is_its_cheapest_run() {
    let data = stored();
    assert!(data.scenes.len() >= 5);
    for scene in &data.scenes {
        let case = sph_cases::find_case(&scene.case).unwrap();
        let methods = case.info().methods;
        for tol in [0.01, 0.03, 0.10] {
            let a = advise(&data, &scene.case, methods, &scene.fixed, tol).unwrap();
            assert_eq!(a.scene, scene.key);
            assert_eq!(a.confidence, Confidence::High, "{}", scene.key);
            let best = scene
                .runs
                .iter()
                .filter(|r| methods.contains(&r.method.as_str()))
                .filter(|r| r.error.is_some_and(|e| e.abs() <= tol))
                .filter(|r| {
                    scene
                        .runs
                        .iter()
                        .filter(|q| {
                            q.line == r.line
                                && if scene.finer_is_larger {
                                    q.resolution > r.resolution
                                } else {
                                    q.resolution < r.resolution
                                }
                        })
                        .all(|q| q.error.is_some_and(|e| e.abs() <= tol))
                })
                .map(|r| r.cpu_seconds)
                .fold(f64::INFINITY, f64::min);
            match &a.run {
                Some(r) => assert!(
                    r.cpu_seconds <= 1.5 * best,
                    "{} at {tol}: {} s against the cheapest {best} s",
                    scene.key,
                    r.cpu_seconds
                ),
                None => assert!(best.is_infinite(), "{} at {tol}", scene.key),
            }
        }
    }
}
