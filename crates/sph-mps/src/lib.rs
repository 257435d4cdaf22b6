//! # sph-mps: the Hamiltonian moving-particle model for hyperelastic solids
//!
//! One solver, [`MpsSolver`], generic over the dimension (`D2` plane strain, `D3`) and the
//! hyperelastic material, after the MPS paper (Falahaty, Gotoh & Khayyer, after Suzuki &
//! Koshizuka 2008):
//!
//! - [`wls`]: the weight of eq 6, the moment matrix `A_i` of eq 5, the weighted-least-squares
//!   deformation gradient of eq 4, and the energy-consistent force of eq 7 (`f_i = −∂U/∂x_i`,
//!   `U = Σ_i V_i ψ(F_i)`);
//! - [`sph_core::pressure`]: follower surface pressure on tagged boundary particles (Nanson's formula);
//! - [`stabilisation`] (beyond the paper, off by default): a penalty potential on the residual
//!   of the WLS fit that removes the zero-energy modes of eq 4–5 and keeps the model
//!   Hamiltonian;
//! - [`solver`]: body set-up in the reference configuration (total Lagrangian: neighbours,
//!   weights and `A_i⁻¹` are fixed) and the symplectic time step (velocity Verlet by default,
//!   the paper's symplectic Euler of eq 8 as an option), `Δt = C l0 / c`.
//!
//! Conventions (docs/methods.md, "Hamiltonian particle model"): `X_ij = X_j − X_i`,
//! `x_ij = x_j − x_i` (the opposite of the SPH crates' `x_i − x_j`), so that eq 4–7 read as
//! printed. Loops are gathers over each particle's own neighbours, parallel with rayon, so results
//! do not depend on the thread schedule.
//!
//! ```
//! use glam::DVec2;
//! use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
//! use sph_core::{Body, Solver, D2};
//! use sph_materials::{ElasticConstants, SaintVenantKirchhoff};
//! use sph_mps::{MpsParams, MpsSolver};
//!
//! // A free block vibrating in a shear mode: the Hamiltonian keeps its energy.
//! let shape = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.02, 0.02))?;
//! let set = ParticleSet::fill(&Lattice::new(2e-3, DVec2::ZERO)?, &shape)?;
//! let body = Body::from(set).with_velocity(|x| DVec2::new(0.1 * (x.y - 0.01), 0.0));
//! let law = SaintVenantKirchhoff::new(ElasticConstants::from_youngs(1e6, 0.3, 1000.0)?);
//! let mut s = MpsSolver::new(body, law, MpsParams::default())?;
//! let e0 = s.energy().total();
//! for _ in 0..200 {
//!     s.step(f64::INFINITY)?;
//! }
//! assert!((s.energy().total() / e0 - 1.0).abs() < 1e-2);
//! # Ok::<(), sph_core::Error>(())
//! ```
#![deny(missing_docs)]

/// glam, whose f64 vectors and matrices (`DVec2`, `DVec3`, `DMat2`, `DMat3`) every API here
/// takes: `use sph_mps::glam::DVec2;` needs no glam dependency of your own.
pub use glam;

pub mod contact;
pub mod solver;
pub mod stabilisation;
pub mod wls;

pub use contact::Contact;
pub use solver::{distribute, Energy, Integrator, MpsParams, MpsSolver};
/// The follower surface pressure (in `sph_core::pressure`, shared with TL).
pub use sph_core::pressure::{PressureFunction, SurfacePressure};
pub use wls::Fit;
