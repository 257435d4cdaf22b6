//! The particles of one body in their initial configuration: what every solver is built from.
//! The `sph-geometry` crate makes them from shapes, lattices, meshes and outlines
//! (`Body::from(set)` for its `ParticleSet`); here, by hand:
//!
//! ```
//! use sph_core::{Body, D2};
//! use glam::DVec2;
//!
//! // A 0.2 × 0.02 plate on a lattice of spacing 1 mm, moving up at 1 m/s.
//! let dp = 1e-3;
//! let x: Vec<DVec2> = (0..20)
//!     .flat_map(|j| (0..200).map(move |i| DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * dp))
//!     .collect();
//! let n = x.len();
//! let body = Body::<D2>::new(x, vec![dp * dp; n], dp).with_velocity(|_| DVec2::new(0.0, 1.0));
//! assert_eq!(body.len(), 200 * 20);
//! assert!(body.validate("plate").is_ok());
//! ```

use crate::dim::Dim;
use crate::error::{check_positive, Error};

/// The particles of one body: initial positions (the reference configuration of the
/// total-Lagrangian methods), volumes, the spacing `dp` that sets the kernel, and optional
/// initial velocities and densities. Masses are `ρ0 V` with the material's `ρ0`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Body<D: Dim> {
    /// Initial positions.
    pub positions: Vec<D::Vector>,
    /// Initial volumes `V⁰`.
    pub volumes: Vec<f64>,
    /// Initial particle spacing `dp` (sets `h`).
    pub dp: f64,
    /// Initial velocities (empty: at rest).
    pub velocities: Vec<D::Vector>,
    /// Initial densities (empty: `ρ0` everywhere). Only the updated-Lagrangian method, whose
    /// state carries a density, can start from other densities; the others refuse them.
    pub densities: Vec<f64>,
}

impl<D: Dim> Body<D> {
    /// A body at rest with reference density.
    pub fn new(positions: Vec<D::Vector>, volumes: Vec<f64>, dp: f64) -> Self {
        Self {
            positions,
            volumes,
            dp,
            velocities: Vec::new(),
            densities: Vec::new(),
        }
    }

    /// With initial velocities `v(x)` (evaluated at each initial position).
    pub fn with_velocity(mut self, v: impl Fn(D::Vector) -> D::Vector) -> Self {
        self.velocities = self.positions.iter().map(|&x| v(x)).collect();
        self
    }

    /// With the given initial velocities (one per particle).
    pub fn with_velocities(mut self, v: Vec<D::Vector>) -> Self {
        self.velocities = v;
        self
    }

    /// With the given initial densities (one per particle; updated-Lagrangian only).
    pub fn with_densities(mut self, rho: Vec<f64>) -> Self {
        self.densities = rho;
        self
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether the body has no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Checks what every solver needs: particles, a positive spacing, one finite volume `> 0`
    /// per particle, finite positions, and velocities (densities) either absent or one per
    /// particle. `what` names the body in the errors.
    ///
    /// # Errors
    /// The first violation, naming the field and the allowed range.
    pub fn validate(&self, what: &str) -> Result<(), Error> {
        let n = self.len();
        if n == 0 {
            return Err(Error::EmptyBody { body: what.into() });
        }
        check_positive("dp", self.dp)?;
        if self.volumes.len() != n {
            return Err(Error::invalid(
                "volumes",
                self.volumes.len(),
                &format!("one per particle ({n})"),
            ));
        }
        if let Some(i) = self
            .volumes
            .iter()
            .position(|v| !(v.is_finite() && *v > 0.0))
        {
            return Err(Error::invalid(
                &format!("volumes[{i}]"),
                self.volumes[i],
                "> 0 and finite",
            ));
        }
        if let Some(i) = self.positions.iter().position(|&x| !D::is_finite(x)) {
            return Err(Error::invalid(
                &format!("positions[{i}]"),
                format!("{:?}", self.positions[i]),
                "finite",
            ));
        }
        for (name, len) in [
            ("velocities", self.velocities.len()),
            ("densities", self.densities.len()),
        ] {
            if len != 0 && len != n {
                return Err(Error::invalid(
                    name,
                    len,
                    &format!("empty or one per particle ({n})"),
                ));
            }
        }
        if let Some(i) = self.velocities.iter().position(|&v| !D::is_finite(v)) {
            return Err(Error::invalid(
                &format!("velocities[{i}]"),
                format!("{:?}", self.velocities[i]),
                "finite",
            ));
        }
        Ok(())
    }

    /// Refuses initial densities (for the methods whose density follows from the deformation).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `densities` when some are given.
    pub fn reject_densities(&self, method: &str) -> Result<(), Error> {
        if self.densities.is_empty() {
            Ok(())
        } else {
            Err(Error::invalid(
                "densities",
                format!("{} values", self.densities.len()),
                &format!("none: {method} takes the density from the material and the deformation"),
            ))
        }
    }

    /// The initial velocities, zero where none were given.
    pub fn velocities_or_rest(&self) -> Vec<D::Vector> {
        if self.velocities.is_empty() {
            vec![D::zero(); self.len()]
        } else {
            self.velocities.clone()
        }
    }
}

/// The per-particle material index of a body of `n` particles with `materials` laws: `material_of`
/// empty (every particle the first law) or one index per particle below `materials`, stored as
/// `u16` (UL's and MPS's `with_materials`).
///
/// # Errors
/// [`Error::InvalidParameter`] naming `materials` (none, or more than 65,536) or `material_of`
/// (wrong length, or an index without a law).
pub fn material_indices(
    materials: usize,
    material_of: &[u32],
    n: usize,
) -> Result<Vec<u16>, Error> {
    if materials == 0 || materials > usize::from(u16::MAX) + 1 {
        return Err(Error::invalid(
            "materials",
            materials,
            "1 to 65536 materials",
        ));
    }
    if !(material_of.is_empty() || material_of.len() == n) {
        return Err(Error::invalid(
            "material_of",
            material_of.len(),
            &format!("empty or one material index per particle ({n})"),
        ));
    }
    if let Some(&m) = material_of.iter().find(|&&m| m as usize >= materials) {
        return Err(Error::invalid(
            "material_of",
            m,
            &format!("a material index below {materials}"),
        ));
    }
    Ok(if material_of.is_empty() {
        vec![0; n]
    } else {
        material_of.iter().map(|&m| m as u16).collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D2;
    use glam::DVec2;

    #[test]
    fn validation_names_the_field() {
        let good = Body::<D2>::new(vec![DVec2::ZERO, DVec2::X], vec![1.0, 1.0], 1.0);
        assert!(good.validate("b").is_ok());
        let e = Body::<D2>::new(vec![], vec![], 1.0).validate("wall");
        assert!(e.unwrap_err().to_string().contains("wall"));
        let e = Body::<D2>::new(vec![DVec2::ZERO], vec![0.0], 1.0).validate("b");
        assert!(e.unwrap_err().to_string().contains("volumes[0]"));
        let e = good
            .clone()
            .with_velocities(vec![DVec2::ZERO])
            .validate("b");
        assert!(e.unwrap_err().to_string().contains("velocities"));
        let e = good.clone().with_densities(vec![1.0]).validate("b");
        assert!(e.unwrap_err().to_string().contains("densities"));
        assert!(good
            .clone()
            .with_densities(vec![1.0, 1.0])
            .reject_densities("tl")
            .is_err());
        let e = Body::<D2>::new(vec![DVec2::ZERO], vec![1.0], -1.0).validate("b");
        assert!(e.unwrap_err().to_string().contains("dp"));
    }
}
