//! Two rubber discs colliding at 5 % of the sound speed, with UL-SPH-ENOG and contact between
//! the bodies; writes `out/examples/ul-impact.h5` (and `.xmf`).
//! `cargo run --example ul_impact`
use sph_solids::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (dp, r) = (1e-3, 0.01);
    let mut set = annulus_polar(DVec2::new(-r - dp, 0.0), 0.0, r, dp)?;
    let right = set.extend(&annulus_polar(DVec2::new(r + dp, 0.0), 0.0, r, dp)?)?;
    let body_of: Vec<u32> = (0..set.len()).map(|i| right.contains(&i) as u32).collect();
    let constants = ElasticConstants::from_youngs(1e7, 0.4, 1200.0)?;
    let v0 = 0.05 * constants.sound_speed;
    let velocities = body_of
        .iter()
        .map(|&b| DVec2::new(if b == 1 { -v0 } else { v0 }, 0.0))
        .collect();
    let body = Body::from(set).with_velocities(velocities);
    let mut solver = UlSolver::new(body, constants, UlShear::non_nested(), UlParams::default())?
        .with_contact(body_of.clone())?;
    let (record, _) = Run::until(1.5 * 4.0 * r / v0)
        .named("ul-impact")
        .write_to("out/examples/ul-impact")
        .execute(&mut solver)?;
    // The discs rebound: the left one now moves left (ids follow the particles).
    let ids = solver.original_index();
    let (mut p, mut m) = (0.0, 0.0);
    for (k, v) in solver.velocities().iter().enumerate() {
        if body_of[ids[k] as usize] == 0 {
            (p, m) = (p + v.x, m + 1.0);
        }
    }
    println!(
        "{} steps; left disc {:.2} m/s after {v0:.2}; {:?}",
        record.steps,
        p / m,
        record.file
    );
    Ok(())
}
