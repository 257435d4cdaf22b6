//! A rubber cantilever swinging from its clamp, with the Hamiltonian particle model (MPS) and
//! a probe at the tip; writes `out/examples/mps-cantilever.h5` (and `.xmf`).
//! `cargo run --example mps_cantilever`
use sph_solids::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (dp, l, h) = (2e-3, 0.1, 0.01);
    let corner = DVec2::new(-0.02, -h / 2.0);
    let plate = Aabb::<D2>::new(corner, DVec2::new(l, h / 2.0))?;
    let set = ParticleSet::fill(&Lattice::new(dp, corner)?, &plate)?;
    let (clamp, n) = (set.select(|x| x.x < 0.0), set.len());
    let tip = set.nearest(DVec2::new(l, 0.0)).expect("particles") as u32;
    // The clamped part at rest; the free part with a tip speed of 0.5 m/s, growing as x².
    let body = Body::from(set).with_velocity(|x| DVec2::new(0.0, 0.5 * (x.x.max(0.0) / l).powi(2)));
    let law = SaintVenantKirchhoff::new(ElasticConstants::from_youngs(2e6, 0.3, 1000.0)?);
    let mut solver = MpsSolver::new(body, law, MpsParams::default())?
        .with_constraints(Constraints::fixed(clamp, n)?)
        .with_probes(vec![Probe::particle("tip", tip)], 1e-4)?;
    let (record, _) = Run::until(0.1)
        .named("mps-cantilever")
        .write_to("out/examples/mps-cantilever")
        .execute(&mut solver)?;
    let tip = &solver.probes()[0];
    let highest = tip.positions.iter().map(|x| x.y).fold(f64::MIN, f64::max);
    println!(
        "{} steps; tip rose to {highest:.4} m; {:?}",
        record.steps, record.file
    );
    Ok(())
}
