//! # sph-solids
//!
//! Particle simulation of elastic solids with large deformation, in 2D (plane strain) and 3D:
//!
//! - total-Lagrangian SPH ([`tl`]): original, hourglass-free (HF) and Ganzenmüller (GM) shear;
//! - updated-Lagrangian SPH ([`ul`]): OG, OAS and the non-nested ENOG, dual-criteria stepping;
//! - the Hamiltonian moving-particle model ([`mps`]).
//!
//! This crate gathers the workspace's crates under one name and offers a [`prelude`] with what
//! a scene needs: shapes and generators, meshes and outlines ([`geometry`]), bodies, materials, the solvers, constraints, loads,
//! probes, rigid tools, and the run loop that writes HDF5 results ([`driver::Run`]). Scenes can
//! also be written as TOML files ([`scene`]) and run by `sph run scene.toml`.
//!
//! ```
//! use sph_solids::prelude::*;
//!
//! // A 0.1 × 0.01 plate clamped at its left end, swinging up: TL-SPH-HF for 1 ms.
//! let dp = 2.5e-3;
//! let plate = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.1, 0.01))?;
//! let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO)?, &plate)?;
//! let clamp = set.select(|x| x.x < 2.0 * dp);
//! let n = set.len();
//! let body = Body::from(set).with_velocity(|x| DVec2::new(0.0, 10.0 * x.x));
//! let law = NeoHookean::new(ElasticConstants::from_youngs(2e6, 0.3, 1000.0)?);
//! let mut solver = TlSolver::new(body, law, TlShear::hourglass_free(), TlParams::default())?
//!     .with_constraints(Constraints::fixed(clamp, n)?);
//! let (record, _) = Run::until(1e-3).execute(&mut solver)?;
//! assert!(record.failure.is_none() && record.time >= 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub use glam;
pub use sph_core as core;
pub use sph_driver as driver;
pub use sph_geometry as geometry;
pub use sph_materials as materials;
pub use sph_mps as mps;
pub use sph_output as output;
pub use sph_scene as scene;
pub use sph_tl as tl;
pub use sph_ul as ul;

/// What a scene needs, in one `use sph_solids::prelude::*;`.
pub mod prelude {
    pub use glam::{DMat2, DMat3, DVec2, DVec3};
    pub use sph_core::relaxation::PairwiseDamping;
    pub use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
    pub use sph_core::{
        Body, Constraint, Constraints, Dim, Field, Loads, Probe, Series, Solver, TimeFunction, D2,
        D3,
    };
    pub use sph_driver::{Run, RunOptions, RunRecord};
    pub use sph_geometry::fit::{fit, FitOptions, FitReport};
    pub use sph_geometry::generate::{
        annulus_lattice, annulus_polar, hollow_sphere, tube_polar, Aabb, Annulus, Cylinder,
        Difference, HollowSphere, Intersection, Lattice, ParticleSet, Shape, Union,
    };
    pub use sph_geometry::mesh::{MeshSolid, Placement, TriMesh};
    pub use sph_geometry::outline::OutlineSolid;
    pub use sph_materials::{
        ElasticConstants, KirchhoffVolDev, Material, MaterialKind, MaterialModel, MooneyRivlinLike,
        NeoHookean, SaintVenantKirchhoff,
    };
    pub use sph_mps::{Contact as MpsContact, MpsParams, MpsSolver};
    pub use sph_scene::Scene;
    pub use sph_tl::{Shear as TlShear, TlParams, TlSolver};
    pub use sph_ul::{Shear as UlShear, Stepping, UlParams, UlSolver};
}
