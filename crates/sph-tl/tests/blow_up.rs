//! Blow-up detection (issue 14, item 8): an inverted particle (`J = det F ≤ 0`) stops a TL run
//! with [`Error::Inverted`] even under Saint Venant–Kirchhoff, whose stress stays finite there
//! and would otherwise let the run go on with an inverted body.

use glam::DVec2;
use sph_core::Body;
use sph_core::{Error, Solver, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, SaintVenantKirchhoff};
use sph_tl::{Shear, TlParams, TlSolver};

const DP: f64 = 0.01;

#[test]
fn a_body_crushed_beyond_zero_volume_stops_as_inverted() {
    let c = ElasticConstants::from_youngs(2.0e6, 0.3975, 1000.0).unwrap();
    let lattice = Lattice::<D2>::new(DP, DVec2::ZERO).unwrap();
    let set = ParticleSet::fill(
        &lattice,
        &Aabb::new(DVec2::ZERO, DVec2::new(10.0 * DP, 6.0 * DP)).unwrap(),
    )
    .unwrap();
    // Uniaxial crush v = (−λ (x − x_c), 0) at 20 c0 at the ends: F_xx = 1 − λt reaches zero
    // after 1/λ = 0.25 dp/c0, about ten steps; nothing elastic stops it in time.
    let lambda = 20.0 * c.sound_speed / (5.0 * DP);
    let velocities = set
        .positions()
        .iter()
        .map(|x| DVec2::new(-lambda * (x.x - 5.0 * DP), 0.0))
        .collect();
    let body = Body::<D2> {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities,
        densities: Vec::new(),
    };
    let params = TlParams {
        damping: false,
        ..TlParams::default()
    };
    for shear in [
        Shear::Original,
        Shear::hourglass_free(),
        Shear::ganzenmuller(),
    ] {
        let mut s =
            TlSolver::new(body.clone(), SaintVenantKirchhoff::new(c), shear, params).unwrap();
        let mut result = Ok(());
        for _ in 0..10_000 {
            if let Err(e) = s.step(f64::INFINITY) {
                result = Err(e);
                break;
            }
        }
        match result {
            Err(Error::Inverted { jacobian, .. }) => assert!(jacobian <= 0.0),
            other => panic!("{shear:?}: expected Inverted, got {other:?}"),
        }
    }
}
