//! # sph-plot
//!
//! The PNG plots of sph-solids' reports (`sph converge`, the validation and trade-off reports):
//! line and log-log plots, outcome maps and particle frames, drawn with plotters' bitmap
//! backend and a bundled DejaVu Sans (licence in `assets/`), so no system font or graphics
//! library is needed. Each line plot's curves are also recorded ([`take_recorded`]) for the
//! reports' HDF5 files.

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../assets/DejaVuSans.ttf");
        // Registering can only fail on a malformed font, which the bundled file is not.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// A line plot as drawn: its file name and the curves (for `validation.h5`).
#[derive(Clone, Debug)]
pub struct PlotRecord {
    /// The PNG's file name (`tl_period_convergence.png`).
    pub file: String,
    /// Title.
    pub title: String,
    /// Axis labels.
    pub x_label: String,
    /// Axis labels.
    pub y_label: String,
    /// The curves: label and points.
    pub series: Vec<(String, Vec<(f64, f64)>)>,
}

static RECORDED: std::sync::Mutex<Vec<PlotRecord>> = std::sync::Mutex::new(Vec::new());

/// The line plots drawn since the last call (in drawing order), for the report's HDF5 file.
pub fn take_recorded() -> Vec<PlotRecord> {
    std::mem::take(&mut *RECORDED.lock().unwrap_or_else(|e| e.into_inner()))
}

/// One named series.
#[derive(Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Draw markers instead of a line.
    pub markers: bool,
}

/// Writes a line plot of `series` to `path` (800 × 500 PNG), and records its curves
/// ([`take_recorded`]).
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<(), String> {
    RECORDED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(PlotRecord {
            file: path
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default(),
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: series
                .iter()
                .map(|s| (s.label.clone(), s.points.clone()))
                .collect(),
        });
    register_font();
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 > x1 {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let pad = |a: f64, b: f64| {
        let d = (b - a).abs().max(1e-12 * a.abs().max(1.0));
        (a - 0.05 * d, b + 0.05 * d)
    };
    let (x0, x1) = pad(x0, x1);
    let (y0, y1) = pad(y0, y1);
    let root = BitMapBackend::new(path, (800, 500)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    for (k, s) in series.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        if s.markers {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(|e| err(&e))?
                .label(s.label.clone())
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(1)))
                .map_err(|e| err(&e))?;
        } else {
            chart
                .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                .map_err(|e| err(&e))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// One panel of a particle picture: points `(x, y, value)`.
pub struct Frame {
    /// Panel title (e.g. the method and time).
    pub title: String,
    /// Particles: position and the colouring value.
    pub points: Vec<(f64, f64, f64)>,
}

/// Colour of `s ∈ [0, 1]`: blue (0) through green to red (1).
fn heat(s: f64) -> HSLColor {
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        1.0
    };
    HSLColor(0.66 * (1.0 - s), 0.9, 0.45)
}

/// A horizontal colour bar at `origin` (pixels) of `width` × 14 px for values 0 … `vmax`, with
/// tick labels at 0, ½ and 1 of the range (the same map as the particles).
fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    origin: (i32, i32),
    width: i32,
    vmax: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (x0, y0) = origin;
    let steps = 100;
    for k in 0..steps {
        let a = x0 + width * k / steps;
        let b = x0 + width * (k + 1) / steps;
        let s = (k as f64 + 0.5) / steps as f64;
        area.draw(&Rectangle::new([(a, y0), (b, y0 + 14)], heat(s).filled()))?;
    }
    area.draw(&Rectangle::new([(x0, y0), (x0 + width, y0 + 14)], BLACK))?;
    for (k, frac) in [0.0, 0.5, 1.0].iter().enumerate() {
        let label = if k == 0 {
            "0".to_string()
        } else {
            format!("{:.3e}", frac * vmax)
        };
        let x = x0 + (width as f64 * frac) as i32 + 6;
        let x = if k == 2 { x } else { x - 6 };
        area.draw(&Text::new(
            label,
            (if k == 2 { x0 + width + 6 } else { x.max(x0) }, y0 + 16),
            ("sans-serif", 13).into_font(),
        ))?;
    }
    Ok(())
}

/// Particle pictures: the frames side by side (same axes, equal aspect), particles coloured by
/// value from 0 (blue) to `vmax` (red; larger values saturate; a colour bar under the title),
/// `columns` panels per row; particles are drawn as discs of diameter ≈ `dp` (at least one
/// pixel).
pub fn particle_frames(
    path: &Path,
    title: &str,
    frames: &[Frame],
    columns: usize,
    vmax: f64,
    dp: f64,
) -> Result<(), String> {
    register_font();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    if frames.is_empty() {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y, _) in frames.iter().flat_map(|f| f.points.iter()) {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    if x0 > x1 {
        return Err(format!("{}: no finite particle", path.display()));
    }
    let pad = 0.03 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let columns = columns.clamp(1, frames.len());
    let rows = frames.len().div_ceil(columns);
    let panel_w = (1600 / columns as u32).max(200);
    let plot_h = ((panel_w - 20) as f64 * (y1 - y0) / (x1 - x0)).clamp(60.0, 900.0) as u32;
    let panel_h = plot_h + 40;
    let root = BitMapBackend::new(path, (panel_w * columns as u32, panel_h * rows as u32 + 60))
        .into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (head, body) = root.split_vertically(60);
    head.draw(&Text::new(
        title.to_string(),
        (10, 6),
        ("sans-serif", 20).into_font(),
    ))
    .map_err(|e| err(&e))?;
    colour_bar(&head, (10, 32), 400, vmax).map_err(|e| err(&e))?;
    let panels = body.split_evenly((rows, columns));
    let radius = ((panel_w as f64 / (x1 - x0) * 0.45 * dp).round() as i32).clamp(1, 4);
    for (frame, area) in frames.iter().zip(panels) {
        let mut chart = ChartBuilder::on(&area)
            .caption(&frame.title, ("sans-serif", 16))
            .margin(8)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                frame
                    .points
                    .iter()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .map(|&(x, y, v)| Circle::new((x, y), radius, heat(v / vmax).filled())),
            )
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// A series of labelled points `(x, y, label)`.
pub struct LabelledSeries {
    /// Legend label.
    pub label: String,
    /// Points with a text label each (e.g. the resolution).
    pub points: Vec<(f64, f64, String)>,
}

/// Writes a log–log plot (800 × 560 PNG): each series as a line with labelled markers, and the
/// points of `front` circled (a Pareto front).
pub fn log_log_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[LabelledSeries],
    front: &[(f64, f64)],
) -> Result<(), String> {
    register_font();
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in pts {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    if x0 > x1 {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let (x0, x1, y0, y1) = (x0 / 1.5, x1 * 1.5, y0 / 1.5, y1 * 1.5);
    let root = BitMapBackend::new(path, (800, 560)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| err(&e))?;
    let compact = |v: &f64| {
        let s = format!("{:.4}", v);
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if *v >= 1000.0 || *v < 1e-3 {
            format!("{v:.0e}")
        } else {
            s.to_string()
        }
    };
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&compact)
        .y_label_formatter(&compact)
        .light_line_style(WHITE.mix(0.0))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    for (k, s) in series.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .map(|p| (p.0, p.1))
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(s.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(
                s.points
                    .iter()
                    .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                    .map(|p| Text::new(p.2.clone(), (p.0, p.1), ("sans-serif", 11).into_font())),
            )
            .map_err(|e| err(&e))?;
    }
    chart
        .draw_series(
            front
                .iter()
                .map(|&p| Circle::new(p, 8, BLACK.stroke_width(2))),
        )
        .map_err(|e| err(&e))?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// One cell of an outcome map.
pub struct MapCell {
    /// Row (method).
    pub row: usize,
    /// Column (severity value).
    pub col: usize,
    /// Outcome class, an index into the map's class names.
    pub class: usize,
    /// Text in the cell.
    pub text: String,
}

/// Writes a grid of coloured cells (rows × columns; green, orange, red, grey for classes 0–3)
/// with a legend of `classes` (PNG).
pub fn outcome_map(
    path: &Path,
    title: &str,
    rows: &[String],
    cols: &[String],
    col_label: &str,
    cells: &[MapCell],
    classes: &[&str],
) -> Result<(), String> {
    register_font();
    const COLOURS: [RGBColor; 4] = [
        RGBColor(90, 180, 90),
        RGBColor(240, 170, 60),
        RGBColor(210, 70, 60),
        RGBColor(170, 170, 170),
    ];
    let (cw, ch, left, top) = (110i32, 34i32, 110i32, 60i32);
    let width = (left + cw * cols.len() as i32 + 20).max(560) as u32;
    let height = (top + ch * rows.len() as i32 + 80) as u32;
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let font = |size: i32| ("sans-serif", size).into_font();
    root.draw(&Text::new(title.to_string(), (10, 10), font(16)))
        .map_err(|e| err(&e))?;
    for (c, name) in cols.iter().enumerate() {
        let x = left + cw * c as i32 + 8;
        root.draw(&Text::new(
            format!("{col_label} = {name}"),
            (x, top - 20),
            font(12),
        ))
        .map_err(|e| err(&e))?;
    }
    for (r, name) in rows.iter().enumerate() {
        let y = top + ch * r as i32 + 10;
        root.draw(&Text::new(name.clone(), (10, y), font(13)))
            .map_err(|e| err(&e))?;
    }
    for cell in cells {
        let (x, y) = (left + cw * cell.col as i32, top + ch * cell.row as i32);
        let colour = COLOURS[cell.class.min(3)];
        root.draw(&Rectangle::new(
            [(x, y), (x + cw - 4, y + ch - 4)],
            colour.filled(),
        ))
        .map_err(|e| err(&e))?;
        root.draw(&Text::new(cell.text.clone(), (x + 8, y + 9), font(13)))
            .map_err(|e| err(&e))?;
    }
    let ly = top + ch * rows.len() as i32 + 20;
    for (k, name) in classes.iter().enumerate().take(4) {
        let x = 10 + 130 * k as i32;
        root.draw(&Rectangle::new(
            [(x, ly), (x + 16, ly + 16)],
            COLOURS[k].filled(),
        ))
        .map_err(|e| err(&e))?;
        root.draw(&Text::new(name.to_string(), (x + 22, ly + 2), font(13)))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
