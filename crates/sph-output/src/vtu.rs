//! Per-frame VTK files beside the HDF5 results: one `<name>_<k>.vtu` (VTK XML unstructured
//! grid) per snapshot and a `<name>.pvd` collection of them with their times, which ParaView,
//! PyVista (VTK) and meshio read directly, without an XDMF reader.
//!
//! Each `.vtu` holds the snapshot's particles as points (the `position` dataset), one `vertex`
//! cell per point, and every other per-particle dataset as point data: scalars, vectors (3
//! components), matrices (9 components, row-major: ParaView shows them as tensors), the
//! integer `id` as `UInt64`. The frame's time is in its field data (`TimeValue`, which VTK
//! readers show as the time) and in the `.pvd`. The data are stored after the XML header in
//! one raw appended block (`header_type="UInt64"`, little-endian): no base64, no compression,
//! the values bit for bit those of the HDF5 file.
//!
//! Files are written to a temporary name and renamed, like the results; an existing `.vtu` or
//! `.pvd` is replaced only if it is a VTK XML file, and frames of an earlier, longer run of
//! the same name beyond the new run's last are removed (only if they are VTK XML files).

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::data::{Dataset, DatasetData};
use crate::safety::{check_destination, TempFile};
use crate::OutputError;

/// The `.pvd` collection of `path_without_ext` (`.pvd` appended).
pub fn pvd_path(path_without_ext: &Path) -> PathBuf {
    crate::with_suffix(path_without_ext, ".pvd")
}

/// The `.vtu` of frame `k` of `path_without_ext`: `<name>_<k>.vtu`, six digits at least.
pub fn vtu_path(path_without_ext: &Path, k: usize) -> PathBuf {
    crate::with_suffix(path_without_ext, &format!("_{k:06}.vtu"))
}

/// Whether `path` starts like a VTK XML file (what this module writes).
fn is_vtk_xml(path: &Path) -> bool {
    let mut head = [0u8; 256];
    let n = std::fs::File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .unwrap_or(0);
    String::from_utf8_lossy(&head[..n]).contains("<VTKFile")
}

/// `path` may be written: absent, or a regular VTK XML file.
fn check_vtk_destination(path: &Path) -> Result<(), OutputError> {
    check_destination(path)?;
    if path.exists() && !is_vtk_xml(path) {
        return Err(OutputError::refused(
            path,
            "it exists and is not a VTK XML file",
        ));
    }
    Ok(())
}

/// The checks [`VtuSeries::create`] makes: the `.pvd` and the first frame's `.vtu` are absent
/// or VTK XML files. Nothing is written.
pub fn check_vtu_destination(path_without_ext: &Path) -> Result<(), OutputError> {
    check_vtk_destination(&pvd_path(path_without_ext))?;
    check_vtk_destination(&vtu_path(path_without_ext, 0))
}

/// The frames of one run, written as they come, and the collection written at the end.
#[derive(Debug)]
pub struct VtuSeries {
    base: PathBuf,
    frames: Vec<(f64, PathBuf)>,
}

impl VtuSeries {
    /// Starts the series `path_without_ext` (frames `<name>_<k>.vtu`, collection `<name>.pvd`).
    ///
    /// # Errors
    /// A `.pvd` or first `.vtu` that exists and is not a VTK XML file (or not a regular file).
    pub fn create(path_without_ext: &Path) -> Result<Self, OutputError> {
        check_vtu_destination(path_without_ext)?;
        Ok(Self {
            base: path_without_ext.to_path_buf(),
            frames: Vec::new(),
        })
    }

    /// Writes the next frame: the snapshot at `time` (step `step`) with `datasets`, which must
    /// hold `position` (f64 `[n, 3]`); per-particle datasets (first dimension `n`) become point
    /// data, others are left out.
    ///
    /// # Errors
    /// No `position`, a destination that may not be replaced, a failed write.
    pub fn write_frame(
        &mut self,
        time: f64,
        step: u64,
        datasets: &[Dataset],
    ) -> Result<(), OutputError> {
        let path = vtu_path(&self.base, self.frames.len());
        check_vtk_destination(&path)?;
        let bytes = frame_bytes(time, step, datasets)
            .map_err(|m| OutputError::invalid(&path, format!("VTU frame: {m}")))?;
        let mut tmp = TempFile::beside(&path, true)?;
        tmp.write_all(&bytes)?;
        tmp.persist(&path)?;
        self.frames.push((time, path));
        Ok(())
    }

    /// Writes the `.pvd` collection and removes the frames beyond the last of an earlier run of
    /// the same name; returns the `.pvd`'s path.
    ///
    /// # Errors
    /// A failed write.
    pub fn finish(self) -> Result<PathBuf, OutputError> {
        let pvd = pvd_path(&self.base);
        let mut xml = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
             byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (time, path) in &self.frames {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            xml.push_str(&format!(
                "    <DataSet timestep=\"{time:?}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                escape(&name)
            ));
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        check_vtk_destination(&pvd)?;
        let mut tmp = TempFile::beside(&pvd, true)?;
        tmp.write_all(xml.as_bytes())?;
        tmp.persist(&pvd)?;
        // Frames of an earlier run beyond ours: stale, and misleading beside the collection.
        let mut k = self.frames.len();
        loop {
            let stale = vtu_path(&self.base, k);
            match std::fs::symlink_metadata(&stale) {
                Ok(m) if m.is_file() && is_vtk_xml(&stale) => {
                    let _ = std::fs::remove_file(&stale);
                }
                _ => break,
            }
            k += 1;
        }
        Ok(pvd)
    }
}

/// `&`, `<`, `>`, `"` as XML entities.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One `.vtu` file: the XML header, then the raw appended data.
fn frame_bytes(time: f64, step: u64, datasets: &[Dataset]) -> Result<Vec<u8>, String> {
    let position = datasets
        .iter()
        .find(|d| d.name == "position")
        .ok_or("no `position` dataset")?;
    let n = match (position.shape(), &position.data) {
        ([n, 3], DatasetData::F64 { .. }) => *n,
        (s, _) => return Err(format!("`position` must be f64 [n, 3], got {s:?}")),
    };
    let mut appended: Vec<u8> = Vec::new();
    // One array of the appended block: its u64 byte count, then its bytes.
    let mut block = |bytes: Vec<u8>| -> usize {
        let offset = appended.len();
        appended.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        appended.extend_from_slice(&bytes);
        offset
    };
    let f64s = |v: &[f64]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut point_data = String::new();
    for d in datasets.iter().filter(|d| d.name != "position") {
        let shape = d.shape();
        if shape.first() != Some(&n) {
            continue;
        }
        let components: usize = shape[1..].iter().product();
        let (kind, bytes) = match &d.data {
            DatasetData::F64 { values, .. } => ("Float64", f64s(values)),
            DatasetData::U64 { values, .. } => (
                "UInt64",
                values.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
        };
        let offset = block(bytes);
        point_data.push_str(&format!(
            "        <DataArray type=\"{kind}\" Name=\"{}\" NumberOfComponents=\"{components}\" \
             format=\"appended\" offset=\"{offset}\"/>\n",
            escape(&d.name)
        ));
    }
    let DatasetData::F64 { values, .. } = &position.data else {
        unreachable!("checked above")
    };
    let points = block(f64s(values));
    let ids: Vec<u8> = (0..n as i64).flat_map(|i| i.to_le_bytes()).collect();
    let connectivity = block(ids);
    let ends: Vec<u8> = (1..=n as i64).flat_map(|i| i.to_le_bytes()).collect();
    let offsets = block(ends);
    // VTK_VERTEX = 1.
    let types = block(vec![1u8; n]);
    let xml = format!(
        "<?xml version=\"1.0\"?>\n\
         <!-- sph-solids snapshot: time {time:?} s, step {step} -->\n\
         <VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n\
         \x20 <UnstructuredGrid>\n\
         \x20   <FieldData>\n\
         \x20     <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
         format=\"ascii\">{time:?}</DataArray>\n\
         \x20   </FieldData>\n\
         \x20   <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">\n\
         \x20     <PointData>\n{point_data}\
         \x20     </PointData>\n\
         \x20     <Points>\n\
         \x20       <DataArray type=\"Float64\" Name=\"position\" NumberOfComponents=\"3\" \
         format=\"appended\" offset=\"{points}\"/>\n\
         \x20     </Points>\n\
         \x20     <Cells>\n\
         \x20       <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" \
         offset=\"{connectivity}\"/>\n\
         \x20       <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" \
         offset=\"{offsets}\"/>\n\
         \x20       <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" \
         offset=\"{types}\"/>\n\
         \x20     </Cells>\n\
         \x20   </Piece>\n\
         \x20 </UnstructuredGrid>\n\
         \x20 <AppendedData encoding=\"raw\">\n_"
    );
    let mut bytes = xml.into_bytes();
    bytes.extend_from_slice(&appended);
    bytes.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_holds_its_points_and_fields_in_the_appended_block() {
        let sets = [
            Dataset::vectors("position", &[[0.0, 1.0, 2.0], [3.0, 4.0, 5.0]]),
            Dataset::scalars("von_mises", &[7.0, 8.0]),
            Dataset::u64("id", vec![1, 0], vec![2]),
        ];
        let bytes = frame_bytes(0.5, 3, &sets).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("NumberOfPoints=\"2\""));
        assert!(text.contains("Name=\"von_mises\" NumberOfComponents=\"1\""));
        assert!(text.contains("type=\"UInt64\" Name=\"id\""));
        // The block starts after `_`; the first array (von_mises) is 16 bytes after its count.
        let marker = b"encoding=\"raw\">\n_";
        let start = bytes
            .windows(marker.len())
            .position(|w| w == marker)
            .unwrap()
            + marker.len();
        let count = u64::from_le_bytes(bytes[start..start + 8].try_into().unwrap());
        assert_eq!(count, 16);
        let first = f64::from_le_bytes(bytes[start + 8..start + 16].try_into().unwrap());
        assert_eq!(first, 7.0);
        assert!(frame_bytes(0.0, 0, &sets[1..]).is_err());
    }
}
