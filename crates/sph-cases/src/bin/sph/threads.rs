//! The worker threads of a run: `--threads N`, else `RAYON_NUM_THREADS` (the variable rayon
//! itself reads), else every core; within 1 to [`MAX_THREADS`] either way, and the pool built
//! here, so a bad count is one line before any work, never a panic inside rayon.

use sph_cases::CaseError;

/// Most worker threads a run accepts (`--threads` or `RAYON_NUM_THREADS`).
pub(super) const MAX_THREADS: usize = 1024;

/// The thread count `requested` (`--threads`) or `env` (`RAYON_NUM_THREADS`, 0 or unset: every
/// core, `cores`) gives.
fn count(requested: Option<usize>, env: Option<&str>, cores: usize) -> Result<usize, CaseError> {
    if let Some(n) = requested {
        if !(1..=MAX_THREADS).contains(&n) {
            return Err(CaseError::InvalidValue {
                key: "--threads".into(),
                value: n.to_string(),
                allowed: format!("1 <= --threads <= {MAX_THREADS}"),
            });
        }
        return Ok(n);
    }
    let Some(text) = env else {
        return Ok(cores.clamp(1, MAX_THREADS));
    };
    match text.trim().parse::<usize>() {
        Ok(0) => Ok(cores.clamp(1, MAX_THREADS)),
        Ok(n) if n <= MAX_THREADS => Ok(n),
        _ => Err(CaseError::InvalidValue {
            key: "RAYON_NUM_THREADS".into(),
            value: text.to_string(),
            allowed: format!(
                "a thread count, 1 to {MAX_THREADS} (0: every core); or unset it and use \
                 --threads"
            ),
        }),
    }
}

/// Builds the global thread pool for the run and returns its size.
///
/// # Errors
/// A count out of range (named as given), or a pool the system cannot start.
pub(super) fn configure(requested: Option<usize>) -> Result<usize, CaseError> {
    let env = std::env::var_os("RAYON_NUM_THREADS").map(|v| v.to_string_lossy().into_owned());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let n = count(requested, env.as_deref(), cores)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| CaseError::Config(format!("starting {n} worker threads: {e}")))?;
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_come_from_the_flag_then_the_variable_then_the_cores() {
        assert_eq!(count(Some(3), Some("9"), 2).unwrap(), 3);
        assert_eq!(count(None, Some("9"), 2).unwrap(), 9);
        assert_eq!(count(None, Some("0"), 2).unwrap(), 2);
        assert_eq!(count(None, None, 2).unwrap(), 2);
        assert_eq!(count(None, Some(" 1024 "), 2).unwrap(), 1024);
        for bad in ["1500", "5000", "-1", "abc", ""] {
            let e = count(None, Some(bad), 2).unwrap_err().to_string();
            assert!(e.starts_with("invalid RAYON_NUM_THREADS = "), "{bad}: {e}");
        }
        for bad in [0, 1025] {
            let e = count(Some(bad), None, 2).unwrap_err().to_string();
            assert!(e.starts_with("invalid --threads = "), "{bad}: {e}");
        }
    }
}
