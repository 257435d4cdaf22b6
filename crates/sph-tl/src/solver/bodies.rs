//! Several deformable bodies in one TL solver and self-contact (see [`crate::contact`]).

use super::TlSolver;
use crate::contact::TlContact;
use sph_core::contact::ContactBodies;
use sph_core::{Dim, Error, NeighborList};
use sph_materials::Material;

/// The default contact stiffness scale `κ` of TL (UL uses 1): measured on two TL discs meeting
/// head-on at 6 % of the sound speed (tests/contact.rs), κ = 1 lets surface particles come
/// within 0.002 dp of each other (the kernel law's contact potential is bounded), κ = 2 keeps
/// them 0.56 dp apart. The time step follows with the contact wave speed `√κ c0`.
pub const DEFAULT_CONTACT_SCALE: f64 = 2.0;

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Splits the particles into bodies, `body[i]` the body of particle `i` (indices from 0):
    /// each body becomes its own reference configuration (its reference neighbours, kernel
    /// sums and correction matrices never reach another body) and bodies touch through the
    /// contact of [`crate::contact`]. All bodies share the solver's material. The contact force
    /// on each body is recorded with the probes as the series `contact_force_<body>` (columns
    /// `x`, `y` (, `z`), as UL's [`sph_core::conventions::CONTACT_SERIES`]). Call before the
    /// first step; one body (all indices equal) is today's solver plus nothing.
    ///
    /// # Errors
    /// `body` of another length than the particles, a solver that has stepped or is built for
    /// ranks, or a particle left with fewer than `D::D` neighbours of its own body.
    pub fn with_bodies(self, body: Vec<u32>) -> Result<Self, Error> {
        self.check_contact_set_up("body", body.len())?;
        let bodies = ContactBodies::new(body);
        let self_contact = match &self.contact {
            Some(c) => c.bodies.self_contact.clone(),
            None => Vec::new(),
        };
        self.install_contact(bodies, self_contact)
    }

    /// Turns on self-contact of body `b` (0 for a one-body solver): particles of the body whose
    /// reference distance is beyond the kernel support (`2h`) push each other apart when they
    /// come closer than `dp` (a strip folding onto itself). Opt-in: detection costs a cell
    /// list on the current positions every step.
    ///
    /// # Errors
    /// `b` not a body of the solver, or the set-up errors of [`TlSolver::with_bodies`].
    pub fn with_self_contact(self, b: u32) -> Result<Self, Error> {
        let n = self.reference.len();
        self.check_contact_set_up("self_contact", n)?;
        let (bodies, mut self_contact) = match &self.contact {
            Some(c) => (c.bodies.clone(), c.bodies.self_contact.clone()),
            None => (ContactBodies::new(vec![0; n]), vec![false]),
        };
        let count = bodies.bodies();
        if b as usize >= count {
            return Err(Error::invalid(
                "self_contact",
                b,
                &format!("a body index below {count}"),
            ));
        }
        self_contact[b as usize] = true;
        let mut solver = self;
        solver.contact = None;
        solver.install_contact(bodies, self_contact)
    }

    fn check_contact_set_up(&self, what: &str, len: usize) -> Result<(), Error> {
        self.built(what)?;
        if self.steps > 0 {
            return Err(Error::invalid(
                what,
                "a solver that has stepped",
                "set before the first step",
            ));
        }
        let n = self.reference.len();
        if len != n {
            return Err(Error::invalid(
                what,
                len,
                &format!("{n} entries (one per particle)"),
            ));
        }
        Ok(())
    }

    /// Restricts the reference neighbours to each body and installs the contact state.
    fn install_contact(
        mut self,
        mut bodies: ContactBodies,
        self_contact: Vec<bool>,
    ) -> Result<Self, Error> {
        if self.contact_friction.is_some() {
            return Err(Error::invalid(
                "contact_friction",
                "set before the bodies or self-contacts",
                "with_contact_friction after with_bodies and with_self_contact",
            ));
        }
        for (k, s) in self_contact.into_iter().enumerate().take(bodies.bodies()) {
            bodies.self_contact[k] = s;
        }
        let n = self.reference.len();
        let (mut off, mut ix) = (Vec::with_capacity(n + 1), Vec::new());
        off.push(0);
        for i in 0..n {
            let bi = bodies.body[i];
            ix.extend(
                self.list
                    .neighbors(i)
                    .iter()
                    .filter(|&&j| bodies.body[j as usize] == bi),
            );
            off.push(ix.len());
        }
        let list = NeighborList::from_parts(off, ix)?;
        if list.num_pairs() != self.list.num_pairs() {
            if let Some(i) = (0..n).find(|&i| list.count(i) < D::D) {
                return Err(Error::TooFewNeighbours {
                    particle: i,
                    found: list.count(i),
                    required: D::D,
                });
            }
            self.build_reference_data(list, |_| true)?;
            self.refresh_rates();
        }
        self.contact = bodies.is_active().then(|| {
            TlContact::new(
                bodies,
                self.dp,
                &self.kernel,
                self.contact_scale,
                self.sound_speed,
                self.density,
            )
        });
        Ok(self)
    }

    /// Coulomb friction on the contact pairs of [`TlSolver::with_bodies`] and
    /// [`TlSolver::with_self_contact`], with the coefficients of `table` per pair of bodies
    /// (the diagonal: a body's self-contact; [`sph_core::contact_friction`]: velocity-level
    /// stick/slide on each contact pair after the kick, the pair's contact force as the normal
    /// force). The series gain `contact_friction_<b>` (mean friction force on body `b`,
    /// sticking fraction), the summary `contact_friction_work`. Call after the bodies and
    /// self-contacts are set; a frictionless table changes nothing.
    ///
    /// # Errors
    /// No contact (one body without self-contact), a table of another number of bodies, a
    /// solver that has stepped or is built for ranks.
    pub fn with_contact_friction(
        mut self,
        table: sph_core::contact_friction::FrictionTable,
    ) -> Result<Self, Error> {
        let n = self.reference.len();
        self.check_contact_set_up("contact_friction", n)?;
        let Some(contact) = &self.contact else {
            return Err(Error::invalid(
                "contact friction",
                "a solver without contact",
                "with_bodies or with_self_contact first",
            ));
        };
        if table.bodies() != contact.bodies.bodies() {
            return Err(Error::invalid(
                "contact friction bodies",
                table.bodies(),
                &format!("the solver's {} bodies", contact.bodies.bodies()),
            ));
        }
        self.contact_friction = (!table.is_frictionless())
            .then(|| sph_core::contact_friction::ContactFriction::new(table, n));
        Ok(self)
    }

    /// Scales the contact stiffness `κ c0²` by `κ` ([`DEFAULT_CONTACT_SCALE`] by default; UL's `contact_scale` is 1). A
    /// stiffer contact holds a harder impact (the contact potential is bounded: the force of
    /// the kernel law vanishes at zero distance); the acceleration criterion of eq 33 shortens
    /// the step accordingly.
    ///
    /// # Errors
    /// `κ` not positive and finite.
    pub fn with_contact_scale(mut self, scale: f64) -> Result<Self, Error> {
        sph_core::error::check_positive("contact_scale", scale)?;
        if !scale.is_finite() {
            return Err(Error::invalid(
                "contact_scale",
                scale,
                "a finite number > 0",
            ));
        }
        self.contact_scale = scale;
        let c0 = self.sound_speed;
        if let Some(c) = &mut self.contact {
            c.set_scale(scale, c0);
        }
        Ok(self)
    }

    /// The stored contact energy `U_c` ([`crate::contact::contact_energy`] summed; 0 without
    /// contact).
    pub fn contact_energy(&self) -> f64 {
        match &self.contact {
            Some(c) => c
                .energy(&self.positions, &self.reference, &self.masses, &self.kernel)
                .unwrap_or(f64::NAN),
            None => 0.0,
        }
    }

    /// Contact pairs (directed) found at the last step (0 without contact).
    pub fn contact_pairs(&self) -> usize {
        self.contact.as_ref().map_or(0, |c| c.num_pairs())
    }

    /// The smallest current distance between two particles that may touch (of different
    /// bodies, or of a self-contacting body beyond the reference support) closer than
    /// `search`; infinity when none or without contact.
    ///
    /// # Errors
    /// Non-finite positions or a non-positive `search`.
    pub fn smallest_contact_gap(&self, search: f64) -> Result<f64, Error> {
        match &self.contact {
            Some(c) => c.smallest_gap(&self.positions, &self.reference, search),
            None => Ok(f64::INFINITY),
        }
    }

    /// Body index per particle (all 0 for one body).
    pub fn bodies(&self) -> Vec<u32> {
        match &self.contact {
            Some(c) => c.bodies.body.clone(),
            None => vec![0; self.reference.len()],
        }
    }
}
