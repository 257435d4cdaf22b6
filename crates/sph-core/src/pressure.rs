//! Follower surface pressure on boundary particles: a gas or fluid pressure, a surface traction
//! normal to the body (the MPS paper's pressurised rubber ring, §IV.A: a radial pressure on the
//! inner circumference). The methods that carry a deformation gradient apply it (TL and MPS:
//! `with_surface_pressure`).
//!
//! Particle `i` of the loaded surface carries a reference area `A⁰_i` (its share of the surface;
//! in 2D a length per unit depth, e.g. `dp`) and a reference **outward** unit normal `N_i` of the
//! body. Its current area vector follows Nanson's formula `n_i a_i = cof(F_i) N_i A⁰_i`
//! ([`crate::dim::cofactor`]), so the load turns and stretches with the deformation, and the
//! pressure `p(t)` (positive = compression, pushing into the body) gives the force
//! `f_i = −p(t) cof(F_i) N_i A⁰_i`. For the ring's inner surface the outward normal of the body
//! points toward the centre, so a positive pressure pushes the wall outward. The load is not
//! conservative (follower load), so it does not enter the energy.
//! [`crate::surface::surface_of`] finds the surface particles of a region with their normals.

use crate::amplitude::Amplitude;
use crate::dim::{cofactor, Dim};
use crate::error::Error;
use std::fmt;
use std::sync::Arc;

/// A scalar function of time (pressure in Pa).
#[derive(Clone)]
pub struct PressureFunction(Arc<dyn Fn(f64) -> f64 + Send + Sync>);

impl PressureFunction {
    /// Wraps a closure `t ↦ p(t)`.
    pub fn new(f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        Self(Arc::new(f))
    }
    /// A constant pressure.
    pub fn constant(p: f64) -> Self {
        Self::new(move |_| p)
    }
    /// `p · a(t)`: a pressure following an amplitude curve.
    pub fn scaled(p: f64, amplitude: Amplitude) -> Self {
        Self::new(move |t| p * amplitude.at(t))
    }
    /// Evaluates at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        (self.0)(t)
    }
}

impl fmt::Debug for PressureFunction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PressureFunction(p(0) = {})", self.at(0.0))
    }
}

/// A pressure on a set of surface particles; see the module documentation.
#[derive(Clone, Debug)]
pub struct SurfacePressure<D: Dim> {
    /// The loaded particles.
    pub particles: Vec<u32>,
    /// Reference outward unit normals of the body, one per particle, or `None` to estimate
    /// them from the neighbourhood: `N_i = −Σ_j w_ij X_ij / |Σ_j w_ij X_ij|` (the neighbours lie
    /// inside the body, so the weighted mean offset points inward).
    pub normals: Option<Vec<D::Vector>>,
    /// Reference areas `A⁰_i` (2D: lengths per unit depth), one per particle, or `None` for
    /// `dp^(d−1)`.
    pub areas: Option<Vec<f64>>,
    /// The pressure `p(t)` (positive pushes into the body).
    pub pressure: PressureFunction,
}

impl<D: Dim> SurfacePressure<D> {
    /// A constant pressure `p` on `particles`, normals estimated, areas `dp^(d−1)`.
    pub fn constant(particles: Vec<u32>, p: f64) -> Self {
        Self {
            particles,
            normals: None,
            areas: None,
            pressure: PressureFunction::constant(p),
        }
    }
}

/// A validated surface pressure with resolved normals and areas, as a solver applies it.
#[derive(Clone, Debug)]
pub struct ResolvedPressure<D: Dim> {
    /// The loaded particles.
    pub particles: Vec<u32>,
    /// `A⁰_k N_k`, one per loaded particle.
    pub area_normal: Vec<D::Vector>,
    /// The pressure `p(t)`.
    pub pressure: PressureFunction,
}

impl<D: Dim> ResolvedPressure<D> {
    /// Validates `sp` against a body of `n` particles; `estimate(i)` gives the unnormalised
    /// inward offset `Σ_j w_ij X_ij` of particle `i`.
    pub fn resolve(
        sp: SurfacePressure<D>,
        n: usize,
        dp: f64,
        estimate: impl Fn(usize) -> D::Vector,
    ) -> Result<Self, Error> {
        let m = sp.particles.len();
        if let Some(&bad) = sp.particles.iter().find(|&&i| i as usize >= n) {
            return Err(Error::invalid(
                "surface_pressure.particles",
                bad,
                &format!("0..{n} (the body's particles)"),
            ));
        }
        let areas = match sp.areas {
            None => vec![dp.powi(D::D as i32 - 1); m],
            Some(a) if a.len() == m => {
                if let Some(k) = a.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                    return Err(Error::invalid(
                        &format!("surface_pressure.areas[{k}]"),
                        a[k],
                        "> 0 and finite",
                    ));
                }
                a
            }
            Some(a) => {
                return Err(Error::invalid(
                    "surface_pressure.areas",
                    a.len(),
                    &format!("one per loaded particle ({m})"),
                ))
            }
        };
        let normals: Vec<D::Vector> = match sp.normals {
            None => sp
                .particles
                .iter()
                .map(|&i| {
                    let s = estimate(i as usize);
                    let l = D::norm(s);
                    if l > 0.0 && l.is_finite() {
                        Ok(s * (-1.0 / l))
                    } else {
                        Err(Error::invalid(
                            "surface_pressure.normals",
                            format!("particle {i} has a symmetric neighbourhood"),
                            "given normals, or surface particles (not interior ones)",
                        ))
                    }
                })
                .collect::<Result<_, _>>()?,
            Some(nv) if nv.len() == m => nv
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    let l = D::norm(v);
                    if l > 0.0 && l.is_finite() {
                        Ok(v * (1.0 / l))
                    } else {
                        Err(Error::invalid(
                            &format!("surface_pressure.normals[{k}]"),
                            format!("{v:?}"),
                            "finite and non-zero",
                        ))
                    }
                })
                .collect::<Result<_, _>>()?,
            Some(nv) => {
                return Err(Error::invalid(
                    "surface_pressure.normals",
                    nv.len(),
                    &format!("one per loaded particle ({m})"),
                ))
            }
        };
        Ok(Self {
            particles: sp.particles,
            area_normal: normals.iter().zip(&areas).map(|(&v, &a)| v * a).collect(),
            pressure: sp.pressure,
        })
    }

    /// Adds the accelerations `−p(t) cof(F_i) N_i A⁰_i / m_i` of the pressure at time `t` to
    /// `acc`, with the deformation gradients `deformation` and inverse masses `inv_mass(i)`.
    #[inline]
    pub fn add_accelerations(
        &self,
        t: f64,
        deformation: &[D::Matrix],
        inv_mass: impl Fn(usize) -> f64,
        acc: &mut [D::Vector],
    ) {
        let p = self.pressure.at(t);
        for (&i, &an) in self.particles.iter().zip(&self.area_normal) {
            let i = i as usize;
            let f = cofactor::<D>(deformation[i]) * an * (-p);
            acc[i] += f * inv_mass(i);
        }
    }

    /// Keeps only the loaded particles of a subset and relabels them (`inv[old] = new`, or
    /// `u32::MAX` for a particle outside it): one rank's share of a distributed run.
    pub fn restrict(&mut self, inv: &[u32]) {
        let (particles, normals): (Vec<u32>, Vec<D::Vector>) = self
            .particles
            .iter()
            .zip(&self.area_normal)
            .filter(|(&i, _)| inv[i as usize] != u32::MAX)
            .map(|(&i, &n)| (inv[i as usize], n))
            .unzip();
        (self.particles, self.area_normal) = (particles, normals);
    }
}
