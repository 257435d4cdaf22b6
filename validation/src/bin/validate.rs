//! Runs the validation cases and regenerates `docs/validation.md`.
//!
//! ```text
//! cargo run --release -p sph-validation --bin validate -- tl [--medium] [--fine] [--table2] [--force]
//! cargo run --release -p sph-validation --bin validate -- mps [--full] [--fine] [--force]
//! cargo run --release -p sph-validation --bin validate -- ul [--fine] [--force]
//! cargo run --release -p sph-validation --bin validate -- extreme [--short] [--force]
//! cargo run --release -p sph-validation --bin validate -- impacts [--fine] [--paper] [--force]
//! cargo run --release -p sph-validation --bin validate -- contact [--force]
//! cargo run --release -p sph-validation --bin validate -- geometry [--force]
//! cargo run --release -p sph-validation --bin validate -- report
//! ```
//! Runs are stored under `validation/results/` and reused unless `--force`; `report` only reads
//! them. Each run keeps its HDF5 file under `target/validation-results/<id>/` with the command
//! that recreates it. `--plan` (before the subcommand) prints the runs a selection would make,
//! one `id<TAB>command` a line, and runs nothing: long runs can be started from the shell with
//! that command (written to `target/validation-results/<id>/command.txt`), and a later
//! `validate` adopts the finished file instead of running again.

use clap::{Parser, Subcommand};
use sph_validation::{
    contact, extreme, geometry, h5report, hf_laplacian, impacts, mesh_physics, mps, mps_stab, plot,
    store, taylor, tl, tradeoff, ul, workspace_root,
};
use std::fmt::Write as _;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "validate", about = "Validation runs and docs/validation.md")]
struct Cli {
    /// Print the runs the selection would make (`id<TAB>command`), run nothing.
    #[arg(long, global = true)]
    plan: bool,
    /// Make only the runs whose id starts with this (ids as `--plan` prints them); the others
    /// are used when stored and skipped otherwise (tl, mps, ul, extreme, impacts, tradeoff).
    #[arg(long, global = true, value_name = "ID_PREFIX")]
    runs: Option<String>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// TL validation runs (H/dp = 10 always; --medium adds 20, --fine adds 40, --table2 the
    /// thin plate), then the report.
    Tl {
        /// Include H/dp = 20.
        #[arg(long)]
        medium: bool,
        /// Include H/dp = 40: Table 1 with TL-HF, every row (with `--table2`, Table 2 too).
        #[arg(long)]
        fine: bool,
        /// Include Table 2 (H = 0.01, TL-HF at H/dp = 20).
        #[arg(long)]
        table2: bool,
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// MPS validation runs (MPS paper §IV) and the stabilisation study, then the report.
    Mps {
        /// Include the slab at the paper's resolution (hours) and the H/dp = 20 plate with the
        /// frame clamp.
        #[arg(long)]
        full: bool,
        /// Include the stabilisation study's H/dp = 20 plate and H/dp = 40 static cantilever.
        #[arg(long)]
        fine: bool,
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// UL validation runs (UL paper §6), then the report.
    Ul {
        /// Include the 3D plate at H/dp = 5, all three modes (200,000 particles; 25–60 min each).
        #[arg(long)]
        fine: bool,
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// Extreme TL scenes (punching, pulling, cylinder, stent; TL paper §4.2–4.6), then the
    /// report. Hours in full; `--short` skips the strip to 1000 %, the cylinder and the stent.
    Extreme {
        /// Skip the longest runs.
        #[arg(long)]
        short: bool,
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// UL impacts (UL paper §6.4–6.6) and the Hertz contact verification, then the report.
    Impacts {
        /// Add the Hertz runs at R/dp = 30 (ENOG; ≈ 230,000 particles each).
        #[arg(long)]
        fine: bool,
        /// Add the colliding balls at the paper's resolution (ENOG; 310,000 particles).
        #[arg(long)]
        paper: bool,
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// Contact and friction: the incline block (TL-HF, UL-ENOG, MPS; 2D and 3D), then the
    /// report.
    Contact {
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// Plasticity: the Taylor bar (UL-GNOG, UL-OG at R/dp 4, 6, 8; UL-OAS; TL, TL-GM at 3)
    /// against the published final length and radius, then the report.
    Taylor {
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// Speed–accuracy runs (Pareto fronts) and the stability map, then the reports
    /// (docs/tradeoffs.md). Hours in full; `--quick` runs coarse resolutions and a reduced map
    Tradeoff {
        #[arg(long)]
        quick: bool,
        #[arg(long)]
        force: bool,
        /// Only the scenes/sweeps whose key starts with this (plate, homog, cantilever, lame,
        /// rings, column, features, example: `sph converge` on an example scene file)
        #[arg(long)]
        only: Option<String>,
    },
    /// Meshes (sphere, torus, cube) filled with body-fitted particles against their analytic
    /// volumes and surfaces, relaxation off and on, then the report.
    Geometry {
        /// Re-run stored results.
        #[arg(long)]
        force: bool,
    },
    /// TL-HF's Laplacian normalised per particle against the paper's ζ (homogeneous
    /// compression, the plate against FE, the undamped plate, Lamb's breathing sphere), then
    /// the report.
    HfLaplacian {
        /// Re-run stored runs.
        #[arg(long)]
        force: bool,
    },
    /// Regenerate docs/validation.md from the stored runs.
    Report,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    store::set_plan_only(cli.plan);
    store::set_run_filter(cli.runs.clone());
    if let Command::Tl {
        medium,
        fine,
        table2,
        force,
    } = cli.command
    {
        if let Err(e) = tl::run_all(tl::Selection {
            force,
            fine,
            medium,
            table2,
        }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Mps { full, fine, force } = cli.command {
        // The stabilisation study first: it holds the paper's model on the ring and the slab.
        if let Err(e) = mps_stab::run_all(mps_stab::Selection { force, fine })
            .and_then(|_| mps::run_all(mps::Selection { force, full }))
        {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Ul { fine, force } = cli.command {
        if let Err(e) = ul::run_all(ul::Selection { force, fine }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Extreme { short, force } = cli.command {
        let figs = workspace_root().join("docs").join("validation");
        if let Err(e) = std::fs::create_dir_all(&figs)
            .map_err(|e| e.to_string())
            .and_then(|_| {
                extreme::run_all(extreme::Selection { force, short }, &figs)
                    .map_err(|e| e.to_string())
            })
        {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Impacts { fine, paper, force } = cli.command {
        if let Err(e) = impacts::run_all(impacts::Selection { force, fine, paper }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Contact { force } = cli.command {
        if let Err(e) = contact::run_all(contact::Selection { force }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Taylor { force } = cli.command {
        if let Err(e) = taylor::run_all(taylor::Selection { force }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Tradeoff { quick, force, only } = &cli.command {
        let (quick, force, only) = (*quick, *force, only.clone());
        if let Err(e) = tradeoff::run_all(tradeoff::Selection { quick, force, only }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::Geometry { force } = cli.command {
        if let Err(e) = geometry::run_all(force).and_then(|()| mesh_physics::run_all(force)) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if let Command::HfLaplacian { force } = cli.command {
        if let Err(e) = hf_laplacian::run_all(hf_laplacian::Selection { force }) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    if cli.plan {
        return ExitCode::SUCCESS;
    }
    if let Err(e) = tradeoff::report(&workspace_root()) {
        eprintln!("error: {e}");
        return ExitCode::from(1);
    }
    match report() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn report() -> Result<(), String> {
    let root = workspace_root();
    let docs = root.join("docs");
    let figs = docs.join("validation");
    std::fs::create_dir_all(&figs).map_err(|e| e.to_string())?;
    let mut md = String::new();
    writeln!(md, "# Validation\n").unwrap();
    writeln!(
        md,
        "Generated by `cargo run --release -p sph-validation --bin validate -- report` from the runs \
         stored in `validation/results/` (made by `validate tl --medium --fine`, `validate mps`, `validate ul`, `validate extreme`, `validate impacts` (partly: see its section) and `validate contact`; each stored run \
         records the `sph run` command that reproduces it, and keeps its HDF5 file under \
         `target/validation-results/<id>/`, outside git). The same command writes this \
         report's tables and plotted curves to `target/validation-results/validation.h5` (a \
         group per section, `validation/src/h5report.rs` documents the layout; h5py opens it). \
         Do not edit by hand.\n"
    )
    .unwrap();
    tl::report(&mut md, &figs, "validation")?;
    mps::report(&mut md, &figs, "validation")?;
    mps_stab::report(&mut md, &figs, "validation")?;
    ul::report(&mut md, &figs, "validation")?;
    extreme::report(&mut md, &figs, "validation")?;
    hf_laplacian::report(&mut md)?;
    impacts::report(&mut md, &figs, "validation")?;
    contact::report(&mut md)?;
    taylor::report(&mut md, &figs, "validation")?;
    geometry::report(&mut md)?;
    mesh_physics::report(&mut md)?;
    let out = docs.join("validation.md");
    let tmp = docs.join("validation.md.tmp");
    std::fs::write(&tmp, &md).map_err(|e| e.to_string())?;
    std::fs::rename(&tmp, &out).map_err(|e| e.to_string())?;
    println!("wrote {}", out.display());
    let h5_dir = root.join(store::RESULTS_FILES_DIR);
    std::fs::create_dir_all(&h5_dir).map_err(|e| e.to_string())?;
    let h5 = h5_dir.join("validation.h5");
    h5report::write(&h5, &md, &plot::take_recorded())?;
    println!("wrote {}", h5.display());
    Ok(())
}
