//! The run loop (`sph-driver`, re-exported) and the output-schedule keys every case accepts.

pub use sph_driver::run::*;

/// The output-schedule keys every case accepts: `snapshot_interval`, `monitor_interval` and
/// `probe_interval` (all 0 by default: first and last snapshot, end_time/200, every step).
pub fn output_params() -> Vec<crate::params::Param> {
    use crate::params::{Param, Range};
    vec![
        Param::float(
            "snapshot_interval",
            0.0,
            Range::NonNegative,
            "simulated time between HDF5 snapshots (0: first and last only)",
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
    ]
}
