//! A user's crate: a scene from a TOML text (sph-scene) and the same scene built with the
//! library (sph-core, sph-materials, sph-tl, sph-driver), both run and written (sph-output);
//! the final positions must agree bit for bit. Exits non-zero on any failure.

use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_core::glam::DVec2;
use sph_core::{Body, Constraints, D2};
use sph_driver::{Run, RunOptions};
use sph_materials::{ElasticConstants, NeoHookean};
use sph_scene::Scene;
use sph_tl::{Shear, TlParams, TlSolver};
use std::path::Path;

const SCENE: &str = r#"
name = "external-plate"
dimension = 2
method = "tl-hf"
end_time = 2e-3

[material]
law = "neo-hookean"
density = 1000.0
youngs_modulus = 2e6
nu = 0.3

[[body]]
name = "plate"
dp = 2.5e-3
shape = { box = { min = [0.0, 0.0], max = [0.1, 0.01] } }

[[constraint]]
type = "fixed"
region = { box = { min = [-1.0, -1.0], max = [5e-3, 1.0] } }

[[load]]
type = "gravity"
acceleration = [0.0, -9.81]
"#;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::temp_dir().join(format!("sph-external-{}", std::process::id()));
    let scene = Scene::parse(SCENE, "external.toml", Path::new("."), "external")?;
    let options = RunOptions {
        output: Some(dir.join("scene")),
        ..RunOptions::default()
    };
    let (from_file, _) = scene.run(&options)?;
    if let Some(f) = &from_file.failure {
        return Err(format!("the scene failed: {f}").into());
    }

    let dp = 2.5e-3;
    let plate = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.1, 0.01))?;
    let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO)?, &plate)?;
    let (clamp, n) = (set.select(|x| x.x <= 5e-3), set.len());
    let mut loads = sph_core::Loads::new();
    loads.add_body_acceleration(
        None,
        sph_core::TimeFunction::constant(DVec2::new(0.0, -9.81)),
    );
    let law = NeoHookean::new(ElasticConstants::from_youngs(2e6, 0.3, 1000.0)?);
    let mut solver = TlSolver::new(
        Body::from(set),
        law,
        Shear::hourglass_free(),
        TlParams::default(),
    )?
    .with_constraints(Constraints::fixed(clamp, n)?)
    .with_loads(loads);
    let (in_rust, _) = Run::until(2e-3)
        .write_to(dir.join("rust"))
        .execute(&mut solver)?;
    let last_positions = |file: &Option<std::path::PathBuf>| -> Result<Vec<u64>, String> {
        let path = file.as_ref().ok_or("no results file")?;
        let contents = sph_output::read_file(path).map_err(|e| e.to_string())?;
        let last = contents.snapshots.last().ok_or("no snapshot")?;
        let x = last.dataset("position").and_then(|d| d.as_f64());
        Ok(x.ok_or("no positions")?
            .iter()
            .map(|v| v.to_bits())
            .collect())
    };
    let same = last_positions(&in_rust.file)? == last_positions(&from_file.file)?;
    std::fs::remove_dir_all(&dir)?;
    if in_rust.steps != from_file.steps || !same {
        return Err(format!(
            "the scene file and the library differ: {} and {} steps, same final positions: {same}",
            from_file.steps, in_rust.steps
        )
        .into());
    }
    println!(
        "external crate: the scene file and the library ran {} steps to t = {} s, bit-identical",
        in_rust.steps, in_rust.time
    );
    Ok(())
}
