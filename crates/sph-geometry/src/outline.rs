//! 2D outlines: closed polylines read from a text file of vertices (`.csv`, `.txt`, `.xy`,
//! `.dat`) or from the `<polygon>`/`<polyline>` elements of an SVG drawing (`.svg`), placed by a
//! [`Placement`] (scale, rotation about `z`, translation), as an [`OutlineSolid`]: a 2D
//! [`Shape`] with the distance to its outline.
//!
//! Text: one vertex per line, `x, y` or `x y` (`#` starts a comment), a blank line between loops;
//! the last vertex joins the first. Several loops make holes and islands by the even-odd rule
//! (a point is inside when it is inside an odd number of loops), whatever the loops'
//! orientations. SVG's `y` axis points down; it is turned up (`y → −y`) so that the part reads
//! as drawn. SVG `transform` attributes are refused (not silently ignored): apply them in the
//! drawing program first (Inkscape: Path ▸ Object to Path, then save as plain SVG).
//!
//! An outline that crosses itself has no well-defined inside: it is refused with the number of
//! crossings and the first pair of segments.
//!
//! ```
//! use sph_geometry::outline::OutlineSolid;
//! use sph_geometry::{generate::Shape, glam::DVec2};
//!
//! // An L-shaped plate from its six corners.
//! let l = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
//! let solid = OutlineSolid::new(vec![l.iter().map(|&(x, y)| DVec2::new(x, y)).collect()], "L")?;
//! assert!(solid.contains(DVec2::new(0.5, 1.5)) && !solid.contains(DVec2::new(1.5, 1.5)));
//! assert_eq!(solid.area(), 3.0);
//! # Ok::<(), sph_core::Error>(())
//! ```

use crate::file_error;
use crate::generate::Shape;
use crate::mesh::Placement;
use crate::Boundary;
use glam::{DVec2, DVec3};
use sph_core::{Error, D2};
use std::path::Path;

/// A 2D region bounded by closed polylines (even-odd rule).
#[derive(Clone, Debug)]
pub struct OutlineSolid {
    name: String,
    loops: Vec<Vec<DVec2>>,
    /// Segments `(a, b)` of every loop.
    segments: Vec<(DVec2, DVec2)>,
    bounds: (DVec2, DVec2),
    area: f64,
}

/// Reads the loops of an outline file, by extension (see the module documentation).
pub fn read_loops(path: &Path) -> Result<Vec<Vec<DVec2>>, Error> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| file_error(&name, e))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("svg") => svg_loops(&text, &name),
        Some("csv" | "txt" | "xy" | "dat") => text_loops(&text, &name),
        _ => Err(file_error(
            &name,
            "unknown outline format: allowed extensions are .csv, .txt, .xy, .dat and .svg",
        )),
    }
}

fn text_loops(text: &str, name: &str) -> Result<Vec<Vec<DVec2>>, Error> {
    let mut loops = vec![Vec::new()];
    for (k, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            if !loops.last().is_some_and(|l: &Vec<DVec2>| l.is_empty()) {
                loops.push(Vec::new());
            }
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let parsed: Option<Vec<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        match parsed.as_deref() {
            Some([x, y]) if x.is_finite() && y.is_finite() => {
                loops.last_mut().expect("one loop").push(DVec2::new(*x, *y))
            }
            // A header line before any vertex (e.g. `x,y`) is allowed.
            None if k == 0 => {}
            _ => {
                return Err(file_error(
                    name,
                    format!("line {}: `{line}` is not two finite numbers `x, y`", k + 1),
                ))
            }
        }
    }
    loops.retain(|l| !l.is_empty());
    Ok(loops)
}

fn svg_loops(text: &str, name: &str) -> Result<Vec<Vec<DVec2>>, Error> {
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| file_error(name, format!("not a readable SVG file: {e}")))?;
    let mut loops = Vec::new();
    for node in doc.descendants().filter(|n| n.is_element()) {
        let tag = node.tag_name().name();
        if !(tag == "polygon" || tag == "polyline") {
            continue;
        }
        if node.ancestors().any(|a| a.attribute("transform").is_some()) {
            return Err(file_error(
                name,
                format!("a <{tag}> under a `transform` attribute: apply the transform in the drawing first"),
            ));
        }
        let points = node.attribute("points").unwrap_or("");
        let numbers: Result<Vec<f64>, _> = points
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .map(|f| f.parse::<f64>())
            .collect();
        let numbers = match numbers {
            Ok(v) if v.len() % 2 == 0 && v.iter().all(|x| x.is_finite()) => v,
            _ => {
                return Err(file_error(
                    name,
                    format!("<{tag}> points `{points}` are not pairs of finite numbers"),
                ))
            }
        };
        loops.push(
            numbers
                .chunks_exact(2)
                .map(|p| DVec2::new(p[0], -p[1]))
                .collect(),
        );
    }
    if loops.is_empty() {
        return Err(file_error(name, "no <polygon> or <polyline> element"));
    }
    Ok(loops)
}

/// Twice the signed area of a closed loop (positive counter-clockwise).
fn twice_area(l: &[DVec2]) -> f64 {
    (0..l.len())
        .map(|i| l[i].perp_dot(l[(i + 1) % l.len()]))
        .sum()
}

/// Whether segments `p1p2` and `q1q2` cross (proper crossing, or touching away from a shared
/// end point of neighbouring segments, which the caller excludes).
fn segments_cross(p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2) -> bool {
    let o = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let (d1, d2) = (o(q1, q2, p1), o(q1, q2, p2));
    let (d3, d4) = (o(p1, p2, q1), o(p1, p2, q2));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: DVec2, b: DVec2, c: DVec2| {
        c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
    };
    (d1 == 0.0 && on(q1, q2, p1))
        || (d2 == 0.0 && on(q1, q2, p2))
        || (d3 == 0.0 && on(p1, p2, q1))
        || (d4 == 0.0 && on(p1, p2, q2))
}

impl OutlineSolid {
    /// The region of `loops` (each closed implicitly; a repeated closing vertex and repeated
    /// consecutive vertices are dropped); `name` names it in errors.
    ///
    /// # Errors
    /// No loop, a loop of fewer than three distinct vertices or zero area, non-finite
    /// coordinates, or an outline that crosses itself (with the number of crossings).
    pub fn new(loops: Vec<Vec<DVec2>>, name: &str) -> Result<Self, Error> {
        let mut clean = Vec::new();
        for (k, mut l) in loops.into_iter().enumerate() {
            if l.iter().any(|v| !v.is_finite()) {
                return Err(file_error(
                    name,
                    format!("loop {} has a non-finite vertex", k + 1),
                ));
            }
            l.dedup();
            while l.len() > 1 && l.first() == l.last() {
                l.pop();
            }
            if l.len() < 3 {
                return Err(file_error(
                    name,
                    format!(
                        "loop {} has {} distinct vertices: a closed outline needs at least 3",
                        k + 1,
                        l.len()
                    ),
                ));
            }
            clean.push(l);
        }
        if clean.is_empty() {
            return Err(file_error(name, "no vertices: an outline needs at least 3"));
        }
        // Segments with the loop and position they come from (neighbours share an end).
        let mut segments = Vec::new();
        let mut owner = Vec::new();
        for (k, l) in clean.iter().enumerate() {
            for i in 0..l.len() {
                segments.push((l[i], l[(i + 1) % l.len()]));
                owner.push((k, i, l.len()));
            }
        }
        let (crossings, first) = count_crossings(&segments, &owner);
        if crossings > 0 {
            let ((ka, ia), (kb, ib)) = first.expect("a crossing");
            return Err(file_error(
                name,
                format!(
                    "the outline crosses itself ({crossings} crossings; first: segment {} of loop {} and segment {} of loop {}): its inside is undefined",
                    ia + 1,
                    ka + 1,
                    ib + 1,
                    kb + 1
                ),
            ));
        }
        if let Some(k) = clean.iter().position(|l| twice_area(l) == 0.0) {
            return Err(file_error(
                name,
                format!(
                    "loop {} encloses no area (its vertices are on one line)",
                    k + 1
                ),
            ));
        }
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for v in clean.iter().flatten() {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let mut solid = Self {
            name: name.into(),
            loops: clean,
            segments,
            bounds: (lo, hi),
            area: 0.0,
        };
        // Even-odd area: a loop inside an odd number of others is a hole.
        solid.area = solid
            .loops
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let depth = solid
                    .loops
                    .iter()
                    .enumerate()
                    .filter(|&(j, other)| j != k && crossing_parity(other, l[0]))
                    .count();
                let a = 0.5 * twice_area(l).abs();
                if depth % 2 == 0 {
                    a
                } else {
                    -a
                }
            })
            .sum();
        Ok(solid)
    }

    /// Reads `path` ([`read_loops`]), places it (rotation about `z` only) and makes the region.
    pub fn read(path: &Path, placement: &Placement) -> Result<Self, Error> {
        placement.validate()?;
        if placement.degrees != 0.0
            && placement.axis.normalize().abs_diff_eq(DVec3::Z, 1e-12)
                == placement.axis.normalize().abs_diff_eq(-DVec3::Z, 1e-12)
        {
            return Err(Error::invalid(
                "rotate.axis",
                format!("{:?}", placement.axis.to_array()),
                "[0, 0, 1] or omitted (a 2D outline turns about z)",
            ));
        }
        let name = path.display().to_string();
        let r = placement.rotation();
        let loops = read_loops(path)?
            .into_iter()
            .map(|l| {
                l.into_iter()
                    .map(|v| {
                        let x = r * (v.extend(0.0) * placement.scale) + placement.translate;
                        DVec2::new(x.x, x.y)
                    })
                    .collect()
            })
            .collect();
        Self::new(loops, &name)
    }

    /// The loops as cleaned.
    pub fn loops(&self) -> &[Vec<DVec2>] {
        &self.loops
    }

    /// The enclosed area.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// The distance from `x` to the outline and the closest point on it.
    pub fn closest(&self, x: DVec2) -> (f64, DVec2) {
        let mut best = (f64::INFINITY, x);
        for &(a, b) in &self.segments {
            let ab = b - a;
            let t = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
            let p = a + ab * t;
            let d = (x - p).length_squared();
            if d < best.0 {
                best = (d, p);
            }
        }
        (best.0.sqrt(), best.1)
    }
}

/// Whether `x` is inside the closed loop `l` by the crossing number (even-odd).
fn crossing_parity(l: &[DVec2], x: DVec2) -> bool {
    let mut inside = false;
    let n = l.len();
    for i in 0..n {
        let (a, b) = (l[i], l[(i + 1) % n]);
        if (a.y > x.y) != (b.y > x.y) {
            let t = (x.y - a.y) / (b.y - a.y);
            if x.x < a.x + t * (b.x - a.x) {
                inside = !inside;
            }
        }
    }
    inside
}

/// Crossings between non-neighbouring segments: sweep over `x` with the segments sorted by
/// their left end, so only segments whose `x` ranges overlap are compared.
#[allow(clippy::type_complexity)]
fn count_crossings(
    segments: &[(DVec2, DVec2)],
    owner: &[(usize, usize, usize)],
) -> (usize, Option<((usize, usize), (usize, usize))>) {
    let mut order: Vec<usize> = (0..segments.len()).collect();
    let left = |s: usize| segments[s].0.x.min(segments[s].1.x);
    let right = |s: usize| segments[s].0.x.max(segments[s].1.x);
    order.sort_by(|&a, &b| left(a).total_cmp(&left(b)));
    let neighbours = |a: usize, b: usize| {
        let ((ka, ia, n), (kb, ib, _)) = (owner[a], owner[b]);
        ka == kb && ((ia + 1) % n == ib || (ib + 1) % n == ia)
    };
    let mut count = 0;
    let mut first = None;
    for (p, &a) in order.iter().enumerate() {
        for &b in &order[p + 1..] {
            if left(b) > right(a) {
                break;
            }
            if neighbours(a, b) {
                // Neighbours share an end; they cross only by folding back on each other.
                let (sa, sb) = (segments[a], segments[b]);
                let (shared, ea, eb) = if sa.1 == sb.0 {
                    (sa.1, sa.0, sb.1)
                } else {
                    (sa.0, sa.1, sb.0)
                };
                let (u, v) = (ea - shared, eb - shared);
                if u.perp_dot(v) == 0.0 && u.dot(v) > 0.0 {
                    count += 1;
                    first.get_or_insert(((owner[a].0, owner[a].1), (owner[b].0, owner[b].1)));
                }
                continue;
            }
            let (sa, sb) = (segments[a], segments[b]);
            if segments_cross(sa.0, sa.1, sb.0, sb.1) {
                count += 1;
                let (x, y) = ((owner[a].0, owner[a].1), (owner[b].0, owner[b].1));
                first.get_or_insert(if x <= y { (x, y) } else { (y, x) });
            }
        }
    }
    (count, first)
}

impl Shape<D2> for OutlineSolid {
    fn contains(&self, x: DVec2) -> bool {
        if !(x.cmpge(self.bounds.0).all() && x.cmple(self.bounds.1).all()) {
            return false;
        }
        self.loops.iter().filter(|l| crossing_parity(l, x)).count() % 2 == 1
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        self.bounds
    }
}

impl Boundary<D2> for OutlineSolid {
    fn signed_distance_on_side(&self, x: DVec2, inside: bool) -> (f64, DVec2) {
        let (d, p) = self.closest(x);
        if d > 0.0 {
            let away = (x - p) / d;
            return if inside { (-d, -away) } else { (d, away) };
        }
        self.signed_distance(x)
    }

    fn signed_distance(&self, x: DVec2) -> (f64, DVec2) {
        let (d, p) = self.closest(x);
        let inside = self.contains(x);
        if d > 0.0 {
            let away = (x - p) / d;
            return if inside { (-d, -away) } else { (d, away) };
        }
        // On the outline: the normal of the nearest segment, turned outward by a probe.
        let seg = self
            .segments
            .iter()
            .min_by(|s, t| {
                let f = |s: &(DVec2, DVec2)| {
                    let ab = s.1 - s.0;
                    let t = ((x - s.0).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                    (x - (s.0 + ab * t)).length_squared()
                };
                f(s).total_cmp(&f(t))
            })
            .expect("segments");
        let n = (seg.1 - seg.0).perp().normalize();
        let eps = 1e-9 * (self.bounds.1 - self.bounds.0).max_element();
        (0.0, if self.contains(x + n * eps) { -n } else { n })
    }

    fn volume(&self) -> f64 {
        self.area
    }

    fn name(&self) -> &str {
        &self.name
    }
}
