//! Issue 15: what a library run writes by default, for every method: 51 frames (the `sph`
//! command's default), an integer particle `id` in every snapshot (the identity for TL and MPS,
//! UL's original index, which UL reorders), an XDMF sidecar that meshio and VTK read (checked
//! when python3 has h5py; each reader skipped with a notice when it is not installed), and
//! compression that is honoured or refused, never ignored.

use std::path::{Path, PathBuf};

use sph_solids::output::{read_file, xmf_path, DatasetData};
use sph_solids::prelude::*;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-solids-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn plate(dp: f64) -> ParticleSet<D2> {
    let corner = DVec2::new(0.0, 0.0);
    let rect = Aabb::<D2>::new(corner, DVec2::new(0.02, 0.006)).unwrap();
    ParticleSet::fill(&Lattice::new(dp, corner).unwrap(), &rect).unwrap()
}

fn constants() -> ElasticConstants {
    ElasticConstants::from_youngs(1e7, 0.4, 1200.0).unwrap()
}

/// Every snapshot's `id` as integers (the dataset must be stored as u64, `[n]`).
fn ids_per_snapshot(h5: &Path) -> Vec<Vec<u64>> {
    let contents = read_file(h5).unwrap();
    contents
        .snapshots
        .iter()
        .map(|s| match &s.dataset("id").expect("an id dataset").data {
            DatasetData::U64 { values, shape } => {
                assert_eq!(shape, &[values.len()], "{}: id shape", s.name);
                values.clone()
            }
            other => panic!("{}: id is not stored as integers: {other:?}", s.name),
        })
        .collect()
}

fn is_permutation(ids: &[u64]) -> bool {
    let mut sorted = ids.to_vec();
    sorted.sort_unstable();
    sorted.iter().enumerate().all(|(k, &i)| i == k as u64)
}

#[test]
fn every_method_writes_51_frames_with_integer_ids_by_default() {
    let dir = scratch("frames");
    let end = 2e-4;

    let mut tl = TlSolver::new(
        Body::from(plate(1e-3)),
        NeoHookean::new(constants()),
        TlShear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap();
    let (record, _) = Run::until(end)
        .write_to(dir.join("tl"))
        .execute(&mut tl)
        .unwrap();
    let tl_ids = ids_per_snapshot(record.file.as_ref().unwrap());
    assert_eq!(tl_ids.len(), 51);
    let identity: Vec<u64> = (0..tl.len() as u64).collect();
    assert!(tl_ids.iter().all(|ids| *ids == identity));

    let mut mps = MpsSolver::new(
        Body::from(plate(1e-3)),
        SaintVenantKirchhoff::new(constants()),
        MpsParams::default(),
    )
    .unwrap();
    let (record, _) = Run::until(end)
        .write_to(dir.join("mps"))
        .execute(&mut mps)
        .unwrap();
    let mps_ids = ids_per_snapshot(record.file.as_ref().unwrap());
    assert_eq!(mps_ids.len(), 51);
    assert!(mps_ids.iter().all(|ids| *ids == identity));

    // UL, from a reversed input so that its spatial sort moves the particles.
    let lattice: Body<D2> = Body::from(plate(1e-3));
    let body = Body::<D2>::new(
        lattice.positions.iter().rev().copied().collect(),
        lattice.volumes.iter().rev().copied().collect(),
        lattice.dp,
    );
    let mut ul = UlSolver::new(
        body,
        constants(),
        UlShear::non_nested(),
        UlParams::default(),
    )
    .unwrap();
    let (record, _) = Run::until(end)
        .write_to(dir.join("ul"))
        .execute(&mut ul)
        .unwrap();
    let ul_ids = ids_per_snapshot(record.file.as_ref().unwrap());
    assert_eq!(ul_ids.len(), 51);
    assert!(ul_ids.iter().all(|ids| is_permutation(ids)));
    assert_ne!(
        ul_ids[0], identity,
        "the reversed input must have been reordered"
    );
    let last: Vec<u64> = ul.original_index().iter().map(|&i| u64::from(i)).collect();
    assert_eq!(ul_ids.last().unwrap(), &last);

    readers_check(&[
        xmf_path(&dir.join("tl")),
        xmf_path(&dir.join("mps")),
        xmf_path(&dir.join("ul")),
    ]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compression_is_honoured_or_refused() {
    let dir = scratch("compress");
    let solver = || {
        TlSolver::new(
            Body::from(plate(5e-4)),
            NeoHookean::new(constants()),
            TlShear::hourglass_free(),
            TlParams::default(),
        )
        .unwrap()
    };
    let run = |name: &str| Run::until(1e-4).write_to(dir.join(name));
    let (plain, _) = run("plain").execute(&mut solver()).unwrap();
    let (packed, _) = run("packed").compress(6).execute(&mut solver()).unwrap();
    let (plain, packed) = (plain.file.unwrap(), packed.file.unwrap());
    assert_eq!(
        read_file(&plain).unwrap().snapshots,
        read_file(&packed).unwrap().snapshots
    );
    let size = |p: &Path| std::fs::metadata(p).unwrap().len();
    assert!(
        size(&packed) < size(&plain),
        "{} vs {}",
        size(&packed),
        size(&plain)
    );

    for (run, what) in [
        (run("level0").compress(0), "1 (fastest) to 9"),
        (run("level10").compress(10), "1 (fastest) to 9"),
        (Run::until(1e-4).compress(4), "no results file"),
    ] {
        let e = run.execute(&mut solver()).expect_err("refused");
        assert!(
            e.to_string().contains("compression") && e.to_string().contains(what),
            "{e}"
        );
    }
    assert!(!dir.join("level0.h5").exists() && !dir.join("level10.h5").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `crates/sph-output/tests/xdmf_readers_check.py` on `files`: meshio and VTK read the same
/// frames, times, points, cells and fields as h5py.
fn readers_check(files: &[PathBuf]) {
    python_check("crates/sph-output/tests/xdmf_readers_check.py", files);
}

/// Issue 42: a probe samples any output field the solver offers, at every monitor sample, into
/// `/probes/<name>/fields`; on a particle the values are the field's own there (compared with
/// the snapshots at the times both were written, bit for bit); on a UL body, whose particles
/// are reordered, the probe follows its particle. A field the solver lacks is refused before
/// the run.
#[test]
fn probes_sample_any_output_field() {
    let dir = scratch("probe-fields");
    let body = Body::from(plate(1e-3));
    let corner = DVec2::new(0.0005, 0.0005);
    let at_corner = (0..body.positions.len())
        .find(|&i| body.positions[i] == corner)
        .unwrap() as u32;
    let tip = Probe::at("tip", DVec2::new(0.02, 0.003), &body).unwrap();
    let probes = vec![
        Probe::particle("corner", at_corner).with_fields(&["von_mises", "velocity"]),
        tip.with_fields(&["deformation_gradient", "jacobian"]),
    ];
    let mut tl = TlSolver::new(
        body.clone().with_velocity(|x| DVec2::new(0.0, 5.0 * x.x)),
        NeoHookean::new(constants()),
        TlShear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap()
    .with_probes(probes.clone(), 0.0)
    .unwrap();
    let (record, _) = Run::until(2e-4)
        .write_to(dir.join("tl"))
        .execute(&mut tl)
        .unwrap();
    let file = read_file(record.file.as_ref().unwrap()).unwrap();
    let corner = &file.probes["corner"];
    let times = corner.field("time").unwrap().as_f64().unwrap();
    assert_eq!(times.len(), record.monitor.len());
    let vm = corner.field("von_mises").unwrap().as_f64().unwrap();
    let v = corner.field("velocity").unwrap();
    assert_eq!(v.shape(), &[times.len(), 3]);
    let mut compared = 0;
    for snap in &file.snapshots {
        if let Some(k) = times.iter().position(|&t| t == snap.time) {
            let field = snap.dataset("von_mises").unwrap().as_f64().unwrap();
            assert_eq!(vm[k].to_bits(), field[at_corner as usize].to_bits());
            compared += 1;
        }
    }
    assert_eq!(compared, 51, "every snapshot time is a monitor time");
    let f = file.probes["tip"].field("deformation_gradient").unwrap();
    assert_eq!(f.shape(), &[times.len(), 3, 3]);
    assert!(f.as_f64().unwrap().iter().all(|x| x.is_finite()));

    // UL reorders its particles: the probe follows the particle it was given.
    let mut ul = UlSolver::new(
        body.with_velocity(|x| DVec2::new(0.0, 5.0 * x.x)),
        constants(),
        UlShear::non_nested(),
        UlParams::default(),
    )
    .unwrap()
    .with_probes(
        vec![Probe::particle("corner", at_corner).with_fields(&["velocity"])],
        0.0,
    )
    .unwrap();
    let (record, _) = Run::until(2e-4)
        .write_to(dir.join("ul"))
        .execute(&mut ul)
        .unwrap();
    let file = read_file(record.file.as_ref().unwrap()).unwrap();
    let sampled = file.probes["corner"]
        .field("velocity")
        .unwrap()
        .as_f64()
        .unwrap();
    let last = file.snapshots.last().unwrap();
    let ids = last.dataset("id").unwrap();
    let row = match &ids.data {
        DatasetData::U64 { values, .. } => values.iter().position(|&i| i == u64::from(at_corner)),
        _ => None,
    }
    .unwrap();
    let v = last.dataset("velocity").unwrap().as_f64().unwrap();
    assert_eq!(&sampled[sampled.len() - 3..], &v[3 * row..3 * row + 3]);

    // A field the method does not offer: refused before anything is written.
    let mut bad = TlSolver::new(
        Body::from(plate(1e-3)),
        NeoHookean::new(constants()),
        TlShear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap()
    .with_probes(
        vec![Probe::particle("p", 0).with_fields(&["pressure"])],
        0.0,
    )
    .unwrap();
    let e = Run::until(1e-4)
        .write_to(dir.join("bad"))
        .execute(&mut bad)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("probe `p` field") && e.contains("von_mises"),
        "{e}"
    );
    assert!(!dir.join("bad.h5").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 42: with `vtu`, every snapshot is also a VTU file (`<name>_<k>.vtu`) and their
/// collection `<name>.pvd`, beside the HDF5 file: as many frames, the same times, points and
/// fields, read back by meshio and VTK (each skipped with a notice when not installed); a
/// shorter run of the same name removes the frames the longer one left beyond its own.
#[test]
fn vtu_frames_and_their_collection_match_the_hdf5_snapshots() {
    let dir = scratch("vtu");
    let run = |end: f64| {
        let mut tl = TlSolver::new(
            Body::from(plate(1e-3)).with_velocity(|x| DVec2::new(0.0, 5.0 * x.x)),
            NeoHookean::new(constants()),
            TlShear::hourglass_free(),
            TlParams::default(),
        )
        .unwrap();
        Run::until(end)
            .snapshot_every(5e-5)
            .write_to(dir.join("plate"))
            .vtu()
            .execute(&mut tl)
            .unwrap()
            .0
    };
    let long = run(4e-4);
    assert!(dir.join("plate_000008.vtu").is_file());
    let record = run(2e-4);
    let pvd = record.collection.clone().unwrap();
    assert_eq!(pvd, dir.join("plate.pvd"));
    let text = std::fs::read_to_string(&pvd).unwrap();
    assert_eq!(text.matches("<DataSet").count(), 5);
    assert!(dir.join("plate_000004.vtu").is_file());
    assert!(
        !dir.join("plate_000005.vtu").exists(),
        "a stale frame is left"
    );
    assert!(long.collection.is_some());
    // Without a results file there is nowhere to put them.
    let mut tl = TlSolver::new(
        Body::from(plate(1e-3)),
        NeoHookean::new(constants()),
        TlShear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap();
    let e = Run::until(1e-4)
        .vtu()
        .execute(&mut tl)
        .unwrap_err()
        .to_string();
    assert!(e.contains("vtu"), "{e}");
    python_check("crates/sph-output/tests/vtu_readers_check.py", &[pvd]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs a check script with python3 when h5py and numpy are there (else a notice).
fn python_check(script: &str, files: &[PathBuf]) {
    let has_h5py = std::process::Command::new("python3")
        .args(["-c", "import h5py, numpy"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !has_h5py {
        println!("notice: python3 with h5py not available; {script} skipped");
        return;
    }
    let out = std::process::Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join(script))
        .args(files)
        .output()
        .expect("run python3");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(out.status.success(), "{script} failed:\n{text}");
}

/// Issue 42: a results file explains itself: `/meta` has the units, the dimension, the
/// plane-strain depth of a 2D run, the sign of reaction forces and what a probe holds; every
/// series its `description` (a tool's and a grip's columns), the same sentences as
/// `sph_core::conventions` (which the user guide quotes).
#[test]
fn results_files_carry_their_units_and_conventions() {
    use sph_solids::core::conventions;
    let dir = scratch("conventions");
    let set = plate(1e-3);
    let (grip, n) = (set.select(|x| x.x < 1e-3), set.len());
    let mut grips = Constraints::new();
    grips
        .push_named("grip", Constraint::Fixed { particles: grip }, n)
        .unwrap();
    let punch = ToolShape::ball(DVec2::new(0.015, 0.009), 0.003).unwrap();
    let motion = ToolMotion::new(DVec2::new(0.0, -1.0), 1.0, 0.0, f64::INFINITY).unwrap();
    let mut tl = TlSolver::new(
        Body::from(set),
        NeoHookean::new(constants()),
        TlShear::hourglass_free(),
        TlParams::default(),
    )
    .unwrap()
    .with_constraints(grips)
    .with_tools(vec![RigidTool::new("punch", punch, motion)])
    .unwrap();
    let (record, _) = Run::until(1e-4)
        .write_to(dir.join("plate"))
        .execute(&mut tl)
        .unwrap();
    let file = read_file(record.file.unwrap()).unwrap();
    assert_eq!(file.meta["units"], conventions::UNITS);
    assert_eq!(file.meta["dimension"], 2);
    assert_eq!(file.meta["per_unit_depth"], conventions::PLANE_STRAIN);
    assert_eq!(file.meta["reaction_forces"], conventions::REACTIONS);
    assert_eq!(file.meta["probes"], conventions::PROBES);
    assert_eq!(file.series["punch"].description, conventions::TOOL_SERIES);
    assert_eq!(file.series["grip"].description, conventions::GRIP_SERIES);
    let _ = std::fs::remove_dir_all(&dir);
}
