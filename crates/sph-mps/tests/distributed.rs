//! Distributed MPS runs on in-process ranks (`sph_core::comm::ThreadRanks`): the same final
//! state as one process, bit for bit, for 1, 2 and 3 ranks; momentum conserved; halo as
//! computed.

use glam::DVec2;
use sph_core::comm::{Communicator, ThreadRanks};
use sph_core::{Body, Constraint, Constraints, Probe, Solver, WendlandC2, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{ElasticConstants, SaintVenantKirchhoff};
use sph_mps::{distribute, Integrator, MpsParams, MpsSolver};
use std::sync::Arc;

const DP: f64 = 0.01;

/// A 24 × 4 cantilever plate (96 particles) swinging up from a clamp at its left end.
fn plate(clamped: bool, params: MpsParams) -> MpsSolver<D2, SaintVenantKirchhoff> {
    let shape = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.24, 0.04)).unwrap();
    let set = ParticleSet::fill(&Lattice::new(DP, DVec2::ZERO).unwrap(), &shape).unwrap();
    let clamp = set.select(|x| x.x < 3.0 * DP);
    let body = Body::from(set).with_velocity(|x| DVec2::new(0.0, 3.0 * x.x));
    let law = SaintVenantKirchhoff::new(ElasticConstants::from_youngs(2e6, 0.3, 1000.0).unwrap());
    let s = MpsSolver::new(body, law, params).unwrap();
    let kernel = WendlandC2::<D2>::from_spacing(DP, 1.3).unwrap();
    let probe = Probe::point(
        "tip",
        DVec2::new(0.24, 0.02),
        s.reference_positions(),
        s.volumes(),
        &kernel,
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

const STEPS: usize = 80;

struct Outcome {
    positions: Vec<DVec2>,
    velocities: Vec<DVec2>,
    probe: Vec<DVec2>,
    momentum: glam::DVec3,
    energy: (f64, f64),
}

fn run(s: &mut dyn Solver<D2>) -> Outcome {
    for _ in 0..STEPS {
        s.step(f64::INFINITY).unwrap();
    }
    Outcome {
        positions: s.positions().to_vec(),
        velocities: s.velocities().to_vec(),
        probe: s.probes()[0].positions.clone(),
        momentum: s.momentum().unwrap(),
        energy: s.energies().unwrap(),
    }
}

fn distributed(ranks: usize, clamped: bool, params: MpsParams) -> Vec<Outcome> {
    ThreadRanks::run(ranks, |comm: Arc<dyn Communicator>| {
        let mut s = distribute(plate(clamped, params), comm).unwrap();
        run(&mut s)
    })
}

fn variants() -> [MpsParams; 3] {
    let d = MpsParams::default();
    [
        d,
        MpsParams {
            integrator: Integrator::SymplecticEuler,
            damping: 5.0,
            ..d
        },
        MpsParams {
            stabilisation: 0.5,
            ..d
        },
    ]
}

#[test]
fn one_two_and_three_ranks_end_bit_identical_to_one_process() {
    for params in variants() {
        let serial = run(&mut plate(true, params));
        for ranks in 1..=3 {
            for (rank, d) in distributed(ranks, true, params).iter().enumerate() {
                let at = format!("{params:?} on {ranks} ranks, rank {rank}");
                assert!(d.positions == serial.positions, "{at}: positions differ");
                assert!(d.velocities == serial.velocities, "{at}: velocities differ");
                assert!(d.probe == serial.probe, "{at}: probe differs");
                // Sums over ranks group the particles differently: equal to round-off.
                let tol = 1e-12 * (serial.energy.0 + serial.energy.1);
                assert!((d.energy.0 - serial.energy.0).abs() <= tol, "{at}");
                assert!((d.energy.1 - serial.energy.1).abs() <= tol, "{at}");
                assert!((d.momentum - serial.momentum).length() <= 1e-12, "{at}");
            }
        }
    }
}

#[test]
fn a_free_plate_keeps_its_momentum_on_three_ranks() {
    let initial = plate(false, MpsParams::default()).linear_momentum();
    for d in distributed(3, false, MpsParams::default()) {
        let p = DVec2::new(d.momentum.x, d.momentum.y);
        assert!(
            (p - initial).length() <= 1e-12 * initial.length(),
            "{p:?} vs {initial:?}"
        );
    }
}

#[test]
fn the_halo_is_two_neighbour_layers_across_the_cut() {
    ThreadRanks::run(2, |comm: Arc<dyn Communicator>| {
        let s = plate(true, MpsParams::default());
        let list = s.neighbors().clone();
        let d = distribute(s, comm).unwrap();
        let dom = d.domain();
        let rank = dom.comm().rank();
        // 96 particles in 24 columns of 4, cut across x; r_e = 2.1 dp reaches two columns,
        // so each halo layer is two columns of 4 (equal weights by symmetry: 48 each).
        assert_eq!(dom.partition().owned(rank).len(), 48);
        let (h1, h2) = dom.partition().halo_layers(rank, &list);
        assert_eq!((h1.len(), h2.len()), (8, 8));
        let extra = dom.halo_sizes()[2];
        assert_eq!(dom.halo_sizes(), [8, 8, extra]);
        assert_eq!(dom.received(), 16 + extra);
    });
}
