//! Stored and recomputed reference pair data ([`PairStorage`]) give the same run bit for bit:
//! every shear treatment, 2D and 3D, a jittered body with free surfaces, a clamp, damping and
//! the pairwise relaxation.

use sph_core::relaxation::PairwiseDamping;
use sph_core::{Body, Constraints, Dim, Solver, D2, D3};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, NeoHookean};
use sph_tl::{PairStorage, Shear, TlParams, TlSolver};

/// A jittered block of `n` particles per side, swinging: a shear velocity field, the bottom
/// layer clamped.
fn body<D: Dim>(n: usize) -> (Body<D>, Constraints<D>) {
    let dp = 0.01;
    let top = D::vector([n as f64 * dp, n as f64 * dp, n as f64 * dp]);
    let set = ParticleSet::fill(
        &Lattice::<D>::new(dp, D::zero()).unwrap(),
        &Aabb::<D>::new(D::zero(), top).unwrap(),
    )
    .unwrap();
    let mut positions = set.positions().to_vec();
    for (k, x) in positions.iter_mut().enumerate() {
        let jitter = |s: u64| ((k as u64 * 2_654_435_761 + s) % 997) as f64 / 997.0 - 0.5;
        *x += D::vector([
            0.1 * dp * jitter(3),
            0.1 * dp * jitter(5),
            0.1 * dp * jitter(11),
        ]);
    }
    let clamp = Constraints::fixed(set.select(|x| D::component(x, 1) < dp), set.len()).unwrap();
    let velocities = positions
        .iter()
        .map(|&x| D::vector([3.0 * D::component(x, 1), 0.0, -D::component(x, 0)]))
        .collect();
    let body = Body::<D> {
        positions,
        volumes: set.volumes().to_vec(),
        dp,
        velocities,
        densities: Vec::new(),
    };
    (body, clamp)
}

fn run<D: Dim>(
    n: usize,
    shear: Shear,
    storage: PairStorage,
    relax: bool,
) -> TlSolver<D, NeoHookean> {
    let (body, clamp) = body::<D>(n);
    let law = NeoHookean::new(ElasticConstants::from_youngs(1e6, 0.45, 1100.0).unwrap());
    let params = TlParams {
        pair_storage: storage,
        ..TlParams::default()
    };
    let mut s = TlSolver::new(body, law, shear, params)
        .unwrap()
        .with_constraints(clamp);
    if relax {
        let damping = PairwiseDamping::new(PairwiseDamping::viscosity_for(1.0, 1100.0, 1e6, 0.1));
        s = s.with_relaxation(damping.unwrap()).unwrap();
    }
    for _ in 0..60 {
        s.step(f64::INFINITY).unwrap();
    }
    s
}

fn check<D: Dim>(n: usize) {
    for shear in [
        Shear::Original,
        Shear::hourglass_free(),
        Shear::ganzenmuller(),
    ] {
        for relax in [false, true] {
            let stored = run::<D>(n, shear, PairStorage::Stored, relax);
            let recomputed = run::<D>(n, shear, PairStorage::Recomputed, relax);
            assert_eq!(stored.pair_storage(), PairStorage::Stored);
            assert_eq!(recomputed.pair_storage(), PairStorage::Recomputed);
            // The runs moved (the comparison is not of two resting bodies) ...
            let moved = stored
                .positions()
                .iter()
                .zip(stored.reference_positions())
                .any(|(&x, &x0)| D::norm(x - x0) > 1e-5);
            assert!(moved, "{shear:?}: nothing moved");
            // ... and agree to the last bit.
            assert_eq!(
                stored.positions(),
                recomputed.positions(),
                "{shear:?} {relax}"
            );
            assert_eq!(
                stored.velocities(),
                recomputed.velocities(),
                "{shear:?} {relax}"
            );
            assert_eq!(
                stored.deformation_gradients(),
                recomputed.deformation_gradients(),
                "{shear:?} {relax}"
            );
            assert_eq!(
                stored.disorder(),
                recomputed.disorder(),
                "{shear:?} {relax}"
            );
        }
    }
}

#[test]
fn stored_and_recomputed_pair_data_give_the_same_run_2d() {
    check::<D2>(9);
}

#[test]
fn stored_and_recomputed_pair_data_give_the_same_run_3d() {
    check::<D3>(5);
}

#[test]
fn the_default_stores_and_the_key_names_round_trip() {
    assert_eq!(TlParams::default().pair_storage, PairStorage::Stored);
    for s in [PairStorage::Stored, PairStorage::Recomputed] {
        assert_eq!(PairStorage::from_name(s.name()), Some(s));
    }
    assert_eq!(PairStorage::from_name("auto"), None);
}

#[test]
fn coincident_reference_positions_are_refused_in_either_form() {
    let (mut body, _) = body::<D2>(6);
    body.positions[7] = body.positions[8];
    let law = NeoHookean::new(ElasticConstants::from_youngs(1e6, 0.45, 1100.0).unwrap());
    for shear in [Shear::hourglass_free(), Shear::ganzenmuller()] {
        for storage in [PairStorage::Stored, PairStorage::Recomputed] {
            let params = TlParams {
                pair_storage: storage,
                ..TlParams::default()
            };
            let e = TlSolver::new(body.clone(), law, shear, params)
                .err()
                .unwrap_or_else(|| panic!("{shear:?} {storage:?}: accepted"))
                .to_string();
            assert!(
                e.contains("positions") && e.contains("coincides with a neighbour"),
                "{shear:?} {storage:?}: {e}"
            );
        }
    }
}
