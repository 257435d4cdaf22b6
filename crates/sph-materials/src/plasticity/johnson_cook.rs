//! The Johnson–Cook flow stress (Johnson & Cook 1983, "A constitutive model and data for metals
//! subjected to large strains, high strain rates and high temperatures", eq. 1):
//!
//! `σ_y = (A + B ε̄p^n) (1 + C ln ε̇*) (1 − T*^m)`,
//!
//! with `ε̇* = max(ε̇̄p/ε̇0, 1)` and `T* = clamp((T − T_room)/(T_melt − T_room), 0, 1)`. The two
//! clamps are not in the paper's equation but are how it is used (LS-DYNA `*MAT_015`, Abaqus):
//! without the first the rate factor goes to −∞ as `ε̇̄p → 0`, i.e. on every step that starts to
//! yield; without the second `T*^m` is NaN below room temperature for a fractional `m` and the
//! flow stress negative above melting. Adiabatic heating raises the temperature by
//! `β σ_y Δε̄p / (ρ c_p)`, β the fraction of the plastic work turned into heat (Taylor & Quinney
//! 1934; ≈ 0.9 for metals).

use serde::{Deserialize, Serialize};
use sph_core::error::{check_closed_range, check_non_negative, check_positive};
use sph_core::Error;

/// Thermal softening `1 − T*^m` of the Johnson–Cook law, with optional adiabatic heating.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalSoftening {
    /// Thermal-softening exponent `m`, > 0.
    pub m: f64,
    /// Room (transition) temperature `T_room` (K), > 0.
    pub room_temperature: f64,
    /// Melting temperature `T_melt` (K), > `T_room`.
    pub melting_temperature: f64,
    /// Initial temperature of the material (K), > 0.
    pub initial_temperature: f64,
    /// Taylor–Quinney fraction β of the plastic work turned into heat, in [0, 1] (0: isothermal
    /// at the initial temperature; ≈ 0.9 for metals).
    pub taylor_quinney: f64,
    /// Specific heat `c_p` (J/(kg K)), > 0.
    pub specific_heat: f64,
}

/// Johnson–Cook flow-stress constants (Johnson & Cook 1983, eq. 1 and Table 1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JohnsonCook {
    /// `A` (Pa): the yield stress at `ε̄p = 0`, reference rate and room temperature; > 0.
    pub a: f64,
    /// `B` (Pa): the strain-hardening coefficient; ≥ 0.
    pub b: f64,
    /// `n`: the strain-hardening exponent; > 0.
    pub n: f64,
    /// `C`: the strain-rate coefficient; ≥ 0 (0: rate-independent).
    pub c: f64,
    /// Reference strain rate `ε̇0` (1/s), > 0 (the paper's is 1/s).
    pub reference_strain_rate: f64,
    /// Thermal softening (`None`: the flow stress does not depend on temperature).
    pub thermal: Option<ThermalSoftening>,
}

impl JohnsonCook {
    /// `Ok` if every constant is in its range (named as the scene keys name them).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first constant out of range.
    pub fn validate(&self) -> Result<(), Error> {
        check_positive("A", self.a)?;
        check_non_negative("B", self.b)?;
        check_positive("n", self.n)?;
        check_non_negative("C", self.c)?;
        check_positive("reference_strain_rate", self.reference_strain_rate)?;
        if let Some(t) = &self.thermal {
            check_positive("m", t.m)?;
            check_positive("room_temperature", t.room_temperature)?;
            if !(t.melting_temperature.is_finite() && t.melting_temperature > t.room_temperature) {
                return Err(Error::invalid(
                    "melting_temperature",
                    t.melting_temperature,
                    &format!("finite and > room_temperature = {}", t.room_temperature),
                ));
            }
            check_positive("initial_temperature", t.initial_temperature)?;
            check_closed_range("taylor_quinney", t.taylor_quinney, 0.0, 1.0)?;
            check_positive("specific_heat", t.specific_heat)?;
        }
        Ok(())
    }

    /// Strain hardening `A + B ε̄p^n` and its slope `n B ε̄p^(n−1)` (Johnson & Cook 1983,
    /// eq. 1, first factor). The slope is `+∞` at `ε̄p = 0` for `n < 1`.
    #[inline]
    pub fn strain_hardening(&self, eps_p: f64) -> (f64, f64) {
        let eps = eps_p.max(0.0);
        let pow = eps.powf(self.n);
        let slope = if eps > 0.0 {
            self.n * self.b * pow / eps
        } else if self.n < 1.0 && self.b > 0.0 {
            f64::INFINITY
        } else if self.n == 1.0 {
            self.b
        } else {
            0.0
        };
        (self.a + self.b * pow, slope)
    }

    /// Strain-rate factor `1 + C ln max(ε̇̄p/ε̇0, 1)` and its derivative with respect to
    /// `ε̇̄p` (Johnson & Cook 1983, eq. 1, second factor, with the clamp of the module docs:
    /// rates below `ε̇0`, including 0, give 1).
    #[inline]
    pub fn rate_factor(&self, plastic_strain_rate: f64) -> (f64, f64) {
        let ratio = plastic_strain_rate / self.reference_strain_rate;
        if ratio > 1.0 {
            (1.0 + self.c * ratio.ln(), self.c / plastic_strain_rate)
        } else {
            (1.0, 0.0)
        }
    }

    /// Homologous temperature `T* = clamp((T − T_room)/(T_melt − T_room), 0, 1)` (Johnson &
    /// Cook 1983, eq. 1, with the clamp of the module docs).
    #[inline]
    pub fn homologous_temperature(thermal: &ThermalSoftening, temperature: f64) -> f64 {
        ((temperature - thermal.room_temperature)
            / (thermal.melting_temperature - thermal.room_temperature))
            .clamp(0.0, 1.0)
    }

    /// Thermal-softening factor `1 − T*^m` at `temperature` (Johnson & Cook 1983, eq. 1, third
    /// factor); 1 without thermal softening.
    #[inline]
    pub fn thermal_factor(&self, temperature: f64) -> f64 {
        match &self.thermal {
            Some(t) => 1.0 - Self::homologous_temperature(t, temperature).powf(t.m),
            None => 1.0,
        }
    }

    /// The temperature of a particle whose plastic work has raised it by `temperature_rise`
    /// (the initial temperature without thermal softening is irrelevant and taken as 0).
    #[inline]
    pub fn temperature(&self, temperature_rise: f64) -> f64 {
        match &self.thermal {
            Some(t) => t.initial_temperature + temperature_rise,
            None => 0.0,
        }
    }

    /// The Johnson–Cook flow stress `σ_y(ε̄p, ε̇̄p, T)` of eq. 1 (with both clamps).
    #[inline]
    pub fn flow_stress(&self, eps_p: f64, plastic_strain_rate: f64, temperature: f64) -> f64 {
        self.strain_hardening(eps_p).0
            * self.rate_factor(plastic_strain_rate).0
            * self.thermal_factor(temperature)
    }

    /// Adiabatic temperature rise `β σ_y Δε̄p / (ρ c_p)` of a plastic increment (the plastic
    /// work per unit volume `σ_y Δε̄p`, the Taylor–Quinney fraction β of it heat, no
    /// conduction); 0 without thermal softening.
    #[inline]
    pub fn adiabatic_heating(&self, flow_stress: f64, delta_eps_p: f64, density: f64) -> f64 {
        match &self.thermal {
            Some(t) => t.taylor_quinney * flow_stress * delta_eps_p / (density * t.specific_heat),
            None => 0.0,
        }
    }
}
