//! Coulomb friction between bodies (and within a self-contacting body) in penalty contact:
//! the pair law of [`crate::friction`] applied to the contact pairs of
//! [`crate::contact::ContactBodies`] (TL) or of a UL solver's contact list, one implementation
//! for every family that has a pair-wise normal contact force.
//!
//! # The scheme
//!
//! The normal contact is a penalty force (the contact pressure of the contact density, see
//! `sph_ul::contact` and `sph_tl::contact`): each contact pair `(i, j)` carries a repulsive
//! force `F_ij ≥ 0` along its direction `e_ij` in the step's force evaluation (at the half-step
//! positions of the position-Verlet step). Friction is applied at the velocity level right after
//! the step's kick `v^{n+1} = v^n + Δt a`, as the velocity-level stick/return of
//! [`crate::friction`] (J. J. Moreau, *Unilateral contact and dry friction in finite freedom
//! dynamics*, 1988; the stick/slip return of J. O. Hallquist, G. L. Goudreau and D. J. Benson,
//! *Sliding interfaces with contact-impact in large-scale Lagrangian computations*, CMAME 51,
//! 1985), with the pair's normal impulse `J_n = F_n Δt` in place of a tool's normal velocity
//! change.
//!
//! **The interface normal.** The pairs of a particle reach several partners at oblique angles
//! (up to the kernel support in UL), so `e_ij` is not the normal of the interface: with it, the
//! bound `μ Σ_j F_ij` would exceed `μ` times the normal force by the pairs' mean `1/cos φ`, and
//! the slip would be measured partly across the interface (measured on the sliding block: 13 %
//! too much friction with UL-ENOG). Each particle's interface normal is the direction of its
//! total contact force, `n_i = a_c,i/|a_c,i|` (for a flat interface, the surface normal on both
//! sides), and the pair's normal is `n_ij = (n_i − n_j)/|n_i − n_j|` (`e_ij` if that vanishes):
//! the pair's normal force is `F_n = F_ij max(e_ij·n_ij, 0)`, so the pairs' normal forces add up
//! to the normal component of the contact force, and the slip is measured in the interface.
//! Then:
//!
//! 1. the pair's tangential relative velocity `v_t = v_ij − (v_ij·n_ij) n_ij`,
//!    `v_ij = v_i − v_j` (after the kick, so the stick removes the slip that the step's forces,
//!    gravity included, produced);
//! 2. **trial (stick)**: the impulse that stops that slip, `J* = −m_eff v_t`, with the pair's
//!    effective mass `m_eff = m_red F_n / max(S_i, S_j)` (below), `S_i` the sum of particle
//!    `i`'s frictional pairs' normal forces;
//! 3. stick if `|J*| ≤ μ_s J_n`, else **slide**: `J = −μ_k J_n v_t/|v_t|`;
//! 4. `v_i += J/m_i`, `v_j −= J/m_j` (a fully constrained particle is not moved and counts as
//!    infinitely heavy: `m_red = m` of the free partner; the constraint takes the reaction).
//!
//! `m_red = m_i m_j/(m_i + m_j)` stops the pair's slip exactly when the pair is alone. A
//! particle usually has several contact pairs, and the pairs are treated at once (Jacobi): `n`
//! pairs each asking for the full stick impulse would change the particle's velocity `n` times
//! too much (the slip reverses and grows). Each pair therefore asks for its share of the
//! particle's normal force, `F_n / max(S_i, S_j)`, of the stick impulse: the stick impulses on
//! any particle add up to at most what stops its slip against a common partner velocity
//! (`Σ_j m_red,ij F_n,ij / max(S_i, S_j) ≤ m_i`), and since demand and supply (`μ_s F_n Δt`) are
//! both proportional to `F_n`, the stick test of a particle's pairs is the particle's own
//! Coulomb test `m_red |v_t| ≤ μ_s max(S_i, S_j) Δt`, as at a tool. (Sharing by the count of
//! pairs instead, `m_red / max(n_i, n_j)`, lets the weak far pairs of UL's kernel-wide contact
//! slide while their share of the stick is not taken up by the others: measured, a block that
//! should stick crept 0.15 dp in 0.3 s.) The slip that the sharing leaves when the partner is
//! shared by more force than the particle is removed by the following steps. In the slide
//! branch the impulse is `μ_k J_n`, and never more than the stick impulse
//! (`μ_k J_n ≤ μ_s J_n < |J*|`): no overshoot either.
//!
//! Why this scheme and not a force-level regularised law (a tangential spring, or a ramp
//! `μ(|v_t|)`): those need a regularisation stiffness or velocity whose value changes the
//! result and, for a spring, the time step; this one has none (the only regularisation is the
//! time step itself), sticks with no elastic creep beyond the under-relaxed remainder, and a
//! frictionless contact never enters the code (bit-identical results).
//!
//! **Momentum.** Each pair impulse is computed from operands that are exact negatives of each
//! other seen from the two ends (`v_ji = −v_ij`, `e_ji = −e_ij`, `m_red` and `F_n` symmetric),
//! so the two impulses are equal and opposite bit for bit; the total momentum changes only by
//! the impulse the constrained partners take ([`ContactFriction::apply`] returns it).
//!
//! **Work.** The work of the friction impulses is accumulated exactly from each velocity
//! change, `Σ_i m_i Δv_i · (v_i + ½ Δv_i)` (the kinetic energy change they make), and is
//! dissipation (≤ 0) when no partner is driven.

use crate::error::Error;
use crate::friction::{coulomb_velocity_change, Friction};
use crate::parallel::gather;
use crate::scene::Series;
use crate::state::{StateReader, StateWriter};
use crate::{Dim, NeighborList};

/// The Coulomb coefficients of every pair of bodies (symmetric; the diagonal is a body's
/// self-contact).
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionTable {
    bodies: usize,
    table: Vec<Friction>,
}

impl FrictionTable {
    /// No friction between any of `bodies` bodies.
    pub fn new(bodies: usize) -> Self {
        Self {
            bodies,
            table: vec![Friction::NONE; bodies * bodies],
        }
    }

    /// Sets the coefficients between bodies `a` and `b` (both orders; `a == b`: the body's
    /// self-contact).
    ///
    /// # Errors
    /// A body index out of range.
    pub fn set(&mut self, a: u32, b: u32, friction: Friction) -> Result<(), Error> {
        for x in [a, b] {
            if x as usize >= self.bodies {
                return Err(Error::invalid(
                    "contact friction body",
                    x,
                    &format!("a body index below {}", self.bodies),
                ));
            }
        }
        let (a, b) = (a as usize, b as usize);
        self.table[a * self.bodies + b] = friction;
        self.table[b * self.bodies + a] = friction;
        Ok(())
    }

    /// The coefficients between bodies `a` and `b`.
    #[inline]
    pub fn get(&self, a: u32, b: u32) -> Friction {
        self.table[a as usize * self.bodies + b as usize]
    }

    /// Number of bodies.
    pub fn bodies(&self) -> usize {
        self.bodies
    }

    /// Whether every pair of bodies is frictionless.
    pub fn is_frictionless(&self) -> bool {
        self.table.iter().all(Friction::is_frictionless)
    }
}

/// The reduced mass of a pair, a fully constrained side counting as infinitely heavy; the
/// same bits whichever side is `a` (0 when neither side is free).
#[inline]
pub fn reduced_mass(m_a: f64, free_a: bool, m_b: f64, free_b: bool) -> f64 {
    match (free_a, free_b) {
        (true, true) => m_a * m_b / (m_a + m_b),
        (true, false) => m_a,
        (false, true) => m_b,
        (false, false) => 0.0,
    }
}

/// The friction impulse on particle `i` of one pair (see the module documentation):
/// `relative_velocity` `v_i − v_j`, `normal` the unit pair direction, `effective_mass` the
/// pair's `m_eff`, `normal_impulse` `J_n = F_n Δt ≥ 0`. Returns the impulse and whether the
/// pair sticks; the negated operands give the negated impulse bit for bit.
///
/// ```
/// use sph_core::contact_friction::pair_friction_impulse;
/// use sph_core::{glam::DVec2, Friction, D2};
/// let f = Friction::new(0.5, 0.3)?;
/// // Slipping at 0.1 m/s along x over a normal y, m_eff = 1: stopped if 0.1 ≤ 0.5 J_n.
/// let (j, stick) = pair_friction_impulse::<D2>(DVec2::new(0.1, -2.0), DVec2::Y, 1.0, 1.0, f);
/// assert!(stick && (j - DVec2::new(-0.1, 0.0)).length() < 1e-15);
/// let (j, stick) = pair_friction_impulse::<D2>(DVec2::new(1.0, 0.0), DVec2::Y, 1.0, 1.0, f);
/// assert!(!stick && (j - DVec2::new(-0.3, 0.0)).length() < 1e-15);
/// # Ok::<(), sph_core::Error>(())
/// ```
#[inline]
pub fn pair_friction_impulse<D: Dim>(
    relative_velocity: D::Vector,
    normal: D::Vector,
    effective_mass: f64,
    normal_impulse: f64,
    friction: Friction,
) -> (D::Vector, bool) {
    let slip = relative_velocity - normal * D::dot(relative_velocity, normal);
    // Per unit effective mass: the velocity change of the pair law of `friction`.
    let (dv, stick) = coulomb_velocity_change::<D>(slip, normal_impulse / effective_mass, friction);
    (dv * effective_mass, stick)
}

/// A pair's interface normal and normal force (see the module documentation): the direction
/// `n_ij` of `n_i − n_j` with `n = a_c/|a_c|` (`e_ij` when it vanishes) and
/// `F_n = F_ij max(e_ij·n_ij, 0)`; swapping the ends negates `n_ij` and keeps `F_n`, bit for
/// bit.
#[inline]
pub fn interface_normal<D: Dim>(
    e: D::Vector,
    force: f64,
    contact_i: D::Vector,
    contact_j: D::Vector,
) -> (D::Vector, f64) {
    let unit = |a: D::Vector| {
        let l = D::norm(a);
        if l > 0.0 {
            a / l
        } else {
            D::zero()
        }
    };
    let d = unit(contact_i) - unit(contact_j);
    let l = D::norm(d);
    if l > 0.0 && l.is_finite() {
        let n = d / l;
        (n, force * D::dot(e, n).max(0.0))
    } else {
        (e, force)
    }
}

/// Per particle, the result of one friction pass.
#[derive(Clone, Copy, Debug)]
struct Change<V> {
    dv: V,
    /// Frictional pairs with a normal force, and those of them that stuck.
    active: u32,
    sticking: u32,
}

/// Friction between contacting bodies: the coefficients, the per-step pass, the work it did,
/// the per-body series `contact_friction_<b>`.
#[derive(Clone, Debug)]
pub struct ContactFriction<D: Dim> {
    table: FrictionTable,
    /// Per particle: the sum of its frictional pairs' normal forces of the last pass.
    loads: Vec<f64>,
    changes: Vec<Change<D::Vector>>,
    /// Work of the friction impulses since `t = 0` (`Σ m Δv·(v + ½Δv)`, ≤ 0 when dissipative).
    work: f64,
    /// Per body: the friction impulse the other bodies gave it since the last record, and the
    /// time since then.
    impulse: Vec<D::Vector>,
    elapsed: f64,
    /// Per body: frictional pairs and sticking pairs of the last pass.
    last_counts: Vec<(u64, u64)>,
    series: Vec<Series>,
}

/// The force columns of the series (then `sticking`).
const AXES: [&str; 3] = ["x", "y", "z"];

/// What the series `contact_friction_<b>` holds.
pub const CONTACT_FRICTION_SERIES: &str = "body-body contact friction: `time` (s); `x`, `y`, \
     `z` (3D) the mean friction force the other bodies (and, with self-contact, the body \
     itself) exert on this body over the interval since the previous row (N; N/m in 2D); \
     `sticking` the fraction of this body's frictional contact pairs that stuck in the last step \
     (0 with no contact)";

impl<D: Dim> ContactFriction<D> {
    /// Friction with the coefficients of `table`, `n` particles.
    pub fn new(table: FrictionTable, n: usize) -> Self {
        let bodies = table.bodies();
        let columns: Vec<&str> = AXES[..D::D].iter().chain(&["sticking"]).copied().collect();
        Self {
            table,
            loads: vec![0.0; n],
            changes: Vec::new(),
            work: 0.0,
            impulse: vec![D::zero(); bodies],
            elapsed: 0.0,
            last_counts: vec![(0, 0); bodies],
            series: (0..bodies)
                .map(|b| {
                    Series::new(&format!("contact_friction_{b}"), &columns)
                        .with_description(CONTACT_FRICTION_SERIES)
                })
                .collect(),
        }
    }

    /// The coefficients.
    pub fn table(&self) -> &FrictionTable {
        &self.table
    }

    /// Work of the friction impulses since `t = 0` (J; J/m in 2D).
    pub fn work(&self) -> f64 {
        self.work
    }

    /// The per-body series.
    pub fn series(&self) -> &[Series] {
        &self.series
    }

    /// Clears the work and the series (at `t = 0`).
    pub fn reset(&mut self) {
        self.work = 0.0;
        self.elapsed = 0.0;
        self.impulse.iter_mut().for_each(|x| *x = D::zero());
        for s in &mut self.series {
            *s = Series::new(
                &s.name,
                &s.columns.iter().map(String::as_str).collect::<Vec<_>>(),
            )
            .with_description(&s.description);
        }
    }

    /// One friction pass after a kick of length `dt` (see the module documentation):
    /// `list` the contact pairs (symmetric, each row of particle `i`), `body` the body per
    /// particle, `pair(i, k, j)` the unit direction `e_ij` (from `j` to `i`) and repulsive force
    /// `F_ij ≥ 0` of the pair at position `k` of `list` (the same bits from both ends up to the
    /// sign of `e`), `contact[i]` particle `i`'s contact acceleration of the same evaluation
    /// (its direction is the interface normal), `free[i]` false for fully constrained
    /// particles. Changes `velocities` and returns the momentum change `Σ m Δv` (non-zero only
    /// through constrained partners).
    #[allow(clippy::too_many_arguments)]
    pub fn apply(
        &mut self,
        list: &NeighborList,
        body: &[u32],
        pair: impl Fn(usize, usize, usize) -> (D::Vector, f64) + Sync + Send,
        contact: &[D::Vector],
        velocities: &mut [D::Vector],
        masses: &[f64],
        free: &[bool],
        dt: f64,
    ) -> D::Vector {
        let n = velocities.len();
        let table = &self.table;
        let offsets = list.offsets();
        let pair = |i: usize, k: usize, j: usize| {
            let (e, f) = pair(i, k, j);
            let (n, f_n) = interface_normal::<D>(e, f, contact[i], contact[j]);
            (n, f_n)
        };
        // The normal force of each particle's frictional pairs, summed in row order.
        self.loads.resize(n, 0.0);
        gather(
            &mut self.loads,
            #[inline(always)]
            |i, s| {
                let (bi, base) = (body[i], offsets[i]);
                *s = 0.0;
                for (k, &j) in list.neighbors(i).iter().enumerate() {
                    if !table.get(bi, body[j as usize]).is_frictionless() {
                        *s += pair(i, base + k, j as usize).1;
                    }
                }
            },
        );
        let loads = &self.loads;
        let v = &*velocities;
        self.changes.resize(
            n,
            Change {
                dv: D::zero(),
                active: 0,
                sticking: 0,
            },
        );
        gather(
            &mut self.changes,
            #[inline(always)]
            |i, out| {
                let mut change = Change {
                    dv: D::zero(),
                    active: 0,
                    sticking: 0,
                };
                if free[i] && loads[i] > 0.0 {
                    let (bi, base) = (body[i], offsets[i]);
                    let mut impulse = D::zero();
                    for (k, &j) in list.neighbors(i).iter().enumerate() {
                        let j = j as usize;
                        let friction = table.get(bi, body[j]);
                        if friction.is_frictionless() {
                            continue;
                        }
                        let (e, f_n) = pair(i, base + k, j);
                        if f_n <= 0.0 {
                            continue;
                        }
                        let m_eff = reduced_mass(masses[i], true, masses[j], free[j])
                            * (f_n / loads[i].max(loads[j]));
                        let (imp, stick) =
                            pair_friction_impulse::<D>(v[i] - v[j], e, m_eff, f_n * dt, friction);
                        impulse += imp;
                        change.active += 1;
                        change.sticking += u32::from(stick);
                    }
                    change.dv = impulse / masses[i];
                }
                *out = change;
            },
        );
        // Apply, with the work and the per-body impulse, in particle order (deterministic).
        let mut momentum = D::zero();
        let mut work = 0.0;
        self.last_counts.iter_mut().for_each(|c| *c = (0, 0));
        for (i, c) in self.changes.iter().enumerate() {
            if c.active == 0 {
                continue;
            }
            let m = masses[i];
            let b = body[i] as usize;
            work += m * D::dot(c.dv, velocities[i] + c.dv * 0.5);
            velocities[i] += c.dv;
            momentum += c.dv * m;
            self.impulse[b] += c.dv * m;
            self.last_counts[b].0 += u64::from(c.active);
            self.last_counts[b].1 += u64::from(c.sticking);
        }
        self.work += work;
        self.elapsed += dt;
        momentum
    }

    /// Records a row of every body's series at `time`: the mean friction force since the last
    /// row and the sticking fraction of the last pass.
    pub fn record(&mut self, time: f64) {
        for (b, s) in self.series.iter_mut().enumerate() {
            let mut row: Vec<f64> = (0..D::D)
                .map(|k| {
                    if self.elapsed > 0.0 {
                        D::component(self.impulse[b], k) / self.elapsed
                    } else {
                        0.0
                    }
                })
                .collect();
            let (active, sticking) = self.last_counts[b];
            row.push(if active > 0 {
                sticking as f64 / active as f64
            } else {
                0.0
            });
            s.push(time, &row);
        }
        self.impulse.iter_mut().for_each(|x| *x = D::zero());
        self.elapsed = 0.0;
    }

    /// Writes the work, the open interval and the series to a checkpoint.
    pub fn save(&self, out: &mut StateWriter) {
        out.f64s("contact_friction", &[self.work, self.elapsed]);
        out.vectors::<D>("contact_friction_impulse", &self.impulse);
        crate::state::save_series(out, &self.series);
    }

    /// Reads what [`ContactFriction::save`] wrote.
    ///
    /// # Errors
    /// A checkpoint without it or of another body count.
    pub fn restore(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        let [work, elapsed] = input.scalars::<2>("contact_friction")?;
        (self.work, self.elapsed) = (work, elapsed);
        self.impulse = input.vectors::<D>("contact_friction_impulse", Some(self.impulse.len()))?;
        crate::state::restore_series(input, &mut self.series)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{D2, D3};
    use glam::{DVec2, DVec3};

    #[test]
    fn the_pair_impulse_is_antisymmetric_bit_for_bit() {
        let f = Friction::new(0.4, 0.3).unwrap();
        let (v, e) = (
            DVec3::new(0.3, -1.7, 0.123_456_789),
            DVec3::new(0.2, 0.9, -0.1).normalize(),
        );
        for (m, jn) in [(1.0, 0.1), (0.7, 10.0), (3.3, 1e-4)] {
            let (a, sa) = pair_friction_impulse::<D3>(v, e, m, jn, f);
            let (b, sb) = pair_friction_impulse::<D3>(-v, -e, m, jn, f);
            assert_eq!(sa, sb);
            assert_eq!(a, -b, "{m} {jn}");
            // Tangential, and never more than stops the slip.
            assert!(a.dot(e).abs() < 1e-15);
            let slip = v - e * v.dot(e);
            assert!(a.length() <= m * slip.length() * (1.0 + 1e-15));
        }
        assert_eq!(
            reduced_mass(2.0, true, 3.0, true),
            reduced_mass(3.0, true, 2.0, true)
        );
        assert_eq!(reduced_mass(2.0, true, 3.0, false), 2.0);
        assert_eq!(reduced_mass(2.0, false, 3.0, true), 3.0);
    }

    #[test]
    fn the_interface_normal_is_the_contact_force_direction_and_antisymmetric() {
        // An oblique pair across a flat interface (contact forces along ±y): the normal is y
        // and the normal force the pair force's y component.
        let e = DVec2::new(1.0, 1.0).normalize();
        let (ci, cj) = (DVec2::new(0.0, 5.0), DVec2::new(0.0, -3.0));
        let (n, f) = interface_normal::<D2>(e, 2.0, ci, cj);
        assert_eq!(n, DVec2::Y);
        assert!((f - 2.0 * e.y).abs() < 1e-15);
        let (m, g) = interface_normal::<D2>(-e, 2.0, cj, ci);
        assert_eq!((m, g), (-n, f));
        // No contact forces: the pair direction.
        assert_eq!(
            interface_normal::<D2>(e, 2.0, DVec2::ZERO, DVec2::ZERO),
            (e, 2.0)
        );
        // Arbitrary operands: the same bits from both ends.
        let (ci, cj) = (DVec3::new(0.3, 1.7, -0.2), DVec3::new(-0.1, -2.2, 0.4));
        let e = DVec3::new(0.2, 0.9, 0.1).normalize();
        let (n, f) = interface_normal::<D3>(e, 1.3, ci, cj);
        let (m, g) = interface_normal::<D3>(-e, 1.3, cj, ci);
        assert_eq!((m, g), (-n, f));
    }

    #[test]
    fn the_table_is_symmetric_and_checked() {
        let mut t = FrictionTable::new(3);
        assert!(t.is_frictionless());
        t.set(0, 2, Friction::new(0.5, 0.4).unwrap()).unwrap();
        assert_eq!(t.get(2, 0), t.get(0, 2));
        assert!(t.get(0, 1).is_frictionless() && !t.is_frictionless());
        assert!(t.set(0, 3, Friction::NONE).is_err());
    }

    /// A particle on a row of fixed partners, all pairs normal along y: `n` pairs asking for
    /// the full stick each would reverse the slip; the under-relaxed pass stops it exactly
    /// when the partners are fixed and counted alike, and conserves momentum between free
    /// particles.
    #[test]
    fn several_pairs_stop_the_slip_without_overshoot_and_conserve_momentum() {
        let f = Friction::new(1.0, 0.8).unwrap();
        // Particle 0 free above fixed particles 1..=3.
        let x = [
            DVec2::new(0.0, 1.0),
            DVec2::new(-1.0, 0.0),
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
        ];
        let list = NeighborList::from_parts(vec![0, 3, 4, 5, 6], vec![1, 2, 3, 0, 0, 0]).unwrap();
        let pair = |i: usize, _k: usize, j: usize| ((x[i] - x[j]).normalize(), 10.0);
        let mut fr = ContactFriction::<D2>::new(
            {
                let mut t = FrictionTable::new(2);
                t.set(0, 1, f).unwrap();
                t
            },
            4,
        );
        let body = [0, 1, 1, 1];
        let mut v = vec![DVec2::new(0.2, 0.0), DVec2::ZERO, DVec2::ZERO, DVec2::ZERO];
        let masses = [1.0; 4];
        let free = [true, false, false, false];
        let none = [DVec2::ZERO; 4];
        let p = fr.apply(&list, &body, pair, &none, &mut v, &masses, &free, 1.0);
        // The middle pair is along y: it stops x fully with a third of the mass; the oblique
        // pairs only their tangential part: the slip is reduced, never reversed.
        assert!(v[0].x >= 0.0 && v[0].x < 0.2, "{}", v[0]);
        assert!((p - v[0] + DVec2::new(0.2, 0.0)).length() < 1e-15);
        assert!(fr.work() < 0.0);
        // Two free particles of different bodies: equal and opposite changes.
        let list = NeighborList::from_parts(vec![0, 1, 2], vec![1, 0]).unwrap();
        let y = [DVec2::new(0.0, 1.0), DVec2::ZERO];
        let pair = |i: usize, _k: usize, j: usize| ((y[i] - y[j]).normalize(), 1.0);
        let mut v = vec![DVec2::new(0.3, -0.1), DVec2::new(-0.1, 0.2)];
        let masses = [1.5, 0.5];
        let p = fr.apply(
            &list,
            &[0, 1],
            pair,
            &none,
            &mut v,
            &masses,
            &[true, true],
            1.0,
        );
        assert!(p.length() < 1e-16, "{p}");
        // Stuck: the tangential velocities are equal.
        assert!((v[0].x - v[1].x).abs() < 1e-15, "{v:?}");
        fr.record(1.0);
        assert_eq!(fr.series()[0].column("sticking").unwrap(), &[1.0]);
    }
}
