//! Dimension-agnostic datasets.

use serde::{Deserialize, Serialize};

/// The values of a [`Dataset`]: a flat, row-major buffer and its shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum DatasetData {
    /// 64-bit floats.
    F64 {
        /// Row-major values; `values.len()` is the product of `shape`.
        values: Vec<f64>,
        /// Dimensions, outermost first (the particle index for per-particle fields).
        shape: Vec<usize>,
    },
    /// 64-bit unsigned integers (ids, counts, flags).
    U64 {
        /// Row-major values; `values.len()` is the product of `shape`.
        values: Vec<u64>,
        /// Dimensions, outermost first.
        shape: Vec<usize>,
    },
}

impl DatasetData {
    /// The shape.
    pub fn shape(&self) -> &[usize] {
        match self {
            DatasetData::F64 { shape, .. } | DatasetData::U64 { shape, .. } => shape,
        }
    }

    /// The number of stored values.
    pub fn len(&self) -> usize {
        match self {
            DatasetData::F64 { values, .. } => values.len(),
            DatasetData::U64 { values, .. } => values.len(),
        }
    }

    /// Whether no values are stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `"f64"` or `"u64"`.
    pub fn type_name(&self) -> &'static str {
        match self {
            DatasetData::F64 { .. } => "f64",
            DatasetData::U64 { .. } => "u64",
        }
    }
}

/// One named field of a snapshot (or any dataset), independent of the problem's dimension.
///
/// Conventions (see the crate docs): scalars `[n]`, vectors `[n, 3]` (2D padded with `z = 0`),
/// matrices `[n, 3, 3]` (2D padded with zeros).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dataset {
    /// The dataset's name inside its group: non-empty, no `/`.
    pub name: String,
    /// The values.
    pub data: DatasetData,
}

impl Dataset {
    /// The values when they are f64 (row-major), else `None`.
    pub fn as_f64(&self) -> Option<&[f64]> {
        match &self.data {
            DatasetData::F64 { values, .. } => Some(values),
            _ => None,
        }
    }

    /// An f64 dataset of any shape.
    pub fn f64(name: impl Into<String>, values: Vec<f64>, shape: Vec<usize>) -> Self {
        Dataset {
            name: name.into(),
            data: DatasetData::F64 { values, shape },
        }
    }

    /// A u64 dataset of any shape.
    pub fn u64(name: impl Into<String>, values: Vec<u64>, shape: Vec<usize>) -> Self {
        Dataset {
            name: name.into(),
            data: DatasetData::U64 { values, shape },
        }
    }

    /// Per-particle f64 scalars, shape `[n]`.
    pub fn scalars(name: impl Into<String>, values: &[f64]) -> Self {
        Self::f64(name, values.to_vec(), vec![values.len()])
    }

    /// Per-particle u64 scalars (ids, flags), shape `[n]`.
    pub fn u64_scalars(name: impl Into<String>, values: &[u64]) -> Self {
        Self::u64(name, values.to_vec(), vec![values.len()])
    }

    /// Per-particle 3D vectors, shape `[n, 3]`.
    pub fn vectors(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        Self::f64(
            name,
            values.iter().flatten().copied().collect(),
            vec![values.len(), 3],
        )
    }

    /// Per-particle 2D vectors, stored as `[n, 3]` with `z = 0` so ParaView reads them as
    /// ordinary 3D points and vectors.
    pub fn vectors_2d(name: impl Into<String>, values: &[[f64; 2]]) -> Self {
        Self::f64(
            name,
            values.iter().flat_map(|v| [v[0], v[1], 0.0]).collect(),
            vec![values.len(), 3],
        )
    }

    /// Per-particle 3×3 matrices (rows outer), shape `[n, 3, 3]`.
    pub fn matrices(name: impl Into<String>, values: &[[[f64; 3]; 3]]) -> Self {
        Self::f64(
            name,
            values.iter().flatten().flatten().copied().collect(),
            vec![values.len(), 3, 3],
        )
    }

    /// Per-particle 2×2 matrices (rows outer), stored as `[n, 3, 3]` with zeros in the third
    /// row and column, the same shape as in 3D.
    pub fn matrices_2d(name: impl Into<String>, values: &[[[f64; 2]; 2]]) -> Self {
        Self::f64(
            name,
            values
                .iter()
                .flat_map(|m| [m[0][0], m[0][1], 0.0, m[1][0], m[1][1], 0.0, 0.0, 0.0, 0.0])
                .collect(),
            vec![values.len(), 3, 3],
        )
    }

    /// The shape.
    pub fn shape(&self) -> &[usize] {
        self.data.shape()
    }

    /// Checks name and shape; `Err` carries the reason.
    pub fn validate(&self) -> Result<(), String> {
        check_name(&self.name).map_err(|e| format!("dataset name {:?}: {e}", self.name))?;
        let shape = self.shape();
        if shape.is_empty() {
            return Err(format!(
                "dataset {:?}: shape must have at least one dimension",
                self.name
            ));
        }
        let expected = shape
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .ok_or_else(|| format!("dataset {:?}: shape {shape:?} overflows", self.name))?;
        if expected != self.data.len() {
            return Err(format!(
                "dataset {:?}: shape {shape:?} needs {expected} values, got {}",
                self.name,
                self.data.len()
            ));
        }
        Ok(())
    }
}

/// A name usable as an HDF5 link name in this layout.
pub(crate) fn check_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() {
        Err("must not be empty")
    } else if name.contains('/') {
        Err("must not contain '/'")
    } else if name == "." || name == ".." {
        Err("must not be '.' or '..'")
    } else if name.contains('\0') {
        Err("must not contain NUL")
    } else {
        Ok(())
    }
}
