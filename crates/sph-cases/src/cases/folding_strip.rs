//! A thin elastic strip folded shut until its faces touch: the check of TL self-contact
//! ([`sph_tl::TlSolver::with_self_contact`]) with its momentum and energy budgets.
//!
//! **Set-up.** A free, straight strip of length `length` (0.1 m) and thickness
//! `H = length / aspect` (`aspect` 30), plane strain, cut from a cell-centred lattice of spacing
//! `dp = H / resolution` (`resolution`: particles through the thickness), neo-Hookean rubber
//! (E = 2 MPa, ν = 0.3, ρ0 = 1000: c0 = 51.9 m/s) without Kelvin–Voigt damping. At t = 0 each
//! half turns about the strip's midpoint toward the other, like a sheet of paper being folded
//! shut: the right half (x > 0) with angular velocity ω, the left half with −ω, so the tips
//! rise at `tip_speed` (10 m/s, 0.19 c0; ω = tip_speed / (length/2)); the mean velocity is
//! removed, so the centre of mass stays at rest. The strip bends about its middle, curls into a
//! loop, and at about 12 ms the inner faces of its two ends meet and push each other back —
//! particles a whole strip apart in the reference configuration (no reference neighbours),
//! which only self-contact keeps apart. Thrown twice as hard (`tip_speed = 20`) the halves
//! meet face to face over a longer stretch, at a closing speed the default contact stiffness
//! does not hold (`contact_scale` 2: the faces pass, smallest gap 0.003 dp; 10 holds them 0.66
//! dp apart).
//!
//! TL-HF with the paper's single ζ (`laplacian = "paper"`) blows up on this strip without
//! Kelvin–Voigt damping (non-finite positions at 11.6 ms at `resolution` 4, with and without
//! self-contact); this case's TL-HF default is therefore the normalised Laplacian
//! (`laplacian = "normalised"`), which runs undamped.
//!
//! A free body is chosen over a clamped or driven one because its budgets are exact statements
//! with nothing to model: no external force acts, so the linear momentum `Σ m v` stays at its
//! initial value (the contact pair forces are equal and opposite bit for bit), and the energy
//! `E = K + W + U_c` (kinetic, strain `Σ V⁰ ψ(F)`, stored contact energy
//! [`sph_tl::TlSolver::contact_energy`], conservative) stays at `E0 = K0` up to the time
//! integrator's error (TL with the original shear) — and, with TL-HF and TL-GM, up to what their
//! shear terms add (not the gradient of `W`: `K + W` is not their invariant even without
//! contact). A clamp would need the reaction's work.
//!
//! Summary, measured after every step (not at samples only) by the case's watch:
//! `smallest_gap` — the smallest distance, in dp, between two particles whose reference
//! distance is at least the kernel support 2h (null if none came within 2 dp); with
//! `self_contact = true` the faces stop about 0.6 dp apart (surface particles sit dp/2 inside
//! the faces, so the faces touch at 1 dp), without it they pass through each other (gap ≈ 0);
//! `gap_time` when it was smallest; `momentum_error` — the largest `|P(t) − P(0)| / (M v_tip)`;
//! `energy_error` — the largest `|E(t) − E0| / E0` and `energy_error_final` at the end;
//! `contact_energy_peak` — the largest `U_c / E0`; `contact_pairs_max` (directed);
//! `kinetic_energy_initial` (J per metre of depth); `self_contact`.

use crate::cases::tl_common::{material, meta, schedule, shear_of, tl_numerics, tl_params};
use crate::cases::tl_common::{TL_FIELDS, TL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{drive, finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use serde_json::{json, Map, Value as Json};
use sph_core::contact::ContactBodies;
use sph_core::{
    Body, Dim, Error, Field, Kernel, Probe, Series, Solver, StateReader, StateWriter, StepInfo, D2,
};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet};
use sph_materials::{MaterialKind, MaterialModel};
use sph_tl::TlSolver;

/// The strip folded shut.
pub struct FoldingStrip;

/// The keys of the case, then the TL keys (Kelvin–Voigt damping off by default: the energy
/// budget is closed only without it).
fn folding_params() -> Params {
    let mut specs = vec![
        Param::float("length", 0.1, Range::Positive, "strip length L (m)"),
        Param::float(
            "aspect",
            30.0,
            Range::Closed(5.0, 200.0),
            "L / H, length over thickness",
        ),
        Param::int(
            "resolution",
            4,
            Range::Closed(2.0, 40.0),
            "particles through the thickness H (dp = H / resolution)",
        ),
        Param::float(
            "tip_speed",
            10.0,
            Range::Positive,
            "speed of the tips relative to the midpoint at t = 0 (m/s; each half turns \
             rigidly about the midpoint toward the other)",
        ),
        Param::float("end_time", 0.02, Range::Positive, "simulated time (s)"),
        Param::bool(
            "self_contact",
            true,
            "self-contact of the strip (false: the faces pass through each other)",
        ),
        Param::float(
            "contact_scale",
            sph_tl::DEFAULT_CONTACT_SCALE,
            Range::Closed(0.1, 100.0),
            "κ of the contact stiffness κ c0² (TL's default 2)",
        ),
        Param::choice(
            "material",
            "neo-hookean",
            &["neo-hookean", "linear-elastic", "kirchhoff-vol-dev"],
            "constitutive law",
        ),
        Param::float("youngs_modulus", 2e6, Range::Positive, "E (Pa)"),
        Param::float("nu", 0.3, Range::Open(-1.0, 0.5), "Poisson's ratio"),
        Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
    ];
    specs.extend(tl_params());
    let mut p = Params::new("folding-strip", specs);
    p.set_text("damping", "false").expect("valid default");
    p
}

impl Case for FoldingStrip {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "folding-strip",
            description: "a free elastic strip folded shut until its faces touch: TL \
                          self-contact, smallest gap, momentum and energy budgets (2D)",
            methods: TL_METHODS,
        }
    }

    fn params(&self) -> Params {
        folding_params()
    }

    /// TL-HF undamped with the normalised Laplacian (see the module documentation).
    fn params_for(&self, method: &str) -> Params {
        let mut p = folding_params();
        if method == "tl-hf" {
            p.set_text("laplacian", "normalised")
                .expect("a TL case offers the normalised Laplacian");
        }
        p
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        if options.ranks.as_ref().is_some_and(|c| c.size() > 1) {
            return Err(CaseError::InvalidValue {
                key: "ranks".into(),
                value: "more than 1".into(),
                allowed: "1 for folding-strip (its watch measures every pair after every step)"
                    .into(),
            });
        }
        let (length, aspect, res) = (p.f64("length"), p.f64("aspect"), p.int("resolution"));
        let along = aspect * res as f64;
        if (along - along.round()).abs() > 1e-9 || along.round() as i64 % 2 != 0 {
            return Err(CaseError::InvalidValue {
                key: "aspect".into(),
                value: aspect.to_string(),
                allowed: format!(
                    "aspect × resolution an even whole number (particles along the strip; \
                     resolution = {res})"
                ),
            });
        }
        let thickness = length / aspect;
        let dp = thickness / res as f64;
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let kind: MaterialKind = p.text("material").parse()?;
        let mat = material(kind, e, nu, rho)?;
        let lo = D2::vector([-0.5 * length, -0.5 * thickness, 0.0]);
        let hi = D2::vector([0.5 * length, 0.5 * thickness, 0.0]);
        let set = ParticleSet::fill(&Lattice::<D2>::new(dp, lo)?, &Aabb::<D2>::new(lo, hi)?)?;
        let tip_speed = p.f64("tip_speed");
        let velocities = fold_velocities::<D2>(set.positions(), 0.5 * length, tip_speed);
        let body = Body::<D2> {
            positions: set.positions().to_vec(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        let shear = shear_of(method, p)?;
        let mut solver = TlSolver::new(body, mat, shear, tl_numerics(p))?
            .with_contact_scale(p.f64("contact_scale"))?;
        let self_contact = p.flag("self_contact");
        if self_contact {
            solver = solver.with_self_contact(0)?;
        }
        let mut watch = FoldWatch::new(solver, dp, tip_speed)?;
        let mut m = meta("folding-strip", method, p, watch.len());
        m.insert(
            "guarded_particles".into(),
            json!(watch.inner.guarded_particles()),
        );
        let summarise = move |s: &dyn Solver<D2>, _: &RunRecord| {
            let mut out = Map::new();
            // The watch's figures; a gap of infinity (nothing came within 2 dp) is null.
            for (name, value) in s.figures() {
                if WATCH_FIGURES.contains(&name) {
                    out.insert(name.into(), finite_or_null(value));
                }
            }
            out.insert("self_contact".into(), json!(self_contact));
            out
        };
        Ok(drive::<D2>(
            &mut watch,
            m,
            schedule(p, p.f64("end_time")),
            TL_FIELDS,
            options,
            summarise,
        )?)
    }
}

/// The velocities of the fold: each half turning rigidly about the midpoint (the origin) toward
/// the other, the right half (x > 0) with `ω = tip_speed / half_length`, the left with `−ω`, the
/// mean velocity removed (equal masses: the centre of mass stays at rest).
pub fn fold_velocities<D: Dim>(
    positions: &[D::Vector],
    half_length: f64,
    tip_speed: f64,
) -> Vec<D::Vector> {
    let omega = tip_speed / half_length;
    let mut v: Vec<D::Vector> = positions
        .iter()
        .map(|&x| {
            let (px, py) = (D::component(x, 0), D::component(x, 1));
            let w = if px > 0.0 { omega } else { -omega };
            D::vector([-w * py, w * px, 0.0])
        })
        .collect();
    let n = v.len().max(1) as f64;
    let mean = v.iter().fold(D::zero(), |a, &b| a + b) / n;
    v.iter_mut().for_each(|x| *x -= mean);
    v
}

/// The names of the watch's figures ([`Solver::figures`] of the watched solver), in order.
const WATCH_FIGURES: [&str; 8] = [
    "smallest_gap",
    "gap_time",
    "momentum_error",
    "energy_error",
    "energy_error_final",
    "contact_energy_peak",
    "contact_pairs_max",
    "kinetic_energy_initial",
];

/// A TL solver watched after every step: the smallest distance between particles that were
/// beyond the kernel support apart in the reference configuration (found with the contact
/// detection of [`sph_core::contact`], independently of whether the solver has self-contact),
/// the largest momentum change and the largest change of `K + W + U_c`. Everything else is
/// the solver's; the watch's figures join the solver's [`Solver::figures`] and its checkpoint.
struct FoldWatch<D: Dim>
where
    MaterialModel: sph_materials::Material<D>,
{
    inner: TlSolver<D, MaterialModel>,
    /// Every particle in one body with self-contact: the detection of candidate pairs.
    candidates: ContactBodies,
    /// The kernel support 2h (the reference distance beyond which a pair is a candidate).
    support: f64,
    dp: f64,
    /// Momentum and energy at t = 0 and their scales.
    momentum0: D::Vector,
    momentum_scale: f64,
    energy0: f64,
    /// `[smallest gap (m), its time, momentum error, energy error, final energy error,
    /// contact energy peak / E0, contact pairs max]`.
    figures: [f64; 7],
}

impl<D: Dim> FoldWatch<D>
where
    MaterialModel: sph_materials::Material<D>,
{
    fn new(inner: TlSolver<D, MaterialModel>, dp: f64, tip_speed: f64) -> Result<Self, Error> {
        let n = inner.len();
        let mut candidates = ContactBodies::new(vec![0; n]);
        candidates.self_contact[0] = true;
        let support = inner.kernel().cutoff();
        let momentum0 = inner.linear_momentum();
        let mass: f64 = inner.masses().iter().sum();
        let energy0 = Self::total_energy(&inner);
        let mut w = Self {
            inner,
            candidates,
            support,
            dp,
            momentum0,
            momentum_scale: mass * tip_speed,
            energy0,
            figures: [f64::INFINITY, f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0],
        };
        w.observe()?;
        Ok(w)
    }

    /// `K + W + U_c`.
    fn total_energy(s: &TlSolver<D, MaterialModel>) -> f64 {
        let e = s.energy();
        e.kinetic + e.strain + s.contact_energy()
    }

    /// Updates the running extremes with the current state.
    fn observe(&mut self) -> Result<(), Error> {
        let x = self.inner.positions();
        let list = self.candidates.detect::<D>(
            x,
            self.inner.reference_positions(),
            2.0 * self.dp,
            self.support,
        )?;
        let mut gap = f64::INFINITY;
        for i in 0..x.len() {
            for &j in list.neighbors(i) {
                gap = gap.min(D::norm(x[i] - x[j as usize]));
            }
        }
        let f = &mut self.figures;
        if gap < f[0] {
            f[0] = gap;
            f[1] = self.inner.time();
        }
        let dp = D::norm(self.inner.linear_momentum() - self.momentum0) / self.momentum_scale;
        f[2] = f[2].max(dp);
        let uc = self.inner.contact_energy();
        let e = self.inner.energy();
        let de = (e.kinetic + e.strain + uc - self.energy0) / self.energy0;
        f[3] = f[3].max(de.abs());
        f[4] = de;
        f[5] = f[5].max(uc / self.energy0);
        f[6] = f[6].max(self.inner.contact_pairs() as f64);
        Ok(())
    }
}

impl<D: Dim> Solver<D> for FoldWatch<D>
where
    MaterialModel: sph_materials::Material<D>,
{
    fn method(&self) -> &'static str {
        self.inner.method()
    }

    fn step(&mut self, max_dt: f64) -> Result<StepInfo, Error> {
        let info = self.inner.step(max_dt)?;
        self.observe()?;
        Ok(info)
    }

    fn stable_dt(&self) -> f64 {
        self.inner.stable_dt()
    }

    fn check_time_step(&self) -> Result<(), Error> {
        self.inner.check_time_step()
    }

    fn substep_dt(&self) -> f64 {
        self.inner.substep_dt()
    }

    fn time(&self) -> f64 {
        self.inner.time()
    }

    fn step_count(&self) -> u64 {
        self.inner.step_count()
    }

    fn len(&self) -> usize {
        self.inner.len()
    }

    fn positions(&self) -> &[D::Vector] {
        self.inner.positions()
    }

    fn velocities(&self) -> &[D::Vector] {
        self.inner.velocities()
    }

    fn particle_ids(&self) -> std::borrow::Cow<'_, [u32]> {
        self.inner.particle_ids()
    }

    fn field_names(&self) -> Vec<&'static str> {
        self.inner.field_names()
    }

    fn field(&self, name: &str) -> Option<Field<D>> {
        self.inner.field(name)
    }

    fn probes(&self) -> &[Probe<D>] {
        self.inner.probes()
    }

    fn series(&self) -> Vec<Series> {
        self.inner.series()
    }

    fn energies(&self) -> Option<(f64, f64)> {
        self.inner.energies()
    }

    fn momentum(&self) -> Option<glam::DVec3> {
        self.inner.momentum()
    }

    /// The solver's state, then the watch's extremes.
    fn save_state(&self, out: &mut StateWriter) -> Result<(), Error> {
        self.inner.save_state(out)?;
        out.f64s("fold_watch", &self.figures);
        Ok(())
    }

    fn restore_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        self.inner.restore_state(input)?;
        let f = input.f64s("fold_watch", Some(self.figures.len()))?;
        self.figures.copy_from_slice(&f);
        Ok(())
    }

    fn pair_visits(&self) -> Option<u64> {
        self.inner.pair_visits()
    }

    /// The solver's figures, then the watch's ([`WATCH_FIGURES`]; the gap in dp).
    fn figures(&self) -> Vec<(&'static str, f64)> {
        let mut all = self.inner.figures();
        let f = &self.figures;
        let values = [
            f[0] / self.dp,
            f[1],
            f[2],
            f[3],
            f[4],
            f[5],
            f[6],
            self.energy0,
        ];
        all.extend(WATCH_FIGURES.iter().copied().zip(values));
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn the_fold_turns_the_halves_toward_each_other_about_the_midpoint() {
        let x = [
            DVec2::new(-0.05, 0.0),
            DVec2::new(-0.01, 0.001),
            DVec2::new(0.01, 0.001),
            DVec2::new(0.05, 0.0),
        ];
        let v = fold_velocities::<D2>(&x, 0.05, 10.0);
        // Tips rise at 10 m/s relative to the mean; the mean is zero.
        let mean = v.iter().fold(DVec2::ZERO, |a, &b| a + b) / 4.0;
        assert!(mean.length() < 1e-12, "{mean}");
        assert!((v[3].y - v[1].y - 10.0 + 2.0).abs() < 1e-12, "{v:?}");
        assert!((v[0].y - v[3].y).abs() < 1e-12, "{v:?}");
        // Mirror symmetry: x-velocities opposite, the upper fibres pushed together.
        assert!((v[1].x + v[2].x).abs() < 1e-12 && v[2].x < 0.0, "{v:?}");
    }
}
