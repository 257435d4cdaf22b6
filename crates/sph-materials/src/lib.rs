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
#![deny(missing_docs)]

pub mod constants;
pub mod laws;
pub mod material;
pub mod model;
pub mod stress;

pub use constants::ElasticConstants;
pub use laws::kirchhoff_vol_dev::{DeviatorDimension, KirchhoffVolDev};
pub use laws::mooney_rivlin::MooneyRivlinLike;
pub use laws::neo_hookean::NeoHookean;
pub use laws::saint_venant_kirchhoff::{LinearElastic, SaintVenantKirchhoff};
pub use material::Material;
pub use model::{MaterialKind, MaterialModel, MATERIAL_NAMES};
pub use stress::von_mises;
