//! The plastic laws of a scene's `[material]` (`law = "j2"` or `"johnson-cook"`) and their keys;
//! the elastic part of a plastic material is its `youngs_modulus` and `nu` (or `bulk_modulus` and
//! `shear_modulus`), read by [`Scene::material`](super::Scene): hypoelastic for the UL methods,
//! a Hencky (logarithmic) law for `tl` and `tl-gm`.

use super::*;
use sph_materials::plasticity::{IsotropicHardening, JohnsonCook, PlasticLaw, ThermalSoftening};

/// Defaults of the optional Johnson–Cook keys.
const DEFAULT_REFERENCE_STRAIN_RATE: f64 = 1.0;
const DEFAULT_TAYLOR_QUINNEY: f64 = 0.9;

/// The methods that carry a plastic law (UL: the hypoelastic radial return; TL: the
/// finite-strain exponential-map return on a Hencky law, `sph_tl::solver::plastic`).
pub(super) const PLASTIC_METHODS: [&str; 5] = ["ul-og", "ul-oas", "ul-gnog", "tl", "tl-gm"];

/// Whether `law` names a plastic law.
pub(super) fn is_plastic(law: &str) -> bool {
    sph_materials::PLASTIC_LAW_NAMES.contains(&law.trim())
}

impl Scene {
    /// The plastic law of `[material]`, or `None` for an elastic law. Keys of a law the material
    /// does not have are an error, never ignored; so are out-of-range constants (named
    /// `material.<key>`).
    pub(super) fn plastic_law(
        &self,
        span: std::ops::Range<usize>,
        s: &MaterialSpec,
    ) -> Result<Option<PlasticLaw>, SceneError> {
        let law = s.law.trim();
        let at = |key: &'static str| At {
            span: span.clone(),
            key,
        };
        let j2_keys = [
            ("yield_stress", s.yield_stress.is_some()),
            ("hardening_modulus", s.hardening_modulus.is_some()),
            ("saturation_stress", s.saturation_stress.is_some()),
            ("saturation_exponent", s.saturation_exponent.is_some()),
        ];
        let jc_keys = [
            ("A", s.jc_a.is_some()),
            ("B", s.jc_b.is_some()),
            ("n", s.jc_n.is_some()),
            ("C", s.jc_c.is_some()),
            ("m", s.jc_m.is_some()),
            ("reference_strain_rate", s.reference_strain_rate.is_some()),
            ("room_temperature", s.room_temperature.is_some()),
            ("melting_temperature", s.melting_temperature.is_some()),
            ("temperature", s.temperature.is_some()),
            ("taylor_quinney", s.taylor_quinney.is_some()),
            ("specific_heat", s.specific_heat.is_some()),
        ];
        let foreign = |keys: &[(&'static str, bool)], owner: &str| -> Result<(), SceneError> {
            match keys.iter().find(|k| k.1) {
                Some((key, _)) => Err(self.error_in(
                    &at(key),
                    &format!("material.{key}"),
                    format!("a key of law = \"{owner}\", not of law = \"{law}\""),
                )),
                None => Ok(()),
            }
        };
        let required = |key: &'static str, v: Option<f64>| {
            v.ok_or_else(|| {
                self.error_in(
                    &at("law"),
                    &format!("material.{key}"),
                    format!("law = \"{law}\" needs `{key}`"),
                )
            })
        };
        let plastic = match law {
            "j2" => {
                foreign(&jc_keys, "johnson-cook")?;
                let yield_stress = required("yield_stress", s.yield_stress)?;
                let hardening_modulus = s.hardening_modulus.unwrap_or(0.0);
                PlasticLaw::J2(match (s.saturation_stress, s.saturation_exponent) {
                    (None, None) => IsotropicHardening::Linear {
                        yield_stress,
                        hardening_modulus,
                    },
                    (Some(saturation_stress), Some(saturation_exponent)) => {
                        IsotropicHardening::Saturation {
                            yield_stress,
                            hardening_modulus,
                            saturation_stress,
                            saturation_exponent,
                        }
                    }
                    (Some(_), None) => return Err(self.error_in(
                        &at("saturation_stress"),
                        "material.saturation_exponent",
                        "saturation hardening needs both saturation_stress and saturation_exponent",
                    )),
                    (None, Some(_)) => return Err(self.error_in(
                        &at("saturation_exponent"),
                        "material.saturation_stress",
                        "saturation hardening needs both saturation_stress and saturation_exponent",
                    )),
                })
            }
            "johnson-cook" => {
                foreign(&j2_keys, "j2")?;
                let thermal_keys = [s.jc_m, s.room_temperature, s.melting_temperature];
                let thermal = if thermal_keys.iter().any(Option::is_some)
                    || s.temperature.is_some()
                    || s.taylor_quinney.is_some()
                    || s.specific_heat.is_some()
                {
                    let room_temperature = required("room_temperature", s.room_temperature)?;
                    Some(ThermalSoftening {
                        m: required("m", s.jc_m)?,
                        room_temperature,
                        melting_temperature: required(
                            "melting_temperature",
                            s.melting_temperature,
                        )?,
                        initial_temperature: s.temperature.unwrap_or(room_temperature),
                        taylor_quinney: s.taylor_quinney.unwrap_or(DEFAULT_TAYLOR_QUINNEY),
                        specific_heat: required("specific_heat", s.specific_heat)?,
                    })
                } else {
                    None
                };
                PlasticLaw::JohnsonCook(JohnsonCook {
                    a: required("A", s.jc_a)?,
                    b: required("B", s.jc_b)?,
                    n: required("n", s.jc_n)?,
                    c: s.jc_c.unwrap_or(0.0),
                    reference_strain_rate: s
                        .reference_strain_rate
                        .unwrap_or(DEFAULT_REFERENCE_STRAIN_RATE),
                    thermal,
                })
            }
            _ => {
                foreign(&j2_keys, "j2")?;
                foreign(&jc_keys, "johnson-cook")?;
                return Ok(None);
            }
        };
        plastic.validate().map_err(|e| {
            let key = match &e {
                sph_core::Error::InvalidParameter { field, .. } => field.clone(),
                _ => "law".into(),
            };
            let at = At {
                span: span.clone(),
                key: &key,
            };
            self.error_in(&at, &format!("material.{key}"), e.to_string())
        })?;
        Ok(Some(plastic))
    }
}
