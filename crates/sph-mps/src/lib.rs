//! # sph-mps: the Hamiltonian moving-particle model for hyperelastic solids
//!
//! One solver, [`MpsSolver`], generic over the dimension (`D2` plane strain, `D3`) and the
//! hyperelastic material, after the MPS paper (Falahaty, Gotoh & Khayyer, after Suzuki &
//! Koshizuka 2008):
//!
//! - [`wls`]: the weight of eq 6, the moment matrix `A_i` of eq 5, the weighted-least-squares
//!   deformation gradient of eq 4, and the energy-consistent force of eq 7 (`f_i = −∂U/∂x_i`,
//!   `U = Σ_i V_i ψ(F_i)`);
//! - [`pressure`]: follower surface pressure on tagged boundary particles (Nanson's formula);
//! - [`stabilisation`] (beyond the paper, off by default): a penalty potential on the residual
//!   of the WLS fit that removes the zero-energy modes of eq 4–5 and keeps the model
//!   Hamiltonian;
//! - [`solver`]: body set-up in the reference configuration (total Lagrangian: neighbours,
//!   weights and `A_i⁻¹` are fixed) and the symplectic time step (velocity Verlet by default,
//!   the paper's symplectic Euler of eq 8 as an option), `Δt = C l0 / c`.
//!
//! Conventions (METHODS.md, "Hamiltonian particle model"): `X_ij = X_j − X_i`,
//! `x_ij = x_j − x_i` (the opposite of the SPH crates' `x_i − x_j`), so that eq 4–7 read as
//! printed. Loops are gathers over each particle's own neighbours, parallel with rayon, so results
//! do not depend on the thread schedule.
#![deny(missing_docs)]

pub mod contact;
pub mod pressure;
pub mod solver;
pub mod stabilisation;
pub mod wls;

pub use contact::Contact;
pub use pressure::{PressureFunction, SurfacePressure};
pub use solver::{Energy, Integrator, MpsBody, MpsParams, MpsSolver};
pub use wls::Fit;
