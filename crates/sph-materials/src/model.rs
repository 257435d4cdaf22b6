//! Picking a law by name: [`MaterialKind`] (what a scene asks for) and [`MaterialModel`] (the
//! built law, dispatching [`Material`] for 2D and 3D).

use crate::laws::kirchhoff_vol_dev::{DeviatorDimension, KirchhoffVolDev};
use crate::laws::mooney_rivlin::MooneyRivlinLike;
use crate::laws::neo_hookean::NeoHookean;
use crate::laws::saint_venant_kirchhoff::SaintVenantKirchhoff;
use crate::{ElasticConstants, Material};
use glam::DMat3;
use serde::{Deserialize, Serialize};
use sph_core::{Dim, Error};
use std::fmt;
use std::str::FromStr;

/// The names [`MaterialKind::from_str`] accepts.
pub const MATERIAL_NAMES: [&str; 5] = [
    "linear-elastic",
    "saint-venant-kirchhoff",
    "neo-hookean",
    "kirchhoff-vol-dev",
    "mooney-rivlin",
];

fn default_c2_fraction() -> f64 {
    MooneyRivlinLike::MPS_PAPER_C2_FRACTION
}

/// Which constitutive law a scene uses, with the law's options but not its elastic constants.
/// Serialised with a `kind` tag (`kind = "neo-hookean"`); parsed from a bare name by
/// [`FromStr`]. Build the law with [`MaterialKind::build`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MaterialKind {
    /// The TL paper's linear elastic law (eq. 5) = Saint Venant–Kirchhoff.
    LinearElastic,
    /// Saint Venant–Kirchhoff (TL eq. 5, MPS eq. 11).
    SaintVenantKirchhoff,
    /// Neo-Hookean (TL eq. 7–8).
    NeoHookean,
    /// Volumetric–deviatoric Kirchhoff law (TL eq. 10–14).
    KirchhoffVolDev {
        /// The `d` of the isochoric split (default `d = D::D`, the paper's).
        #[serde(default)]
        deviator: DeviatorDimension,
    },
    /// Mooney–Rivlin-like compressible law (MPS eq. 12), matched to the elastic constants at
    /// small strain.
    MooneyRivlin {
        /// `c₂ / (c₁ + c₂)`, default the MPS paper's ratio (≈ 0.0741).
        #[serde(default = "default_c2_fraction")]
        c2_fraction: f64,
    },
}

impl MaterialKind {
    /// Builds the law from the constants (every law's constructor validates its own options).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid law option (e.g. `c2_fraction`).
    pub fn build(self, constants: ElasticConstants) -> Result<MaterialModel, Error> {
        MaterialModel::build(self, constants)
    }

    /// The canonical name (one of [`MATERIAL_NAMES`]).
    pub fn name(&self) -> &'static str {
        match self {
            MaterialKind::LinearElastic => "linear-elastic",
            MaterialKind::SaintVenantKirchhoff => "saint-venant-kirchhoff",
            MaterialKind::NeoHookean => "neo-hookean",
            MaterialKind::KirchhoffVolDev { .. } => "kirchhoff-vol-dev",
            MaterialKind::MooneyRivlin { .. } => "mooney-rivlin",
        }
    }
}

impl fmt::Display for MaterialKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MaterialKind {
    type Err = Error;
    /// Parses one of [`MATERIAL_NAMES`] (law options take their defaults).
    fn from_str(s: &str) -> Result<Self, Error> {
        Ok(match s.trim() {
            "linear-elastic" => MaterialKind::LinearElastic,
            "saint-venant-kirchhoff" => MaterialKind::SaintVenantKirchhoff,
            "neo-hookean" => MaterialKind::NeoHookean,
            "kirchhoff-vol-dev" => MaterialKind::KirchhoffVolDev {
                deviator: DeviatorDimension::default(),
            },
            "mooney-rivlin" => MaterialKind::MooneyRivlin {
                c2_fraction: default_c2_fraction(),
            },
            other => {
                return Err(Error::invalid(
                    "material",
                    other,
                    &format!("one of {}", MATERIAL_NAMES.join(", ")),
                ))
            }
        })
    }
}

/// A built constitutive law, chosen at run time and dispatched by a `match` (hoist the match out
/// of hot loops by matching once and calling a generic kernel with the inner law, or accept one
/// well-predicted branch per call). Serialised with a `kind` tag and the law's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum MaterialModel {
    /// Saint Venant–Kirchhoff = the TL paper's linear elastic law (TL eq. 5).
    #[serde(alias = "linear-elastic")]
    SaintVenantKirchhoff(SaintVenantKirchhoff),
    /// Neo-Hookean (TL eq. 7–8).
    NeoHookean(NeoHookean),
    /// Volumetric–deviatoric Kirchhoff law (TL eq. 10–14).
    KirchhoffVolDev(KirchhoffVolDev),
    /// Mooney–Rivlin-like compressible law (MPS eq. 12).
    MooneyRivlin(MooneyRivlinLike),
}

impl MaterialModel {
    /// Builds the law `kind` from `constants`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid law option (e.g. `c2_fraction`).
    pub fn build(kind: MaterialKind, constants: ElasticConstants) -> Result<Self, Error> {
        Ok(match kind {
            MaterialKind::LinearElastic | MaterialKind::SaintVenantKirchhoff => {
                MaterialModel::SaintVenantKirchhoff(SaintVenantKirchhoff::new(constants))
            }
            MaterialKind::NeoHookean => MaterialModel::NeoHookean(NeoHookean::new(constants)),
            MaterialKind::KirchhoffVolDev { deviator } => {
                MaterialModel::KirchhoffVolDev(KirchhoffVolDev::with_deviator(constants, deviator))
            }
            MaterialKind::MooneyRivlin { c2_fraction } => MaterialModel::MooneyRivlin(
                MooneyRivlinLike::from_constants(constants, c2_fraction)?,
            ),
        })
    }
}

/// Forwards a method to the wrapped law.
macro_rules! dispatch {
    ($self:ident, $law:ident => $e:expr) => {
        match $self {
            MaterialModel::SaintVenantKirchhoff($law) => $e,
            MaterialModel::NeoHookean($law) => $e,
            MaterialModel::KirchhoffVolDev($law) => $e,
            MaterialModel::MooneyRivlin($law) => $e,
        }
    };
}

impl<D: Dim> Material<D> for MaterialModel {
    #[inline]
    fn name(&self) -> &'static str {
        dispatch!(self, m => Material::<D>::name(m))
    }
    #[inline]
    fn constants(&self) -> &ElasticConstants {
        dispatch!(self, m => Material::<D>::constants(m))
    }
    #[inline(always)]
    fn second_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        dispatch!(self, m => Material::<D>::second_piola_kirchhoff(m, f))
    }
    #[inline(always)]
    fn first_piola_kirchhoff(&self, f: D::Matrix) -> D::Matrix {
        dispatch!(self, m => Material::<D>::first_piola_kirchhoff(m, f))
    }
    #[inline(always)]
    fn kirchhoff_stress(&self, f: D::Matrix) -> D::Matrix {
        dispatch!(self, m => Material::<D>::kirchhoff_stress(m, f))
    }
    fn cauchy_stress_3d(&self, f: D::Matrix) -> DMat3 {
        dispatch!(self, m => Material::<D>::cauchy_stress_3d(m, f))
    }
    #[inline]
    fn strain_energy_density(&self, f: D::Matrix) -> Option<f64> {
        dispatch!(self, m => Material::<D>::strain_energy_density(m, f))
    }
    #[inline(always)]
    fn hf_split(&self, f: D::Matrix, zeta: f64) -> (D::Matrix, f64) {
        dispatch!(self, m => Material::<D>::hf_split(m, f, zeta))
    }
}
