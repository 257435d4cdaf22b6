//! The default backend: pure Rust through `hdf5-pure`.
//!
//! The skeleton file is built with `FileBuilder` (latest format, no userblock); every later
//! call opens nothing new but stages its group on the open read-write `File` and commits,
//! which appends the new objects, repoints the superblock last and fsyncs. So each call is
//! durable and a crash leaves the previous valid state, and memory stays bounded by one call.

use std::path::{Path, PathBuf};

use hdf5_pure::{AttrValue, DatasetBuilder, File, FileBuilder};

use crate::data::{Dataset, DatasetData};
use crate::writer::{chunk_shape, Attr, GroupSpec, Sink, TOP_GROUPS};
use crate::{Compression, OutputError};

pub(crate) const BACKEND: &str = "hdf5-pure";

pub(crate) fn err(path: &Path, context: impl Into<String>, e: hdf5_pure::Error) -> OutputError {
    OutputError::Hdf5 {
        path: path.to_path_buf(),
        backend: BACKEND,
        context: context.into(),
        message: e.to_string(),
    }
}

pub(crate) fn attr_value(a: &Attr) -> AttrValue {
    match a {
        Attr::F64(v) => AttrValue::F64(*v),
        Attr::I64(v) => AttrValue::I64(*v),
        Attr::U64(v) => AttrValue::U64(*v),
        Attr::U8(v) => AttrValue::U8(*v),
        Attr::Str(s) => AttrValue::VarLenString(s.clone()),
    }
}

fn dataset_into(b: &mut DatasetBuilder, ds: &Dataset, compression: Compression) {
    let shape: Vec<u64> = ds.shape().iter().map(|&d| d as u64).collect();
    match &ds.data {
        DatasetData::F64 { values, .. } => b.with_f64_data(values),
        DatasetData::U64 { values, .. } => b.with_u64_data(values),
    }
    .with_shape(&shape);
    if let (Compression::Deflate(level), Some(chunk)) = (compression, chunk_shape(ds.shape())) {
        let chunk: Vec<u64> = chunk.iter().map(|&d| d as u64).collect();
        b.with_chunks(&chunk)
            .with_shuffle()
            .with_deflate(u32::from(level));
    }
}

pub(crate) struct PureSink {
    path: PathBuf,
    file: File,
    compression: Compression,
}

impl PureSink {
    pub(crate) fn create(
        path: &Path,
        root_attrs: &[(String, Attr)],
        compression: Compression,
    ) -> Result<Box<dyn Sink>, OutputError> {
        let mut builder = FileBuilder::new();
        for (name, a) in root_attrs {
            builder.set_attr(name, attr_value(a));
        }
        for g in TOP_GROUPS {
            let gb = builder.create_group(g);
            builder.add_group(gb.finish());
        }
        builder
            .write(path)
            .map_err(|e| err(path, "create the file", e))?;
        let file = File::open_rw(path).map_err(|e| err(path, "open the file read-write", e))?;
        Ok(Box::new(PureSink {
            path: path.to_path_buf(),
            file,
            compression,
        }))
    }
}

impl Sink for PureSink {
    fn write_group(&mut self, group: &GroupSpec<'_>, replace: bool) -> Result<(), OutputError> {
        let ctx = format!("write group /{}", group.path);
        let compression = self.compression;
        let root = self.file.root();
        if replace {
            root.delete(&group.path)
                .map_err(|e| err(&self.path, ctx.clone(), e))?;
        }
        root.create_group_with(&group.path, |g| {
            for (name, a) in &group.attrs {
                g.set_attr(name, attr_value(a));
            }
            for ds in &group.datasets {
                g.create_dataset(&ds.name, |b| dataset_into(b, ds, compression));
            }
        })
        .map_err(|e| err(&self.path, ctx.clone(), e))?;
        drop(root);
        self.file.commit().map_err(|e| err(&self.path, ctx, e))
    }

    fn close(self: Box<Self>) -> Result<(), OutputError> {
        let PureSink { path, file, .. } = *self;
        file.close().map_err(|e| err(&path, "close the file", e))
    }
}
