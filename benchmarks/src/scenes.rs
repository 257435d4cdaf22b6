//! The scenes of the whole-run benchmarks (`case-timings`, `instructions`): each as `sph run`
//! arguments with its group and thread counts.

/// One scene: a label, the `sph run` arguments, the thread counts, and its group.
pub struct Scene {
    /// `anchors`, `extreme`, `memory` or `impacts` (`case-timings --only`).
    pub group: &'static str,
    /// The row's label in docs/performance.md.
    pub label: &'static str,
    /// The arguments of `sph run` (case, method, `--set` keys).
    pub args: Vec<&'static str>,
    /// The thread counts it is timed at.
    pub threads: &'static [usize],
    /// The SPHinXsys test that runs the same case (an anchor row), as its path in a SPHinXsys
    /// build directory (`benchmarks/sphinxsys/README.md`; `case-timings --sphinxsys`).
    pub sphinxsys: Option<&'static str>,
}

/// The scenes: the anchor cases of the performance target (the SPHinXsys comparison; the UL
/// plate also with its kernel data frozen over the advection step, the scheme of SPHinXsys's
/// test) and one row per extreme TL scene (a short, representative slice of each run).
pub fn scenes() -> Vec<Scene> {
    let both: &'static [usize] = &[1, 2];
    vec![
        Scene {
            group: "anchors",
            label: "2D oscillating plate, TL, H/dp 10, t = 1 s",
            args: vec![
                "oscillating-plate-2d",
                "--method",
                "tl",
                "--set",
                "h_over_dp=1.3",
                "--set",
                "end_time=1",
            ],
            threads: both,
            sphinxsys: Some(
                "tests/2d_examples/test_2d_oscillating_beam/bin/test_2d_oscillating_beam",
            ),
        },
        Scene {
            group: "anchors",
            label: "2D oscillating plate, UL-ENOG dual stepping, H/dp 10, t = 1 s",
            args: vec![
                "oscillating-plate-2d",
                "--method",
                "ul-enog",
                "--set",
                "h_over_dp=1.3",
                "--set",
                "end_time=1",
            ],
            threads: both,
            sphinxsys: Some(
                "tests/2d_examples/test_2d_oscillating_beam_UL/bin/test_2d_oscillating_beam_UL",
            ),
        },
        Scene {
            group: "anchors",
            label: "2D oscillating plate, UL-ENOG dual stepping, kernel data frozen over the \
                    advection step (SPHinXsys's scheme), H/dp 10, t = 1 s",
            args: vec![
                "oscillating-plate-2d",
                "--method",
                "ul-enog",
                "--set",
                "h_over_dp=1.3",
                "--set",
                "end_time=1",
                "--set",
                "refresh_kernel_data=false",
            ],
            threads: both,
            sphinxsys: Some(
                "tests/2d_examples/test_2d_oscillating_beam_UL/bin/test_2d_oscillating_beam_UL",
            ),
        },
        Scene {
            group: "anchors",
            label: "3D twisting column, TL-HF, 10×10×61, Ω0 400, t = 0.5 s",
            args: vec![
                "twisting-column-3d",
                "--method",
                "tl-hf",
                "--set",
                "h_over_dp=1.3",
                "--set",
                "resolution=10",
                "--set",
                "end_time=0.5",
                "--set",
                "nu=0.45",
                "--set",
                "omega0=400",
                "--set",
                "clamp_layers=1",
                "--set",
                "cfl=0.5",
            ],
            threads: both,
            sphinxsys: Some(
                "tests/3d_examples/test_3d_twisting_column/bin/test_3d_twisting_column",
            ),
        },
        Scene {
            group: "extreme",
            label: "punching strip, TL-HF, H/dp 30, to 50 %",
            args: vec!["punching-strip-2d", "--method", "tl-hf"],
            threads: &[2],
            sphinxsys: None,
        },
        Scene {
            group: "extreme",
            label: "pulling strip, TL-HF, L/dp 30, to stretch 2",
            args: vec![
                "pulling-strip-2d",
                "--method",
                "tl-hf",
                "--set",
                "stretch=2",
            ],
            threads: &[2],
            sphinxsys: None,
        },
        Scene {
            group: "extreme",
            label: "pulling cylinder, TL-HF, dp 0.1 mm, to stretch 1.5",
            args: vec![
                "pulling-cylinder-3d",
                "--method",
                "tl-hf",
                "--set",
                "stretch=1.5",
            ],
            threads: &[2],
            sphinxsys: None,
        },
        Scene {
            group: "extreme",
            label: "stent, point forces, TL-HF, dp = wall/3, to 0.02 ms",
            args: vec!["stent-3d", "--method", "tl-hf", "--set", "end_time=2e-5"],
            threads: &[2],
            sphinxsys: None,
        },
        memory_scene("stored"),
        memory_scene("recomputed"),
        Scene {
            group: "impacts",
            label: "colliding hollow balls 3D, UL-ENOG, dp 2 mm, v0 0.08 c0, to 8 ms",
            args: vec![
                "colliding-balls-3d",
                "--method",
                "ul-enog",
                "--set",
                "dp=0.002",
            ],
            threads: &[2],
            sphinxsys: None,
        },
        Scene {
            group: "impacts",
            label: "ball–plate 3D, UL-ENOG, dp 5 mm, v0 0.12 c0, to 2 ms",
            args: vec![
                "ball-plate-3d",
                "--method",
                "ul-enog",
                "--set",
                "dp=0.005",
                "--set",
                "end_time=0.002",
            ],
            threads: &[2],
            sphinxsys: None,
        },
        Scene {
            group: "impacts",
            label: "Hertz impact of two spheres, UL-ENOG, R/dp 10, whole contact",
            args: vec!["hertz-impact-3d", "--method", "ul-enog"],
            threads: &[2],
            sphinxsys: None,
        },
    ]
}

/// The memory row of 3D TL-HF above 1e5 particles with the reference pair data `pair_data`
/// (`stored` or `recomputed`): the 107,484-particle bending column, 0.03 s.
fn memory_scene(pair_data: &'static str) -> Scene {
    let (label, key) = match pair_data {
        "stored" => (
            "bending column 3D, TL-HF, H/dp 26, stored pair data, 0.03 s",
            "pair_data=stored",
        ),
        "recomputed" => (
            "bending column 3D, TL-HF, H/dp 26, recomputed pair data, 0.03 s",
            "pair_data=recomputed",
        ),
        other => unreachable!("pair data `{other}`: stored or recomputed"),
    };
    Scene {
        group: "memory",
        label,
        args: vec![
            "bending-column-3d",
            "--method",
            "tl-hf",
            "--set",
            "resolution=26",
            "--set",
            "end_time=0.03",
            "--set",
            "monitor_interval=0.03",
            "--set",
            key,
        ],
        threads: &[2],
        sphinxsys: None,
    }
}
