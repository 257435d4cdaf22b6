//! # sph-core
//!
//! The geometry of particles that every sph-solids method shares: the spatial dimension as a type
//! ([`dim`]), smoothing kernels ([`kernel`]), neighbour search ([`neighbor`]), per-pair kernel data
//! ([`pairs`]), the kernel-gradient correction matrix ([`correction`]), particle generators
//! ([`generate`]), constraints, loads, amplitude curves ([`amplitude`]) and probes a scene attaches ([`scene`]), rigid tools with
//! frictionless contact ([`tool`]), quasi-static relaxation ([`relaxation`]), the particle
//! disorder indicator ([`disorder`]), the [`solver::Solver`] trait, the instruction set the loops
//! run with ([`wide`]), and what a distributed run
//! needs: communicators ([`comm`]), decomposition ([`decomposition`]) and a rank's share
//! ([`distributed`]).
//!
//! Conventions (docs/methods.md): particle `i`, neighbour `j`; `x_ij = x_i − x_j`, `e_ij = x_ij/r_ij`
//! points from `j` to `i`; `∇_i W_ij = W′(r_ij) e_ij` with `W′ ≤ 0`.
#![deny(missing_docs)]
// Per-axis loops index several small arrays at once; iterator chains would obscure them.
#![allow(clippy::needless_range_loop)]

/// glam, whose f64 vectors and matrices (`DVec2`, `DVec3`, `DMat2`, `DMat3`) every API here
/// takes: `use sph_core::glam::DVec2;` needs no glam dependency of your own.
pub use glam;

pub mod amplitude;
pub mod body;
pub mod budget;
pub mod comm;
pub mod conventions;
pub mod correction;
pub mod decomposition;
pub mod diagnostics;
pub mod dim;
pub mod disorder;
pub mod distributed;
pub mod error;
pub mod generate;
pub mod kernel;
pub mod neighbor;
pub mod pairs;
pub mod parallel;
pub mod pressure;
pub mod relaxation;
pub mod scene;
pub mod solver;
pub mod state;
pub mod surface;
pub mod team;
pub mod tool;
pub mod wide;

pub use amplitude::Amplitude;
pub use body::Body;
pub use dim::{Dim, D2, D3};
pub use error::Error;
pub use kernel::{Kernel, WendlandC2};
pub use neighbor::{CellGrid, NeighborList, NeighbourValues};
pub use pairs::PairKernel;
pub use relaxation::{PairwiseDamper, PairwiseDamping};
pub use scene::{Constraint, Constraints, Loads, Probe, Series, TimeFunction};
pub use solver::{EnergyBudget, Field, Solver, StepInfo};
pub use state::{StateReader, StateWriter};
pub use tool::{RigidTool, ToolMotion, ToolShape};
