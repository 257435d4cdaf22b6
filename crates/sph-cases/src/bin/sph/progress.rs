//! The progress display of a run: a bar on a terminal, log lines otherwise.

use super::*;

/// The progress display: a bar on a terminal; otherwise a line on stderr every `log_every`
/// seconds of wall time (and at the end), so a batch job's log shows where the run is. When
/// `report` is set (SIGUSR1), a line at once, whatever `log_every` says; it is cleared. With
/// a `--log` file (`logged`), the lines go there too, behind a terminal's bar as well.
pub(super) fn progress_display(
    terminal: bool,
    log_every: f64,
    report: Arc<AtomicBool>,
    logged: bool,
) -> Result<Option<ProgressSink>, CaseError> {
    use std::sync::atomic::Ordering;
    if !(log_every.is_finite() && log_every >= 0.0) {
        return Err(CaseError::InvalidValue {
            key: "--log-every".into(),
            value: sph_core::error::Num(log_every).to_string(),
            allowed: "seconds >= 0 (0: no log lines)".into(),
        });
    }
    const SCALE: f64 = 1e6;
    if terminal {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(4));
        bar.set_style(
            ProgressStyle::with_template("{bar:30} t = {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        let last = std::sync::Mutex::new(0.0f64);
        return Ok(Some(ProgressSink::new(move |p: &Progress| {
            if logged {
                let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
                let due = if p.finished {
                    true
                } else {
                    log_every > 0.0 && p.wall_seconds - *last >= log_every
                };
                if due {
                    *last = p.wall_seconds;
                    console::log_only(&progress_line(p));
                }
            }
            if p.finished {
                bar.finish_and_clear();
                return;
            }
            if report.swap(false, Ordering::Relaxed) {
                bar.suspend(|| say(&progress_line(p)));
            }
            bar.set_length((p.end_time * SCALE) as u64);
            bar.set_position((p.time * SCALE) as u64);
            bar.set_message(format!(
                "{:.4} / {:.4} s  {:.3e} particle-steps/s",
                p.time,
                p.end_time,
                p.particle_steps_per_second()
            ));
        })));
    }
    let last = std::sync::Mutex::new(0.0f64);
    Ok(Some(ProgressSink::new(move |p: &Progress| {
        let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
        // A line every `log_every` seconds (none when 0), and a last one at the end of a run
        // that printed any (a short run prints none); one whenever SIGUSR1 asks.
        let due = if p.finished {
            *last > 0.0 || logged
        } else {
            log_every > 0.0 && p.wall_seconds - *last >= log_every
        };
        let asked = report.swap(false, Ordering::Relaxed);
        if !(due || asked) {
            return;
        }
        *last = p.wall_seconds;
        say(&progress_line(p));
    })))
}

/// One progress line: time reached, share done, steps, rate, elapsed and remaining wall time.
fn progress_line(p: &Progress) -> String {
    let done = (p.time / p.end_time).clamp(0.0, 1.0);
    let eta = if done > 0.0 {
        format!("{:.0} s", p.wall_seconds * (1.0 - done) / done)
    } else {
        "–".into()
    };
    format!(
        "t = {:.6e} / {:.6e} s ({:.1} %), {} steps, {:.3e} particle-steps/s, {:.0} s elapsed, ETA {eta}",
        p.time,
        p.end_time,
        100.0 * done,
        p.steps,
        p.particle_steps_per_second(),
        p.wall_seconds
    )
}
