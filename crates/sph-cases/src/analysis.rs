//! Figures derived from recorded time series: oscillation period and amplitude, contact
//! intervals.

/// Times at which `y(t) − level` changes sign downward (from > 0 to ≤ 0), linearly interpolated.
pub fn downward_crossings(t: &[f64], y: &[f64], level: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for k in 1..t.len().min(y.len()) {
        let (a, b) = (y[k - 1] - level, y[k] - level);
        if a > 0.0 && b <= 0.0 {
            let s = a / (a - b);
            out.push(t[k - 1] + s * (t[k] - t[k - 1]));
        }
    }
    out
}

/// The period of an oscillation about `level`, averaged over the full periods recorded: the
/// time between the first and the last downward crossing divided by the number of periods
/// between them. `None` with fewer than two crossings (less than one full period).
pub fn mean_period(t: &[f64], y: &[f64], level: f64) -> Option<f64> {
    let c = downward_crossings(t, y, level);
    (c.len() >= 2).then(|| (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64)
}

/// Half the peak-to-peak range of `y`.
pub fn half_range(y: &[f64]) -> f64 {
    let (lo, hi) = extremes(y);
    0.5 * (hi - lo)
}

/// Minimum and maximum of `y` (`(+∞, −∞)` when empty).
pub fn extremes(y: &[f64]) -> (f64, f64) {
    y.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

/// The first contact of a sampled force magnitude `f(t)`: the first run of consecutive samples
/// with `f > 0`, as `(start, end)` with each end half-way between the last zero sample and the
/// first non-zero one (so the error is at most half a sample interval per end). A contact force
/// is exactly zero while no pair interacts, so no threshold is needed. `None` without contact;
/// the end is the last sample when the contact has not ended.
pub fn first_contact(t: &[f64], f: &[f64]) -> Option<(f64, f64)> {
    let n = t.len().min(f.len());
    let first = (0..n).find(|&k| f[k] > 0.0)?;
    let last = (first..n).take_while(|&k| f[k] > 0.0).last()?;
    let start = if first > 0 {
        0.5 * (t[first - 1] + t[first])
    } else {
        t[first]
    };
    let end = if last + 1 < n {
        0.5 * (t[last] + t[last + 1])
    } else {
        t[last]
    };
    Some((start, end))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_contact_brackets_the_non_zero_run() {
        let t: Vec<f64> = (0..10).map(|k| k as f64).collect();
        let f = [0.0, 0.0, 1.0, 3.0, 2.0, 0.0, 0.0, 5.0, 0.0, 0.0];
        assert_eq!(first_contact(&t, &f), Some((1.5, 4.5)));
        assert_eq!(first_contact(&t, &[0.0; 10]), None);
        assert_eq!(first_contact(&t[..4], &f[..4]), Some((1.5, 3.0)));
    }

    #[test]
    fn period_of_a_sampled_sine_is_recovered() {
        // 3.7 periods of period 0.25 sampled at 1e-3: linear interpolation of the crossings is
        // accurate to O(Δt²/T²) ≈ 1e-5 relative.
        let t: Vec<f64> = (0..=925).map(|k| k as f64 * 1e-3).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&t| 0.3 * (2.0 * std::f64::consts::PI * t / 0.25).sin())
            .collect();
        let p = mean_period(&t, &y, 0.0).unwrap();
        assert!((p - 0.25).abs() < 1e-5 * 0.25, "{p}");
        assert!((half_range(&y) - 0.3).abs() < 1e-3);
        assert!(mean_period(&t[..200], &y[..200], 0.0).is_none());
    }
}
