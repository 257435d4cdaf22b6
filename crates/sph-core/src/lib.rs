//! # sph-core
//!
//! The geometry of particles that every sph-solids method shares: the spatial dimension as a type
//! ([`dim`]), smoothing kernels ([`kernel`]), neighbour search ([`neighbor`]), per-pair kernel data
//! ([`pairs`]), the kernel-gradient correction matrix ([`correction`]), bodies ([`body`]; their
//! particles come from the `sph-geometry` crate), constraints, loads, amplitude curves
//! ([`amplitude`]) and probes a scene attaches ([`scene`]), rigid tools with
//! kinematic contact ([`tool`]) and Coulomb friction ([`friction`]), quasi-static relaxation ([`relaxation`]), the particle
//! disorder indicator ([`disorder`]), the [`solver::Solver`] trait, the instruction set the loops
//! run with ([`wide`]), and what a distributed run
//! needs: communicators ([`comm`]), decomposition ([`decomposition`]) and a rank's share
//! ([`distributed`]).
//!
//! Conventions (docs/methods.md): particle `i`, neighbour `j`; `x_ij = x_i − x_j`, `e_ij = x_ij/r_ij`
//! points from `j` to `i`; `∇_i W_ij = W′(r_ij) e_ij` with `W′ ≤ 0`.
//!
//! Where a scene starts: a body (its particles usually from the `sph-geometry` crate's shapes,
//! lattices and meshes), and what the scene attaches to the solver a method crate builds from it
//! (`sph-tl`, `sph-ul`, `sph-mps`; `sph-driver` runs it):
//!
//! ```
//! use sph_core::{glam::DVec2, Amplitude, Body, Constraint, Constraints, Loads, Probe};
//! use sph_core::{TimeFunction, D2};
//!
//! // A 0.1 × 0.01 strip: 100 × 10 particles at the cell centres of a 1 mm lattice.
//! let dp = 1e-3;
//! let x: Vec<DVec2> = (0..10)
//!     .flat_map(|j| (0..100).map(move |i| DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * dp))
//!     .collect();
//! let n = x.len();
//! let select = |f: &dyn Fn(DVec2) -> bool| -> Vec<u32> {
//!     (0..n as u32).filter(|&i| f(x[i as usize])).collect()
//! };
//! // Held at its left end; its right end pulled at 0.5 m/s, reached smoothly over 2 ms.
//! let mut grips = Constraints::<D2>::new();
//! grips.push(Constraint::Fixed { particles: select(&|x| x.x < dp) }, n)?;
//! let pull = TimeFunction::scaled(DVec2::new(0.5, 0.0), Amplitude::smooth_step(0.0, 2e-3)?);
//! let right = select(&|x| x.x > 0.1 - dp);
//! grips.push_named("grip", Constraint::PrescribedVelocity { particles: right, velocity: pull }, n)?;
//! // Gravity, and a probe of the stress and the stretch at the middle.
//! let mut loads = Loads::<D2>::new();
//! loads.add_body_acceleration(None, TimeFunction::constant(DVec2::new(0.0, -9.81)));
//! let body = Body::<D2>::new(x.clone(), vec![dp * dp; n], dp);
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
pub mod contact;
pub mod contact_friction;
pub mod conventions;
pub mod correction;
pub mod decomposition;
pub mod diagnostics;
pub mod dim;
pub mod disorder;
pub mod distributed;
pub mod error;
pub mod friction;
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

/// Particle layouts for this crate's unit tests (the generators live in `sph-geometry`, which
/// depends on this crate).
#[cfg(test)]
pub(crate) mod testing {
    use crate::dim::Dim;

    /// The cell centres `(n + ½) dp` of an `n[0] × n[1] (× n[2])` block from the origin, first
    /// axis fastest (the order of sph-geometry's lattice fill).
    pub fn cell_centres<D: Dim>(n: [usize; 3], dp: f64) -> Vec<D::Vector> {
        let nz = if D::D == 3 { n[2] } else { 1 };
        let mut out = Vec::new();
        for k in 0..nz {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let c = [i, j, k].map(|m| (m as f64 + 0.5) * dp);
                    out.push(D::vector(c));
                }
            }
        }
        out
    }
}
