//! # sph-tl: total-Lagrangian SPH for elastic solids
//!
//! One solver, [`TlSolver`], generic over the dimension (`D2` plane strain, `D3`) and the
//! material, with the shear treatment chosen when the body is built ([`Shear`]):
//!
//! - [`Shear::Original`]: TL-SPH, stress divergence with the correction matrix (TL paper eq 20–22);
//! - [`Shear::HourglassFree`]: TL-SPH-HF, shear acceleration from the Laplacian of position
//!   (eq 25–29), see [`hourglass_free`];
//! - [`Shear::Ganzenmuller`]: TL-SPH with Ganzenmüller's hourglass penalty, see [`ganzenmuller`].
//!
//! Kernel data, neighbour lists and the correction matrices are computed once in the reference
//! configuration. Each step is the position-Verlet scheme of eq 30–32 ([`solver`]) with the time
//! step of eq 33 and Kelvin–Voigt damping (eq 23–24, [`damping`]). Loops are gathers over each
//! particle's own neighbours, parallel with rayon, so results do not depend on the thread
//! schedule.
#![deny(missing_docs)]

pub mod damping;
pub mod ganzenmuller;
pub mod hourglass_free;
pub mod original;
pub mod solver;

pub use solver::{Energy, Shear, TlParams, TlSolver};
