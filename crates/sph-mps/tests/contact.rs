//! Penalty contact between two bodies of one MPS solver: two blocks approaching head-on bounce
//! off each other, with linear momentum conserved to round-off and the total energy (kinetic +
//! strain + contact potential) conserved to the integrator's O(Δt²) error.

mod common;

use common::*;
use glam::DVec2;
use sph_core::Body;
use sph_core::{Solver, D2};
use sph_geometry::generate::ParticleSet;
use sph_mps::{Contact, MpsParams, MpsSolver};

#[test]
fn blocks_bounce_with_momentum_and_energy_conserved() {
    // Two 6 × 6 blocks, 3 dp apart (beyond r_e = 2.1 dp, so no reference neighbours between
    // them), moving toward each other at 0.5 m/s (c0 ≈ 10 m/s for E = 1e5, ρ0 = 1000).
    let a = block::<D2>([6, 6, 1]);
    let mut b = block::<D2>([6, 6, 1]);
    b.translate(DVec2::new(9.0 * DP, 0.0));
    let mut set = ParticleSet::<D2>::new();
    set.extend(&a).unwrap();
    let second = set.extend(&b).unwrap();
    let n = set.len();
    let v0 = 0.5;
    let velocities: Vec<DVec2> = (0..n)
        .map(|i| DVec2::new(if second.contains(&i) { -v0 } else { v0 }, 0.0))
        .collect();
    let body_of: Vec<u32> = (0..n).map(|i| second.contains(&i) as u32).collect();
    let body = Body::<D2> {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities,
        densities: Vec::new(),
    };
    let mut s = MpsSolver::new(body, svk(), MpsParams::default())
        .unwrap()
        .with_contact(Contact::between(body_of.clone()))
        .unwrap();
    let e0 = s.energy().total();
    let scale: f64 = s.masses().iter().map(|m| m * v0).sum();
    let mut max_dev: f64 = 0.0;
    // Approach (3 dp at 1 m/s relative: 6 ms), contact, separation: run 40 ms.
    while s.time() < 0.04 {
        s.step(f64::INFINITY).unwrap();
        max_dev = max_dev.max((s.energy().total() / e0 - 1.0).abs());
        // Linear momentum: pair forces are equal and opposite; round-off only (1e-12 of Σ m|v|).
        let p: DVec2 = s.linear_momentum();
        assert!(p.length() <= 1e-12 * scale);
    }
    // The blocks have bounced: the first moves left, the second right.
    let velocities: Vec<DVec2> = s.velocities().to_vec();
    let mean_vx = |body: u32| {
        let picked: Vec<f64> = velocities
            .iter()
            .zip(&body_of)
            .filter(|(_, b)| **b == body)
            .map(|(v, _)| v.x)
            .collect();
        picked.iter().sum::<f64>() / picked.len() as f64
    };
    println!(
        "after 40 ms: block velocities {:.4} / {:.4} m/s, max |E/E0 − 1| = {max_dev:.2e}",
        mean_vx(0),
        mean_vx(1)
    );
    assert!(
        mean_vx(0) < 0.0 && mean_vx(1) > 0.0,
        "the blocks must bounce"
    );
    // Energy: the contact potential is part of the Hamiltonian, so velocity Verlet conserves
    // the total to O(Δt²) (measured 4.8e-4; bound 10× that); a contact
    // force that did not derive from the potential would show O(1) changes.
    assert!(max_dev < 5e-3, "energy deviation {max_dev}");
}

#[test]
fn contact_input_is_validated() {
    let s = solver::<D2, _>([4, 4, 1], svk());
    let e = s.with_contact(Contact::between(vec![0; 3])).err().unwrap();
    assert!(e.to_string().contains("contact.body_of"), "{e}");
}

/// Two bodies within r_e of each other at t = 0 would share reference neighbours (bonded, not
/// in contact): refused before any step.
#[test]
fn bodies_sharing_reference_neighbours_are_refused() {
    let a = block::<D2>([6, 6, 1]);
    let mut b = block::<D2>([6, 6, 1]);
    // Facing particles 2 dp apart (surfaces 1 dp): within r_e = 2.1 dp. (The test above has
    // them 4 dp apart.)
    b.translate(DVec2::new(7.0 * DP, 0.0));
    let mut set = ParticleSet::<D2>::new();
    set.extend(&a).unwrap();
    let second = set.extend(&b).unwrap();
    let n = set.len();
    let body_of: Vec<u32> = (0..n).map(|i| second.contains(&i) as u32).collect();
    let body = Body::<D2>::new(set.positions().to_vec(), set.volumes().to_vec(), DP);
    let e = MpsSolver::new(body, svk(), MpsParams::default())
        .unwrap()
        .with_contact(Contact::between(body_of))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("contact.body_of") && e.contains("r_e"), "{e}");
}
