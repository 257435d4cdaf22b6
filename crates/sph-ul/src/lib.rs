//! # sph-ul: updated-Lagrangian SPH for elastic solids
//!
//! One solver, [`UlSolver`], generic over the dimension (`D2`, `D3`), following Zhang,
//! Lourenço, Wu, Zhang & Hu, "Essentially non-hourglass and non-tensile-instability SPH elastic
//! dynamics" (the UL paper), §2–5. The shear treatment is chosen when the body is built
//! ([`Shear`]) and hoisted out of the inner loops:
//!
//! - [`Shear::Original`] (`ul-og`): nested shear, velocity gradient → Jaumann rate of the shear
//!   stress → stress divergence (eq 6–8, 13–14), see [`nested`];
//! - [`Shear::ArtificialStress`] (`ul-oas`): OG plus Gray–Monaghan–Swift artificial stress, in 2D
//!   and 3D through the symmetric eigen-decomposition, see [`artificial_stress`];
//! - [`Shear::NonNested`] (`ul-enog`): shear acceleration accumulated from the angular-momentum
//!   conservative Laplacian of velocity (eq 19–20), or the non-conservative eq 18, see
//!   [`non_nested`];
//! - [`Shear::Generalized`] (`ul-gnog`): OG's nested shear stress (any law, plastic ones
//!   included) plus an accumulated penalty on the pair velocity that the velocity gradients do
//!   not predict (Zhang, Wu, Lourenço & Hu 2024, arXiv 2409.11474), see [`generalized`].
//!
//! Plastic bodies ([`UlSolver::with_plasticity`], OG and OAS): J2 or Johnson–Cook plasticity
//! by the radial return of `τ` after each of its updates, with the equivalent plastic strain as
//! history ([`plastic`]).
//!
//! Pressure and continuity use the low-dissipation Riemann solver (eq 11–12) with the equation of
//! state `p = c0²(ρ − ρ0)` (eq 4), see [`riemann`]. Time integration is the position-Verlet scheme
//! (eq 23–25) inside the dual-criteria time stepping of §5 (eq 21–22), see [`stepping`] and
//! [`solver`]: neighbour lists and the correction matrix are rebuilt only at advection steps and
//! frozen over the acoustic sub-steps, the kernel data over that list are refreshed every
//! sub-step (`UlParams::refresh_kernel_data`; docs/methods.md freezes them too, which softens a long
//! oscillation secularly); particles are reordered in cell order
//! at every rebuild ([`UlSolver::original_index`] maps back to the input order).
//!
//! Separate bodies: [`UlSolver::with_contact`] splits the particles into bodies that keep their
//! own neighbours and meet through docs/methods.md's contact pressure ([`contact`]: repulsive,
//! antisymmetric per pair, so momentum is conserved; the contact force on each body is
//! recorded as a series). Without it every particle belongs to one body, and colliding parts of
//! one material meet through the ordinary neighbour search, as Gray et al. did.
//!
//! Energy: [`UlSolver::energy`] gives the stored energies; the energy budget ([`energy`],
//! `Solver::energy_budget`) adds the work of the Riemann dissipation, the pressure jump's
//! density diffusion, OAS's artificial stress, loads and contact, accumulated per acoustic step,
//! so that its residual measures what the scheme leaves unaccounted.
//!
//! Loops are gathers over each particle's own neighbours, parallel with rayon, so results do not
//! depend on the thread schedule. Acoustic sub-steps allocate only small scratch (the row
//! slices of the kernel-data refresh, the contact buffer); rebuilds reuse or replace their own
//! buffers.
//!
//! ```
//! use glam::DVec2;
//! use sph_geometry::generate::annulus_polar;
//! use sph_core::{Body, Solver};
//! use sph_materials::ElasticConstants;
//! use sph_ul::{Shear, UlParams, UlSolver};
//!
//! // A rubber disc flying at 1 m/s: `step` is one advection step of the dual-criteria scheme
//! // (several acoustic sub-steps), so it advances by `0.2 h / |v|max`.
//! let set = annulus_polar(DVec2::ZERO, 0.0, 0.01, 1e-3)?;
//! let body = Body::from(set).with_velocity(|_| DVec2::new(1.0, 0.0));
//! let c = ElasticConstants::from_youngs(1e7, 0.4, 1200.0)?;
//! let mut s = UlSolver::new(body, c, Shear::non_nested(), UlParams::default())?;
//! let info = s.step(f64::INFINITY)?;
//! assert!(s.acoustic_step_count() > 1 && info.time > 0.0);
//! // Momentum is conserved to round-off.
//! assert!((s.linear_momentum().x - 1.0 * s.masses().iter().sum::<f64>()).abs() < 1e-12);
//! # Ok::<(), sph_core::Error>(())
//! ```
#![deny(missing_docs)]

/// glam, whose f64 vectors and matrices (`DVec2`, `DVec3`, `DMat2`, `DMat3`) every API here
/// takes: `use sph_ul::glam::DVec2;` needs no glam dependency of your own.
pub use glam;

pub mod artificial_stress;
pub mod contact;
pub mod energy;
pub mod generalized;
pub mod nested;
pub mod non_nested;
pub mod plastic;
pub mod riemann;
pub mod shear;
pub mod solver;
pub mod stepping;

pub use energy::{AccumulatedWork, Energy};
pub use non_nested::LaplacianForm;
pub use riemann::RiemannScheme;
pub use shear::Shear;
pub use solver::{UlParams, UlSolver};
pub use stepping::Stepping;
