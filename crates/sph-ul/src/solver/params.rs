//! The numerical parameters of the UL solver and their defaults.

use super::*;

/// Numerical parameters (defaults: UL paper §5–6).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct UlParams {
    /// Smoothing length over particle spacing (1.3; cut-off 2h = 2.6 dp).
    pub h_over_dp: f64,
    /// Dual (default) or single-criterion time stepping.
    pub stepping: Stepping,
    /// `CFL_ad` of eq 21 (0.2).
    pub cfl_advection: f64,
    /// `CFL_ac` of eq 22 (0.4).
    pub cfl_acoustic: f64,
    /// Floor of `|v|max` in eq 21, as a fraction of `c0` (0.01: at most `20 h/c0`, i.e. 50
    /// acoustic sub-steps, per advection step for a body nearly at rest).
    pub speed_floor: f64,
    /// Riemann solver form (default: SPHinXsys's solid tests, β = 1 and no pressure jump; see
    /// [`RiemannScheme`]).
    pub riemann: RiemannScheme,
    /// Correct the velocity gradient with `B` (eq 26) in OG/OAS too. Default false: the paper's
    /// eq 14 has none, and only the uncorrected gradient makes the OG pair (eq 13–14)
    /// energy-consistent (`Σ V τ:L` cancels the shear power exactly; measured: with `B` a free
    /// block gains 5% energy in 10 ms, without it never gains). ENOG's output stress always
    /// uses `B` (eq 26).
    pub corrected_velocity_gradient: bool,
    /// ENOG: integrate the shear stress for output (eq 6–8 with eq 26; it never feeds back into
    /// the motion). Off saves one matrix per pair per sub-step (a quarter of the 2D plate's
    /// time); `von_mises` then shows the pressure part only and the energy budget uses the
    /// exact shear work instead of the estimate from `τ`. The `sph` cases and scene files turn
    /// it on exactly when snapshots are written.
    pub track_shear_stress: bool,
    /// Reorder particles in cell order at rebuilds (cache locality; default true).
    pub reorder: bool,
    /// Recompute the pair kernel data (`e_ij`, `r_ij`, `W′`) from the half-step positions
    /// in every acoustic sub-step, over the neighbour list of the last rebuild (the list, the
    /// cell list and `B` stay those of the rebuild). Default **on**. Off is docs/methods.md's scheme
    /// (the data of the rebuild serve the whole advection step), which makes the 2D plate
    /// (ENOG, H/dp = 10, v_f = 0.05) soften secularly: its period grows 0.278 → 0.298 s within
    /// 3 s and 0.277 → 0.366 s within 10 s, the amplitude growing with it; with the refresh the
    /// period stays 0.2749–0.2756 s over 3 s (0.2754 → 0.2741 s over 10 s). Cost, measured by
    /// `ul-stepping` (docs/performance.md, Intel Xeon, two threads): 1.34–1.39× the time per
    /// sub-step of the frozen data; dual stepping stays 3.8× faster than single in 2D (H/dp
    /// 10–30) and 2.6× in 3D (H/dp 3).
    pub refresh_kernel_data: bool,
    /// Guard threshold of the correction matrix (see `sph_core::correction`).
    pub correction_min_eigenvalue: f64,
    /// Let particles that lose every neighbour (numerical fracture) fly on ballistically,
    /// counting them ([`UlSolver::isolated_max`]), instead of stopping with
    /// `Error::LostNeighbours` (default false).
    pub allow_isolated: bool,
    /// Scale `κ` of the contact pressure between bodies, `p_c = κ c0² ρ_c` (1: docs/methods.md; see
    /// [`crate::contact`]). Only used with [`UlSolver::with_contact`].
    pub contact_scale: f64,
    /// Keep the energy budget ([`UlSolver::energy_budget`]): the force gather also sums the
    /// dissipative part of the Riemann pressure (and OAS's artificial stress) per particle,
    /// and every acoustic step accumulates the work of those parts, of contact, of ENOG's
    /// `A_s` and of loads (default true). Measured cost: +12 % on the 2D plate with ENOG on
    /// one and on two threads (`sph run oscillating-plate-2d --method ul-enog --set
    /// h_over_dp=1.3 --set end_time=0.25 --no-output --set energy_budget=true|false`, Intel
    /// Xeon, median of 5: 4.31 / 3.85 s and 2.64 / 2.36 s), almost all of it per pair in the
    /// force gather; earlier, on a loaded machine (CPU time, one thread, median of 3): +7 % on
    /// the 2D rings with ENOG (`colliding-rings-2d --set end_time=0.01`), +2 % on the 3D balls
    /// with OG (`colliding-balls-3d --method ul-og --set dp=0.0025 --set end_time=0.002`).
    pub energy_budget: bool,
}

impl UlParams {
    /// The allowed `h_over_dp`, `lo ≤ h/dp ≤ hi` (as TL's).
    pub const H_OVER_DP_RANGE: (f64, f64) = (0.5, 3.0);
    /// The allowed CFL numbers of eq 21 and 22, `lo < CFL < hi`.
    pub const CFL_RANGE: (f64, f64) = (0.0, 1.0);

    /// Checks every parameter against its range (the ranges the `sph` command's keys and scene
    /// files share).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), Error> {
        let (lo, hi) = Self::H_OVER_DP_RANGE;
        check_closed_range("h_over_dp", self.h_over_dp, lo, hi)?;
        let (lo, hi) = Self::CFL_RANGE;
        check_open_range("cfl_advection", self.cfl_advection, lo, hi)?;
        check_open_range("cfl_acoustic", self.cfl_acoustic, lo, hi)?;
        check_positive("speed_floor", self.speed_floor)?;
        check_positive("correction_min_eigenvalue", self.correction_min_eigenvalue)?;
        check_positive("contact_scale", self.contact_scale)
    }
}

impl Default for UlParams {
    fn default() -> Self {
        Self {
            h_over_dp: 1.3,
            stepping: Stepping::Dual,
            cfl_advection: 0.2,
            cfl_acoustic: 0.4,
            speed_floor: 0.01,
            riemann: RiemannScheme::SphinxsysTests,
            corrected_velocity_gradient: false,
            track_shear_stress: true,
            reorder: true,
            correction_min_eigenvalue: DEFAULT_MIN_EIGENVALUE,
            allow_isolated: false,
            refresh_kernel_data: true,
            contact_scale: 1.0,
            energy_budget: true,
        }
    }
}
