//! The signals a run answers.
//!
//! - SIGINT, SIGTERM, SIGHUP (how an interactive run usually dies: its terminal closed) and
//!   SIGQUIT stop the run after its current step: a last snapshot, the results file completed
//!   with `status: interrupted at t = … (SIG…)`, the summary written, exit status 128 + the
//!   signal. A second one takes the signal's default action (the process ends at once).
//! - SIGUSR1 and SIGUSR2 print a progress line at the next report and the run goes on (as `dd`
//!   does), whatever `--log-every` says.
//!
//! signal-hook rather than ctrlc: it tells the signals apart (the exit status) and offers the
//! second-signal escape without a handler thread.

use sph_cases::runner::Interrupt;
use sph_cases::CaseError;
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::Arc;

/// The signals that stop a run after its current step.
#[cfg(unix)]
pub(super) const STOPPING: [i32; 4] = [
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGTERM,
    signal_hook::consts::SIGHUP,
    signal_hook::consts::SIGQUIT,
];

/// What the handlers set: the stopping signal's number, and a request for a progress line.
pub(super) struct Signals {
    /// The signal that asked the run to stop (0: none yet).
    pub(super) stop: Interrupt,
    /// Set by SIGUSR1/SIGUSR2; the progress display prints a line and clears it.
    pub(super) report: Arc<AtomicBool>,
}

/// Installs the handlers (see the module documentation).
#[cfg(unix)]
pub(super) fn install() -> Result<Signals, CaseError> {
    use signal_hook::consts::{SIGUSR1, SIGUSR2};
    use signal_hook::flag;
    let stop: Interrupt = Arc::new(AtomicUsize::new(0));
    let report = Arc::new(AtomicBool::new(false));
    let seen = Arc::new(AtomicBool::new(false));
    let fail = |e: std::io::Error| CaseError::Config(format!("installing signal handlers: {e}"));
    for sig in STOPPING {
        // Order matters: the check for an earlier signal runs before this one is recorded.
        flag::register_conditional_default(sig, Arc::clone(&seen)).map_err(fail)?;
        flag::register(sig, Arc::clone(&seen)).map_err(fail)?;
        flag::register_usize(sig, Arc::clone(&stop), sig as usize).map_err(fail)?;
    }
    for sig in [SIGUSR1, SIGUSR2] {
        flag::register(sig, Arc::clone(&report)).map_err(fail)?;
    }
    Ok(Signals { stop, report })
}

/// Elsewhere the signals keep their default; the flags are never set.
#[cfg(not(unix))]
pub(super) fn install() -> Result<Signals, CaseError> {
    Ok(Signals {
        stop: Arc::new(AtomicUsize::new(0)),
        report: Arc::new(AtomicBool::new(false)),
    })
}
