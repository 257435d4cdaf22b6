//! The run loop (`sph-driver`, re-exported) and the output-schedule keys every case accepts.

pub use sph_driver::run::*;

/// The material-history fields a case writes beside its own where the solver offers them
/// (plastic bodies: `plastic_strain`, and `temperature` with adiabatic heating).
pub const HISTORY_FIELDS: [&str; 2] = ["plastic_strain", "temperature"];

/// A case's output fields: `base`, then each of [`HISTORY_FIELDS`] that `offered` (the
/// solver's `field_names`) contains, so an elastic run writes exactly `base`.
pub fn case_fields(base: &[&'static str], offered: &[&'static str]) -> Vec<&'static str> {
    let mut fields = base.to_vec();
    fields.extend(HISTORY_FIELDS.iter().filter(|f| offered.contains(f)));
    fields
}

/// The output-schedule keys every case accepts: `snapshot_interval` and `snapshots` (0 and 50
/// by default: a snapshot every `end_time/50`, 51 frames; `snapshots = 1` for the first and
/// last only), `monitor_interval` (0: end_time/200), `probe_interval` (0: every step) and
/// `max_steps` (0: no limit).
pub fn output_params() -> Vec<crate::params::Param> {
    use crate::params::{Param, Range};
    vec![
        Param::float(
            "snapshot_interval",
            0.0,
            Range::NonNegative,
            "simulated time between HDF5 snapshots (0: end_time/snapshots)",
        ),
        Param::int(
            "snapshots",
            i64::from(DEFAULT_SNAPSHOTS),
            Range::Closed(1.0, MAX_SNAPSHOTS_KEY),
            "snapshots after the initial one, evenly spaced to end_time, when \
             snapshot_interval = 0 (1: the first and last only)",
        ),
        Param::float(
            "monitor_interval",
            0.0,
            Range::NonNegative,
            "time between disorder/energy samples (0: end_time/200)",
        ),
        Param::float(
            "probe_interval",
            0.0,
            Range::NonNegative,
            "time between probe samples (0: every step)",
        ),
        Param::int(
            "max_steps",
            0,
            Range::Closed(0.0, 1e15),
            "most steps the run may take; reaching it before end_time stops the run with a \
             diagnostic, results kept (0: no limit)",
        ),
    ]
}

/// Largest value of the key `snapshots`.
pub const MAX_SNAPSHOTS_KEY: f64 = 10_000.0;
