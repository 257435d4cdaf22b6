//! Shared helpers of the sph-ul tests (the material, bodies, the two-particle solver).
#![allow(dead_code)]

use glam::DVec2;
use sph_core::{Body, Dim, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet, Shape};
use sph_materials::ElasticConstants;
use sph_ul::{RiemannScheme, Shear, UlParams, UlSolver};

/// Particle spacing of every body here (1 cm).
pub const DP: f64 = 0.01;

/// The UL paper's 2D plate material: E = 2 MPa, ν = 0.3975, ρ0 = 1000 kg/m³.
pub fn constants() -> ElasticConstants {
    ElasticConstants::from_youngs(2.0e6, 0.3975, 1000.0).unwrap()
}

/// Its sound speed, 57.0 m/s.
pub fn c0() -> f64 {
    constants().sound_speed
}

/// The three UL variants: OG, OAS, ENOG.
pub fn variants() -> [Shear; 3] {
    [
        Shear::Original,
        Shear::artificial_stress(),
        Shear::non_nested(),
    ]
}

/// A block of `n[0] × n[1] (× n[2])` particles with its corner at the origin.
pub fn block<D: Dim>(n: [usize; 3]) -> ParticleSet<D> {
    let size = D::vector([n[0] as f64 * DP, n[1] as f64 * DP, n[2] as f64 * DP]);
    let lattice = Lattice::<D>::new(DP, D::zero()).unwrap();
    ParticleSet::fill(
        &lattice,
        &Aabb::<D>::from_corner(D::zero(), size).unwrap() as &dyn Shape<D>,
    )
    .unwrap()
}

/// The body of `set` with velocities `v` and the reference density.
pub fn body<D: Dim>(set: &ParticleSet<D>, v: Vec<D::Vector>) -> Body<D> {
    Body {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities: v,
        densities: Vec::new(),
    }
}

/// The mean of `x`.
pub fn centroid<D: Dim>(x: &[D::Vector]) -> D::Vector {
    x.iter().fold(D::zero(), |s, &p| s + p) * (1.0 / x.len() as f64)
}

/// The largest `|v|`.
pub fn max_norm<D: Dim>(v: &[D::Vector]) -> f64 {
    v.iter().map(|&a| D::norm(a)).fold(0.0, f64::max)
}

/// Two particles `dp` apart on the x axis with velocities `v0`, `v1` and densities `rho`.
pub fn pair_body(v0: DVec2, v1: DVec2, rho: [f64; 2]) -> Body<D2> {
    Body {
        positions: vec![DVec2::ZERO, DVec2::new(DP, 0.0)],
        volumes: vec![DP * DP; 2],
        dp: DP,
        velocities: vec![v0, v1],
        densities: rho.to_vec(),
    }
}

/// An ENOG solver of [`pair_body`] with the Riemann `scheme`, no reordering.
pub fn pair_solver(v0: DVec2, v1: DVec2, rho: [f64; 2], scheme: RiemannScheme) -> UlSolver<D2> {
    let params = UlParams {
        riemann: scheme,
        reorder: false,
        ..UlParams::default()
    };
    UlSolver::new(
        pair_body(v0, v1, rho),
        constants(),
        Shear::non_nested(),
        params,
    )
    .unwrap()
}
