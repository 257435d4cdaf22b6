//! The finite-element reference of the 2D oscillating plate: the small-amplitude period of its
//! first bending mode in plane-strain linear elasticity, per small-strain law, clamp, thickness
//! and Poisson's ratio (`validation/fem/plate_modes.py`, which writes
//! `validation/results/fem-plate-modes.json`; a P2 mesh study with Richardson extrapolation,
//! documented in `validation/fem/README.md`).
//!
//! The SPH methods do not all discretise the same 2D material: plain TL and TL-GM with the
//! Saint Venant–Kirchhoff law are plane-strain Hooke at small strain, while TL-HF's
//! volumetric–deviatoric law and the UL solvers split the stress with the spatial dimension
//! (`d = 2`: `λ_eff = K − G` instead of `K − 2G/3`, a softer plate). Each method is therefore
//! measured against the continuum of its own law ([`law_of`]); the Hooke value is the plane-strain
//! plate itself.

use serde_json::Value;

/// The small-strain law a method has in 2D plane strain, as the FE file names it: `hooke` for
/// TL and TL-GM (SVK), `d2-split` for TL-HF and the UL methods. UL-ENOG's shear term (eq 19,
/// ζ = 3.5) is not exactly the split's `G ∇²v` (the FE README's lattice analysis), and UL-OAS
/// adds an artificial stress: for both the split is the nearest law, not their exact limit.
pub fn law_of(method: &str) -> &'static str {
    match method {
        "tl" | "tl-gm" => "hooke",
        _ => "d2-split",
    }
}

fn file() -> Option<Value> {
    let path = crate::store::results_dir().join("fem-plate-modes.json");
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

/// The extrapolated FE period (s) of the plate with `law`, `clamp` (`frame` or `solid`),
/// thickness `h` (m) and Poisson's ratio `nu`, if the file holds that entry.
pub fn period(law: &str, clamp: &str, h: f64, nu: f64) -> Option<f64> {
    let doc = file()?;
    doc["entries"].as_array()?.iter().find_map(|e| {
        let p = &e["params"];
        let same = |k: &str, v: f64| p[k].as_f64().is_some_and(|x| (x - v).abs() < 1e-12);
        (p["law"] == law && p["clamp"] == clamp && same("H", h) && same("nu", nu))
            .then(|| e["period_best"].as_f64())
            .flatten()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stored_reference_has_both_laws_and_the_softer_split_is_slower() {
        // The committed FE file: the d = 2 split is softer in plane strain, so its period is
        // longer than Hooke's at every ν (by 0.6–4 %, the in-plane moduli's ratio).
        for nu in [0.22, 0.3, 0.3975, 0.4] {
            let hooke = period("hooke", "frame", 0.02, nu).expect("hooke entry");
            let split = period("d2-split", "frame", 0.02, nu).expect("split entry");
            assert!(
                split > hooke && split < 1.05 * hooke,
                "{nu}: {hooke} {split}"
            );
        }
        assert_eq!(period("hooke", "frame", 0.02, 0.5), None);
    }
}
