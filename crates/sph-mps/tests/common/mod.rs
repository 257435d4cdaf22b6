//! Shared helpers of the sph-mps tests (bodies, random states, materials).
#![allow(dead_code)]

use sph_core::Body;
use sph_core::Dim;
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::Material;
use sph_materials::{ElasticConstants, MooneyRivlinLike, SaintVenantKirchhoff};
use sph_mps::{MpsParams, MpsSolver};

/// Particle spacing of every body here (the MPS paper's cantilever beam: 2 mm).
pub const DP: f64 = 0.002;

/// The MPS paper's cantilever-beam material (§IV.E): E = 1e5 Pa, ν = 0.3; ρ0 = 1000 kg/m³.
pub fn svk() -> SaintVenantKirchhoff {
    SaintVenantKirchhoff::new(ElasticConstants::from_youngs(1.0e5, 0.3, 1000.0).unwrap())
}

/// The MPS paper's rubber (§IV.A, eq 12).
pub fn mooney() -> MooneyRivlinLike {
    MooneyRivlinLike::mps_paper()
}

/// A block of `n[0] × n[1] (× n[2])` particles with its corner at the origin.
pub fn block<D: Dim>(n: [usize; 3]) -> ParticleSet<D> {
    let size = D::vector([n[0] as f64 * DP, n[1] as f64 * DP, n[2] as f64 * DP]);
    let lattice = Lattice::<D>::new(DP, D::zero()).unwrap();
    ParticleSet::fill(&lattice, &Aabb::<D>::from_corner(D::zero(), size).unwrap()).unwrap()
}

pub fn body<D: Dim>(set: &ParticleSet<D>) -> Body<D> {
    Body {
        positions: set.positions().to_vec(),
        volumes: set.volumes().to_vec(),
        dp: DP,
        velocities: Vec::new(),
        densities: Vec::new(),
    }
}

pub fn solver<D: Dim, M: Material<D>>(n: [usize; 3], material: M) -> MpsSolver<D, M> {
    solver_with(n, material, MpsParams::default())
}

pub fn solver_with<D: Dim, M: Material<D>>(
    n: [usize; 3],
    material: M,
    params: MpsParams,
) -> MpsSolver<D, M> {
    let s = MpsSolver::new(body(&block::<D>(n)), material, params).unwrap();
    // A regular block needs no guard on A_i (so F = I exactly at rest).
    assert_eq!(s.guarded_particles(), 0);
    s
}

/// A deterministic pseudo-random number generator (LCG) giving values in [−1, 1].
pub struct Lcg(pub u64);

impl Lcg {
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    pub fn vector<D: Dim>(&mut self) -> D::Vector {
        D::vector([self.uniform(), self.uniform(), self.uniform()])
    }
    pub fn matrix<D: Dim>(&mut self) -> D::Matrix {
        let v: Vec<f64> = (0..9).map(|_| self.uniform()).collect();
        D::matrix_from_fn(|r, c| v[3 * r + c])
    }
}

/// `x = G X + random(±amp dp)` with `G = I + stretch · random`, about the centroid.
pub fn deformed<D: Dim>(
    reference: &[D::Vector],
    rng: &mut Lcg,
    stretch: f64,
    amp: f64,
) -> Vec<D::Vector> {
    let g = D::identity() + rng.matrix::<D>() * stretch;
    let c = centroid::<D>(reference);
    reference
        .iter()
        .map(|&x| c + g * (x - c) + rng.vector::<D>() * (amp * DP))
        .collect()
}

/// Random velocities of magnitude ≤ `v0` with zero total momentum (equal masses).
pub fn random_velocities<D: Dim>(n: usize, rng: &mut Lcg, v0: f64) -> Vec<D::Vector> {
    let v: Vec<D::Vector> = (0..n).map(|_| rng.vector::<D>() * v0).collect();
    let mean = centroid::<D>(&v);
    v.into_iter().map(|x| x - mean).collect()
}

pub fn centroid<D: Dim>(x: &[D::Vector]) -> D::Vector {
    x.iter().fold(D::zero(), |s, &p| s + p) * (1.0 / x.len() as f64)
}

pub fn max_norm<D: Dim>(v: &[D::Vector]) -> f64 {
    v.iter().map(|&a| D::norm(a)).fold(0.0, f64::max)
}
