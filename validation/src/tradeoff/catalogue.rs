//! What `validate tradeoff` runs: the Pareto scenes (case, resolutions, methods and the
//! measure of each run's error) and the severity sweeps of the stability map.

/// How a run's error is measured.
#[derive(Clone, Copy, Debug)]
pub(super) enum Measure {
    /// `|num / den − 1|` of two summary keys (a closed form computed by the case).
    ClosedForm {
        num: &'static str,
        den: &'static str,
    },
    /// A summary key that already is the relative error.
    Error { key: &'static str },
    /// `num / T_FE − 1` with `T_FE` the finite-element period of the plate with this clamp,
    /// thickness and ν for the small-strain law of the run's method
    /// ([`crate::fem_plate`]).
    FiniteElement {
        num: &'static str,
        clamp: &'static str,
        thickness: f64,
        nu: f64,
    },
}

/// One line of a Pareto plot: a method (and variant) over resolutions.
pub(super) struct Line {
    pub(super) label: &'static str,
    pub(super) method: &'static str,
    pub(super) extra: &'static [&'static str],
}

/// One scene of the speed–accuracy study.
pub(super) struct Scene {
    pub(super) key: &'static str,
    pub(super) title: &'static str,
    pub(super) case: &'static str,
    pub(super) fixed: &'static [&'static str],
    pub(super) resolution_key: &'static str,
    pub(super) quick: &'static [f64],
    pub(super) full: &'static [f64],
    pub(super) lines: Vec<Line>,
    pub(super) measure: Measure,
    pub(super) reference_note: &'static str,
}

fn line(label: &'static str, method: &'static str, extra: &'static [&'static str]) -> Line {
    Line {
        label,
        method,
        extra,
    }
}

pub(super) fn scenes() -> Vec<Scene> {
    vec![
        Scene {
            key: "plate2d",
            title: "2D oscillating plate: period (v_f = 0.05, to t = 0.6 s)",
            case: "oscillating-plate-2d",
            fixed: &["end_time=0.6"],
            resolution_key: "resolution",
            quick: &[4.0, 6.0, 8.0],
            full: &[5.0, 10.0, 20.0, 40.0],
            lines: vec![
                line("tl", "tl", &[]),
                line("tl-hf", "tl-hf", &[]),
                line("tl-gm", "tl-gm", &[]),
                line("ul-og", "ul-og", &[]),
                line("ul-oas", "ul-oas", &[]),
                line("ul-enog", "ul-enog", &[]),
                line("ul-enog single", "ul-enog", &["stepping=single"]),
                line("ul-enog frozen", "ul-enog", &["refresh_kernel_data=false"]),
            ],
            measure: Measure::FiniteElement {
                num: "period",
                clamp: "frame",
                thickness: 0.02,
                nu: 0.3975,
            },
            reference_note: "Reference: the small-amplitude period of the same plate (frame \
                clamp, ν = 0.3975) from plane-strain finite elements (`validation/fem/\
                plate_modes.py`: P2 mesh study, extrapolated), for the small-strain law each \
                method discretises: plane-strain Hooke for TL and TL-GM (Saint Venant–Kirchhoff), \
                the d = 2 deviatoric split (λ_eff = K − G, 0.64 % slower at this ν) for TL-HF and \
                the UL methods (UL-ENOG's shear term and UL-OAS's artificial stress make the \
                split their nearest law, not their exact limit). The runs start at v_f = 0.05: \
                the amplitude itself shortens the period by 0.1–0.25 % (TL-HF at H/dp 40, TL \
                Table 1 in docs/validation.md, v_f 0.05 against 0.01), below the errors here. \
                Earlier versions of this report used the Richardson extrapolation of TL-HF's \
                finest runs (0.25722 s, fitted order 0.53), which the FE value (0.26444 s) shows \
                was far outside the asymptotic range.",
        },
        Scene {
            key: "homog",
            title: "Homogeneous plane-strain compression by 20 %: punch force",
            case: "punching-strip-2d",
            fixed: &["punch_width=0.027", "compression=0.2"],
            resolution_key: "resolution",
            quick: &[10.0, 15.0, 20.0],
            full: &[10.0, 20.0, 30.0, 45.0, 60.0],
            lines: vec![
                line("tl", "tl", &[]),
                line("tl-hf", "tl-hf", &[]),
                line("tl-gm", "tl-gm", &[]),
            ],
            measure: Measure::ClosedForm {
                num: "reaction_force",
                den: "theory_homogeneous_force",
            },
            reference_note: "Reference: the closed-form homogeneous plane-strain state of the \
                compressible neo-Hookean law (the punches are wider than the bulged strip, so \
                the state is homogeneous).",
        },
        Scene {
            key: "cantilever",
            title: "Static cantilever under a tip load (MPS): tip deflection",
            case: "static-cantilever-2d",
            fixed: &["end_time=2.0"],
            resolution_key: "resolution",
            quick: &[4.0, 6.0],
            full: &[5.0, 10.0, 20.0, 40.0],
            lines: vec![line("mps", "mps", &[])],
            measure: Measure::Error {
                key: "tip_deflection_error_timoshenko",
            },
            reference_note: "Reference: Timoshenko beam theory (bending plus shear) for the \
                clamped cantilever (the case computes it).",
        },
        Scene {
            key: "lame",
            title: "Pressurised ring, 1 kPa (MPS): inner-radius displacement",
            case: "pressurised-ring-2d",
            fixed: &[
                "outer_radius=4",
                "pressure=1000",
                "damping=30",
                "end_time=1.5",
            ],
            resolution_key: "dp",
            quick: &[0.3, 0.2],
            full: &[0.2, 0.1, 0.05],
            lines: vec![line("mps", "mps", &[])],
            measure: Measure::ClosedForm {
                num: "inner_displacement_final",
                den: "inner_displacement_theory",
            },
            reference_note: "Reference: Lamé's thick-walled cylinder in plane strain with the \
                small-strain E and ν of the Mooney–Rivlin law.",
        },
        Scene {
            key: "hertz",
            title: "Hertz impact of two solid spheres (UL, 1 m/s each): contact time",
            case: "hertz-impact-3d",
            fixed: &[],
            resolution_key: "resolution",
            quick: &[6.0, 8.0, 10.0],
            // Not 30 (226,130 particles, about 13 min a line at two threads): with the quick
            // points the lines have five resolutions; the accuracy at R/dp 30 is in the impacts
            // section of docs/validation.md.
            full: &[10.0, 15.0, 20.0],
            lines: vec![
                line("ul-og", "ul-og", &[]),
                line("ul-oas", "ul-oas", &[]),
                line("ul-enog", "ul-enog", &[]),
                line("ul-enog kappa 2", "ul-enog", &["contact_stiffness=2"]),
            ],
            measure: Measure::ClosedForm {
                num: "contact_time",
                den: "contact_time_theory",
            },
            reference_note: "Reference: Hertz's quasi-static impact of two identical elastic \
                spheres (contact time 2.87 (m*²/(R* E*² v))^(1/5), computed by the case). The \
                resolution is R/dp. `ul-enog kappa 2` doubles the contact pressure's scale \
                (`contact_stiffness = 2`): the gap between the two ENOG lines is what the \
                contact model's one constant changes.",
        },
        Scene {
            key: "plate3d",
            title: "3D simply supported plate, mode (1, 1) (UL): period",
            case: "oscillating-plate-3d",
            // Two thin-plate periods of mode (1, 1), as the UL Table 3 runs.
            fixed: &["end_time=0.1064"],
            resolution_key: "resolution",
            quick: &[],
            // H/dp is a whole number ≥ 2 (a whole number of rows through the thickness); 5
            // would be 200,000 particles and about four hours a line on this machine.
            full: &[2.0, 3.0, 4.0],
            lines: vec![
                line("ul-og", "ul-og", &[]),
                line("ul-oas", "ul-oas", &[]),
                line("ul-enog", "ul-enog", &[]),
                line("ul-og B", "ul-og", &["ul_corrected_gradient=true"]),
                line("ul-oas B", "ul-oas", &["ul_corrected_gradient=true"]),
            ],
            measure: Measure::ClosedForm {
                num: "period",
                den: "period_theory",
            },
            reference_note: "Reference: the Kirchhoff thin-plate period of the simply supported \
                plate's mode (1, 1) (computed by the case; H/L = 1/40, so shear and rotary \
                inertia change it by well under 1 %). The resolution is H/dp (3 = the paper's \
                coarsest, 43,200 particles). `ul-og` and `ul-oas` take the velocity gradient \
                of eq 14 as printed (their default, the energy-consistent form); the `B` lines \
                multiply it by the correction matrix (eq 26, `ul_corrected_gradient = true`), \
                which makes it exact for a linear velocity field. Without `B` the gradient is \
                underestimated wherever a free surface cuts a particle's kernel support; \
                through a plate three particles thick that is every particle but the middle \
                row, so the bending field's ∂v_x/∂z no longer cancels ∂v_z/∂x, and the plate \
                carries a spurious transverse shear strain, stiff against bending by about \
                (L/H)²: at H/dp 3 it keeps its (1, 1) shape (snapshots) but swings 2.65 times \
                too fast. With `B` that stiffening is gone and what remains is the opposite \
                error of a plate two or three particles thick (too soft, the more so at H/dp 2, \
                where the period exceeds the simulated two thin-plate periods and no period is \
                measured; the table of every run gives its amplitude, about v T/(2π) for the \
                initial 1 m/s, i.e. T ≈ 0.07–0.08 s). The `B` runs were timed on a day when \
                this machine ran the TL plate anchor 1.65 times slower (7.0 against 4.25 s): \
                compare their cost with the other lines by work, not CPU seconds. The near-exact OG and \
                OAS periods at H/dp 2 without `B` are these two errors cancelling, not \
                accuracy. ENOG's shear force is a Laplacian of the velocity (eq 18–19), with \
                no gradient to lose that cancellation.",
        },
    ]
}

/// One severity sweep of the stability map.
pub(super) struct Sweep {
    pub(super) key: &'static str,
    pub(super) title: &'static str,
    pub(super) case: &'static str,
    pub(super) methods: &'static [&'static str],
    pub(super) fixed: &'static [&'static str],
    pub(super) parameter: &'static str,
    pub(super) quick: &'static [f64],
    pub(super) full: &'static [f64],
    /// Settings `--quick` adds to every run of the sweep (a coarser or shorter run, so the
    /// quick map stays within minutes); its runs are stored apart (`…-quick`) and shown only
    /// where the sweep has no run at the full settings.
    pub(super) quick_fixed: &'static [&'static str],
    /// What to know when reading the map (printed under its title; empty: nothing).
    pub(super) note: &'static str,
}

/// The note of the large-deformation maps (punching, pulling).
const LARGE_DEFORMATION: &str =
    "The disorder indicator is measured against the reference spacing, so under a \
                stretch λ the same relative zigzag reads about λ times larger, and the sharp \
                gradients at the grips, the punch corners and the neck are non-affine at the \
                kernel scale too: the 0.25 limit, set on small-deformation pictures, marks all \
                but the mildest cells here. Read these maps by comparing methods at equal \
                severity. Calibration from the stored validation pictures (docs/validation.md, \
                TL-SPH: extreme deformation, H/dp 30): TL-HF's strip pulled to stretch 6 is \
                visibly ordered at 1.20 while TL's rows pair up at 7.32; punched to 50 %, TL-HF \
                reads 1.31, TL-GM 2.72 and TL 12.7.";

pub(super) fn sweeps() -> Vec<Sweep> {
    const PLATE: &[&str] = &["tl", "tl-hf", "tl-gm", "ul-og", "ul-oas", "ul-enog"];
    const TL: &[&str] = &["tl", "tl-hf", "tl-gm"];
    vec![
        Sweep {
            key: "plate-vf",
            title: "2D plate, initial tip speed v_f (H/dp 10, to 1 s)",
            case: "oscillating-plate-2d",
            methods: PLATE,
            fixed: &["end_time=1.0"],
            parameter: "vf",
            // Not 0.3 in --quick: UL-ENOG there (H/dp 5) took 1.85 million advection steps,
            // 694 s, its dual stepping down to one acoustic sub-step per step.
            quick: &[0.05, 0.15],
            full: &[0.01, 0.05, 0.1, 0.15, 0.2, 0.3],
            quick_fixed: &["resolution=5", "end_time=0.5"],
            note: "",
        },
        Sweep {
            key: "plate-nu",
            title: "2D plate, Poisson's ratio ν (H/dp 10, v_f 0.05, to 0.3 s: the sound speed, \
                and with it the number of steps, grows as 1/√(1 − 2ν))",
            case: "oscillating-plate-2d",
            methods: PLATE,
            fixed: &["end_time=0.3"],
            parameter: "nu",
            quick: &[0.3, 0.45, 0.49],
            full: &[0.3, 0.4, 0.45, 0.49, 0.499, 0.4999],
            quick_fixed: &["resolution=5"],
            note: "",
        },
        Sweep {
            key: "plate-cfl",
            title:
                "2D plate, TL CFL number of eq 33 (H/dp 10, v_f 0.05, to 1 s; allowed 0 < cfl < 1)",
            case: "oscillating-plate-2d",
            methods: TL,
            fixed: &["end_time=1.0"],
            parameter: "cfl",
            quick: &[0.3, 0.9, 1.2],
            full: &[0.3, 0.6, 0.8, 0.9, 0.99, 1.2],
            quick_fixed: &["resolution=5", "end_time=0.5"],
            note: "",
        },
        Sweep {
            key: "plate-cfl-ul",
            title: "2D plate, UL acoustic CFL of eq 22 (H/dp 10, v_f 0.05, to 1 s; allowed < 1)",
            case: "oscillating-plate-2d",
            methods: &["ul-og", "ul-oas", "ul-enog"],
            fixed: &["end_time=1.0"],
            parameter: "ul_cfl_acoustic",
            quick: &[0.3, 0.9, 1.2],
            full: &[0.3, 0.4, 0.6, 0.8, 0.99, 1.2],
            quick_fixed: &["resolution=5", "end_time=0.5"],
            note: "",
        },
        Sweep {
            key: "rings-v0",
            title: "Colliding rings, impact speed v0/c0 (UL, dp 1 mm, contact on)",
            case: "colliding-rings-2d",
            methods: &["ul-og", "ul-oas", "ul-enog"],
            fixed: &["v0_unit=c0", "contact=true"],
            parameter: "v0",
            quick: &[0.04, 0.1],
            full: &[0.04, 0.06, 0.08, 0.1, 0.12, 0.14],
            quick_fixed: &["dp=0.002"],
            note: "",
        },
        Sweep {
            key: "punch-compression",
            title: "Punching strip, final compression (TL, H/dp 15, paper's punches, centre free)",
            case: "punching-strip-2d",
            methods: TL,
            fixed: &["resolution=15"],
            parameter: "compression",
            quick: &[0.2, 0.5],
            full: &[0.1, 0.2, 0.3, 0.4, 0.5, 0.6],
            quick_fixed: &[],
            note: LARGE_DEFORMATION,
        },
        Sweep {
            key: "pull-stretch",
            title: "Pulling strip, final stretch (TL, L/dp 15, clamped grips)",
            case: "pulling-strip-2d",
            methods: TL,
            fixed: &["resolution=15"],
            parameter: "stretch",
            quick: &[2.0, 6.0],
            full: &[2.0, 3.0, 4.0, 6.0, 8.0, 11.0],
            quick_fixed: &[],
            note: LARGE_DEFORMATION,
        },
        Sweep {
            key: "column-omega",
            title:
                "Twisting column, initial angular velocity Ω0 (rad/s; ν 0.49, 10×10×60, to 0.3 s)",
            case: "twisting-column-3d",
            methods: TL,
            fixed: &["nu=0.49", "end_time=0.3"],
            parameter: "omega0",
            quick: &[105.0, 400.0],
            full: &[105.0, 200.0, 300.0, 400.0, 500.0, 600.0],
            quick_fixed: &["end_time=0.1"],
            note: "",
        },
    ]
}
