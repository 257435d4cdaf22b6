//! The optional backend: the HDF5 C library through `hdf5-metno` (cargo feature `hdf5-metno`).
//!
//! The file stays open from creation to `finish`; each call creates its group and flushes the
//! file, so what a call wrote is on disk when it returns.

use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;
use hdf5::{File, Group, Location};

use crate::data::{Dataset, DatasetData};
use crate::writer::{chunk_shape, Attr, GroupSpec, Sink, TOP_GROUPS};
use crate::{Compression, OutputError};

const BACKEND: &str = "hdf5-metno";

fn err(path: &Path, context: impl Into<String>, e: hdf5::Error) -> OutputError {
    OutputError::Hdf5 {
        path: path.to_path_buf(),
        backend: BACKEND,
        context: context.into(),
        message: e.to_string(),
    }
}

fn write_attr(loc: &Location, name: &str, a: &Attr) -> hdf5::Result<()> {
    match a {
        Attr::F64(v) => loc.new_attr::<f64>().create(name)?.write_scalar(v),
        Attr::I64(v) => loc.new_attr::<i64>().create(name)?.write_scalar(v),
        Attr::U64(v) => loc.new_attr::<u64>().create(name)?.write_scalar(v),
        Attr::U8(v) => loc.new_attr::<u8>().create(name)?.write_scalar(v),
        Attr::Str(s) => {
            let v: VarLenUnicode = s
                .parse()
                .map_err(|e| hdf5::Error::from(format!("string attribute {name:?}: {e}")))?;
            loc.new_attr::<VarLenUnicode>()
                .create(name)?
                .write_scalar(&v)
        }
    }
}

fn write_dataset(g: &Group, ds: &Dataset, compression: Compression) -> hdf5::Result<()> {
    let shape: Vec<usize> = ds.shape().to_vec();
    let chunk = match compression {
        Compression::Deflate(level) => chunk_shape(&shape).map(|c| (c, level)),
        Compression::None => None,
    };
    // The same filters as the pure backend, in the same order: shuffle, then deflate.
    macro_rules! create {
        ($t:ty, $values:expr) => {{
            let b = g.new_dataset::<$t>().shape(shape);
            let b = match chunk {
                Some((c, level)) => b.chunk(c).shuffle().deflate(level),
                None => b,
            };
            b.create(ds.name.as_str())?.write_raw($values.as_slice())
        }};
    }
    match &ds.data {
        DatasetData::F64 { values, .. } => create!(f64, values),
        DatasetData::U64 { values, .. } => create!(u64, values),
    }
}

pub(crate) struct MetnoSink {
    path: PathBuf,
    file: File,
    compression: Compression,
}

impl MetnoSink {
    pub(crate) fn create(
        path: &Path,
        root_attrs: &[(String, Attr)],
        compression: Compression,
    ) -> Result<Box<dyn Sink>, OutputError> {
        if matches!(compression, Compression::Deflate(_)) && !hdf5::filters::deflate_available() {
            return Err(OutputError::BackendUnavailable {
                backend: BACKEND.to_string(),
                reason: "the HDF5 C library was built without the deflate (zlib) filter".into(),
            });
        }
        let file = File::create(path).map_err(|e| err(path, "create the file", e))?;
        let init = || -> hdf5::Result<()> {
            for (name, a) in root_attrs {
                write_attr(&file, name, a)?;
            }
            for g in TOP_GROUPS {
                file.create_group(g)?;
            }
            file.flush()
        };
        init().map_err(|e| err(path, "write the skeleton", e))?;
        Ok(Box::new(MetnoSink {
            path: path.to_path_buf(),
            file,
            compression,
        }))
    }
}

impl Sink for MetnoSink {
    fn write_group(&mut self, group: &GroupSpec<'_>, replace: bool) -> Result<(), OutputError> {
        let write = || -> hdf5::Result<()> {
            if replace && self.file.link_exists(&group.path) {
                self.file.unlink(&group.path)?;
            }
            let g = self.file.create_group(&group.path)?;
            for (name, a) in &group.attrs {
                write_attr(&g, name, a)?;
            }
            for ds in &group.datasets {
                write_dataset(&g, ds, self.compression)?;
            }
            self.file.flush()
        };
        write().map_err(|e| err(&self.path, format!("write group /{}", group.path), e))
    }

    fn close(self: Box<Self>) -> Result<(), OutputError> {
        let MetnoSink { path, file, .. } = *self;
        file.flush()
            .and_then(|()| file.close())
            .map_err(|e| err(&path, "close the file", e))
    }
}
