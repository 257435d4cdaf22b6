//! Distributed TL runs on in-process ranks (`sph_core::comm::ThreadRanks`): the same final state
//! as one process, bit for bit, for 1, 2 and 3 ranks; momentum conserved; halo as computed.

use glam::DVec3;
use sph_core::comm::{Communicator, ThreadRanks};
use sph_core::{Body, Constraint, Constraints, Probe, Solver, D3};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, NeoHookean};
use sph_tl::{distribute, HfLaplacian, PairStorage, Shear, TlParams, TlSolver};
use std::sync::Arc;

const DP: f64 = 0.1;

/// A 4 × 4 × 16 column of side 0.4 (256 particles), bending sideways.
fn column(clamped: bool, shear: Shear, storage: PairStorage) -> TlSolver<D3, NeoHookean> {
    column_built(clamped, shear, storage, false)
}

/// The column, built whole (`TlSolver::new`) or for ranks (`TlSolver::for_ranks`: no
/// neighbour data until distributed).
fn column_built(
    clamped: bool,
    shear: Shear,
    storage: PairStorage,
    for_ranks: bool,
) -> TlSolver<D3, NeoHookean> {
    let params = TlParams {
        pair_storage: storage,
        ..TlParams::default()
    };
    column_with(clamped, shear, params, for_ranks)
}

/// The column with any numerical parameters.
fn column_with(
    clamped: bool,
    shear: Shear,
    params: TlParams,
    for_ranks: bool,
) -> TlSolver<D3, NeoHookean> {
    let shape = Aabb::<D3>::new(DVec3::ZERO, DVec3::new(0.4, 0.4, 1.6)).unwrap();
    let set = ParticleSet::fill(&Lattice::new(DP, DVec3::ZERO).unwrap(), &shape).unwrap();
    let clamp = set.select(|x| x.z < 2.0 * DP);
    let body = Body::from(set).with_velocity(|x| DVec3::new(0.5 * x.z, 0.2 * x.z, 0.0));
    let law = NeoHookean::new(ElasticConstants::from_youngs(2e6, 0.4, 1000.0).unwrap());
    let s = if for_ranks {
        TlSolver::for_ranks(body, law, shear, params).unwrap()
    } else {
        TlSolver::new(body, law, shear, params).unwrap()
    };
    let probe = Probe::point(
        "tip",
        DVec3::new(0.2, 0.2, 1.6),
        s.reference_positions(),
        s.volumes(),
        s.kernel(),
    )
    .unwrap();
    let n = s.len();
    let s = s.with_probes(vec![probe], 0.0).unwrap();
    if clamped {
        let mut c = Constraints::new();
        c.push(Constraint::Fixed { particles: clamp }, n).unwrap();
        s.with_constraints(c)
    } else {
        s
    }
}

const STEPS: usize = 60;

struct Outcome {
    positions: Vec<DVec3>,
    velocities: Vec<DVec3>,
    probe: Vec<DVec3>,
    momentum: DVec3,
    energy: (f64, f64),
    time: f64,
}

fn run(s: &mut dyn Solver<D3>) -> Outcome {
    for _ in 0..STEPS {
        s.step(f64::INFINITY).unwrap();
    }
    Outcome {
        positions: s.positions().to_vec(),
        velocities: s.velocities().to_vec(),
        probe: s.probes()[0].positions.clone(),
        momentum: s.momentum().unwrap(),
        energy: s.energies().unwrap(),
        time: s.time(),
    }
}

/// A rank's outcome equals the one-process run's: positions, velocities and probe bit for bit,
/// energies and momentum to 1e-12 (sums over ranks group the particles differently).
fn assert_same_as_serial(d: &Outcome, serial: &Outcome, at: &str) {
    assert_eq!(d.time, serial.time, "{at}");
    assert!(d.positions == serial.positions, "{at}: positions differ");
    assert!(d.velocities == serial.velocities, "{at}: velocities differ");
    assert!(d.probe == serial.probe, "{at}: probe differs");
    let tol = 1e-12 * (serial.energy.0 + serial.energy.1);
    assert!((d.energy.0 - serial.energy.0).abs() <= tol, "{at}");
    assert!((d.energy.1 - serial.energy.1).abs() <= tol, "{at}");
    assert!((d.momentum - serial.momentum).length() <= 1e-12, "{at}");
}

fn distributed(ranks: usize, clamped: bool, shear: Shear, storage: PairStorage) -> Vec<Outcome> {
    ThreadRanks::run(ranks, |comm: Arc<dyn Communicator>| {
        let mut s = distribute(column(clamped, shear, storage), comm).unwrap();
        run(&mut s)
    })
}

/// As [`distributed`], each rank building only its share's reference data.
fn distributed_for_ranks(ranks: usize, shear: Shear, storage: PairStorage) -> Vec<Outcome> {
    ThreadRanks::run(ranks, |comm: Arc<dyn Communicator>| {
        let mut s = distribute(column_built(true, shear, storage, true), comm).unwrap();
        run(&mut s)
    })
}

#[test]
fn ranks_that_build_only_their_share_end_bit_identical_to_one_process() {
    for shear in [
        Shear::hourglass_free(),
        Shear::Original,
        Shear::ganzenmuller(),
    ] {
        let whole = column(true, shear, PairStorage::Stored);
        let guarded = whole.guarded_particles();
        let serial = run(&mut column(true, shear, PairStorage::Stored));
        for (ranks, storage) in
            (1..=3).flat_map(|r| [(r, PairStorage::Stored), (r, PairStorage::Recomputed)])
        {
            let outcomes = distributed_for_ranks(ranks, shear, storage);
            for (rank, d) in outcomes.iter().enumerate() {
                let at = format!(
                    "{} built for {ranks} ranks ({}), rank {rank}",
                    shear.method_name(),
                    storage.name()
                );
                assert_same_as_serial(d, &serial, &at);
            }
        }
        // The guarded particles are counted once, by their owners.
        let counts = ThreadRanks::run(3, |comm: Arc<dyn Communicator>| {
            let s = distribute(column_built(true, shear, PairStorage::Stored, true), comm).unwrap();
            s.local().guarded_particles()
        });
        assert!(
            counts.iter().all(|&g| g == guarded),
            "{counts:?} vs {guarded}"
        );
    }
}

#[test]
fn each_rank_holds_only_its_share_of_the_pairs() {
    let whole = column(true, Shear::hourglass_free(), PairStorage::Stored);
    let total = whole.neighbors().num_pairs();
    let local = ThreadRanks::run(3, |comm: Arc<dyn Communicator>| {
        let s = distribute(
            column_built(true, Shear::hourglass_free(), PairStorage::Stored, true),
            comm,
        )
        .unwrap();
        s.local().neighbors().num_pairs()
    });
    // Owned rows and halo layer 1's: each rank well under the whole body's pairs.
    for &l in &local {
        assert!(l < total, "{l} of {total}");
    }
    assert!(
        local.iter().sum::<usize>() < 2 * total,
        "{local:?} of {total}"
    );
}

#[test]
fn a_solver_built_for_ranks_does_not_step_before_it_is_distributed() {
    let mut s = column_built(true, Shear::hourglass_free(), PairStorage::Stored, true);
    assert!(s.is_deferred());
    let e = s.step(f64::INFINITY).unwrap_err().to_string();
    assert!(e.contains("step") && e.contains("distribute"), "{e}");
}

#[test]
fn a_body_with_an_isolated_particle_is_refused_on_every_rank_as_on_one_process() {
    let shape = Aabb::<D3>::new(DVec3::ZERO, DVec3::new(0.4, 0.4, 0.4)).unwrap();
    let set = ParticleSet::fill(&Lattice::new(DP, DVec3::ZERO).unwrap(), &shape).unwrap();
    let mut body = Body::from(set);
    body.positions.push(DVec3::new(5.0, 5.0, 5.0));
    body.volumes.push(DP * DP * DP);
    let law = NeoHookean::new(ElasticConstants::from_youngs(2e6, 0.4, 1000.0).unwrap());
    let one = TlSolver::new(
        body.clone(),
        law,
        Shear::hourglass_free(),
        TlParams::default(),
    )
    .err()
    .unwrap()
    .to_string();
    let errors = ThreadRanks::run(2, |comm: Arc<dyn Communicator>| {
        let s = TlSolver::for_ranks(
            body.clone(),
            law,
            Shear::hourglass_free(),
            TlParams::default(),
        )
        .unwrap();
        distribute(s, comm).err().unwrap().to_string()
    });
    assert!(errors.iter().all(|e| *e == one), "{errors:?} vs {one}");
}

#[test]
fn one_two_and_three_ranks_end_bit_identical_to_one_process() {
    for shear in [
        Shear::hourglass_free(),
        Shear::Original,
        Shear::ganzenmuller(),
    ] {
        let serial = run(&mut column(true, shear, PairStorage::Stored));
        // Each rank's pair data stored (its slots of the whole list) or recomputed from its
        // own reference positions: both end as the one process with stored data.
        for (ranks, storage) in
            (1..=3).flat_map(|r| [(r, PairStorage::Stored), (r, PairStorage::Recomputed)])
        {
            for (rank, d) in distributed(ranks, true, shear, storage).iter().enumerate() {
                let at = format!(
                    "{} on {ranks} ranks ({}), rank {rank}",
                    shear.method_name(),
                    storage.name()
                );
                assert_same_as_serial(d, &serial, &at);
            }
        }
    }
}

/// TL-HF with the normalised Laplacian: each rank computes `ζ_i` of its owned particles and
/// of the halo layer whose rows are complete (built for ranks), or picks them from the whole
/// body's (cut from a built solver); either way the run ends as the one process, bit for bit.
#[test]
fn the_normalised_laplacian_on_ranks_ends_bit_identical_to_one_process() {
    let shear = Shear::hourglass_free();
    for storage in [PairStorage::Stored, PairStorage::Recomputed] {
        let params = TlParams {
            pair_storage: storage,
            hf_laplacian: HfLaplacian::Normalised,
            ..TlParams::default()
        };
        let serial = run(&mut column_with(true, shear, params, false));
        let paper = run(&mut column(true, shear, storage));
        assert!(
            serial.positions != paper.positions,
            "the normalised Laplacian changes the motion"
        );
        for ranks in 1..=3 {
            for for_ranks in [false, true] {
                let outcomes = ThreadRanks::run(ranks, |comm: Arc<dyn Communicator>| {
                    let mut s =
                        distribute(column_with(true, shear, params, for_ranks), comm).unwrap();
                    run(&mut s)
                });
                for (rank, d) in outcomes.iter().enumerate() {
                    let at = format!(
                        "normalised on {ranks} ranks ({}, built for ranks: {for_ranks}), rank {rank}",
                        storage.name()
                    );
                    assert_same_as_serial(d, &serial, &at);
                }
            }
        }
    }
}

#[test]
fn a_free_column_keeps_its_momentum_on_three_ranks() {
    let initial = column(false, Shear::hourglass_free(), PairStorage::Stored).linear_momentum();
    for d in distributed(3, false, Shear::hourglass_free(), PairStorage::Recomputed) {
        let scale = initial.length();
        assert!(
            (d.momentum - initial).length() <= 1e-12 * scale,
            "{:?} vs {initial:?}",
            d.momentum
        );
        assert!(d.positions.iter().all(|x| x.is_finite()));
    }
}

#[test]
fn the_halo_is_the_neighbours_not_owned_and_theirs() {
    ThreadRanks::run(2, |comm: Arc<dyn Communicator>| {
        let s = column(true, Shear::hourglass_free(), PairStorage::Stored);
        let list = s.neighbors().clone();
        let d = distribute(s, comm).unwrap();
        let dom = d.domain();
        let rank = dom.comm().rank();
        let p = dom.partition();
        // 256 particles, 16 per layer, equal neighbour counts by symmetry: 128 each, cut
        // across z between layers 8 and 9; the cut-off 2.3 dp reaches two layers.
        assert_eq!(p.owned(rank).len(), 128);
        let (h1, h2) = p.halo_layers(rank, &list);
        assert_eq!((h1.len(), h2.len()), (32, 32));
        // The probe at the top is owned by rank 1; rank 0 receives its particles too.
        let extra = dom.halo_sizes()[2];
        assert_eq!(dom.halo_sizes(), [32, 32, extra]);
        assert_eq!(extra > 0, rank == 0);
        assert_eq!(dom.received(), 64 + extra);
        assert_eq!(dom.global().len(), 128 + 64 + extra);
        assert_eq!(dom.neighbour_ranks(), vec![1 - rank]);
        // Every halo particle is a neighbour of an owned one or of layer 1.
        for &i in &h1 {
            assert!(list
                .neighbors(i as usize)
                .iter()
                .any(|&j| p.owner(j as usize) == rank));
        }
    });
}
