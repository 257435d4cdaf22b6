//! The rigid tools a body touches as one collection, and the meters of their reactions.

use crate::dim::Dim;
use crate::error::Error;
use crate::scene::Series;

use super::RigidTool;

/// The rigid tools a body touches, as every method attaches them: their contact pass (the
/// impulses of one step summed per tool), reaction meters, contact counts, the work of the
/// contact and friction on the body, the series each tool records, and their checkpoint state.
///
/// A method calls [`ToolSet::begin_step`], then [`ToolSet::enforce`] once or more after its
/// velocity update, then [`ToolSet::end_step`] with the step's length; [`ToolSet::record`] on
/// its probe schedule.
///
/// ```
/// use sph_core::friction::Friction;
/// use sph_core::tool::{RigidTool, ToolMotion, ToolSet, ToolShape};
/// use sph_core::{glam::DVec2, D2};
/// // A floor with friction under one particle sliding at 1 m/s and pressed into it.
/// let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y)?;
/// let tool = RigidTool::new("floor", floor, ToolMotion::fixed())
///     .with_friction(Friction::new(0.5, 0.5)?);
/// let mut tools = ToolSet::new(vec![tool], &[], 100.0)?;
/// let (x, mut v) = (vec![DVec2::new(0.0, 0.0)], vec![DVec2::new(1.0, -0.2)]);
/// tools.begin_step();
/// tools.enforce(0.1, 0.1, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true], true);
/// tools.end_step(0.1);
/// // The normal change 0.2 m/s stops the approach; friction takes 0.5 · 0.2 off the slide.
/// assert!((v[0] - DVec2::new(0.9, 0.0)).length() < 1e-15);
/// assert!(tools.work().friction < 0.0);
/// # Ok::<(), sph_core::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct ToolSet<D: Dim> {
    tools: Vec<RigidTool<D>>,
    meters: Vec<ReactionMeter<D>>,
    friction_meters: Vec<ReactionMeter<D>>,
    /// Particles in contact with, and sticking to, each tool in the last step.
    contacts: Vec<usize>,
    sticking: Vec<usize>,
    /// This step's impulses on the body per tool (all, friction part).
    impulses: Vec<D::Vector>,
    friction_impulses: Vec<D::Vector>,
    work: ToolWork,
    series: Vec<Series>,
}

/// Work done on the body by the tools since `t = 0` (J; J/m in 2D).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolWork {
    /// By the normal contact velocity changes (≤ 0 against tools at rest: the contact is
    /// perfectly inelastic).
    pub contact: f64,
    /// By the friction velocity changes.
    pub friction: f64,
    /// Energy the friction dissipated (≥ 0; `−friction` when the tools are at rest).
    pub friction_dissipated: f64,
}

impl<D: Dim> Default for ToolSet<D> {
    fn default() -> Self {
        Self {
            tools: Vec::new(),
            meters: Vec::new(),
            friction_meters: Vec::new(),
            contacts: Vec::new(),
            sticking: Vec::new(),
            impulses: Vec::new(),
            friction_impulses: Vec::new(),
            work: ToolWork::default(),
            series: Vec::new(),
        }
    }
}

impl<D: Dim> ToolSet<D> {
    /// The tools a body of sound speed `sound_speed` touches; `taken` are names the tools'
    /// series must not reuse (a method's named constraints).
    ///
    /// # Errors
    /// A tool name that is not a name ([`crate::error::check_name`]); two tools (or a tool and
    /// a taken name) with the same name; a tool at or above the body's sound speed.
    pub fn new(tools: Vec<RigidTool<D>>, taken: &[&str], sound_speed: f64) -> Result<Self, Error> {
        let mut names: Vec<&str> = taken.to_vec();
        for t in &tools {
            crate::error::check_name("tool name", &t.name)?;
            // The step follows the body's wave speed, not the tool's: a tool faster than
            // sound outruns the contact and collapses the step within a few dozen steps.
            let speed = t.max_speed();
            if speed >= sound_speed {
                return Err(Error::invalid(
                    &format!("speed of tool `{}`", t.name),
                    crate::error::Num(speed),
                    &format!(
                        "0 <= tool speed < {} m/s, the body's sound speed c0 (a faster tool \
                         outruns the contact)",
                        crate::error::Num(sound_speed)
                    ),
                ));
            }
            if names.contains(&t.name.as_str()) {
                return Err(Error::invalid(
                    "tool name",
                    format!("{:?}", t.name),
                    "non-empty and unique among the body's tools and named constraints",
                ));
            }
            names.push(&t.name);
        }
        let n = tools.len();
        let mut set = Self {
            tools,
            meters: vec![ReactionMeter::default(); n],
            friction_meters: vec![ReactionMeter::default(); n],
            contacts: vec![0; n],
            sticking: vec![0; n],
            impulses: vec![D::zero(); n],
            friction_impulses: vec![D::zero(); n],
            work: ToolWork::default(),
            series: Vec::new(),
        };
        set.reset_series(0.0);
        Ok(set)
    }

    /// The tools.
    pub fn tools(&self) -> &[RigidTool<D>] {
        &self.tools
    }

    /// Whether there is no tool.
    pub fn is_empty(&self) -> bool {
        self.tools.is_empty()
    }

    /// Number of tools.
    pub fn len(&self) -> usize {
        self.tools.len()
    }

    /// Whether some tool has friction.
    pub fn has_friction(&self) -> bool {
        self.tools.iter().any(|t| !t.friction.is_frictionless())
    }

    /// Particles in contact with each tool in the last step.
    pub fn contacts(&self) -> &[usize] {
        &self.contacts
    }

    /// Work the tools did on the body since `t = 0`.
    pub fn work(&self) -> ToolWork {
        self.work
    }

    /// The impulse the tools gave the body in the last step (every tool, friction included):
    /// a solver's momentum balance counts it with its supports' reactions.
    pub fn step_impulse(&self) -> D::Vector {
        self.impulses.iter().fold(D::zero(), |s, &j| s + j)
    }

    /// Adds `work` to the normal contact work. A solver whose kick booked its forces' work on
    /// velocities the tools then changed corrects the tools' booking by it, so that the forces
    /// are booked on the velocities the particles keep (`sph_ul`'s energy budget).
    pub fn add_contact_work(&mut self, work: f64) {
        self.work.contact += work;
    }

    /// The energy-budget terms of the tools (see [`crate::EnergyBudget`]: minus the work done
    /// on the body): `tool_contact` and `friction`; empty without tools.
    pub fn budget_terms(&self) -> Vec<(&'static str, f64)> {
        if self.is_empty() {
            return Vec::new();
        }
        vec![
            ("tool_contact", -self.work.contact),
            ("friction", -self.work.friction),
        ]
    }

    /// The figures of the tools for a run's summary: `tool_contact_work`, `friction_work`
    /// (work on the body) and `friction_dissipated`; empty without tools.
    pub fn figures(&self) -> Vec<(&'static str, f64)> {
        if self.is_empty() {
            return Vec::new();
        }
        vec![
            ("tool_contact_work", self.work.contact),
            ("friction_work", self.work.friction),
            ("friction_dissipated", self.work.friction_dissipated),
        ]
    }

    /// Starts a step: no impulse yet.
    pub fn begin_step(&mut self) {
        self.impulses.iter_mut().for_each(|j| *j = D::zero());
        self.friction_impulses
            .iter_mut()
            .for_each(|j| *j = D::zero());
    }

    /// One contact pass of every tool ([`RigidTool::enforce_contact`], same arguments), adding
    /// each tool's impulses and work; `count` records the particles in contact (the first pass
    /// of a step).
    #[allow(clippy::too_many_arguments)]
    pub fn enforce(
        &mut self,
        t_end: f64,
        lookahead: f64,
        offset: impl Fn(usize, D::Vector) -> f64 + Copy,
        max_offset: f64,
        positions: &[D::Vector],
        velocities: &mut [D::Vector],
        masses: &[f64],
        movable: &[bool],
        count: bool,
    ) {
        for (k, tool) in self.tools.iter().enumerate() {
            let out = tool.enforce_contact(
                t_end, lookahead, offset, max_offset, positions, velocities, masses, movable,
            );
            self.impulses[k] += out.impulse;
            self.friction_impulses[k] += out.friction_impulse;
            self.work.contact += out.normal_work;
            self.work.friction += out.friction_work;
            self.work.friction_dissipated += out.friction_dissipation;
            if count {
                self.contacts[k] = out.active;
                self.sticking[k] = out.sticking;
            }
        }
    }

    /// Ends a step of length `dt`: each tool's reaction `−impulse/dt` into its meters.
    pub fn end_step(&mut self, dt: f64) {
        for (meter, &impulse) in self.meters.iter_mut().zip(&self.impulses) {
            meter.add(-impulse / dt, dt);
        }
        for (k, meter) in self.friction_meters.iter_mut().enumerate() {
            if !self.tools[k].friction.is_frictionless() {
                meter.add(-self.friction_impulses[k] / dt, dt);
            }
        }
    }

    /// Empty series, one per tool, with a first row at time `t`.
    pub fn reset_series(&mut self, t: f64) {
        let axes = &["force_x", "force_y", "force_z"][..D::D];
        let friction_axes = &["friction_x", "friction_y", "friction_z"][..D::D];
        self.series = self
            .tools
            .iter()
            .map(|t| {
                let mut columns = vec!["displacement"];
                columns.extend_from_slice(axes);
                columns.push("contacts");
                let mut description = crate::conventions::TOOL_SERIES.to_string();
                if !t.friction.is_frictionless() {
                    columns.extend_from_slice(friction_axes);
                    columns.push("sticking");
                    description = format!(
                        "{description}; {}",
                        crate::conventions::TOOL_FRICTION_SERIES
                    );
                }
                // A tool off a straight line: its displacement vector, and the angle it turned.
                if !t.motion.is_straight() {
                    columns.extend_from_slice(
                        &["displacement_x", "displacement_y", "displacement_z"][..D::D],
                    );
                }
                if t.motion.rotation().is_some() {
                    columns.push("angle");
                }
                Series::new(&t.name, &columns).with_description(&description)
            })
            .collect();
        self.contacts.iter_mut().for_each(|c| *c = 0);
        self.sticking.iter_mut().for_each(|c| *c = 0);
        self.record(t);
    }

    /// Appends one row to every tool's series: travel, mean reactions since the last row,
    /// contacts (and friction).
    pub fn record(&mut self, t: f64) {
        let mut row = Vec::with_capacity(12);
        for (k, tool) in self.tools.iter().enumerate() {
            row.clear();
            row.push(tool.motion.distance(t));
            let f = self.meters[k].take_mean();
            row.extend((0..D::D).map(|c| D::component(f, c)));
            row.push(self.contacts[k] as f64);
            if !tool.friction.is_frictionless() {
                let f = self.friction_meters[k].take_mean();
                row.extend((0..D::D).map(|c| D::component(f, c)));
                let active = self.contacts[k];
                row.push(if active > 0 {
                    self.sticking[k] as f64 / active as f64
                } else {
                    0.0
                });
            }
            if !tool.motion.is_straight() {
                let u = tool.motion.displacement(t);
                row.extend((0..D::D).map(|c| D::component(u, c)));
            }
            if tool.motion.rotation().is_some() {
                row.push(tool.motion.angle(t));
            }
            self.series[k].push(t, &row);
        }
    }

    /// The tools' series.
    pub fn series(&self) -> &[Series] {
        &self.series
    }

    /// Writes the running state: contact counts, meters, work, series.
    pub fn save(&self, out: &mut crate::StateWriter) {
        let contacts: Vec<u64> = self.contacts.iter().map(|&c| c as u64).collect();
        out.u64s("tool_contacts", &contacts);
        let sticking: Vec<u64> = self.sticking.iter().map(|&c| c as u64).collect();
        out.u64s("tool_sticking", &sticking);
        ReactionMeter::save_all(out, "tool_meters", &self.meters);
        ReactionMeter::save_all(out, "tool_friction_meters", &self.friction_meters);
        let w = self.work;
        out.f64s("tool_work", &[w.contact, w.friction, w.friction_dissipated]);
        crate::state::save_series(out, &self.series);
    }

    /// Reads back [`ToolSet::save`] into a tool set built from the same scene.
    ///
    /// # Errors
    /// A mismatch of names or sizes ([`Error::Checkpoint`]).
    pub fn restore(&mut self, input: &mut crate::StateReader<'_>) -> Result<(), Error> {
        let n = Some(self.tools.len());
        let contacts = input.u64s("tool_contacts", n)?;
        self.contacts = contacts.into_iter().map(|c| c as usize).collect();
        let sticking = input.u64s("tool_sticking", n)?;
        self.sticking = sticking.into_iter().map(|c| c as usize).collect();
        ReactionMeter::restore_all(input, "tool_meters", &mut self.meters)?;
        ReactionMeter::restore_all(input, "tool_friction_meters", &mut self.friction_meters)?;
        let [contact, friction, friction_dissipated] = input.scalars::<3>("tool_work")?;
        self.work = ToolWork {
            contact,
            friction,
            friction_dissipated,
        };
        crate::state::restore_series(input, &mut self.series)
    }
}

/// Time average of a force from the impulses of successive steps (a tool's or a grip's
/// reaction), reset at each sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactionMeter<D: Dim> {
    impulse: D::Vector,
    elapsed: f64,
    last: D::Vector,
}

impl<D: Dim> Default for ReactionMeter<D> {
    fn default() -> Self {
        Self {
            impulse: D::zero(),
            elapsed: 0.0,
            last: D::zero(),
        }
    }
}

impl<D: Dim> ReactionMeter<D> {
    /// Adds a force acting over `dt`.
    pub fn add(&mut self, force: D::Vector, dt: f64) {
        self.impulse += force * dt;
        self.elapsed += dt;
        self.last = force;
    }

    /// Writes the meters' running sums (checkpoints).
    pub fn save_all(out: &mut crate::StateWriter, name: &str, meters: &[Self]) {
        let mut v = Vec::with_capacity(2 * meters.len());
        let mut e = Vec::with_capacity(meters.len());
        for m in meters {
            v.push(m.impulse);
            v.push(m.last);
            e.push(m.elapsed);
        }
        out.vectors::<D>(name, &v);
        out.f64s(name, &e);
    }

    /// Reads back [`ReactionMeter::save_all`] into as many meters.
    pub fn restore_all(
        input: &mut crate::StateReader<'_>,
        name: &str,
        meters: &mut [Self],
    ) -> Result<(), crate::Error> {
        let v = input.vectors::<D>(name, Some(2 * meters.len()))?;
        let e = input.f64s(name, Some(meters.len()))?;
        for (k, m) in meters.iter_mut().enumerate() {
            (m.impulse, m.last, m.elapsed) = (v[2 * k], v[2 * k + 1], e[k]);
        }
        Ok(())
    }

    /// The mean force since the last call (the last step's force if no time elapsed).
    pub fn take_mean(&mut self) -> D::Vector {
        let mean = if self.elapsed > 0.0 {
            self.impulse / self.elapsed
        } else {
            self.last
        };
        self.impulse = D::zero();
        self.elapsed = 0.0;
        mean
    }
}
