//! `sph advise`: before any run, the method and resolution expected to be cheapest for a
//! tolerance, from the project's stored trade-off runs (docs/tradeoffs.md).
//!
//! The stored runs are the Pareto scenes of `validate tradeoff`, embedded in this crate as
//! `data/tradeoffs.json` (written by `validate report` beside docs/tradeoffs.md, checked by a
//! test of the validation crate). A case is matched to the scene it is (high confidence when
//! its settings are those stored, medium when it changes them) or to the nearest scene class
//! (same kind of problem; medium when dimension and method family match, low otherwise),
//! stated as such. The suggestion is the cheapest stored run of that scene within the
//! tolerance whose finer runs are all within it too (a method that has converged there, not one
//! whose error merely crosses zero), the rule of docs/tradeoffs.md's tables; its cost for the
//! case asked about is predicted from the stored run's CPU time per particle-step and the
//! case's own dry run.

use serde::{Deserialize, Serialize};

/// One stored run of a trade-off scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredRun {
    /// The line of the plot (`tl-hf`, `ul-enog single`).
    pub line: String,
    /// The method.
    pub method: String,
    /// The line's own settings (`stepping=single`).
    pub extra: Vec<String>,
    /// The refinement value (H/dp, or a spacing).
    pub resolution: f64,
    /// Signed relative error against the scene's reference (null: none measured).
    pub error: Option<f64>,
    /// CPU seconds of the run (2 threads, no output).
    pub cpu_seconds: f64,
    /// Its work: neighbour pairs visited by the force evaluations (null: not recorded).
    pub work: Option<f64>,
    /// Particles.
    pub particles: f64,
    /// Steps.
    pub steps: f64,
}

/// One trade-off scene: a case with fixed settings and its runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredScene {
    /// Key (`plate2d`).
    pub key: String,
    /// Title (as in docs/tradeoffs.md).
    pub title: String,
    /// The case.
    pub case: String,
    /// Its fixed settings.
    pub fixed: Vec<String>,
    /// The refinement key.
    pub resolution_key: String,
    /// A finer run has a larger refinement value.
    pub finer_is_larger: bool,
    /// 2 or 3.
    pub dimension: u32,
    /// The kind of problem (`vibration`, `compression`, `static`, `pressure`, `impact`).
    pub kind: String,
    /// The runs.
    pub runs: Vec<StoredRun>,
}

/// The embedded trade-off data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TradeoffData {
    /// How the file was made.
    pub generated_by: String,
    /// The scenes.
    pub scenes: Vec<StoredScene>,
}

/// The trade-off data this build carries (`data/tradeoffs.json`).
pub fn stored() -> TradeoffData {
    serde_json::from_str(include_str!("../data/tradeoffs.json"))
        .expect("the embedded trade-off data is valid (checked by the validation crate)")
}

impl StoredScene {
    fn finer(&self, a: f64, b: f64) -> bool {
        if self.finer_is_larger {
            a > b
        } else {
            a < b
        }
    }

    /// The cheapest run within `tolerance` whose finer runs of the same line are all within it
    /// too (the rule of docs/tradeoffs.md's "to reach error ≤" tables).
    pub fn cheapest(&self, tolerance: f64) -> Option<&StoredRun> {
        let within = |r: &StoredRun| r.error.is_some_and(|e| e.abs() <= tolerance);
        self.runs
            .iter()
            .filter(|r| {
                within(r)
                    && r.cpu_seconds > 0.0
                    && self
                        .runs
                        .iter()
                        .filter(|q| q.line == r.line && self.finer(q.resolution, r.resolution))
                        .all(within)
            })
            .min_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds))
    }
}

/// How far the stored scene stands for the problem asked about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Confidence {
    /// The case's own stored runs, its settings unchanged.
    High,
    /// The case with other settings, or a scene of the same kind, dimension and methods.
    Medium,
    /// A scene of the same kind only.
    Low,
}

/// The kind of problem and dimension of each case, and the stored scene it is nearest to.
const CASE_CLASSES: &[(&str, &str, u32)] = &[
    ("oscillating-plate-2d", "vibration", 2),
    ("oscillating-plate-3d", "vibration", 3),
    ("bending-column-3d", "vibration", 3),
    ("twisting-column-3d", "vibration", 3),
    ("cantilever-plate-2d", "vibration", 2),
    ("punching-strip-2d", "compression", 2),
    ("pulling-strip-2d", "compression", 2),
    ("pulling-cylinder-3d", "compression", 3),
    ("stent-3d", "compression", 3),
    ("static-cantilever-2d", "static", 2),
    ("slab-tension-2d", "static", 2),
    ("pressurised-ring-2d", "pressure", 2),
    ("hertz-impact-3d", "impact", 3),
    ("taylor-bar-3d", "impact", 3),
    ("colliding-rings-2d", "impact", 2),
    ("colliding-balls-3d", "impact", 3),
    ("ball-plate-2d", "impact", 2),
    ("ball-plate-3d", "impact", 3),
    // A body on a rigid tool, loaded slowly (gravity): nearest to the tool-compression scenes.
    ("incline-block", "compression", 2),
    // A free body thrown into a fold: its faces meet at speed, nearest to the impacts.
    ("folding-strip", "impact", 2),
];

/// The kind and dimension of a case (`None` for a case not in the table).
pub fn class_of(case: &str) -> Option<(&'static str, u32)> {
    CASE_CLASSES
        .iter()
        .find(|c| c.0 == case)
        .map(|c| (c.1, c.2))
}

/// What `sph advise` says.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Advice {
    /// The stored scene the advice rests on.
    pub scene: String,
    /// Its title.
    pub title: String,
    /// How far it stands for the problem asked about.
    pub confidence: Confidence,
    /// Why, in words.
    pub why: String,
    /// The suggested run (`None`: no stored run meets the tolerance).
    pub run: Option<StoredRun>,
    /// The refinement key of the suggestion.
    pub resolution_key: String,
}

/// The advice for a case with the given `set` assignments (and the methods it runs), for a
/// relative `tolerance`.
pub fn advise(
    data: &TradeoffData,
    case: &str,
    methods: &[&str],
    set: &[String],
    tolerance: f64,
) -> Option<Advice> {
    let (kind, dimension) = class_of(case)?;
    let (scene, confidence, why) = if let Some(s) = data.scenes.iter().find(|s| s.case == case) {
        let key = |a: &String| a.split('=').next().unwrap_or("").trim().to_string();
        let changed: Vec<String> = set
            .iter()
            .filter(|a| !s.fixed.contains(a) && key(a) != s.resolution_key)
            .cloned()
            .collect();
        if changed.is_empty() {
            (
                s,
                Confidence::High,
                format!(
                    "this case's own stored runs ({})",
                    if s.fixed.is_empty() {
                        "its default settings".to_string()
                    } else {
                        format!("settings {}", s.fixed.join(" "))
                    }
                ),
            )
        } else {
            (
                s,
                Confidence::Medium,
                format!(
                    "this case's stored runs, made with {} and not with {}: the error at a \
                     resolution depends on the set-up",
                    if s.fixed.is_empty() {
                        "its defaults".to_string()
                    } else {
                        s.fixed.join(" ")
                    },
                    changed.join(" ")
                ),
            )
        }
    } else {
        return nearest(data, case, kind, dimension, methods, tolerance);
    };
    Some(advice_on(scene, confidence, why, methods, tolerance))
}

/// The advice that `scene` gives: its cheapest run within `tolerance` among `methods` only.
fn advice_on(
    scene: &StoredScene,
    confidence: Confidence,
    why: String,
    methods: &[&str],
    tolerance: f64,
) -> Advice {
    let mut usable = scene.clone();
    usable.runs.retain(|r| methods.contains(&r.method.as_str()));
    Advice {
        scene: scene.key.clone(),
        title: scene.title.clone(),
        confidence,
        why,
        run: usable.cheapest(tolerance).cloned(),
        resolution_key: scene.resolution_key.clone(),
    }
}

/// The advice for a problem without stored runs of its own (`subject` names it in the
/// reasons): the nearest stored scene of the same `kind`, preferring one that runs one of
/// `methods` (a suggestion needs one), then the same dimension; if no scene of the kind runs
/// them, the nearest that does (low confidence). `None` if no stored scene runs any of
/// `methods` or resembles the kind.
pub fn nearest(
    data: &TradeoffData,
    subject: &str,
    kind: &str,
    dimension: u32,
    methods: &[&str],
    tolerance: f64,
) -> Option<Advice> {
    let runs_methods =
        |s: &StoredScene| s.runs.iter().any(|r| methods.contains(&r.method.as_str()));
    let mut best: Option<(&StoredScene, u32)> = None;
    for s in data.scenes.iter() {
        // The methods first (a suggestion needs them), then the kind, then the dimension.
        let score = u32::from(runs_methods(s)) * 4
            + u32::from(s.kind == kind) * 2
            + u32::from(s.dimension == dimension);
        if (s.kind == kind || runs_methods(s)) && best.is_none_or(|(_, b)| score > b) {
            best = Some((s, score));
        }
    }
    let (scene, score) = best?;
    let confidence = if score == 7 {
        Confidence::Medium
    } else {
        Confidence::Low
    };
    let why = if scene.kind == kind {
        format!(
            "no stored runs of {subject}: the nearest stored scene of the same kind ({kind}{}{}), \
             whose errors at a resolution may differ",
            if scene.dimension == dimension {
                ", same dimension"
            } else {
                ", another dimension"
            },
            if runs_methods(scene) {
                ", same methods"
            } else {
                ", other methods"
            }
        )
    } else {
        format!(
            "no stored runs of {subject}, and no stored scene of its kind ({kind}) runs its \
             methods: the nearest that does ({}, {}), a different problem whose errors at a \
             resolution may differ widely",
            scene.kind,
            if scene.dimension == dimension {
                "same dimension"
            } else {
                "another dimension"
            }
        )
    };
    Some(advice_on(scene, confidence, why, methods, tolerance))
}

/// Particles across the thinnest part of each stored scene's body per unit of its refinement
/// value, and whether the value is a spacing (across = factor / value) or a count (across =
/// factor × value). From the cases' geometry: the plates, the punching strip and the cantilever
/// refine by H/dp across their height; the Lamé ring (inner radius 1.5 m, outer 4 m, fixed in
/// the stored runs) by its spacing across a 2.5 m wall; the Hertz ball by R/dp across its
/// diameter.
const ACROSS: &[(&str, f64, bool)] = &[
    ("plate2d", 1.0, false),
    ("homog", 1.0, false),
    ("cantilever", 1.0, false),
    ("lame", 2.5, true),
    ("hertz", 2.0, false),
    ("plate3d", 1.0, false),
];

/// Particles across the thinnest part of the body of stored scene `key` at refinement value
/// `resolution` (`None` for a scene not in the table).
pub fn particles_across(key: &str, resolution: f64) -> Option<f64> {
    let &(_, factor, spacing) = ACROSS.iter().find(|a| a.0 == key)?;
    Some(if spacing {
        factor / resolution
    } else {
        factor * resolution
    })
}

/// The kind of problem a scene file holds, as the stored scenes are classed: rigid tools or a
/// constraint that prescribes a velocity drive it (`compression`); else a pressure load
/// (`pressure`); else a quasi-static relaxation (`static`); else two or more bodies meet
/// (`impact`); else it is left to move (`vibration`).
pub fn scene_kind(spec: &sph_scene::spec::SceneSpec) -> &'static str {
    let driven = spec.constraints.iter().any(|c| {
        let c = c.get_ref();
        c.kind != "fixed" && c.velocity.iter().flatten().any(|&v| v != 0.0)
    });
    if !spec.tools.is_empty() || driven {
        "compression"
    } else if spec.loads.iter().any(|l| l.get_ref().kind == "pressure") {
        "pressure"
    } else if spec.relaxation.is_some() {
        "static"
    } else if spec.bodies.len() > 1 {
        "impact"
    } else {
        "vibration"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every case has a class, and every class kind has a stored scene.
    #[test]
    fn every_case_has_a_class_with_stored_runs() {
        let data = stored();
        for case in crate::all_cases() {
            let name = case.info().name;
            let (kind, _) = class_of(name).unwrap_or_else(|| panic!("{name} has no class"));
            assert!(
                data.scenes.iter().any(|s| s.kind == kind),
                "{name}: no stored scene of kind {kind}"
            );
        }
    }

    /// Every stored scene says how many particles its thinnest part has at a resolution.
    #[test]
    fn every_stored_scene_has_its_particles_across() {
        for s in stored().scenes {
            let r = s.runs[0].resolution;
            let n = particles_across(&s.key, r).unwrap_or_else(|| panic!("{}", s.key));
            assert!(n >= 2.0, "{}: {n} across at {r}", s.key);
        }
        assert_eq!(particles_across("hertz", 10.0), Some(20.0));
        assert_eq!(particles_across("lame", 0.1), Some(25.0));
    }

    /// A problem with no scene of its kind running its methods falls back to a scene that
    /// runs them, with low confidence, and says so.
    #[test]
    fn a_kind_without_the_methods_falls_back_to_a_scene_that_runs_them() {
        let data = stored();
        // The stored pressure scene runs MPS only.
        let a = nearest(&data, "ring.toml", "pressure", 2, &["mps"], 0.05).unwrap();
        assert_eq!(
            (a.scene.as_str(), a.confidence),
            ("lame", Confidence::Medium)
        );
        let b = nearest(&data, "ring.toml", "pressure", 2, &["tl-hf"], 0.05).unwrap();
        assert_eq!(b.confidence, Confidence::Low);
        assert!(b.run.iter().all(|r| r.method == "tl-hf"), "{b:?}");
        assert!(b.why.contains("no stored scene of its kind"), "{}", b.why);
        assert!(nearest(&data, "x", "pressure", 2, &["no-such-method"], 0.05).is_some());
    }

    /// A stored case asked about with its stored settings gets its own cheapest run, with
    /// high confidence; other settings lower it.
    #[test]
    fn a_stored_case_gets_its_own_cheapest_run() {
        let data = stored();
        let plate = data.scenes.iter().find(|s| s.key == "plate2d").unwrap();
        let methods: Vec<&str> = vec!["tl", "tl-hf", "tl-gm", "ul-og", "ul-oas", "ul-enog"];
        let a = advise(&data, "oscillating-plate-2d", &methods, &plate.fixed, 0.03).unwrap();
        assert_eq!(a.confidence, Confidence::High);
        assert_eq!(a.run.as_ref(), plate.cheapest(0.03));
        let b = advise(
            &data,
            "oscillating-plate-2d",
            &methods,
            &["nu=0.45".to_string()],
            0.03,
        )
        .unwrap();
        assert_eq!(b.confidence, Confidence::Medium);
        let c = advise(&data, "bending-column-3d", &["tl-hf"], &[], 0.03).unwrap();
        assert!(c.confidence != Confidence::High, "{c:?}");
        assert!(
            c.why.contains("no stored runs of bending-column-3d"),
            "{}",
            c.why
        );
    }
}
