//! Benchmark case 1: the oscillating plate (TL paper §4.1, Fig. 2; UL paper §6.1).
//!
//! A plate strip of free length `L` and thickness `H` (centred on y = 0) continues into a
//! clamping base: the strip extends `base_length` into the base and the base adds
//! `base_layers` layers above, below and behind it, as in SPHinXsys's `test_2d_oscillating_beam`
//! (SL = 0.06, BW = 4 layers). Which particles are held fixed is the key `clamp` ([`Clamp`]):
//! `frame` (default) holds only the frame around the embedded strip — the base rectangle
//! `[−SL − BW, 0] × [−(H/2 + BW), H/2 + BW]` minus the strip — and leaves the embedded strip
//! particles free between the fixed layers, as SPHinXsys's beam does and as the TL paper
//! describes it ("clamped between several layers of constrained SPH particles", Fig. 2);
//! `solid` holds every particle with x < 0, the embedded strip included (stiffer: the plate's
//! root cannot bend inside the base). The initial velocity is the first cantilever mode
//! (TL eq 34–36), `v_y = v_f c f(x)/f(L)` for x > 0, `c = √(K/ρ0)`. The tip probe is the
//! material point (L, 0), interpolated (Shepard) from the particles around it.

use crate::analysis::{extremes, mean_period};
use crate::cases::tl_common::{material, run_tl, tl_params};
use crate::cases::ul_common::{run_ul, ul_params, UL_METHODS};
use crate::error::CaseError;
use crate::params::{Param, Params, Range};
use crate::runner::{finite_or_null, RunOptions, RunRecord};
use crate::{Case, CaseInfo};
use glam::DVec2;
use serde_json::{json, Map, Value as Json};
use sph_core::error::Num;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Dim, Probe, Solver, D2};
use sph_geometry::generate::{Aabb, Lattice, ParticleSet, Shape};
use sph_materials::{DeviatorDimension, MaterialKind};

/// `kL` of the first cantilever mode (root of cos kL cosh kL = −1, TL eq 36).
pub const KL: f64 = 1.875;

/// Methods the plate runs: the TL family (h = 1.15 dp) and the UL family (h = 1.3 dp).
pub const PLATE_METHODS: &[&str] = &[
    "tl-hf", "tl", "tl-gm", "ul-enog", "ul-og", "ul-oas", "ul-gnog",
];

/// The oscillating plate, 2D plane strain.
pub struct OscillatingPlate2d;

/// Which particles of a plate's clamping base are held fixed (case key `clamp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clamp {
    /// Only the frame around the embedded strip (the base minus the strip rectangle): the
    /// embedded strip particles move, held between the fixed layers. SPHinXsys's
    /// `test_2d_oscillating_beam` (its constraint shape is the base polygon minus the beam
    /// polygon), the set-up of the TL and UL papers' plate.
    Frame,
    /// Every particle with x < 0: the embedded strip is rigid.
    Solid,
}

impl Clamp {
    /// The key's words.
    pub const CHOICES: &'static [&'static str] = &["frame", "solid"];

    /// The case key with the case's default (the oscillating plate: `frame`, the TL and UL
    /// papers' set-up; the MPS cantilever plate: `solid`, see its documentation).
    pub fn param(default: Clamp) -> Param {
        Param::choice(
            "clamp",
            match default {
                Self::Frame => "frame",
                Self::Solid => "solid",
            },
            Self::CHOICES,
            "fixed particles of the base: frame = the layers around the embedded strip \
             (SPHinXsys's beam, the papers' set-up; the embedded strip moves), solid = every \
             particle with x < 0",
        )
    }

    /// The clamp of the case key `clamp`.
    pub fn of(p: &Params) -> Result<Self, CaseError> {
        match p.text("clamp") {
            "frame" => Ok(Self::Frame),
            "solid" => Ok(Self::Solid),
            other => Err(CaseError::InvalidValue {
                key: "clamp".into(),
                value: other.into(),
                allowed: Self::CHOICES.join(", "),
            }),
        }
    }

    /// The region of [`plate_particles`] this clamp holds fixed.
    pub fn region(self) -> &'static str {
        match self {
            Self::Frame => "frame",
            Self::Solid => "base",
        }
    }

    /// The fixed particles of a plate built by [`plate_particles`].
    ///
    /// # Errors
    /// `frame` with an empty frame (`base_layers = 0` leaves only the back wall, which cannot
    /// clamp the strip; a frame needs layers above and below it).
    pub fn fixed(self, set: &ParticleSet<D2>, base_layers: i64) -> Result<Vec<u32>, CaseError> {
        if self == Self::Frame && base_layers < 1 {
            return Err(CaseError::InvalidValue {
                key: "clamp".into(),
                value: "frame".into(),
                allowed: "solid when base_layers = 0 (a frame needs fixed layers above and below \
                          the strip)"
                    .into(),
            });
        }
        Ok(set.tagged(self.region())?)
    }
}

/// Thin-plate period `T = 2π/ω`, `ω² = E H² k⁴ / (12 ρ (1 − ν²))` (TL eq 37).
pub fn thin_plate_period(length: f64, thickness: f64, youngs: f64, nu: f64, density: f64) -> f64 {
    let k = KL / length;
    let omega2 = youngs * thickness * thickness * k.powi(4) / (12.0 * density * (1.0 - nu * nu));
    2.0 * std::f64::consts::PI / omega2.sqrt()
}

/// The mode shape `f(x)` of TL eq 35.
pub fn mode_shape(x: f64, length: f64) -> f64 {
    let k = KL / length;
    let kl = KL;
    (kl.sin() + kl.sinh()) * ((k * x).cos() - (k * x).cosh())
        - (kl.cos() + kl.cosh()) * ((k * x).sin() - (k * x).sinh())
}

/// The plate's particles: strip plus base, with the regions `base` (x < 0) and `frame` (the
/// base minus the strip rectangle: `base_layers` layers above, below and behind the embedded
/// strip) tagged.
pub fn plate_particles(
    length: f64,
    thickness: f64,
    resolution: i64,
    base_length: f64,
    base_layers: i64,
) -> Result<(ParticleSet<D2>, f64), CaseError> {
    let dp = thickness / resolution as f64;
    // Whole numbers of spacings so that every boundary lies on a lattice-cell face.
    let sl = (base_length / dp).round().max(1.0) * dp;
    let nl = (length / dp).round();
    if (nl * dp - length).abs() > 1e-9 * length {
        return Err(CaseError::InvalidValue {
            key: "length".into(),
            value: Num(length).to_string(),
            allowed: format!(
                "a whole multiple of dp = thickness/resolution = {}",
                Num(dp)
            ),
        });
    }
    let bw = base_layers as f64 * dp;
    let half = 0.5 * thickness;
    let base = Aabb::<D2>::new(DVec2::new(-sl - bw, -half - bw), DVec2::new(0.0, half + bw))?;
    let strip = Aabb::<D2>::new(DVec2::new(-sl, -half), DVec2::new(length, half))?;
    let shape = base.union(strip);
    let lattice = Lattice::<D2>::new(dp, DVec2::new(-sl - bw, -half - bw))?;
    let mut set = ParticleSet::fill(&lattice, &shape)?;
    set.tag_where("base", |_, x| x.x < 0.0)?;
    // Particle centres lie half a spacing inside the lattice cells, so these tests never meet
    // a boundary exactly.
    set.tag_where("frame", |_, x| x.x < 0.0 && (x.x < -sl || x.y.abs() > half))?;
    Ok((set, dp))
}

impl Case for OscillatingPlate2d {
    fn info(&self) -> CaseInfo {
        CaseInfo {
            name: "oscillating-plate-2d",
            description:
                "cantilever plate clamped in a base, first-mode initial velocity (TL §4.1, UL §6.1)",
            methods: PLATE_METHODS,
        }
    }

    fn params(&self) -> Params {
        let mut specs = vec![
            Param::float("length", 0.2, Range::Positive, "free length L (m)"),
            Param::float("thickness", 0.02, Range::Positive, "thickness H (m)"),
            Param::int("resolution", 10, Range::Closed(2.0, 400.0), "H/dp"),
            Param::float("nu", 0.3975, Range::Open(-1.0, 0.5), "Poisson's ratio"),
            Param::float("youngs_modulus", 2e6, Range::Positive, "E (Pa)"),
            Param::float("density", 1000.0, Range::Positive, "ρ0 (kg/m³)"),
            Param::float("vf", 0.05, Range::NonNegative, "initial tip speed / c0"),
            Param::float("end_time", 1.0, Range::Positive, "simulated time (s)"),
            Param::float(
                "base_length",
                0.06,
                Range::Positive,
                "length of strip inside the base (m)",
            ),
            Param::int(
                "base_layers",
                4,
                Range::Closed(1.0, 20.0),
                "base layers above, below and behind the strip",
            ),
            Clamp::param(Clamp::Frame),
            Param::choice(
                "material",
                "linear-elastic",
                &["linear-elastic", "neo-hookean", "kirchhoff-vol-dev"],
                "constitutive law (TL paper: linear elastic; tl-hf: the HF law of TL eq. 10–14)",
            ),
            Param::choice(
                "deviator",
                "spatial",
                &["spatial", "embedded-3d"],
                "kirchhoff-vol-dev only: isochoric split with d = 2 (spatial, the papers') or \
                 d = 3 on the plane-strain embedding (embedded-3d: plane-strain Hooke at small \
                 strain)",
            ),
        ];
        specs.extend(tl_params());
        specs.extend(ul_params());
        let mut p = Params::new("oscillating-plate-2d", specs);
        p.set_text("probe_interval", "5e-4").expect("valid default");
        p
    }

    fn params_for(&self, method: &str) -> Params {
        crate::cases::tl_common::with_hf_paper_law(self.params(), method)
    }

    fn run(
        &self,
        method: &str,
        p: &Params,
        options: &RunOptions,
    ) -> Result<(RunRecord, Map<String, Json>), CaseError> {
        let (l, h) = (p.f64("length"), p.f64("thickness"));
        let (e, nu, rho) = (p.f64("youngs_modulus"), p.f64("nu"), p.f64("density"));
        let kind = material_kind(p)?;
        let mat = material(kind, e, nu, rho)?;
        let c0 = sph_materials::Material::<D2>::constants(&mat).sound_speed;
        let (set, dp) = plate_particles(
            l,
            h,
            p.int("resolution"),
            p.f64("base_length"),
            p.int("base_layers"),
        )?;
        let velocities = first_mode_velocities(set.positions(), l, p.f64("vf") * c0);
        let base = Clamp::of(p)?.fixed(&set, p.int("base_layers"))?;
        let probe_interval = p.f64("probe_interval");
        let period_theory = thin_plate_period(l, h, e, nu, rho);
        let end_time = p.f64("end_time");
        let summarise = move |s: &dyn Solver<D2>, _: &RunRecord| plate_summary(s, period_theory);
        let tip_at = DVec2::new(l, 0.0);
        if UL_METHODS.contains(&method) {
            let constants = *sph_materials::Material::<D2>::constants(&mat);
            let body = Body::<D2> {
                positions: set.positions().to_vec(),
                volumes: set.volumes().to_vec(),
                dp,
                velocities,
                densities: Vec::new(),
            };
            let reference = set.positions().to_vec();
            let volumes = set.volumes().to_vec();
            return run_ul(
                "oscillating-plate-2d",
                method,
                p,
                body,
                constants,
                |s| {
                    let mut c = Constraints::new();
                    c.push(Constraint::Fixed { particles: base }, s.len())?;
                    let tip = Probe::point("tip", tip_at, &reference, &volumes, s.kernel())?;
                    Ok(s.with_constraints(c)
                        .with_probes(vec![tip], probe_interval)?)
                },
                end_time,
                options,
                summarise,
            );
        }
        let body = Body::<D2> {
            positions: set.positions().to_vec(),
            volumes: set.volumes().to_vec(),
            dp,
            velocities,
            densities: Vec::new(),
        };
        run_tl(
            "oscillating-plate-2d",
            method,
            p,
            body,
            mat,
            |s| {
                let mut c = Constraints::new();
                let n = s.len();
                c.push(Constraint::Fixed { particles: base }, n)?;
                let tip = Probe::point(
                    "tip",
                    tip_at,
                    s.reference_positions(),
                    s.volumes(),
                    s.kernel(),
                )?;
                Ok(s.with_constraints(c)
                    .with_probes(vec![tip], probe_interval)?)
            },
            end_time,
            options,
            summarise,
        )
    }
}

/// The law of the keys `material` and `deviator` (`deviator = embedded-3d` is an error for a
/// law without an isochoric split).
fn material_kind(p: &Params) -> Result<MaterialKind, CaseError> {
    let kind: MaterialKind = p.text("material").parse()?;
    match (kind, p.text("deviator")) {
        (_, "spatial") => Ok(kind),
        (MaterialKind::KirchhoffVolDev { .. }, "embedded-3d") => {
            Ok(MaterialKind::KirchhoffVolDev {
                deviator: DeviatorDimension::Embedded3d,
            })
        }
        (_, other) => Err(CaseError::InvalidValue {
            key: "deviator".into(),
            value: other.into(),
            allowed: "spatial unless material = kirchhoff-vol-dev (only that law has an \
                      isochoric split)"
                .into(),
        }),
    }
}

/// Period (mean over the full periods of the tip's vertical motion about y = 0), amplitude
/// (largest |y| of the tip), and the thin-plate period.
fn plate_summary(s: &dyn Solver<D2>, period_theory: f64) -> Map<String, Json> {
    let mut m = Map::new();
    if let Some(tip) = s.probes().iter().find(|p| p.name == "tip") {
        let y: Vec<f64> = tip.positions.iter().map(|&x| D2::component(x, 1)).collect();
        let period = mean_period(&tip.times, &y, 0.0);
        let (lo, hi) = extremes(&y);
        m.insert("period".into(), period.map_or(Json::Null, finite_or_null));
        m.insert("amplitude".into(), finite_or_null(lo.abs().max(hi.abs())));
        m.insert(
            "periods_measured".into(),
            json!(crate::analysis::downward_crossings(&tip.times, &y, 0.0)
                .len()
                .saturating_sub(1)),
        );
        if let Some(t) = period {
            m.insert(
                "period_error_vs_theory".into(),
                finite_or_null(t / period_theory - 1.0),
            );
        }
    }
    m.insert("period_theory".into(), json!(period_theory));
    m
}

/// Initial velocity of the first cantilever mode (TL eq 34, MPS eq 13): `v_y = v_tip f(x)/f(L)`
/// on the free part (x > 0), zero in the base.
pub fn first_mode_velocities(positions: &[DVec2], length: f64, v_tip: f64) -> Vec<DVec2> {
    let fl = mode_shape(length, length);
    positions
        .iter()
        .map(|x| {
            if x.x > 0.0 {
                DVec2::new(0.0, v_tip * mode_shape(x.x, length) / fl)
            } else {
                DVec2::ZERO
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thin_plate_periods_match_cases_md() {
        // the papers: T = 0.27009 (ν=0.22), 0.26412 (0.30), 0.25406 (0.3975), 0.25376 (0.40);
        // printed to 5 digits, so 5e-5 relative.
        for (nu, t) in [
            (0.22, 0.27009),
            (0.30, 0.26412),
            (0.3975, 0.25406),
            (0.40, 0.25376),
        ] {
            let p = thin_plate_period(0.2, 0.02, 2e6, nu, 1000.0);
            assert!((p / t - 1.0).abs() < 5e-5, "ν={nu}: {p} vs {t}");
        }
        // H = 0.01 doubles T.
        let p = thin_plate_period(0.2, 0.01, 2e6, 0.4, 1000.0);
        assert!((p / 0.50752 - 1.0).abs() < 5e-5, "{p}");
    }

    #[test]
    fn mode_shape_is_clamped_at_the_root() {
        // f(0) = 0 and f'(0) = 0 (clamped), to round-off of the O(sinh kL) terms.
        assert!(mode_shape(0.0, 0.2).abs() < 1e-12);
        let d = (mode_shape(1e-6, 0.2) - mode_shape(-1e-6, 0.2)) / 2e-6;
        assert!(d.abs() < 1e-6, "{d}");
    }

    #[test]
    fn plate_has_1000_free_particles_at_h_over_dp_10() {
        let (set, dp) = plate_particles(0.2, 0.02, 10, 0.06, 4).unwrap();
        assert_eq!(dp, 0.002);
        let free = set.untagged("base").unwrap().len();
        assert_eq!(free, 1000);
        // Base: (30 + 4) columns × (10 + 8) rows.
        assert_eq!(set.tagged("base").unwrap().len(), 34 * 18);
        // Frame: the base minus the 30 × 10 embedded strip.
        assert_eq!(set.tagged("frame").unwrap().len(), 34 * 18 - 30 * 10);
    }

    #[test]
    fn frame_clamp_leaves_the_embedded_strip_free_and_surrounds_it() {
        let (set, dp) = plate_particles(0.2, 0.02, 10, 0.06, 4).unwrap();
        let frame = Clamp::Frame.fixed(&set, 4).unwrap();
        let x = set.positions();
        // Every embedded strip particle is free; every frame particle lies outside the strip.
        for &i in &frame {
            let p = x[i as usize];
            assert!(p.x < -0.06 || p.y.abs() > 0.01, "{p:?} is in the strip");
        }
        let embedded = (0..x.len())
            .filter(|&i| x[i].x < 0.0 && x[i].x > -0.06 && x[i].y.abs() < 0.01)
            .count();
        assert_eq!(embedded, 300);
        assert_eq!(frame.len() + embedded, 34 * 18);
        // 4 layers above and below and 4 columns behind.
        let above = frame.iter().filter(|&&i| x[i as usize].y > 0.01).count();
        assert_eq!(above, 4 * 34);
        let behind = frame
            .iter()
            .filter(|&&i| x[i as usize].x < -0.06 && x[i as usize].y.abs() < 0.01)
            .count();
        assert_eq!(behind, 4 * 10);
        assert!(dp > 0.0);
        assert!(Clamp::Frame.fixed(&set, 0).is_err());
        assert_eq!(Clamp::Solid.fixed(&set, 0).unwrap().len(), 34 * 18);
    }
}
