//! A rubber block on a fixed floor squeezed by a rigid frictionless punch, quasi-statically,
//! with TL-SPH-HF; writes `out/examples/tl-squeeze.h5` (and `.xmf` for ParaView).
//! `cargo run --example tl_squeeze`
use sph_solids::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (dp, w, h) = (0.5e-3, 0.02, 0.01);
    let corner = DVec2::new(-w / 2.0, 0.0);
    let block = Aabb::<D2>::new(corner, DVec2::new(w / 2.0, h))?;
    let set = ParticleSet::fill(&Lattice::new(dp, corner)?, &block)?;
    let (floor, n) = (set.select(|x| x.y < dp), set.len());
    let law = NeoHookean::new(ElasticConstants::from_youngs(1e7, 0.45, 1100.0)?);
    // A punch half as wide as the block, pressing 2 mm down at 1 m/s after a 0.2 ms start.
    let punch = ToolShape::cuboid(DVec2::new(-w / 4.0, h), DVec2::new(w / 4.0, h + 1e-3))?;
    let motion = ToolMotion::new(DVec2::new(0.0, -1.0), 1.0, 2e-4, 2e-3)?;
    let mut grips = Constraints::new();
    grips.push_named("floor", Constraint::Fixed { particles: floor }, n)?;
    let params = TlParams {
        stretch_limited_dt: true,
        ..TlParams::default()
    };
    let relax = PairwiseDamping::new(PairwiseDamping::viscosity_for(1.0, 1100.0, 1e7, h))?;
    let mut solver = TlSolver::new(Body::from(set), law, TlShear::hourglass_free(), params)?
        .with_constraints(grips)
        .with_tools(vec![RigidTool::new("punch", punch, motion.clone())])?
        .with_relaxation(relax)?;
    let (record, _) = Run::until(1.25 * motion.arrival_time())
        .named("tl-squeeze")
        .write_to("out/examples/tl-squeeze")
        .execute(&mut solver)?;
    let series = solver.series();
    let punch = series.iter().find(|s| s.name == "punch").expect("recorded");
    let force = punch.column("force_y").and_then(|f| f.last().copied());
    println!(
        "{} steps; punch force {force:?} N/m; {:?}",
        record.steps, record.file
    );
    Ok(())
}
