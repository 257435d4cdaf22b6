//! The HDF5 C library backend (feature `hdf5-metno`): same layout, same values.
#![cfg(feature = "hdf5-metno")]

mod common;

use std::path::Path;
use std::process::Command;

use common::*;
use sph_output::{read_file, xmf_path, Backend, Compression};

#[test]
fn metno_written_pure_read_round_trip() {
    let dir = scratch("metno");
    let base = dir.join("run");
    let h5 = write_all(&base, Backend::Metno);
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    assert!(xmf_path(&base).exists());
    check_contents(&read_file(&h5).unwrap());
}

#[test]
fn both_backends_write_identical_content() {
    let dir = scratch("both");
    let pure = write_all(&dir.join("pure"), Backend::Pure);
    let metno = write_all(&dir.join("metno"), Backend::Metno);
    assert_eq!(read_file(&pure).unwrap(), read_file(&metno).unwrap());
    // Same sidecar apart from the file name it points at.
    let xp = std::fs::read_to_string(xmf_path(&dir.join("pure"))).unwrap();
    let xm = std::fs::read_to_string(xmf_path(&dir.join("metno"))).unwrap();
    assert_eq!(xp.replace("pure.h5:", "X:"), xm.replace("metno.h5:", "X:"));
}

#[test]
fn h5py_reads_identical_values_from_both_backends() {
    let has_h5py = Command::new("python3")
        .args(["-c", "import h5py"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !has_h5py {
        println!("notice: python3 with h5py not available; h5py cross-check skipped");
        return;
    }
    let dir = scratch("h5py");
    let pure = write_all(&dir.join("pure"), Backend::Pure);
    let metno = write_all(&dir.join("metno"), Backend::Metno);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/h5py_check.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(&pure)
        .arg(&metno)
        .output()
        .expect("run python3");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(out.status.success(), "h5py_check.py failed:\n{text}");
}

/// Both backends compress the same way (same chunks, same filters): identical content, the
/// pure reader decodes what the C library deflated, h5py reads identical values and storage
/// settings from both, and a level-9 file of a smooth run is smaller than the plain one.
#[test]
fn both_backends_deflate_identically() {
    let dir = scratch("deflate-both");
    let pure = write_all_with(&dir.join("pure"), Backend::Pure, Compression::Deflate(9));
    let metno = write_all_with(&dir.join("metno"), Backend::Metno, Compression::Deflate(9));
    check_contents(&read_file(&metno).unwrap());
    assert_eq!(read_file(&pure).unwrap(), read_file(&metno).unwrap());
    let n = 20_000;
    let sp = write_smooth(&dir.join("sp"), Backend::Pure, Compression::Deflate(9), n);
    let sm = write_smooth(&dir.join("sm"), Backend::Metno, Compression::Deflate(9), n);
    let plain = write_smooth(&dir.join("plain"), Backend::Metno, Compression::None, n);
    assert_eq!(read_file(&sp).unwrap(), read_file(&plain).unwrap());
    assert_eq!(read_file(&sm).unwrap(), read_file(&plain).unwrap());
    let size = |p: &Path| std::fs::metadata(p).unwrap().len();
    assert!(
        size(&sm) * 2 < size(&plain),
        "{} vs {}",
        size(&sm),
        size(&plain)
    );
    if python_has(&["h5py"]) {
        run_python_check("h5py_check.py", &[&pure, &metno]);
        run_python_check("h5py_check.py", &[&sp, &sm]);
    } else {
        println!("notice: python3 with h5py not available; h5py cross-check skipped");
    }
}
