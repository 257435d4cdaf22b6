//! Issue 42: every new scene key against the same set-up built with the library, bit for bit
//! (final positions, and the series where there are some): parameters and overrides,
//! each amplitude curve on constraint velocities, gravity and point loads, surface pressure,
//! tool paths, velocity curves and rotation, the laws' options, probe fields.

use glam::{DVec2, DVec3};
use sph_core::pressure::{PressureFunction, SurfacePressure};
use sph_core::relaxation::PairwiseDamping;
use sph_core::surface::surface_of;
use sph_core::tool::{RigidTool, ToolMotion, ToolShape};
use sph_core::{Amplitude, Constraint, Constraints, Loads, Probe, Solver, TimeFunction, D2};
use sph_driver::{Run, RunOptions};
use sph_geometry::generate::{annulus_polar, Aabb, Lattice, ParticleSet};
use sph_materials::{
    DeviatorDimension, ElasticConstants, KirchhoffVolDev, MaterialModel, MooneyRivlinLike,
    NeoHookean,
};
use sph_output::{read_file, FileContents};
use sph_scene::Scene;
use sph_tl::{Shear, TlParams, TlSolver};
use std::path::{Path, PathBuf};

/// A 20 × 4 mm plate of 80 particles, TL-HF, to 1 ms.
const PLATE: &str = r#"dimension = 2
method = "tl-hf"
end_time = 1e-3

[material]
law = "neo-hookean"
density = 1000.0
youngs_modulus = 1e6
nu = 0.3

[[body]]
name = "plate"
dp = 1e-3
shape = { box = { min = [0.0, 0.0], max = [0.02, 0.004] } }
"#;

const END: f64 = 1e-3;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-scene-keys-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn parse(text: &str) -> Scene {
    Scene::parse(text, "s.toml", Path::new("."), "s").unwrap()
}

/// The scene's results file.
fn run_scene(scene: &Scene, dir: &Path, name: &str) -> FileContents {
    let options = RunOptions {
        output: Some(dir.join(name)),
        ..RunOptions::default()
    };
    let (record, _) = scene.run(&options).unwrap();
    assert!(record.failure.is_none(), "{name}: {:?}", record.failure);
    read_file(record.file.unwrap()).unwrap()
}

/// The library run's results file.
fn run_rust(solver: &mut dyn Solver<D2>, dir: &Path, name: &str) -> FileContents {
    let (record, _) = Run::until(END)
        .write_to(dir.join(name))
        .execute(solver)
        .unwrap();
    assert!(record.failure.is_none(), "{name}: {:?}", record.failure);
    read_file(record.file.unwrap()).unwrap()
}

/// The final positions' bits.
fn last_positions(c: &FileContents) -> Vec<u64> {
    let last = c.snapshots.last().unwrap();
    let x = last.dataset("position").unwrap().as_f64().unwrap();
    x.iter().map(|v| v.to_bits()).collect()
}

/// Same steps, same final positions, same series and probes, bit for bit; and the body moved.
fn assert_identical(a: &FileContents, b: &FileContents, what: &str) {
    assert_eq!(a.snapshots.len(), b.snapshots.len(), "{what}: snapshots");
    assert_eq!(
        a.snapshots.last().unwrap().step,
        b.snapshots.last().unwrap().step,
        "{what}: steps"
    );
    assert_eq!(
        last_positions(a),
        last_positions(b),
        "{what}: final positions"
    );
    assert_eq!(a.series, b.series, "{what}: series");
    assert_eq!(a.probes, b.probes, "{what}: probes");
    assert_ne!(
        last_positions(a),
        {
            let first = a.snapshots[0]
                .dataset("position")
                .unwrap()
                .as_f64()
                .unwrap();
            first.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        },
        "{what}: nothing moved"
    );
}

fn plate_set() -> ParticleSet<D2> {
    let b = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.02, 0.004)).unwrap();
    ParticleSet::fill(&Lattice::new(1e-3, DVec2::ZERO).unwrap(), &b).unwrap()
}

fn law() -> NeoHookean {
    NeoHookean::new(ElasticConstants::from_youngs(1e6, 0.3, 1000.0).unwrap())
}

fn tl(set: ParticleSet<D2>) -> TlSolver<D2, NeoHookean> {
    TlSolver::new(
        set.into_body(1e-3),
        law(),
        Shear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap()
}

/// The region `[−1, −1] .. [x, 1]`: the left end of the plate.
fn left_end(set: &ParticleSet<D2>, x: f64) -> Vec<u32> {
    set.inside(&Aabb::<D2>::new(DVec2::new(-1.0, -1.0), DVec2::new(x, 1.0)).unwrap())
}

#[test]
fn parameters_and_overrides_give_the_scene_written_out() {
    let dir = scratch("parameters");
    // The plate written with parameters (in any order; one defined through others).
    let with_parameters = r#"dimension = 2
method = "${m}"
end_time = "${5 * T / 5}"

[parameters]
dp = "${H / 4}"
H = 0.004
L = 0.02
T = 1e-3
m = "tl"
label = "plate-${H}"

[material]
density = 1000.0
youngs_modulus = "${1e6}"
nu = 0.3

[[body]]
name = "${label}"
dp = "${dp}"
shape = { box = { min = [0.0, 0.0], max = ["${L}", "${H}"] } }
velocity = [0.0, "${sqrt(4)}"]
"#;
    let scene = parse(with_parameters)
        .set("H", "0.006")
        .unwrap()
        .set("method", "tl-hf")
        .unwrap()
        .set("material.nu", "0.45")
        .unwrap()
        .set("body[plate-0.006].velocity", "[0.5, 1.0]")
        .unwrap()
        .set("numerics.cfl", "0.5")
        .unwrap()
        .set("body[0].shape.box.min.0", "0.001")
        .unwrap();
    assert_eq!(scene.method(), "tl-hf");
    let written = r#"dimension = 2
method = "tl-hf"
end_time = 1e-3

[numerics]
cfl = 0.5

[material]
density = 1000.0
youngs_modulus = 1e6
nu = 0.45

[[body]]
name = "plate-0.006"
dp = 0.0015
shape = { box = { min = [0.001, 0.0], max = [0.02, 0.006] } }
velocity = [0.5, 1.0]
"#;
    let a = run_scene(&scene, &dir, "parameters");
    let b = run_scene(&parse(written), &dir, "written");
    assert_identical(&a, &b, "parameters and overrides");
    // The meta records the overrides and the parameters' values.
    assert_eq!(a.meta["overrides"][0], "H=0.006");
    assert_eq!(a.meta["parameters"]["dp"], 0.0015);
    assert_eq!(a.meta["parameters"]["label"], "plate-0.006");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The four curves, as a scene writes them and as the library builds them.
fn curves() -> Vec<(&'static str, Amplitude)> {
    vec![
        (
            "{ ramp = { start = 1e-4, duration = 5e-4 } }",
            Amplitude::ramp(1e-4, 5e-4).unwrap(),
        ),
        (
            "{ smooth-step = { duration = 8e-4 } }",
            Amplitude::smooth_step(0.0, 8e-4).unwrap(),
        ),
        (
            "{ table = [[0.0, 0.0], [3e-4, 1.0], [6e-4, -0.5]] }",
            Amplitude::table(vec![(0.0, 0.0), (3e-4, 1.0), (6e-4, -0.5)]).unwrap(),
        ),
        (
            "{ sine = { frequency = 2000.0, amplitude = 0.5, phase = 0.3, offset = 0.25 } }",
            Amplitude::sine(2000.0, 0.5, 0.3, 0.25).unwrap(),
        ),
    ]
}

#[test]
fn amplitude_curves_scale_grips_gravity_and_point_loads() {
    let dir = scratch("amplitudes");
    for (k, (toml, amplitude)) in curves().into_iter().enumerate() {
        let text = format!(
            r#"{PLATE}
[[constraint]]
type = "velocity"
name = "grip"
region = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}
velocity = [-0.5, 0.2]
amplitude = {toml}

[[load]]
type = "gravity"
acceleration = [0.0, -200.0]
amplitude = {toml}

[[load]]
type = "point"
force = [0.0, 3.0]
at = [0.02, 0.004]
amplitude = {toml}
"#
        );
        let set = plate_set();
        let (grip, n) = (left_end(&set, 1e-3), set.len());
        let tip = set.nearest(DVec2::new(0.02, 0.004)).unwrap() as u32;
        let mut constraints = Constraints::new();
        let v = TimeFunction::scaled(DVec2::new(-0.5, 0.2), amplitude.clone());
        constraints
            .push_named(
                "grip",
                Constraint::PrescribedVelocity {
                    particles: grip,
                    velocity: v,
                },
                n,
            )
            .unwrap();
        let mut loads = Loads::new();
        let g = DVec2::new(0.0, -200.0);
        loads.add_body_acceleration(None, TimeFunction::scaled(g, amplitude.clone()));
        loads.add_point_force(tip, TimeFunction::scaled(DVec2::new(0.0, 3.0), amplitude));
        let mut solver = tl(set)
            .with_constraints(constraints)
            .with_loads(loads)
            .with_tools(Vec::new())
            .unwrap()
            .with_probes(Vec::new(), 0.0)
            .unwrap();
        let a = run_scene(&parse(&text), &dir, &format!("scene{k}"));
        let b = run_rust(&mut solver, &dir, &format!("rust{k}"));
        assert_identical(&a, &b, toml);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_surface_pressure_from_a_scene_is_the_library_call() {
    let dir = scratch("pressure");
    let text = format!(
        r#"{PLATE}
[[constraint]]
type = "fixed"
region = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}

[[load]]
type = "pressure"
region = {{ box = {{ min = [0.0, 0.002], max = [1.0, 1.0] }} }}
pressure = 2e4
amplitude = {{ smooth-step = {{ duration = 5e-4 }} }}

[[load]]
type = "pressure"
region = {{ box = {{ min = [0.0195, -1.0], max = [1.0, 1.0] }} }}
pressure = -5e3
area = 0.004
normal = [1.0, 0.0]
"#
    );
    let set = plate_set();
    let (clamp, n) = (left_end(&set, 1e-3), set.len());
    // The top half: its surface particles (the top row and the ends of the rows below),
    // each with its own normal and its volume over dp.
    let top = set.inside(&Aabb::<D2>::new(DVec2::new(0.0, 0.002), DVec2::new(1.0, 1.0)).unwrap());
    let surface = surface_of::<D2>(set.positions(), 1e-3, &top).unwrap();
    let on_top = SurfacePressure {
        particles: surface.iter().map(|p| p.index).collect(),
        normals: Some(surface.iter().map(|p| p.normal).collect()),
        areas: Some(
            surface
                .iter()
                .map(|p| set.volumes()[p.index as usize] / 1e-3)
                .collect(),
        ),
        pressure: PressureFunction::scaled(2e4, Amplitude::smooth_step(0.0, 5e-4).unwrap()),
    };
    let end = set.inside(&Aabb::<D2>::new(DVec2::new(0.0195, -1.0), DVec2::new(1.0, 1.0)).unwrap());
    let surface = surface_of::<D2>(set.positions(), 1e-3, &end).unwrap();
    let m = surface.len();
    let pulled = SurfacePressure {
        particles: surface.iter().map(|p| p.index).collect(),
        normals: Some(vec![DVec2::X; m]),
        areas: Some(vec![0.004 / m as f64; m]),
        pressure: PressureFunction::constant(-5e3),
    };
    let mut solver = tl(set)
        .with_surface_pressure(on_top)
        .unwrap()
        .with_surface_pressure(pulled)
        .unwrap()
        .with_constraints(Constraints::fixed(clamp, n).unwrap())
        .with_loads(Loads::new())
        .with_tools(Vec::new())
        .unwrap()
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let a = run_scene(&parse(&text), &dir, "scene");
    let b = run_rust(&mut solver, &dir, "rust");
    assert_identical(&a, &b, "surface pressure");
    // The same on a ring with MPS, estimated normals on a curved surface.
    let ring = r#"dimension = 2
method = "mps"
end_time = 1e-3

[material]
law = "mooney-rivlin"
density = 1000.0
youngs_modulus = 1e6
nu = 0.3
c2_fraction = 0.2

[[body]]
name = "ring"
dp = 1e-3
layout = "polar"
shape = { shell = { centre = [0.0, 0.0], inner = 0.005, outer = 0.01 } }

[[load]]
type = "pressure"
region = { ball = { centre = [0.0, 0.0], radius = 0.006 } }
pressure = 1e4
"#;
    let set = annulus_polar(DVec2::ZERO, 0.005, 0.01, 1e-3).unwrap();
    let inner = set.inside(&sph_geometry::generate::FnShape::new(
        (DVec2::splat(-0.006), DVec2::splat(0.006)),
        |x: DVec2| x.length() <= 0.006,
    ));
    let surface = surface_of::<D2>(set.positions(), 1e-3, &inner).unwrap();
    let sp = SurfacePressure {
        particles: surface.iter().map(|p| p.index).collect(),
        normals: Some(surface.iter().map(|p| p.normal).collect()),
        areas: Some(
            surface
                .iter()
                .map(|p| set.volumes()[p.index as usize] / 1e-3)
                .collect(),
        ),
        pressure: PressureFunction::constant(1e4),
    };
    let constants = ElasticConstants::from_youngs(1e6, 0.3, 1000.0).unwrap();
    let law =
        MaterialModel::MooneyRivlin(MooneyRivlinLike::from_constants(constants, 0.2).unwrap());
    let mut solver = sph_mps::MpsSolver::new(set.into_body(1e-3), law, Default::default())
        .unwrap()
        .with_surface_pressure(sp)
        .unwrap()
        .with_constraints(Constraints::new())
        .with_loads(Loads::new())
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let a = run_scene(&parse(ring), &dir, "ring-scene");
    let b = run_rust(&mut solver, &dir, "ring-rust");
    assert_identical(&a, &b, "MPS ring pressure");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tools_move_along_paths_and_velocity_curves_and_rotate() {
    let dir = scratch("tools");
    let text = format!(
        r#"{PLATE}
[[constraint]]
type = "fixed"
region = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}

[[tool]]
name = "pusher"
shape = {{ ball = {{ centre = [0.015, 0.007], radius = 0.003 }} }}
path = [[0.0, 0.0, 0.0], [4e-4, 0.0, -5e-4], [1e-3, 1e-3, -5e-4]]

[[tool]]
name = "paddle"
shape = {{ box = {{ min = [0.008, 0.0045], max = [0.012, 0.0055] }} }}
velocity = [0.0, -1.0]
amplitude = {{ ramp = {{ duration = 2e-4 }} }}
rotation = {{ centre = [0.01, 0.005], angular_velocity = 300.0, amplitude = {{ sine = {{ frequency = 1000.0 }} }} }}
"#
    );
    let set = plate_set();
    let (clamp, n) = (left_end(&set, 1e-3), set.len());
    let pusher = RigidTool::new(
        "pusher",
        ToolShape::ball(DVec2::new(0.015, 0.007), 0.003).unwrap(),
        ToolMotion::path(vec![
            (0.0, DVec2::ZERO),
            (4e-4, DVec2::new(0.0, -5e-4)),
            (1e-3, DVec2::new(1e-3, -5e-4)),
        ])
        .unwrap(),
    );
    let paddle = RigidTool::new(
        "paddle",
        ToolShape::cuboid(DVec2::new(0.008, 0.0045), DVec2::new(0.012, 0.0055)).unwrap(),
        ToolMotion::translating(
            DVec2::new(0.0, -1.0),
            Some(Amplitude::ramp(0.0, 2e-4).unwrap()),
        )
        .unwrap()
        .rotating(
            DVec2::new(0.01, 0.005),
            DVec3::Z,
            300.0,
            Some(Amplitude::sine(1000.0, 1.0, 0.0, 0.0).unwrap()),
        )
        .unwrap(),
    );
    let mut solver = tl(set)
        .with_constraints(Constraints::fixed(clamp, n).unwrap())
        .with_loads(Loads::new())
        .with_tools(vec![pusher, paddle])
        .unwrap()
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let a = run_scene(&parse(&text), &dir, "scene");
    let b = run_rust(&mut solver, &dir, "rust");
    assert_identical(&a, &b, "tools");
    // Both tools touched the plate, and their series carry the new columns.
    let pusher = &a.series["pusher"];
    assert!(pusher.columns["contacts"].iter().any(|&c| c > 0.0));
    assert_eq!(*pusher.columns["displacement_x"].last().unwrap(), 1e-3);
    let paddle = &a.series["paddle"];
    assert!(paddle.columns["contacts"].iter().any(|&c| c > 0.0));
    assert!(paddle.columns["angle"].iter().any(|&x| x > 0.01));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_law_option_is_the_library_law() {
    let dir = scratch("laws");
    let constants = ElasticConstants::from_youngs(1e6, 0.3, 1000.0).unwrap();
    let cases: Vec<(&str, MaterialModel)> = vec![
        (
            "law = \"mooney-rivlin\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\nc2_fraction = 0.3",
            MaterialModel::MooneyRivlin(MooneyRivlinLike::from_constants(constants, 0.3).unwrap()),
        ),
        (
            "law = \"mooney-rivlin\"\ndensity = 1000.0\nc1 = 3e5\nc2 = 5e4\nlambda = 4e5",
            MaterialModel::MooneyRivlin(MooneyRivlinLike::new(3e5, 5e4, 4e5, 1000.0).unwrap()),
        ),
        (
            "law = \"kirchhoff-vol-dev\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3\ndeviator = \"embedded-3d\"",
            MaterialModel::KirchhoffVolDev(KirchhoffVolDev::with_deviator(
                constants,
                DeviatorDimension::Embedded3d,
            )),
        ),
    ];
    for (k, (material, model)) in cases.into_iter().enumerate() {
        let text = PLATE.replace(
            "law = \"neo-hookean\"\ndensity = 1000.0\nyoungs_modulus = 1e6\nnu = 0.3",
            material,
        );
        let text = format!("{text}\n[[constraint]]\ntype = \"fixed\"\nregion = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}\n\n[[load]]\ntype = \"gravity\"\nacceleration = [0.0, -500.0]\n");
        let set = plate_set();
        let (clamp, n) = (left_end(&set, 1e-3), set.len());
        let mut loads = Loads::new();
        loads.add_body_acceleration(None, TimeFunction::constant(DVec2::new(0.0, -500.0)));
        let mut solver = TlSolver::new(
            set.into_body(1e-3),
            model,
            Shear::hourglass_free(),
            TlParams::default(),
        )
        .unwrap()
        .with_constraints(Constraints::fixed(clamp, n).unwrap())
        .with_loads(loads)
        .with_tools(Vec::new())
        .unwrap()
        .with_probes(Vec::new(), 0.0)
        .unwrap();
        let a = run_scene(&parse(&text), &dir, &format!("scene{k}"));
        let b = run_rust(&mut solver, &dir, &format!("rust{k}"));
        assert_identical(&a, &b, material);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn probe_fields_from_a_scene_are_the_library_probes() {
    let dir = scratch("probes");
    let text = format!(
        r#"{PLATE}
[[constraint]]
type = "fixed"
region = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}

[[load]]
type = "gravity"
acceleration = [0.0, -500.0]

[[probe]]
name = "tip"
at = [0.02, 0.002]
fields = ["von_mises", "displacement", "deformation_gradient", "jacobian", "disorder"]
"#
    );
    let set = plate_set();
    let (clamp, n) = (left_end(&set, 1e-3), set.len());
    let body = set.into_body(1e-3);
    let probe = Probe::at("tip", DVec2::new(0.02, 0.002), &body)
        .unwrap()
        .with_fields(&[
            "von_mises",
            "displacement",
            "deformation_gradient",
            "jacobian",
            "disorder",
        ]);
    let mut loads = Loads::new();
    loads.add_body_acceleration(None, TimeFunction::constant(DVec2::new(0.0, -500.0)));
    let mut solver = TlSolver::new(body, law(), Shear::hourglass_free(), TlParams::default())
        .unwrap()
        .with_constraints(Constraints::fixed(clamp, n).unwrap())
        .with_loads(loads)
        .with_tools(Vec::new())
        .unwrap()
        .with_probes(vec![probe], 0.0)
        .unwrap();
    let a = run_scene(&parse(&text), &dir, "scene");
    let b = run_rust(&mut solver, &dir, "rust");
    assert_identical(&a, &b, "probe fields");
    let tip = &a.probes["tip"];
    assert_eq!(
        tip.field("deformation_gradient").unwrap().shape()[1..],
        [3, 3]
    );
    assert!(tip.field("von_mises").unwrap().as_f64().unwrap()[5] > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The relaxation and a `[numerics]` key set by `--set` on a file that has neither table.
#[test]
fn overrides_add_tables_the_file_lacks() {
    let dir = scratch("added");
    let scene = parse(PLATE)
        .set("relaxation.length", "0.004")
        .unwrap()
        .set("numerics.dt_stretch", "true")
        .unwrap();
    let params = TlParams {
        stretch_limited_dt: true,
        ..TlParams::default()
    };
    let scene = scene.set("body.plate.velocity", "[0.0, 1.0]").unwrap();
    let set = plate_set();
    let relax =
        PairwiseDamping::new(PairwiseDamping::viscosity_for(1.0, 1000.0, 1e6, 0.004)).unwrap();
    let mut solver = TlSolver::new(
        set.into_body(1e-3).with_velocity(|_| DVec2::new(0.0, 1.0)),
        law(),
        Shear::hourglass_free(),
        params,
    )
    .unwrap()
    .with_constraints(Constraints::new())
    .with_loads(Loads::new())
    .with_tools(Vec::new())
    .unwrap()
    .with_probes(Vec::new(), 0.0)
    .unwrap()
    .with_relaxation(relax)
    .unwrap();
    let a = run_scene(&scene, &dir, "scene");
    let b = run_rust(&mut solver, &dir, "rust");
    assert_identical(&a, &b, "added tables");
    let _ = std::fs::remove_dir_all(&dir);
}

/// One line, naming the file, the line and the key (or the override), for every bad value
/// of the new keys.
#[test]
fn bad_values_in_the_new_keys_are_one_line_errors_naming_file_line_and_key() {
    let base = format!(
        "{PLATE}\n[[constraint]]\ntype = \"velocity\"\nregion = {{ box = {{ min = [-1.0, -1.0], max = [1e-3, 1.0] }} }}\nvelocity = [0.0, 1.0]\n"
    );
    // The plate ends on line 14 (line 15 is blank), the constraint's lines: 16
    // [[constraint]], 17 type, 18 region, 19 velocity; the next key is on line 20.
    let with = |extra: &str| format!("{base}{extra}\n");
    let cases: Vec<(String, &str, &[&str])> = vec![
        (with("amplitude = { ramp = { duration = 0.0 } }"), "s.toml:20: constraint[0].amplitude", &["ramp duration", "> 0"]),
        (with("amplitude = { table = [[0.0, 0.0], [0.0, 1.0]] }"), "s.toml:20: constraint[0].amplitude", &["table point 1 time"]),
        (with("amplitude = { table = [[0.0, 0.0, 1.0]] }"), "s.toml:20: constraint[0].amplitude", &["expected [time, value]"]),
        (with("amplitude = { step = { duration = 1.0 } }"), "s.toml:20:", &["unknown variant `step`"]),
        (with("amplitude = { sine = { frequency = -1.0 } }"), "s.toml:20: constraint[0].amplitude", &["sine frequency"]),
        (
            base.replace("type = \"velocity\"", "type = \"fixed\"").replace("velocity = [0.0, 1.0]\n", "amplitude = { ramp = { duration = 1.0 } }\n"),
            "s.toml:19: constraint[0].amplitude",
            &["fixed constraint"],
        ),
        (format!("{PLATE}\n[[load]]\ntype = \"pressure\"\npressure = 1e3\n"), "s.toml:17: load[0].region", &["needs region"]),
        (
            format!("{PLATE}\n[[load]]\ntype = \"pressure\"\nregion = {{ ball = {{ centre = [0.0, 0.0], radius = 0.005 }} }}\npressure = 1e3\narea = -1.0\n"),
            "s.toml:20: load[0].area",
            &["> 0"],
        ),
        (
            format!("{PLATE}\n[[load]]\ntype = \"pressure\"\nregion = {{ ball = {{ centre = [0.0, 0.0], radius = 0.005 }} }}\npressure = 1e3\n").replace("tl-hf", "ul-enog"),
            "s.toml:17: load[0].type",
            &["tl, tl-hf, tl-gm and mps"],
        ),
        (
            format!("{PLATE}\n[[load]]\ntype = \"pressure\"\nregion = {{ ball = {{ centre = [1.0, 1.0], radius = 0.005 }} }}\npressure = 1e3\n"),
            "s.toml:18: load[0].region",
            &["no particle"],
        ),
        (
            format!("{PLATE}\n[[load]]\ntype = \"gravity\"\nacceleration = [0.0, -9.81]\npressure = 1e3\n"),
            "s.toml:19: load[0].pressure",
            &["not a key of a gravity load"],
        ),
        (
            format!("{PLATE}\n[[tool]]\nname = \"t\"\nshape = {{ ball = {{ centre = [0.0, 0.1], radius = 0.01 }} }}\npath = [[0.0, 0.0]]\n"),
            "s.toml:19: tool[0].path",
            &["expected [time, ux, uy]"],
        ),
        (
            format!("{PLATE}\n[[tool]]\nname = \"t\"\nshape = {{ ball = {{ centre = [0.0, 0.1], radius = 0.01 }} }}\npath = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]\n"),
            "s.toml:19: tool[0].path",
            &["waypoint 1 time"],
        ),
        (
            format!("{PLATE}\n[[tool]]\nname = \"t\"\nshape = {{ ball = {{ centre = [0.0, 0.1], radius = 0.01 }} }}\ndirection = [0.0, -1.0]\npath = [[0.0, 0.0, 0.0]]\n"),
            "s.toml:20: tool[0].path",
            &["direction and path were both given"],
        ),
        (
            format!("{PLATE}\n[[tool]]\nname = \"t\"\nshape = {{ ball = {{ centre = [0.0, 0.1], radius = 0.01 }} }}\nrotation = {{ centre = [0.0, 0.0], axis = [1.0, 0.0, 0.0], angular_velocity = 1.0 }}\n"),
            "s.toml:19: tool[0].rotation",
            &["the z axis"],
        ),
        (
            format!("{PLATE}\n[[tool]]\nname = \"t\"\nshape = {{ ball = {{ centre = [0.0, 0.1], radius = 0.01 }} }}\namplitude = {{ ramp = {{ duration = 1.0 }} }}\n"),
            "s.toml:19: tool[0].amplitude",
            &["give velocity too"],
        ),
        (PLATE.replace("nu = 0.3", "nu = 0.3\nc2_fraction = 0.2"), "s.toml:10: material.c2_fraction", &["mooney-rivlin"]),
        (
            PLATE.replace("neo-hookean", "mooney-rivlin").replace("nu = 0.3", "nu = 0.3\nc2_fraction = 1.5"),
            "s.toml:10: material.c2_fraction",
            &["0 <= c2_fraction < 1"],
        ),
        (
            PLATE.replace("neo-hookean", "kirchhoff-vol-dev").replace("nu = 0.3", "nu = 0.3\ndeviator = \"2d\""),
            "s.toml:10: material.deviator",
            &["spatial, embedded-3d"],
        ),
        (
            PLATE.replace("neo-hookean", "mooney-rivlin").replace("youngs_modulus = 1e6\nnu = 0.3", "c1 = 1e5"),
            "s.toml:8: material",
            &["all of c1, c2 and lambda"],
        ),
        (
            format!("{PLATE}\n[[probe]]\nname = \"p\"\nat = [0.0, 0.0]\nfields = [\"pressure\"]\n"),
            "s.toml:19: probe[0].fields",
            &["`pressure`", "von_mises"],
        ),
        (PLATE.replace("dp = 1e-3", "dp = \"${H / 4}\""), "s.toml:13: body[0].dp", &["unknown parameter `H`"]),
        (
            PLATE.replace("dp = 1e-3", "dp = \"${H / 0}\"").replace("[material]", "[parameters]\nH = 1.0\n\n[material]"),
            "s.toml:16: body[0].dp",
            &["not a finite number"],
        ),
        (
            PLATE.replace("[material]", "[parameters]\nend_time = 1.0\n\n[material]"),
            "s.toml:6: parameters.end_time",
            &["a key of the scene itself"],
        ),
        (
            PLATE.replace("[material]", "[parameters]\nsqrt = 1.0\n\n[material]"),
            "s.toml:6: parameters.sqrt",
            &["not a function"],
        ),
        (
            PLATE.replace("[material]", "[parameters]\na = \"${b}\"\nb = \"${2 * a}\"\n\n[material]"),
            "s.toml:6: parameters.a",
            &["defined through itself"],
        ),
        (PLATE.replace("end_time = 1e-3", "end_time = \"${2 +}\""), "s.toml:3: end_time", &["ends too early"]),
    ];
    for (text, prefix, words) in cases {
        let e = match Scene::parse(&text, "s.toml", Path::new("."), "s") {
            Err(e) => e.to_string(),
            Ok(s) => s.run(&RunOptions::default()).expect_err(prefix).to_string(),
        };
        assert!(e.starts_with(prefix), "expected {prefix}…, got: {e}");
        assert!(!e.contains('\n'), "more than one line: {e}");
        for w in words {
            assert!(e.contains(w), "{prefix}: no `{w}` in: {e}");
        }
    }
}

/// Overrides: what they name is checked, a bad value they give names the `--set`, and lines
/// after a key they insert keep the file's numbers.
#[test]
fn overrides_are_checked_and_errors_keep_the_file_s_lines() {
    let set = |key: &str, value: &str| {
        parse(PLATE)
            .set(key, value)
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = set("spacing", "1");
    assert!(
        e.contains("--set spacing=1") && e.contains("neither a key of the scene"),
        "{e}"
    );
    let e = set("body.slab.dp", "1e-3");
    assert!(
        e.contains("no body named `slab`; the body names: plate"),
        "{e}"
    );
    let e = set("body[3].dp", "1e-3");
    assert!(e.contains("index 3 is beyond them"), "{e}");
    let e = set("material", "1");
    assert!(e.contains("is a table"), "{e}");
    let e = set("body.plate.shape.box.min.x", "1");
    assert!(e.contains("index it by number"), "{e}");
    let e = set("parameters.H", "1");
    assert!(e.contains("no parameter `H`"), "{e}");
    // A bad value from an override: the override is named.
    let e = parse(PLATE)
        .set("material.nu", "0.7")
        .unwrap()
        .run(&RunOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("material.nu (from --set material.nu=0.7)"),
        "{e}"
    );
    // Inserted keys shift nothing: an error below them keeps its line.
    let e = parse(&PLATE.replace("dp = 1e-3", "dp = -1e-3"))
        .set("numerics.cfl", "0.5")
        .unwrap()
        .set("material.law", "\"neo-hookean\"")
        .unwrap()
        .set("name", "x")
        .unwrap()
        .run(&RunOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("s.toml:13: body[0].dp"), "{e}");
    // `--method` is an override of `method`.
    let e = parse(PLATE)
        .set("method", "sph")
        .unwrap()
        .run(&RunOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("method (from --set method=sph)") && e.contains("ul-enog"),
        "{e}"
    );
}

/// A parameter file of a case, given where a scene file is expected: what it is and how to run it.
#[test]
fn a_case_parameter_file_says_how_to_run_it() {
    let text = "case = \"oscillating-plate-2d\"\nmethod = \"tl-hf\"\nresolution = 10\n";
    let e = Scene::parse(text, "plate.toml", Path::new("."), "plate")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("plate.toml is a parameter file of case `oscillating-plate-2d`")
            && e.contains("sph run oscillating-plate-2d --config plate.toml"),
        "{e}"
    );
}

/// The numerics keys added with the reference: MPS `stabilisation` and `fit`, UL
/// `contact_scale` and `energy_budget`.
#[test]
fn the_new_numerics_keys_are_the_library_parameters() {
    let dir = scratch("numerics");
    let mps_text = PLATE.replace("tl-hf", "mps")
        + "\n[numerics]\nstabilisation = 3.0\nfit = \"quadratic\"\n\n[[constraint]]\ntype = \"fixed\"\nregion = { box = { min = [-1.0, -1.0], max = [1e-3, 1.0] } }\n\n[[load]]\ntype = \"gravity\"\nacceleration = [0.0, -500.0]\n";
    let set = plate_set();
    let (clamp, n) = (left_end(&set, 1e-3), set.len());
    let mut loads = Loads::new();
    loads.add_body_acceleration(None, TimeFunction::constant(DVec2::new(0.0, -500.0)));
    let params = sph_mps::MpsParams {
        stabilisation: 3.0,
        fit: sph_mps::Fit::Quadratic,
        ..Default::default()
    };
    let mut mps = sph_mps::MpsSolver::new(set.into_body(1e-3), law(), params)
        .unwrap()
        .with_constraints(Constraints::fixed(clamp, n).unwrap())
        .with_loads(loads)
        .with_probes(Vec::new(), 0.0)
        .unwrap();
    let a = run_scene(&parse(&mps_text), &dir, "mps-scene");
    let b = run_rust(&mut mps, &dir, "mps-rust");
    assert_identical(&a, &b, "MPS numerics");
    // Two UL blocks meeting, with a stiffer contact and no energy budget.
    let ul_text = PLATE.replace("tl-hf", "ul-enog").replace(
        "max = [0.02, 0.004] } }",
        "max = [0.01, 0.004] } }\nvelocity = [2.0, 0.0]\n\n[[body]]\nname = \"other\"\ndp = 1e-3\nshape = { box = { min = [0.0105, 0.0], max = [0.0205, 0.004] } }",
    ) + "\n[numerics]\ncontact_scale = 2.0\nenergy_budget = false\n";
    let left = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(0.01, 0.004)).unwrap();
    let right = Aabb::<D2>::new(DVec2::new(0.0105, 0.0), DVec2::new(0.0205, 0.004)).unwrap();
    let mut set = ParticleSet::fill(&Lattice::new(1e-3, DVec2::ZERO).unwrap(), &left).unwrap();
    let k = set.len();
    let other = ParticleSet::fill(
        &Lattice::new(1e-3, DVec2::new(0.0105, 0.0)).unwrap(),
        &right,
    )
    .unwrap();
    set.extend(&other).unwrap();
    let n = set.len();
    let mut v = vec![DVec2::new(2.0, 0.0); k];
    v.extend(vec![DVec2::ZERO; n - k]);
    let body_of: Vec<u32> = (0..n).map(|i| u32::from(i >= k)).collect();
    let params = sph_ul::UlParams {
        contact_scale: 2.0,
        energy_budget: false,
        ..Default::default()
    };
    let constants = ElasticConstants::from_youngs(1e6, 0.3, 1000.0).unwrap();
    let mut ul = sph_ul::UlSolver::new(
        set.into_body(1e-3).with_velocities(v),
        constants,
        sph_ul::Shear::NonNested {
            zeta: None,
            form: sph_ul::LaplacianForm::Conservative,
        },
        params,
    )
    .unwrap()
    .with_constraints(Constraints::new())
    .with_loads(Loads::new())
    .with_contact(body_of)
    .unwrap()
    .with_probes(Vec::new(), 0.0)
    .unwrap();
    let a = run_scene(&parse(&ul_text), &dir, "ul-scene");
    let b = run_rust(&mut ul, &dir, "ul-rust");
    assert_identical(&a, &b, "UL numerics");
    let _ = std::fs::remove_dir_all(&dir);
}
