//! The layout, shared by both backends: validation, naming, JSON → attributes, tmp + rename,
//! and the bookkeeping the XDMF sidecar needs. A backend only implements [`Sink`].

use std::path::{Path, PathBuf};

use serde_json::{Map, Value};

use crate::data::{check_name, Dataset};
use crate::safety::{OutputLock, TempFile};
use crate::xdmf::{self, XdmfSnapshot};
use crate::{Compression, OutputError, ResultWriter, FORMAT_NAME, FORMAT_VERSION};

/// An attribute value, in the types both backends write identically.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Attr {
    F64(f64),
    I64(i64),
    U64(u64),
    U8(u8),
    /// Variable-length UTF-8 string.
    Str(String),
}

/// One group with its attributes and datasets, written as a unit.
pub(crate) struct GroupSpec<'a> {
    /// Path below the root, e.g. `snapshots/000003`.
    pub path: String,
    pub attrs: Vec<(String, Attr)>,
    pub datasets: Vec<&'a Dataset>,
}

/// What a backend provides. Each call must be durable in the file when it returns.
pub(crate) trait Sink: Send {
    /// Writes a new group (`replace`: deleting an existing one at that path first).
    fn write_group(&mut self, group: &GroupSpec<'_>, replace: bool) -> Result<(), OutputError>;
    /// Closes the file; all data must be on disk afterwards.
    fn close(self: Box<Self>) -> Result<(), OutputError>;
}

/// Creates the temporary file with the root attributes and the empty groups `meta`,
/// `snapshots`, `probes`, `series`, `summary`; datasets are then stored with `Compression`.
pub(crate) type SinkFactory =
    fn(&Path, &[(String, Attr)], Compression) -> Result<Box<dyn Sink>, OutputError>;

/// Datasets smaller than this are stored contiguous even when compression is asked for: a
/// chunk index and a filter pipeline cost more than deflate saves on them.
const MIN_COMPRESSED_BYTES: usize = 1024;

/// Target size of one chunk of a compressed dataset.
const CHUNK_BYTES: usize = 1 << 20;

/// The chunk shape of a compressed dataset of `shape` (8-byte elements), or `None` to store
/// it contiguous (small or empty datasets): whole rows of the first dimension, about
/// [`CHUNK_BYTES`] per chunk, never more rows than the dataset has. Both backends use it, so
/// they write the same layout.
pub(crate) fn chunk_shape(shape: &[usize]) -> Option<Vec<usize>> {
    let total: usize = shape.iter().product();
    if shape.is_empty() || total == 0 || 8 * total < MIN_COMPRESSED_BYTES {
        return None;
    }
    let row: usize = shape[1..].iter().product();
    let rows = (CHUNK_BYTES / (8 * row)).clamp(1, shape[0]);
    let mut chunk = shape.to_vec();
    chunk[0] = rows;
    Some(chunk)
}

pub(crate) const TOP_GROUPS: [&str; 5] = ["meta", "snapshots", "probes", "series", "summary"];

pub(crate) struct LayoutWriter {
    tmp: TempFile,
    lock: OutputLock,
    h5: PathBuf,
    xmf: PathBuf,
    sink: Box<dyn Sink>,
    snapshots: Vec<XdmfSnapshot>,
    probes: Vec<String>,
    probe_fields: Vec<String>,
    series: Vec<String>,
}

impl LayoutWriter {
    pub(crate) fn new(
        path_without_ext: &Path,
        factory: SinkFactory,
        compression: Compression,
    ) -> Result<Self, OutputError> {
        let h5 = crate::h5_path(path_without_ext);
        let xmf = crate::xmf_path(path_without_ext);
        // Lock first, then check: the destination cannot change under a held lock (except by
        // someone who ignores it).
        let lock = OutputLock::acquire(&h5)?;
        crate::safety::check_results_destination(path_without_ext)?;
        // Kept if the writer is dropped: the partial results of a run that died.
        let tmp = TempFile::beside(&h5, false)?;
        let root_attrs = vec![
            ("format".to_string(), Attr::Str(FORMAT_NAME.to_string())),
            ("format_version".to_string(), Attr::U64(FORMAT_VERSION)),
        ];
        let sink = factory(tmp.path(), &root_attrs, compression)?;
        Ok(LayoutWriter {
            tmp,
            lock,
            h5,
            xmf,
            sink,
            snapshots: Vec::new(),
            probes: Vec::new(),
            probe_fields: Vec::new(),
            series: Vec::new(),
        })
    }

    fn write_json_group(
        &mut self,
        group: &str,
        map: &Map<String, Value>,
    ) -> Result<(), OutputError> {
        let attrs = json_attrs(map).map_err(|m| OutputError::invalid(self.tmp.path(), m))?;
        self.sink.write_group(
            &GroupSpec {
                path: group.to_string(),
                attrs,
                datasets: Vec::new(),
            },
            true,
        )
    }
}

/// Snapshot group name: at least six digits, zero padded.
pub(crate) fn snapshot_name(index: usize) -> String {
    format!("{index:06}")
}

/// JSON map → attributes (see the crate docs), plus `json` with the whole map.
pub(crate) fn json_attrs(map: &Map<String, Value>) -> Result<Vec<(String, Attr)>, String> {
    let mut attrs = Vec::with_capacity(map.len() + 1);
    for (key, value) in map {
        if key == "json" || check_name(key).is_err() {
            continue;
        }
        let attr = match value {
            Value::Null => continue,
            Value::Bool(b) => Attr::U8(u8::from(*b)),
            Value::Number(n) => {
                if let Some(u) = n.as_u64() {
                    Attr::U64(u)
                } else if let Some(i) = n.as_i64() {
                    Attr::I64(i)
                } else if let Some(f) = n.as_f64() {
                    Attr::F64(f)
                } else {
                    Attr::Str(n.to_string())
                }
            }
            Value::String(s) => {
                if s.contains('\0') {
                    // A C string cannot hold it; the value is still in `json`.
                    continue;
                }
                Attr::Str(s.clone())
            }
            Value::Array(_) | Value::Object(_) => Attr::Str(value.to_string()),
        };
        attrs.push((key.clone(), attr));
    }
    let json = serde_json::to_string(map).map_err(|e| format!("serialising JSON: {e}"))?;
    attrs.push(("json".to_string(), Attr::Str(json)));
    Ok(attrs)
}

impl ResultWriter for LayoutWriter {
    fn write_meta(&mut self, meta: &Map<String, Value>) -> Result<(), OutputError> {
        self.write_json_group("meta", meta)
    }

    fn write_snapshot(
        &mut self,
        time: f64,
        step: u64,
        datasets: &[Dataset],
    ) -> Result<(), OutputError> {
        let invalid = |m: String| OutputError::invalid(self.tmp.path(), format!("snapshot: {m}"));
        let mut names = std::collections::BTreeSet::new();
        for ds in datasets {
            ds.validate().map_err(invalid)?;
            if !names.insert(ds.name.as_str()) {
                return Err(invalid(format!("dataset name {:?} used twice", ds.name)));
            }
        }
        let position = datasets.iter().find(|d| d.name == "position");
        if let Some(p) = position {
            let s = p.shape();
            if p.data.type_name() != "f64" || s.len() != 2 || s[1] != 3 {
                return Err(invalid(format!(
                    "`position` must be f64 [n, 3] (2D padded with z = 0), got {} {s:?}",
                    p.data.type_name()
                )));
            }
        }
        let name = snapshot_name(self.snapshots.len());
        let spec = GroupSpec {
            path: format!("snapshots/{name}"),
            attrs: vec![
                ("time".to_string(), Attr::F64(time)),
                ("step".to_string(), Attr::U64(step)),
            ],
            datasets: datasets.iter().collect(),
        };
        self.sink.write_group(&spec, false)?;
        self.snapshots.push(XdmfSnapshot::of(name, time, datasets));
        Ok(())
    }

    fn write_probe(
        &mut self,
        name: &str,
        times: &[f64],
        positions: &[[f64; 3]],
        velocities: &[[f64; 3]],
    ) -> Result<(), OutputError> {
        check_name(name).map_err(|e| {
            OutputError::invalid(self.tmp.path(), format!("probe name {name:?}: {e}"))
        })?;
        if self.probes.iter().any(|p| p == name) {
            return Err(OutputError::invalid(
                self.tmp.path(),
                format!("probe {name:?} written twice"),
            ));
        }
        if positions.len() != times.len() || velocities.len() != times.len() {
            return Err(OutputError::invalid(
                self.tmp.path(),
                format!(
                    "probe {name:?}: {} times, {} positions, {} velocities (must be equal)",
                    times.len(),
                    positions.len(),
                    velocities.len()
                ),
            ));
        }
        let t = Dataset::scalars("time", times);
        let p = Dataset::vectors("position", positions);
        let v = Dataset::vectors("velocity", velocities);
        self.sink.write_group(
            &GroupSpec {
                path: format!("probes/{name}"),
                attrs: Vec::new(),
                datasets: vec![&t, &p, &v],
            },
            false,
        )?;
        self.probes.push(name.to_string());
        Ok(())
    }

    fn write_probe_fields(
        &mut self,
        name: &str,
        times: &[f64],
        fields: &[Dataset],
    ) -> Result<(), OutputError> {
        let invalid =
            |m: String| OutputError::invalid(self.tmp.path(), format!("probe {name:?}: {m}"));
        if !self.probes.iter().any(|p| p == name) {
            return Err(invalid("fields written before the probe".into()));
        }
        if self.probe_fields.iter().any(|p| p == name) {
            return Err(invalid("fields written twice".into()));
        }
        let mut names = std::collections::BTreeSet::from(["time"]);
        for ds in fields {
            ds.validate().map_err(&invalid)?;
            if !names.insert(ds.name.as_str()) {
                return Err(invalid(format!(
                    "field {:?} repeated or named `time`",
                    ds.name
                )));
            }
            if ds.shape().first() != Some(&times.len()) {
                return Err(invalid(format!(
                    "field {:?}: {:?} rows for {} times",
                    ds.name,
                    ds.shape().first(),
                    times.len()
                )));
            }
        }
        let t = Dataset::scalars("time", times);
        let mut sets = vec![&t];
        sets.extend(fields);
        self.sink.write_group(
            &GroupSpec {
                path: format!("probes/{name}/fields"),
                attrs: Vec::new(),
                datasets: sets,
            },
            false,
        )?;
        self.probe_fields.push(name.to_string());
        Ok(())
    }

    fn write_series(
        &mut self,
        name: &str,
        times: &[f64],
        columns: &[(&str, &[f64])],
        description: &str,
    ) -> Result<(), OutputError> {
        check_name(name).map_err(|e| {
            OutputError::invalid(self.tmp.path(), format!("series name {name:?}: {e}"))
        })?;
        if self.series.iter().any(|p| p == name) {
            return Err(OutputError::invalid(
                self.tmp.path(),
                format!("series {name:?} written twice"),
            ));
        }
        let mut sets = vec![Dataset::scalars("time", times)];
        for (c, values) in columns {
            check_name(c).map_err(|e| {
                OutputError::invalid(
                    self.tmp.path(),
                    format!("series {name:?} column {c:?}: {e}"),
                )
            })?;
            if *c == "time" || sets.iter().any(|d| d.name == *c) {
                return Err(OutputError::invalid(
                    self.tmp.path(),
                    format!("series {name:?}: column {c:?} repeated or named `time`"),
                ));
            }
            if values.len() != times.len() {
                return Err(OutputError::invalid(
                    self.tmp.path(),
                    format!(
                        "series {name:?} column {c:?}: {} values for {} times",
                        values.len(),
                        times.len()
                    ),
                ));
            }
            sets.push(Dataset::scalars(*c, values));
        }
        let attrs = if description.is_empty() {
            Vec::new()
        } else {
            vec![(
                "description".to_string(),
                Attr::Str(description.to_string()),
            )]
        };
        self.sink.write_group(
            &GroupSpec {
                path: format!("series/{name}"),
                attrs,
                datasets: sets.iter().collect(),
            },
            false,
        )?;
        self.series.push(name.to_string());
        Ok(())
    }

    fn write_summary(&mut self, summary: &Map<String, Value>) -> Result<(), OutputError> {
        self.write_json_group("summary", summary)
    }

    fn finish(self: Box<Self>) -> Result<PathBuf, OutputError> {
        let LayoutWriter {
            tmp,
            lock,
            h5,
            xmf,
            sink,
            snapshots,
            ..
        } = *self;
        sink.close()?;
        sync_file(tmp.path())?;
        tmp.persist(&h5)?;
        let h5_name = h5
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let text = xdmf::render(&h5_name, &snapshots);
        let mut xmf_tmp = TempFile::beside(&xmf, true)?;
        xmf_tmp.write_all(text.as_bytes())?;
        xmf_tmp.persist(&xmf)?;
        drop(lock);
        Ok(h5)
    }

    fn final_path(&self) -> &Path {
        &self.h5
    }

    fn temp_path(&self) -> &Path {
        self.tmp.path()
    }
}

fn sync_file(path: &Path) -> Result<(), OutputError> {
    std::fs::File::open(path)
        .and_then(|f| f.sync_all())
        .map_err(|e| OutputError::io(path, "sync", e))
}
