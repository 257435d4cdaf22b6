//! Contact pair detection shared by the method families (DESIGN: one contact layer): the pairs
//! of particles that may touch in the current configuration, between bodies and, where asked,
//! within a body (self-contact). The force law stays in the method crate that owns the state.
//!
//! A pair `(i, j)` is a contact pair when the particles are closer than `range` now and either
//! belong to different bodies, or belong to the same body, that body has self-contact on, and
//! their reference (initial) distance is at least `reference_cutoff` (they are not reference
//! neighbours, so the body's own stress does not already act between them).

use crate::neighbor::distance_squared;
use crate::{CellGrid, Dim, Error, NeighborList, Series};

/// Which pairs may touch: the body of every particle and the bodies with self-contact.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactBodies {
    /// Body index per particle.
    pub body: Vec<u32>,
    /// Per body: whether its particles touch each other (self-contact).
    pub self_contact: Vec<bool>,
}

impl ContactBodies {
    /// `body[i]` per particle; no self-contact. The number of bodies is the largest index + 1.
    pub fn new(body: Vec<u32>) -> Self {
        let bodies = body.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        Self {
            body,
            self_contact: vec![false; bodies],
        }
    }

    /// Number of bodies.
    pub fn bodies(&self) -> usize {
        self.self_contact.len()
    }

    /// Whether detection has anything to find (several bodies or a self-contact).
    pub fn is_active(&self) -> bool {
        self.bodies() > 1 || self.self_contact.iter().any(|&s| s)
    }

    /// The contact pairs at `positions` (symmetric list, rows ascending: deterministic).
    /// `reference` are the reference positions the self-contact exclusion is measured on.
    ///
    /// # Errors
    /// Non-finite positions, or `range`/`reference_cutoff` not positive.
    pub fn detect<D: Dim>(
        &self,
        positions: &[D::Vector],
        reference: &[D::Vector],
        range: f64,
        reference_cutoff: f64,
    ) -> Result<NeighborList, Error> {
        crate::error::check_positive("contact range", range)?;
        crate::error::check_positive("contact reference_cutoff", reference_cutoff)?;
        let all = CellGrid::<D>::build(positions, range)?.neighbor_list(positions, range)?;
        let rc2 = reference_cutoff * reference_cutoff;
        let n = positions.len();
        let (mut off, mut ix) = (Vec::with_capacity(n + 1), Vec::new());
        off.push(0);
        for i in 0..n {
            let start = ix.len();
            let bi = self.body[i];
            for &j in all.neighbors(i) {
                let bj = self.body[j as usize];
                let touch = bi != bj
                    || (self.self_contact[bi as usize]
                        && distance_squared::<D>(reference[i], reference[j as usize]) >= rc2);
                if touch {
                    ix.push(j);
                }
            }
            ix[start..].sort_unstable();
            off.push(ix.len());
        }
        NeighborList::from_parts(off, ix)
    }
}

/// The total contact force on each body (the other bodies' push, and with self-contact the
/// body's own, which sums to zero), recorded per body as the series `contact_force_<body>`
/// (columns `x`, `y`, `z` in 3D; [`crate::conventions::CONTACT_SERIES`]). One recording for
/// every family that has body-body contact.
pub fn body_force_series(bodies: usize, dim: usize) -> Vec<Series> {
    const AXES: [&str; 3] = ["x", "y", "z"];
    (0..bodies)
        .map(|b| {
            Series::new(&format!("contact_force_{b}"), &AXES[..dim])
                .with_description(crate::conventions::CONTACT_SERIES)
        })
        .collect()
}

/// Appends one row, each body's total contact force `forces[b]`, to the series of
/// [`body_force_series`].
pub fn record_body_forces<D: Dim>(series: &mut [Series], time: f64, forces: &[D::Vector]) {
    for (s, &f) in series.iter_mut().zip(forces) {
        let row: Vec<f64> = (0..D::D).map(|k| D::component(f, k)).collect();
        s.push(time, &row);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::D2;
    use glam::DVec2;

    #[test]
    fn pairs_cross_bodies_and_skip_reference_neighbours_within_a_body() {
        // 0 and 1: one body, reference neighbours, now close; 2: same body, far in the
        // reference, now close to 0; 3: other body, close to 1.
        let reference = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(1.5, 0.0),
        ];
        let now = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(-0.5, 0.3),
            DVec2::new(1.5, 0.0),
        ];
        let mut bodies = ContactBodies::new(vec![0, 0, 0, 1]);
        let list = bodies.detect::<D2>(&now, &reference, 1.2, 3.0).unwrap();
        assert_eq!(list.neighbors(0), &[] as &[u32]);
        assert_eq!(list.neighbors(1), &[3]);
        assert_eq!(list.neighbors(3), &[1]);
        bodies.self_contact[0] = true;
        let list = bodies.detect::<D2>(&now, &reference, 1.2, 3.0).unwrap();
        assert_eq!(list.neighbors(0), &[2]);
        assert_eq!(list.neighbors(2), &[0]);
        assert_eq!(list.neighbors(1), &[3]);
    }
}
