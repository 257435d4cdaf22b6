//! Reading a results file back (through `hdf5-pure`), for tests and validation.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use hdf5_pure::{AttrValue, DType, File};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::data::{Dataset, DatasetData};
use crate::pure::err;
use crate::OutputError;

/// One snapshot read back.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// The group name (`000000`, …).
    pub name: String,
    /// Attribute `time`.
    pub time: f64,
    /// Attribute `step`.
    pub step: u64,
    /// The datasets, sorted by name.
    pub datasets: Vec<Dataset>,
}

impl Snapshot {
    /// The dataset called `name`, if any.
    pub fn dataset(&self, name: &str) -> Option<&Dataset> {
        self.datasets.iter().find(|d| d.name == name)
    }
}

/// One probe read back.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Probe {
    /// `time`.
    pub times: Vec<f64>,
    /// `position`, one row per time.
    pub positions: Vec<[f64; 3]>,
    /// `velocity`, one row per time.
    pub velocities: Vec<[f64; 3]>,
    /// `fields/*`: the output fields sampled at the probe, with their own `time` (empty when
    /// none were asked for).
    pub fields: Vec<Dataset>,
}

impl Probe {
    /// The sampled field called `name` (`time` for the sample times), if any.
    pub fn field(&self, name: &str) -> Option<&Dataset> {
        self.fields.iter().find(|d| d.name == name)
    }
}

/// One series read back: `time`, the columns by name and the description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// `time`.
    pub times: Vec<f64>,
    /// The other datasets of the group, by name.
    pub columns: BTreeMap<String, Vec<f64>>,
    /// The attribute `description` (empty if absent).
    pub description: String,
}

/// Everything in a results file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FileContents {
    /// `/meta` (from its `json` attribute; empty if never written).
    pub meta: Map<String, Value>,
    /// `/snapshots/*`, in name (= time) order.
    pub snapshots: Vec<Snapshot>,
    /// `/probes/*` by name.
    pub probes: BTreeMap<String, Probe>,
    /// `/series/*` by name (empty for files of format version 1, which have none).
    pub series: BTreeMap<String, Series>,
    /// `/summary` (from its `json` attribute; empty if never written).
    pub summary: Map<String, Value>,
}

/// Reads a whole results file (a finished `.h5` or a `.tmp` left by an interrupted run).
pub fn read_file(path: impl AsRef<Path>) -> Result<FileContents, OutputError> {
    let path = path.as_ref();
    let file = File::open(path).map_err(|e| err(path, "open the file", e))?;
    let meta = read_json_group(&file, path, "meta")?;
    let summary = read_json_group(&file, path, "summary")?;

    let snaps_group = file
        .group("snapshots")
        .map_err(|e| err(path, "open /snapshots", e))?;
    let mut names = snaps_group
        .groups()
        .map_err(|e| err(path, "list /snapshots", e))?;
    names.sort();
    let mut snapshots = Vec::with_capacity(names.len());
    for name in names {
        let gpath = format!("snapshots/{name}");
        let g = file
            .group(&gpath)
            .map_err(|e| err(path, format!("open /{gpath}"), e))?;
        let attrs = g
            .attrs()
            .map_err(|e| err(path, format!("read attributes of /{gpath}"), e))?;
        let time = match attrs.get("time") {
            Some(AttrValue::F64(t)) => *t,
            other => {
                return Err(OutputError::layout(
                    path,
                    format!("/{gpath}: attribute `time` should be f64, found {other:?}"),
                ))
            }
        };
        let step = match attrs.get("step") {
            Some(AttrValue::U64(s)) => *s,
            other => {
                return Err(OutputError::layout(
                    path,
                    format!("/{gpath}: attribute `step` should be u64, found {other:?}"),
                ))
            }
        };
        let mut ds_names = g
            .datasets()
            .map_err(|e| err(path, format!("list /{gpath}"), e))?;
        ds_names.sort();
        let datasets = ds_names
            .iter()
            .map(|d| read_dataset(&file, path, &format!("{gpath}/{d}"), d))
            .collect::<Result<Vec<_>, _>>()?;
        snapshots.push(Snapshot {
            name,
            time,
            step,
            datasets,
        });
    }

    let probes_group = file
        .group("probes")
        .map_err(|e| err(path, "open /probes", e))?;
    let mut probes = BTreeMap::new();
    for name in probes_group
        .groups()
        .map_err(|e| err(path, "list /probes", e))?
    {
        let f = |d: &str| -> Result<Vec<f64>, OutputError> {
            let p = format!("probes/{name}/{d}");
            match read_dataset(&file, path, &p, d)?.data {
                DatasetData::F64 { values, .. } => Ok(values),
                DatasetData::U64 { .. } => {
                    Err(OutputError::layout(path, format!("/{p} should be f64")))
                }
            }
        };
        let rows = |v: Vec<f64>| -> Vec<[f64; 3]> {
            v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        };
        let mut fields = Vec::new();
        if let Ok(g) = file.group(&format!("probes/{name}/fields")) {
            let mut names = g
                .datasets()
                .map_err(|e| err(path, format!("list /probes/{name}/fields"), e))?;
            names.sort();
            for d in names {
                fields.push(read_dataset(
                    &file,
                    path,
                    &format!("probes/{name}/fields/{d}"),
                    &d,
                )?);
            }
        }
        let probe = Probe {
            times: f("time")?,
            positions: rows(f("position")?),
            velocities: rows(f("velocity")?),
            fields,
        };
        probes.insert(name, probe);
    }

    let mut series = BTreeMap::new();
    if let Ok(group) = file.group("series") {
        for name in group.groups().map_err(|e| err(path, "list /series", e))? {
            let g = file
                .group(&format!("series/{name}"))
                .map_err(|e| err(path, format!("open /series/{name}"), e))?;
            let mut columns = BTreeMap::new();
            for d in g
                .datasets()
                .map_err(|e| err(path, format!("list /series/{name}"), e))?
            {
                let p = format!("series/{name}/{d}");
                match read_dataset(&file, path, &p, &d)?.data {
                    DatasetData::F64 { values, .. } => {
                        columns.insert(d, values);
                    }
                    DatasetData::U64 { .. } => {
                        return Err(OutputError::layout(path, format!("/{p} should be f64")))
                    }
                }
            }
            let times = columns.remove("time").ok_or_else(|| {
                OutputError::layout(path, format!("/series/{name} has no `time` dataset"))
            })?;
            let description = match g.attrs().ok().and_then(|a| a.get("description").cloned()) {
                Some(AttrValue::String(s) | AttrValue::VarLenString(s)) => s,
                _ => String::new(),
            };
            series.insert(
                name,
                Series {
                    times,
                    columns,
                    description,
                },
            );
        }
    }

    Ok(FileContents {
        meta,
        snapshots,
        probes,
        series,
        summary,
    })
}

fn read_dataset(file: &File, path: &Path, dpath: &str, name: &str) -> Result<Dataset, OutputError> {
    let ds = file
        .dataset(dpath)
        .map_err(|e| err(path, format!("open /{dpath}"), e))?;
    let shape: Vec<usize> = ds
        .shape()
        .map_err(|e| err(path, format!("read the shape of /{dpath}"), e))?
        .into_iter()
        .map(|d| d as usize)
        .collect();
    let dtype = ds
        .dtype()
        .map_err(|e| err(path, format!("read the type of /{dpath}"), e))?;
    let data = match dtype {
        DType::F64 => DatasetData::F64 {
            values: ds
                .read_f64()
                .map_err(|e| err(path, format!("read /{dpath}"), e))?,
            shape,
        },
        DType::U64 => DatasetData::U64 {
            values: ds
                .read_u64()
                .map_err(|e| err(path, format!("read /{dpath}"), e))?,
            shape,
        },
        other => {
            return Err(OutputError::layout(
                path,
                format!("/{dpath}: expected f64 or u64, found {other}"),
            ))
        }
    };
    Ok(Dataset {
        name: name.to_string(),
        data,
    })
}

fn read_json_group(
    file: &File,
    path: &Path,
    group: &str,
) -> Result<Map<String, Value>, OutputError> {
    let g = file
        .group(group)
        .map_err(|e| err(path, format!("open /{group}"), e))?;
    let attrs: HashMap<String, AttrValue> = g
        .attrs()
        .map_err(|e| err(path, format!("read attributes of /{group}"), e))?;
    let Some(json) = attrs.get("json") else {
        return Ok(Map::new());
    };
    let text = attr_string(json).ok_or_else(|| {
        OutputError::layout(path, format!("/{group}: attribute `json` is not a string"))
    })?;
    serde_json::from_str(&text).map_err(|e| {
        OutputError::layout(
            path,
            format!("/{group}: attribute `json` is not a JSON object: {e}"),
        )
    })
}

fn attr_string(a: &AttrValue) -> Option<String> {
    match a {
        AttrValue::VarLenString(s) | AttrValue::String(s) | AttrValue::AsciiString(s) => {
            Some(s.clone())
        }
        other => other.as_strings().and_then(|v| v.first().cloned()),
    }
}
