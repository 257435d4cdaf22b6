//! # sph-core
//!
//! The geometry of particles that every sph-solids method shares: the spatial dimension as a type
//! ([`dim`]), smoothing kernels ([`kernel`]), neighbour search ([`neighbor`]), per-pair kernel data
//! ([`pairs`]), the kernel-gradient correction matrix ([`correction`]), particle generators
//! ([`generate`]), constraints, loads, amplitude curves ([`amplitude`]) and probes a scene attaches ([`scene`]), rigid tools with
//! kinematic contact ([`tool`]) and Coulomb friction ([`friction`]), quasi-static relaxation ([`relaxation`]), the particle
//! disorder indicator ([`disorder`]), the [`solver::Solver`] trait, the instruction set the loops
//! run with ([`wide`]), and what a distributed run
//! needs: communicators ([`comm`]), decomposition ([`decomposition`]) and a rank's share
//! ([`distributed`]).
//!
//! Conventions (docs/methods.md): particle `i`, neighbour `j`; `x_ij = x_i − x_j`, `e_ij = x_ij/r_ij`
//! points from `j` to `i`; `∇_i W_ij = W′(r_ij) e_ij` with `W′ ≤ 0`.
//!
//! Where a scene starts: particles from a shape, a body, and what the scene attaches to the
//! solver a method crate builds from it (`sph-tl`, `sph-ul`, `sph-mps`; `sph-driver` runs it):
//!
//! ```
//! use sph_core::generate::{Aabb, Lattice, ParticleSet};
//! use sph_core::{glam::DVec2, Amplitude, Body, Constraint, Constraints, Loads, Probe};
//! use sph_core::{TimeFunction, D2};
//!
//! // A 0.1 × 0.01 strip on a 1 mm lattice.
//! let dp = 1e-3;
//! let strip = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.1, 0.01))?;
//! let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO)?, &strip)?;
//! let n = set.len();
//! // Held at its left end; its right end pulled at 0.5 m/s, reached smoothly over 2 ms.
//! let mut grips = Constraints::<D2>::new();
//! grips.push(Constraint::Fixed { particles: set.select(|x| x.x < dp) }, n)?;
//! let pull = TimeFunction::scaled(DVec2::new(0.5, 0.0), Amplitude::smooth_step(0.0, 2e-3)?);
//! let right = set.select(|x| x.x > 0.1 - dp);
//! grips.push_named("grip", Constraint::PrescribedVelocity { particles: right, velocity: pull }, n)?;
//! // Gravity, and a probe of the stress and the stretch at the middle.
//! let mut loads = Loads::<D2>::new();
//! loads.add_body_acceleration(None, TimeFunction::constant(DVec2::new(0.0, -9.81)));
//! let body = Body::from(set);
//! let mid = Probe::at("mid", DVec2::new(0.05, 0.005), &body)?
//!     .with_fields(&["von_mises", "jacobian"]);
//! assert_eq!((body.len(), grips.named().count()), (1000, 1));
//! # let _ = (loads, mid);
//! # Ok::<(), sph_core::Error>(())
//! ```
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
pub mod friction;
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
pub use friction::Friction;
pub use kernel::{Kernel, WendlandC2};
pub use neighbor::{CellGrid, NeighborList, NeighbourValues};
pub use pairs::PairKernel;
pub use relaxation::{PairwiseDamper, PairwiseDamping};
pub use scene::{Constraint, Constraints, Loads, Probe, Series, TimeFunction};
pub use solver::{EnergyBudget, Field, Solver, StepInfo};
pub use state::{StateReader, StateWriter};
pub use tool::{RigidTool, ToolMotion, ToolSet, ToolShape};
