//! # sph-scene: scenes from TOML files
//!
//! A scene file declares a whole run — bodies from shapes, their materials, one method, regions
//! for constraints, grips, loads and probes, rigid tools, the output schedule — so a new scene
//! needs no Rust. `sph run scene.toml` runs one; [`Scene::from_file`] and [`Scene::run`] do the
//! same from Rust, and build the scene with exactly the library calls a Rust program would make
//! (the tests check that both give bit-identical results).
//!
//! ```toml
//! name = "squeeze"
//! dimension = 2                 # 2 (plane strain) or 3
//! method = "tl-hf"              # tl, tl-hf, tl-gm, ul-og, ul-oas, ul-enog, mps
//! end_time = 2.5e-3
//!
//! [material]                    # one material for every body (or [[material]] tables,
//! law = "neo-hookean"           # each with a name that a body's material = "NAME" picks)
//! density = 1100.0              # neo-hookean, linear-elastic, saint-venant-kirchhoff,
//! youngs_modulus = 1e7          # kirchhoff-vol-dev, mooney-rivlin (UL uses the constants);
//! nu = 0.45                     # E and nu, or bulk_modulus and shear_modulus
//!
//! [numerics]                    # optional; the keys of the method's family (below)
//! dt_stretch = true
//!
//! [output]                      # optional
//! snapshot_interval = 1e-4      # default end_time/50 (0: first and last only)
//!
//! [[body]]
//! name = "block"
//! dp = 5e-4
//! shape = { box = { min = [-0.01, 0.0], max = [0.01, 0.01] } }
//! # layout = "polar"           # concentric layers for a 2D ball/shell or a 3D cylinder
//! # particles = "block.csv"    # instead of shape: x,y[,z],volume per line
//! # velocity = [0.0, -1.0]
//!
//! [[constraint]]
//! type = "fixed"                # fixed, velocity, components (a roller grip)
//! region = { box = { min = [-1.0, -1.0], max = [1.0, 5e-4] } }
//! name = "floor"                # named: its reaction force is recorded (/series/floor)
//!
//! [[tool]]                      # TL methods: rigid, frictionless
//! name = "punch"
//! shape = { box = { min = [-0.005, 0.01], max = [0.005, 0.011] } }
//! direction = [0.0, -1.0]
//! speed = 1.0
//! ramp_time = 2e-4
//! travel = 2e-3
//!
//! [relaxation]                  # TL methods: quasi-static pairwise damping
//! length = 0.01
//!
//! [[probe]]
//! name = "top"
//! at = [0.0, 0.01]
//! ```
//!
//! Every key, with its type, default, unit and the methods that honour it, is in
//! [`reference::keys`] (rendered into docs/user-guide.md, "Scene file reference"; a test keeps
//! the two and the types of [`spec`] in step). Beyond the example above: a `[parameters]`
//! table whose names `${…}` in any value uses (`dp = "${H / 20}"`, arithmetic included);
//! `amplitude` curves (ramp, smooth step, table, sine) on constraint velocities, gravity, point
//! loads, pressures and tool velocities; `type = "pressure"` loads on the surface particles of
//! a region; tools along a `path` or a `velocity` curve, turning about an axis (`rotation`);
//! every law's constants; probes of any output field. [`Scene::set`] (the command's `--set`)
//! overrides any key by its dotted path, or a parameter.
//!
//! Names (of the scene, which names the results file `<name>-<method>.h5`, and of bodies,
//! constraints, tools and probes, which name HDF5 groups) are names, not paths: 1 to 128 bytes
//! without `/`, `\`, control characters, and not `.` or `..`; each unique in its kind.
//!
//! Methods: every family runs any number of bodies, which meet through the method's body–body
//! contact (a TL method gives all its bodies one material; rigid parts are tools);
//! `[[contact]] bodies = ["strip"]` turns on a TL body's self-contact. A key a method cannot honour is
//! an error. Errors name the file, the line and the key, or the override that gave the value.
#![deny(missing_docs)]

/// glam, whose f64 vectors and matrices (`DVec2`, `DVec3`, `DMat2`, `DMat3`) every API here
/// takes: `use sph_scene::glam::DVec2;` needs no glam dependency of your own.
pub use glam;

mod build;
mod expr;
pub mod reference;
mod resolve;
pub mod spec;

pub use build::{numerics_keys, BodyPreview, BodyThickness, Preview, Scene, SceneError, METHODS};
pub use resolve::Override;
