//! `validation.h5`: the report's tables and curves in one HDF5 file, made by the same run of
//! `validate report` that writes `docs/validation.md`, under `target/validation-results/`
//! (outside git, with the runs' own HDF5 files).
//!
//! Layout (h5py: `h5py.File("target/validation-results/validation.h5")`):
//!
//! ```text
//! /                          attrs: source = "docs/validation.md", generated_by
//! /<section>/                one group per `##` section of the report; attr title
//!   table_01/                one group per markdown table, in order
//!     header                 strings [columns]
//!     cells                  strings [rows, columns] — exactly the report's cells
//!     c03_<header>           f64 [rows] for every column whose cells are all numbers
//!                            (`–` and empty → NaN; a `%` column holds the percentages as
//!                            printed, attr unit = "%")
//!   figures/<png stem>/      one group per line plot shown in the section; attrs title,
//!                            x_label, y_label, file
//!     s01_<label>/ x, y      one group per curve; attr label
//! ```
//!
//! The tables are parsed from the generated markdown, so the file holds the same numbers as
//! docs/validation.md by construction; the curves are the points the PNG plots were drawn from.

use crate::plot::PlotRecord;
use hdf5_pure::{AttrValue, FileBuilder, GroupBuilder};
use std::path::Path;

/// One markdown table: header and rows of cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Column headers.
    pub header: Vec<String>,
    /// Rows of cells (as many as the header; short rows are padded with empty cells).
    pub rows: Vec<Vec<String>>,
}

/// One `##` section: title, tables and the PNG files it shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// The heading text.
    pub title: String,
    /// Its tables in order.
    pub tables: Vec<Table>,
    /// The images it links (file names).
    pub images: Vec<String>,
}

fn cells(line: &str) -> Vec<String> {
    let t = line.trim();
    let t = t.strip_prefix('|').unwrap_or(t);
    let t = t.strip_suffix('|').unwrap_or(t);
    t.split('|').map(|c| c.trim().to_string()).collect()
}

fn is_rule(line: &str) -> bool {
    cells(line)
        .iter()
        .all(|c| !c.is_empty() && c.chars().all(|ch| ch == '-' || ch == ':'))
}

/// Splits the report into `##` sections (the text before the first one is dropped) with their
/// tables (`| … |` lines under a header and a `|---|` rule) and linked images.
pub fn parse_sections(md: &str) -> Vec<Section> {
    let mut out: Vec<Section> = Vec::new();
    let lines: Vec<&str> = md.lines().collect();
    let mut k = 0;
    while k < lines.len() {
        let line = lines[k];
        if let Some(title) = line.strip_prefix("## ") {
            out.push(Section {
                title: title.trim().to_string(),
                tables: Vec::new(),
                images: Vec::new(),
            });
        } else if let Some(sec) = out.last_mut() {
            if line.trim_start().starts_with('|')
                && k + 1 < lines.len()
                && lines[k + 1].trim_start().starts_with('|')
                && is_rule(lines[k + 1])
            {
                let header = cells(line);
                let mut rows = Vec::new();
                k += 2;
                while k < lines.len() && lines[k].trim_start().starts_with('|') {
                    let mut r = cells(lines[k]);
                    r.resize(header.len(), String::new());
                    rows.push(r);
                    k += 1;
                }
                sec.tables.push(Table { header, rows });
                continue;
            } else if let Some(start) = line.find("](") {
                if line.trim_start().starts_with("![") {
                    let link = &line[start + 2..];
                    if let Some(end) = link.find(')') {
                        let file = link[..end].rsplit('/').next().unwrap_or("").to_string();
                        sec.images.push(file);
                    }
                }
            }
        }
        k += 1;
    }
    out
}

/// A cell as a number: `0.2742`, `+3.58 %`, `-2.97 %`, `1.2e6`, `5.30e6`; `–`, `-` or empty →
/// NaN; `None` for text.
pub fn number(cell: &str) -> Option<f64> {
    let c = cell.trim();
    if c.is_empty() || c == "–" || c == "-" {
        return Some(f64::NAN);
    }
    let c = c.strip_suffix('%').map_or(c, str::trim);
    let c = c.strip_prefix('+').unwrap_or(c);
    c.parse::<f64>().ok()
}

/// A name usable as an HDF5 link: lower case, `[a-z0-9_]`, at most 48 characters.
pub fn slug(s: &str) -> String {
    let mut out = String::new();
    for ch in s.chars() {
        match ch {
            'a'..='z' | '0'..='9' => out.push(ch),
            'A'..='Z' => out.push(ch.to_ascii_lowercase()),
            _ if !out.ends_with('_') && !out.is_empty() => out.push('_'),
            _ => {}
        }
    }
    let t = out.trim_end_matches('_');
    t.chars().take(48).collect::<String>()
}

fn table_group(parent: &mut GroupBuilder, name: &str, t: &Table) {
    let mut g = parent.create_group(name);
    let header: Vec<&str> = t.header.iter().map(String::as_str).collect();
    g.create_dataset("header").with_vlen_strings(&header);
    let flat: Vec<&str> = t.rows.iter().flatten().map(String::as_str).collect();
    if !flat.is_empty() {
        g.create_dataset("cells")
            .with_vlen_strings(&flat)
            .with_shape(&[t.rows.len() as u64, t.header.len() as u64]);
    }
    for (c, h) in t.header.iter().enumerate() {
        let col: Vec<&str> = t.rows.iter().map(|r| r[c].as_str()).collect();
        let values: Option<Vec<f64>> = col.iter().map(|v| number(v)).collect();
        match values {
            Some(v) if !v.is_empty() && v.iter().any(|x| x.is_finite()) => {
                let ds = g.create_dataset(&format!("c{:02}_{}", c + 1, slug(h)));
                ds.with_f64_data(&v);
                ds.set_attr("header", AttrValue::VarLenString(h.clone()));
                if col.iter().any(|x| x.trim_end().ends_with('%')) {
                    ds.set_attr("unit", AttrValue::VarLenString("%".into()));
                }
            }
            _ => {}
        }
    }
    parent.add_group(g.finish());
}

fn figure_group(parent: &mut GroupBuilder, p: &PlotRecord) {
    let stem = p.file.strip_suffix(".png").unwrap_or(&p.file);
    let mut g = parent.create_group(&slug(stem));
    g.set_attr("title", AttrValue::VarLenString(p.title.clone()));
    g.set_attr("x_label", AttrValue::VarLenString(p.x_label.clone()));
    g.set_attr("y_label", AttrValue::VarLenString(p.y_label.clone()));
    g.set_attr("file", AttrValue::VarLenString(p.file.clone()));
    for (k, (label, pts)) in p.series.iter().enumerate() {
        let mut s = g.create_group(&format!("s{:02}_{}", k + 1, slug(label)));
        s.set_attr("label", AttrValue::VarLenString(label.clone()));
        let x: Vec<f64> = pts.iter().map(|p| p.0).collect();
        let y: Vec<f64> = pts.iter().map(|p| p.1).collect();
        s.create_dataset("x").with_f64_data(&x);
        s.create_dataset("y").with_f64_data(&y);
        g.add_group(s.finish());
    }
    parent.add_group(g.finish());
}

/// Writes `path` (through a temporary file renamed at the end) from the report `md` and the
/// line plots drawn for it.
pub fn write(path: &Path, md: &str, plots: &[PlotRecord]) -> Result<(), String> {
    let mut fb = FileBuilder::new();
    fb.set_attr(
        "source",
        AttrValue::VarLenString("docs/validation.md".into()),
    );
    fb.set_attr(
        "generated_by",
        AttrValue::VarLenString(
            "cargo run --release -p sph-validation --bin validate -- report".into(),
        ),
    );
    let mut used = std::collections::BTreeSet::new();
    for (k, sec) in parse_sections(md).iter().enumerate() {
        // Unique group names even if two headings slug alike.
        let mut name = slug(&sec.title);
        if name.is_empty() || !used.insert(name.clone()) {
            name = format!("{name}_{}", k + 1);
            used.insert(name.clone());
        }
        let mut g = fb.create_group(&name);
        g.set_attr("title", AttrValue::VarLenString(sec.title.clone()));
        for (t, table) in sec.tables.iter().enumerate() {
            table_group(&mut g, &format!("table_{:02}", t + 1), table);
        }
        let figs: Vec<&PlotRecord> = sec
            .images
            .iter()
            .filter_map(|img| plots.iter().rev().find(|p| &p.file == img))
            .collect();
        if !figs.is_empty() {
            let mut f = g.create_group("figures");
            let mut seen = std::collections::BTreeSet::new();
            for p in figs {
                if seen.insert(p.file.clone()) {
                    figure_group(&mut f, p);
                }
            }
            g.add_group(f.finish());
        }
        fb.add_group(g.finish());
    }
    let bytes = fb
        .finish()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let tmp = path.with_extension("h5.tmp");
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_tables_and_images_are_parsed_as_written() {
        let md = "# V\n\nintro\n\n## A: first\n\ntext\n\n| x | T | err |\n|---|---|---|\n\
                  | 10 | 0.2742 | +3.58 % |\n| 20 | – | – |\n\n![p](validation/a_plot.png)\n\n\
                  ## B\n\n| k |\n|---|\n| text |\n";
        let s = parse_sections(md);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].title, "A: first");
        assert_eq!(s[0].tables[0].header, ["x", "T", "err"]);
        assert_eq!(s[0].tables[0].rows[1], ["20", "–", "–"]);
        assert_eq!(s[0].images, ["a_plot.png"]);
        assert_eq!(s[1].tables[0].rows, [["text"]]);
        assert_eq!(number("+3.58 %"), Some(3.58));
        assert_eq!(number("-2.97 %"), Some(-2.97));
        assert!(number("–").unwrap().is_nan());
        assert_eq!(number("completed"), None);
        assert_eq!(
            slug("TL-SPH: the clamp (Table 1)"),
            "tl_sph_the_clamp_table_1"
        );
    }

    #[test]
    fn written_file_reads_back_with_the_report_numbers_and_curves() {
        let md = "## Plate\n\n| H/dp | T | err | status |\n|---|---|---|---|\n\
                  | 10 | 0.2742 | +3.58 % | completed |\n| 40 | – | – | not run |\n\n\
                  ![c](validation/conv.png)\n";
        let plots = [PlotRecord {
            file: "conv.png".into(),
            title: "t".into(),
            x_label: "H/dp".into(),
            y_label: "T".into(),
            series: vec![("TL-HF, frame".into(), vec![(10.0, 0.2742), (40.0, 0.2652)])],
        }];
        let dir = std::env::temp_dir().join(format!("h5report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("validation.h5");
        write(&path, md, &plots).unwrap();
        let f = hdf5_pure::File::open(&path).unwrap();
        let t = f
            .dataset("plate/table_01/c02_t")
            .unwrap()
            .read_f64()
            .unwrap();
        assert_eq!(t[0], 0.2742);
        assert!(t[1].is_nan());
        let e = f
            .dataset("plate/table_01/c03_err")
            .unwrap()
            .read_f64()
            .unwrap();
        assert_eq!(e[0], 3.58);
        // The text column has no numeric dataset; its cells are in `cells`.
        assert!(f.dataset("plate/table_01/c04_status").is_err());
        assert_eq!(
            f.dataset("plate/table_01/cells").unwrap().shape().unwrap(),
            vec![2, 4]
        );
        let y = f
            .dataset("plate/figures/conv/s01_tl_hf_frame/y")
            .unwrap()
            .read_f64()
            .unwrap();
        assert_eq!(y, [0.2742, 0.2652]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
