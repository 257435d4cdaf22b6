//! # sph-materials
//!
//! Constitutive laws and stress measures for sph-solids; no particles, no neighbours.
//!
//! - [`ElasticConstants`]: `E, ν, ρ0` and the derived `K, G, λ, c0` (TL paper eq. 5–6).
//! - [`Material`]: `S`, `P = F S`, `τ = F S Fᵀ`, Cauchy `σ` (3×3), strain energy `ψ`, generic
//!   over the dimension (2D is plane strain, `F_zz = 1`).
//! - Laws: [`SaintVenantKirchhoff`] (= [`LinearElastic`], TL eq. 5 / MPS eq. 11),
//!   [`NeoHookean`] (TL eq. 7–8), [`KirchhoffVolDev`] (TL eq. 10–14),
//!   [`MooneyRivlinLike`] (MPS eq. 12).
//! - [`MaterialKind`] / [`MaterialModel`]: pick a law by name in a scene.
//! - [`von_mises`]: the equivalent stress the papers plot.
//! - [`plasticity`]: J2 and Johnson–Cook plasticity with per-particle history ([`PlasticState`])
//!   and the radial return of a hypoelastic deviatoric stress ([`Plasticity::return_stress`]).
//!
//! ```
//! use sph_core::{Dim, D2};
//! use sph_materials::{von_mises, ElasticConstants, Material, NeoHookean};
//!
//! // Rubber, stretched 20 % in x in plane strain: the stress and its von Mises value.
//! let law = NeoHookean::new(ElasticConstants::from_youngs(1e6, 0.45, 1100.0)?);
//! let f = glam::DMat2::from_diagonal(glam::DVec2::new(1.2, 1.0));
//! let sigma = Material::<D2>::cauchy_stress_3d(&law, f);
//! assert!(sigma.x_axis.x > 0.0 && von_mises(sigma) > 0.0);
//! // Zero stress at rest, for every law.
//! assert_eq!(Material::<D2>::first_piola_kirchhoff(&law, D2::identity()), glam::DMat2::ZERO);
//! # Ok::<(), sph_core::Error>(())
//! ```
#![deny(missing_docs)]

pub mod constants;
pub mod laws;
pub mod material;
pub mod model;
pub mod plasticity;
pub mod stress;

pub use constants::{ElasticConstants, DENSITY_RANGE, MODULUS_RANGE};
pub use laws::kirchhoff_vol_dev::{DeviatorDimension, KirchhoffVolDev};
pub use laws::mooney_rivlin::MooneyRivlinLike;
pub use laws::neo_hookean::NeoHookean;
pub use laws::saint_venant_kirchhoff::{LinearElastic, SaintVenantKirchhoff};
pub use material::Material;
pub use model::{MaterialKind, MaterialModel, MATERIAL_NAMES};
pub use plasticity::{PlasticLaw, PlasticState, Plasticity, PLASTIC_LAW_NAMES};
pub use stress::von_mises;
