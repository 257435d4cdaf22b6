//! The XDMF 3 sidecar that lets ParaView, VisIt and meshio open the snapshots of a results file.
//!
//! One `Grid` collection (`CollectionType="Temporal"`) holds one uniform grid per snapshot
//! that has a `position` dataset (a snapshot without one has no geometry and is left out of
//! the sidecar, though it stays in the `.h5`). Each grid has
//!
//! * a `Time` value (the snapshot's `time` attribute);
//! * a `Polyvertex` topology of `n` one-node cells (`n` = rows of `position`) with its
//!   connectivity as a data item, which meshio requires (it reads cells from it) and VTK's
//!   readers use when present: the snapshot's `id` dataset when that is a permutation of
//!   `0..n` (what `sph-driver` writes), so the connectivity costs no storage; otherwise the
//!   list `0 1 … n-1` inline in the XML;
//! * an `XYZ` geometry read from `/snapshots/<k>/position` (`[n, 3]`, 2D padded `z = 0`);
//! * one `Center="Node"` attribute per dataset whose first dimension is `n`, typed by shape:
//!   `[n]` or `[n, 1]` → `Scalar`, `[n, 3]` → `Vector`, `[n, 6]` → `Tensor6`, `[n, 3, 3]` or
//!   `[n, 9]` → `Tensor`, anything else → `Matrix`. `position` is listed as a `Vector`
//!   attribute too: readers of time series that take the geometry of the first grid only
//!   (meshio's `TimeSeriesReader`) then still get each frame's positions. Datasets of another
//!   first dimension are not per-particle and are not listed.
//!
//! Data items reference the `.h5` by its bare file name, so the pair can be moved together.
//! `f64` data is `NumberType="Float" Precision="8"`; `u64` data (ids) is declared
//! `NumberType="Int" Precision="8"`, which the HDF5 library converts exactly for values
//! below 2⁶³: VTK's XDMF 2 reader has no unsigned 64-bit type.

use std::fmt::Write as _;

/// One field of a snapshot, as far as the sidecar needs it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct XdmfField {
    pub name: String,
    pub is_u64: bool,
    pub shape: Vec<usize>,
}

/// One snapshot, as far as the sidecar needs it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct XdmfSnapshot {
    pub name: String,
    pub time: f64,
    pub fields: Vec<XdmfField>,
    /// The u64 dataset holding a permutation of `0..n` (the particle ids), if any: the
    /// topology's connectivity.
    pub vertex_ids: Option<String>,
}

impl XdmfSnapshot {
    /// What the sidecar needs of the snapshot `name` at `time` with these datasets; the
    /// connectivity is the `id` dataset when it is a permutation of `0..n` (`n` = rows of
    /// `position`).
    pub(crate) fn of(name: String, time: f64, datasets: &[crate::Dataset]) -> Self {
        let position = datasets.iter().find(|d| d.name == "position");
        let vertex_ids = position.and_then(|p| {
            let n = p.shape()[0];
            datasets
                .iter()
                .find(|d| d.name == "id")
                .filter(|d| matches!(d.shape(), [m] | [m, 1] if *m == n))
                .and_then(|d| match &d.data {
                    crate::DatasetData::U64 { values, .. } if is_permutation(values, n) => {
                        Some(d.name.clone())
                    }
                    _ => None,
                })
        });
        XdmfSnapshot {
            name,
            time,
            vertex_ids,
            fields: datasets
                .iter()
                .map(|d| XdmfField {
                    name: d.name.clone(),
                    is_u64: d.data.type_name() == "u64",
                    shape: d.shape().to_vec(),
                })
                .collect(),
        }
    }
}

/// Whether `values` (a u64 dataset of `n` rows, one column) is a permutation of `0..n`: then
/// it can serve as the connectivity of the `Polyvertex` topology.
pub(crate) fn is_permutation(values: &[u64], n: usize) -> bool {
    if values.len() != n {
        return false;
    }
    let mut seen = vec![false; n];
    for &v in values {
        match usize::try_from(v).ok().and_then(|i| seen.get_mut(i)) {
            Some(s) if !*s => *s = true,
            _ => return false,
        }
    }
    true
}

/// The XDMF attribute type for a per-particle dataset of this shape (first dimension = the
/// particle count).
pub fn attribute_type(shape: &[usize]) -> &'static str {
    match shape {
        [_] | [_, 1] => "Scalar",
        [_, 3] => "Vector",
        [_, 6] => "Tensor6",
        [_, 9] | [_, 3, 3] => "Tensor",
        _ => "Matrix",
    }
}

/// Escapes text for XML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// A data item of `field` with `rows` as its first dimension (a rank's share of the body).
fn data_item_rows(
    out: &mut String,
    h5_name: &str,
    snap: &str,
    field: &XdmfField,
    rows: usize,
    indent: &str,
) {
    let mut dims: Vec<String> = field.shape.iter().map(usize::to_string).collect();
    if let Some(d) = dims.first_mut() {
        *d = rows.to_string();
    }
    // Int, not UInt: see the module documentation.
    let number_type = if field.is_u64 { "Int" } else { "Float" };
    let _ = writeln!(
        out,
        "{indent}<DataItem Dimensions=\"{}\" NumberType=\"{number_type}\" Precision=\"8\" Format=\"HDF\">{}:/snapshots/{}/{}</DataItem>",
        dims.join(" "),
        escape(h5_name),
        escape(snap),
        escape(&field.name),
    );
}

fn header(out: &mut String) {
    out.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    out.push_str("<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n");
    out.push_str("<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n");
    out.push_str("  <Domain>\n");
    out.push_str(
        "    <Grid Name=\"snapshots\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
    );
}

fn footer(out: &mut String) {
    out.push_str("    </Grid>\n");
    out.push_str("  </Domain>\n");
    out.push_str("</Xdmf>\n");
}

/// One uniform grid: the snapshot `snap` of the file `h5_name`, with `n` particles (the first
/// dimension of its per-particle datasets there), indented by `ind`; `time` is written when
/// the grid is a member of the temporal collection itself.
fn uniform_grid(
    out: &mut String,
    h5_name: &str,
    grid_name: &str,
    snap: &XdmfSnapshot,
    n: usize,
    time: Option<f64>,
    ind: &str,
) {
    let Some(pos) = snap.fields.iter().find(|f| f.name == "position") else {
        return;
    };
    let n0 = pos.shape[0];
    let item = |out: &mut String, field: &XdmfField, indent: &str| {
        data_item_rows(
            out,
            h5_name,
            &snap.name,
            field,
            n,
            &format!("{ind}{indent}"),
        )
    };
    let _ = writeln!(
        out,
        "{ind}<Grid Name=\"{}\" GridType=\"Uniform\">",
        escape(grid_name)
    );
    if let Some(t) = time {
        let _ = writeln!(out, "{ind}  <Time Value=\"{t:?}\"/>");
    }
    let _ = writeln!(
        out,
        "{ind}  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{n}\" NodesPerElement=\"1\">"
    );
    match snap
        .vertex_ids
        .as_ref()
        .and_then(|id| snap.fields.iter().find(|f| &f.name == id))
    {
        Some(ids) => item(out, ids, "    "),
        None => {
            let _ = write!(
                out,
                "{ind}    <DataItem Dimensions=\"{n}\" NumberType=\"Int\" Precision=\"8\" Format=\"XML\">"
            );
            for k in 0..n {
                let _ = write!(out, "{}{k}", if k == 0 { "" } else { " " });
            }
            out.push_str("</DataItem>\n");
        }
    }
    let _ = writeln!(out, "{ind}  </Topology>");
    let _ = writeln!(out, "{ind}  <Geometry GeometryType=\"XYZ\">");
    item(out, pos, "    ");
    let _ = writeln!(out, "{ind}  </Geometry>");
    // `position` first (see the module documentation), then the others in file order.
    let per_particle = snap
        .fields
        .iter()
        .filter(|f| f.name != "position" && f.shape.first() == Some(&n0));
    for field in std::iter::once(pos).chain(per_particle) {
        let _ = writeln!(
            out,
            "{ind}  <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">",
            escape(&field.name),
            attribute_type(&field.shape)
        );
        item(out, field, "    ");
        let _ = writeln!(out, "{ind}  </Attribute>");
    }
    let _ = writeln!(out, "{ind}</Grid>");
}

/// Renders the sidecar for `snapshots` of the file `h5_name` (a bare file name).
pub(crate) fn render(h5_name: &str, snapshots: &[XdmfSnapshot]) -> String {
    let mut out = String::new();
    header(&mut out);
    for snap in snapshots {
        if let Some(pos) = snap.fields.iter().find(|f| f.name == "position") {
            let n = pos.shape[0];
            uniform_grid(
                &mut out,
                h5_name,
                &snap.name,
                snap,
                n,
                Some(snap.time),
                "      ",
            );
        }
    }
    footer(&mut out);
    out
}

/// Renders the XDMF that presents the per-rank files `rank_files` of a distributed run as one
/// body: per snapshot a spatial collection (with the snapshot's time) of one uniform grid per
/// rank, `counts[r]` particles read from `rank_files[r]`. `snapshots` are the snapshots as rank
/// 0 wrote them (every rank writes the same datasets; only the particle count differs).
pub(crate) fn render_ranks(
    rank_files: &[String],
    counts: &[usize],
    snapshots: &[XdmfSnapshot],
) -> String {
    let mut out = String::new();
    header(&mut out);
    for snap in snapshots {
        if !snap.fields.iter().any(|f| f.name == "position") {
            continue;
        }
        let _ = writeln!(
            out,
            "      <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Spatial\">",
            escape(&snap.name)
        );
        let _ = writeln!(out, "        <Time Value=\"{:?}\"/>", snap.time);
        for (r, (file, &n)) in rank_files.iter().zip(counts).enumerate() {
            if n > 0 {
                let name = format!("rank{r}");
                uniform_grid(&mut out, file, &name, snap, n, None, "        ");
            }
        }
        out.push_str("      </Grid>\n");
    }
    footer(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attribute_types_by_shape() {
        assert_eq!(attribute_type(&[5]), "Scalar");
        assert_eq!(attribute_type(&[5, 1]), "Scalar");
        assert_eq!(attribute_type(&[5, 3]), "Vector");
        assert_eq!(attribute_type(&[5, 3, 3]), "Tensor");
        assert_eq!(attribute_type(&[5, 6]), "Tensor6");
        assert_eq!(attribute_type(&[5, 2, 2]), "Matrix");
    }

    #[test]
    fn permutations_only() {
        assert!(is_permutation(&[2, 0, 1], 3));
        assert!(is_permutation(&[], 0));
        assert!(!is_permutation(&[0, 0, 1], 3), "repeated");
        assert!(!is_permutation(&[0, 1, 3], 3), "out of range");
        assert!(!is_permutation(&[0, 1], 3), "too short");
        assert!(!is_permutation(&[u64::MAX], 1));
    }

    #[test]
    fn escapes_markup() {
        assert_eq!(escape("a<b>&\"'"), "a&lt;b&gt;&amp;&quot;&apos;");
    }
}
