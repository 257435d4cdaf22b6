//! # sph-tl: total-Lagrangian SPH for elastic and elastic–plastic solids
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
//!
//! Plastic bodies ([`TlSolver::with_plasticity`], `tl` and `tl-gm`; `tl-hf` refuses one): J2 or
//! Johnson–Cook plasticity at finite strain, `F = Fe Fp` with a Hencky elastic law and the
//! exponential-map return, the history (`Cp⁻¹`, equivalent plastic strain, temperature rise)
//! stepped with each stress evaluation ([`solver::plastic`]). An elastic body keeps an empty
//! history and takes the elastic branch once per force pass.
//!
//! ```
//! use glam::DVec2;
//! use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
//! use sph_core::{Body, Constraints, Solver, D2};
//! use sph_materials::{ElasticConstants, NeoHookean};
//! use sph_tl::{Shear, TlParams, TlSolver};
//!
//! // A plate clamped at its left end, swinging up; 100 steps of TL-SPH-HF.
//! let dp = 2.5e-3;
//! let shape = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.1, 0.01))?;
//! let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO)?, &shape)?;
//! let clamp = Constraints::fixed(set.select(|x| x.x < 2.0 * dp), set.len())?;
//! let body = Body::from(set).with_velocity(|x| DVec2::new(0.0, 5.0 * x.x));
//! let law = NeoHookean::new(ElasticConstants::from_youngs(2e6, 0.3, 1000.0)?);
//! let mut s = TlSolver::new(body, law, Shear::hourglass_free(), TlParams::default())?
//!     .with_constraints(clamp);
//! for _ in 0..100 {
//!     s.step(f64::INFINITY)?;
//! }
//! assert!(s.time() > 0.0 && s.energy().kinetic > 0.0);
//! # Ok::<(), sph_core::Error>(())
//! ```
#![deny(missing_docs)]

/// glam, whose f64 vectors and matrices (`DVec2`, `DVec3`, `DMat2`, `DMat3`) every API here
/// takes: `use sph_tl::glam::DVec2;` needs no glam dependency of your own.
pub use glam;

pub mod contact;
pub mod damping;
pub mod ganzenmuller;
pub mod hourglass_free;
#[cfg(target_arch = "x86_64")]
mod lanes;
pub mod original;
pub mod reference_pairs;
pub mod solver;

pub use hourglass_free::HfLaplacian;
pub use reference_pairs::PairStorage;
pub use solver::{distribute, Energy, Shear, TlParams, TlSolver, DEFAULT_CONTACT_SCALE};
