//! Figures read from a run's snapshots: particle frames for pictures, and the stress
//! roughness that says whether a stress field oscillates from particle to particle.

use crate::plot::Frame;
use serde_json::{json, Map, Value};
use sph_output::FileContents;

/// Positions (x, y) and von Mises stress of the snapshot nearest to `t`.
pub fn frame_at(c: &FileContents, t: f64, title: &str) -> Option<Frame> {
    let snap = c
        .snapshots
        .iter()
        .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))?;
    let pos = snap.dataset("position")?.as_f64()?;
    let vm = snap.dataset("von_mises")?.as_f64()?;
    let stride = pos.len() / vm.len().max(1);
    let points = vm
        .iter()
        .enumerate()
        .map(|(k, &v)| (pos[stride * k], pos[stride * k + 1], v))
        .collect();
    Some(Frame {
        title: format!("{title}, t = {:.4}", snap.time),
        points,
    })
}

/// A 3D (or 2D) snapshot nearest to `t` projected on the coordinate axes `axes = (a, b)`
/// (0 = x, 1 = y, 2 = z), keeping the particles for which `keep(position)` holds (a slab for a
/// cut), coloured by `field`.
pub fn frame_projected(
    c: &FileContents,
    t: f64,
    title: &str,
    axes: (usize, usize),
    field: &str,
    keep: impl Fn([f64; 3]) -> bool,
) -> Option<Frame> {
    let snap = c
        .snapshots
        .iter()
        .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))?;
    let pos = snap.dataset("position")?.as_f64()?;
    let value = snap.dataset(field)?.as_f64()?;
    let points = value
        .iter()
        .enumerate()
        .filter_map(|(k, &v)| {
            let p = [pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]];
            keep(p).then_some((p[axes.0], p[axes.1], v))
        })
        .collect();
    Some(Frame {
        title: format!("{title}, t = {:.4e}", snap.time),
        points,
    })
}

/// Particle-to-particle roughness of the frame's value in a region: for each particle `i`
/// with `in_region(x, y)`, `|s_i − mean of s_j|` over the other particles closer than `1.6 dp`;
/// returns the 99th percentile of that over the region (in the value's unit: ≈ curvature · dp²
/// for a smooth field, ≈ the amplitude for a zigzag). `None` when the region is empty.
pub fn roughness(frame: &Frame, dp: f64, in_region: impl Fn(f64, f64) -> bool) -> Option<f64> {
    let pts = &frame.points;
    let r2 = (1.6 * dp) * (1.6 * dp);
    let mut dev: Vec<f64> = pts
        .iter()
        .enumerate()
        .filter(|(_, p)| in_region(p.0, p.1))
        .filter_map(|(i, p)| {
            let (mut sum, mut n) = (0.0, 0usize);
            for (j, q) in pts.iter().enumerate() {
                let d2 = (q.0 - p.0).powi(2) + (q.1 - p.1).powi(2);
                if j != i && d2 < r2 {
                    sum += q.2;
                    n += 1;
                }
            }
            (n > 0).then(|| (p.2 - sum / n as f64).abs())
        })
        .collect();
    if dev.is_empty() {
        return None;
    }
    dev.sort_by(f64::total_cmp);
    Some(dev[(dev.len() - 1) * 99 / 100])
}

/// The 99th percentile of the frames' values (a colour scale robust to a few outliers).
pub fn p99_value(frames: &[Frame]) -> f64 {
    let mut v: Vec<f64> = frames
        .iter()
        .flat_map(|f| f.points.iter().map(|p| p.2))
        .filter(|x| x.is_finite())
        .collect();
    if v.is_empty() {
        return 1.0;
    }
    v.sort_by(f64::total_cmp);
    v[(v.len() - 1) * 99 / 100].max(f64::MIN_POSITIVE)
}

/// Stress roughness of colliding rings (see [`roughness`]) at every snapshot, in two windows
/// that move with the rings (the rings meet at x = 0, the left ring is x < 0, the right one
/// x ≥ 0): *near* the collision point — within 0.01 m of each ring's facing extreme (largest x
/// of the left ring, smallest of the right one) and |y| < 0.02 m — and on the *far* sides —
/// more than 0.025 m beyond each ring's centre (mean x) on its outer side. Divided by the
/// largest 99th-percentile von Mises stress of the run (so the stress-free rings before
/// contact do not count as rough): `{time, near, far, scale, windows: "moving"}`; a window
/// without particles gives `null`.
pub fn rings_roughness(c: &FileContents, dp: f64) -> Map<String, Value> {
    let frames: Vec<Frame> = c
        .snapshots
        .iter()
        .filter_map(|s| frame_at(c, s.time, ""))
        .collect();
    let scale = roughness_scale(&frames);
    let mut near = Vec::new();
    let mut far = Vec::new();
    for f in &frames {
        let w = RingWindows::of(f);
        near.push(roughness(f, dp, |x, y| w.near(x, y)).map(|r| r / scale));
        far.push(roughness(f, dp, |x, y| w.far(x, y)).map(|r| r / scale));
    }
    let t: Vec<f64> = c.snapshots.iter().map(|s| s.time).collect();
    let mut m = Map::new();
    m.insert(
        "roughness".into(),
        json!({ "time": t, "near": near, "far": far, "scale": scale, "windows": "moving" }),
    );
    m
}

/// The largest 99th-percentile von Mises stress over the frames (the roughness scale).
fn roughness_scale(frames: &[Frame]) -> f64 {
    frames
        .iter()
        .map(|f| p99_value(std::slice::from_ref(f)))
        .fold(f64::MIN_POSITIVE, f64::max)
}

/// Stress roughness (see [`roughness`]) of every frame (one per snapshot) in the regions
/// `near` and `far`, divided by the largest 99th-percentile von Mises stress of the run:
/// `{roughness: {time, near, far, scale}}`, the form [`roughness_series`] reads.
pub fn roughness_map(
    c: &FileContents,
    frames: &[Frame],
    dp: f64,
    near: &dyn Fn(f64, f64) -> bool,
    far: &dyn Fn(f64, f64) -> bool,
) -> Map<String, Value> {
    let scale = roughness_scale(frames);
    let series = |region: &dyn Fn(f64, f64) -> bool| -> Vec<Option<f64>> {
        frames
            .iter()
            .map(|f| roughness(f, dp, region).map(|r| r / scale))
            .collect()
    };
    let (near, far) = (series(near), series(far));
    let t: Vec<f64> = c.snapshots.iter().map(|s| s.time).collect();
    let mut m = Map::new();
    m.insert(
        "roughness".into(),
        json!({ "time": t, "near": near, "far": far, "scale": scale }),
    );
    m
}

/// The windows of [`rings_roughness`] for one frame.
struct RingWindows {
    /// Centre (mean x) and facing extreme of the left ring.
    left: (f64, f64),
    /// Centre (mean x) and facing extreme of the right ring.
    right: (f64, f64),
}

impl RingWindows {
    fn of(f: &Frame) -> Self {
        let ring = |left: bool| {
            let xs: Vec<f64> = f
                .points
                .iter()
                .map(|p| p.0)
                .filter(|&x| (x < 0.0) == left)
                .collect();
            let mean = xs.iter().sum::<f64>() / xs.len().max(1) as f64;
            let facing = if left {
                xs.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            } else {
                xs.iter().copied().fold(f64::INFINITY, f64::min)
            };
            (mean, facing)
        };
        Self {
            left: ring(true),
            right: ring(false),
        }
    }

    fn near(&self, x: f64, y: f64) -> bool {
        y.abs() < 0.02
            && if x < 0.0 {
                x > self.left.1 - 0.01
            } else {
                x < self.right.1 + 0.01
            }
    }

    fn far(&self, x: f64, _y: f64) -> bool {
        if x < 0.0 {
            x < self.left.0 - 0.025
        } else {
            x > self.right.0 + 0.025
        }
    }
}

/// Whether a stored rings run measured its roughness in the moving windows of
/// [`rings_roughness`] (earlier runs used fixed lab-frame windows).
pub fn has_moving_windows(r: &crate::store::StoredRun) -> bool {
    r.summary
        .get("snapshots")
        .and_then(|s| s.get("roughness"))
        .and_then(|g| g.get("windows"))
        .and_then(Value::as_str)
        == Some("moving")
}

/// The largest value of a roughness series, `None` when every entry is empty.
pub fn peak(v: &[Option<f64>]) -> Option<f64> {
    v.iter().flatten().copied().reduce(f64::max)
}

/// The stored `{time, near, far}` roughness series of a rings run (see [`rings_roughness`]).
#[allow(clippy::type_complexity)]
pub fn roughness_series(
    r: &crate::store::StoredRun,
) -> Option<(Vec<f64>, Vec<Option<f64>>, Vec<Option<f64>>)> {
    let g = r.summary.get("snapshots")?.get("roughness")?;
    let arr = |k: &str| -> Option<Vec<Option<f64>>> {
        Some(g.get(k)?.as_array()?.iter().map(Value::as_f64).collect())
    };
    let t = arr("time")?.into_iter().flatten().collect();
    Some((t, arr("near")?, arr("far")?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roughness_tells_a_zigzag_from_a_smooth_field() {
        let dp = 0.01;
        let lattice = |f: &dyn Fn(i32, i32) -> f64| Frame {
            title: String::new(),
            points: (0..40)
                .flat_map(|i| (0..40).map(move |j| (i, j)))
                .map(|(i, j)| (i as f64 * dp, j as f64 * dp, f(i, j)))
                .collect(),
        };
        let smooth = lattice(&|i, j| 1.0 + 0.01 * (i + j) as f64);
        let zigzag = lattice(&|i, j| 1.0 + 0.3 * if (i + j) % 2 == 0 { 1.0 } else { -1.0 });
        let inside = |x: f64, y: f64| x > 0.05 && x < 0.35 && y > 0.05 && y < 0.35;
        let rs = roughness(&smooth, dp, inside).unwrap();
        let rz = roughness(&zigzag, dp, inside).unwrap();
        assert!(rs < 1e-12, "smooth {rs}");
        // Checkerboard ±0.3: 4 opposite neighbours at dp, 4 equal ones at √2 dp → mean 0 → 0.3.
        assert!((rz - 0.3).abs() < 1e-12, "zigzag {rz}");
        assert!(roughness(&smooth, dp, |_, _| false).is_none());
    }
}
