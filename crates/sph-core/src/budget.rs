//! The particle budget: the generators of `sph_geometry::generate` check it **before** they
//! allocate, so parameters that would need more particles than the machine can hold stop with
//! one clear error (the estimate and the limit) instead of aborting on an allocation failure,
//! panicking on a capacity overflow, or swapping for minutes.
//!
//! A [`Budget`] is a memory limit in bytes. A generator turns its particle count into the
//! estimated peak memory of a whole run with that many particles, [`bytes_per_particle`] per
//! particle (solver state, neighbour list and pair data, probes, output buffers: measured for
//! every method, the largest kept, see [`BYTES_PER_PARTICLE_2D`]), and compares it with the
//! limit. Independently of any limit, more than [`MAX_PARTICLES`] particles (particle indices
//! are `u32`) are always refused.
//!
//! Which budget applies on a thread:
//! - inside [`scoped`], the budget given there; the counts of every generator call in the scope
//!   add up, so a scene of two rings is checked as a whole (the `sph` command runs each case in
//!   a scope: by default 80 % of the available memory, or `--max-memory`);
//! - outside a scope, [`Budget::default_for_process`] (the same 80 % of the memory available
//!   when first asked), each generator call checked on its own.
//!
//! The estimate is deliberately simple (particles × a per-particle figure), so the check is
//! cheap and deterministic for given parameters and limit; it errs on the large side.

use crate::dim::Dim;
use crate::error::Error;

mod limits;
use std::cell::RefCell;
use std::sync::OnceLock;

/// Most particles any generator produces: particle indices are stored as `u32`.
pub const MAX_PARTICLES: u64 = u32::MAX as u64;

/// Estimated peak memory of a 2D run per particle, bytes: the largest measured slope, rounded
/// up by about a fifth.
///
/// Measured as the slope of the peak resident set (`/usr/bin/time -f %M`) between two
/// resolutions of a few-step run with HDF5 output (`sph run <case> --method <m> --set
/// resolution=<r> --set end_time=<a few steps>`):
///
/// | dim | case, resolutions | method: bytes per particle |
/// |---|---|---|
/// | 2D | oscillating-plate-2d, 20 → 80 (5,792 → 85,472 particles) | tl 1,706; tl-hf 1,874; tl-gm 1,863; ul-og 2,460; ul-enog 2,469; ul-oas 2,459 |
/// | 2D | slab-tension-2d, 31 → 124 (2,883 → 46,128) | mps 1,199 |
/// | 3D | bending-column-3d, 10 → 20 (6,300 → 49,200) | tl 4,588; tl-hf 5,022; tl-gm 5,008 (before the TL pair data were slimmed; now tl-hf 2,816, and 1,014 with `pair_data = recomputed`) |
/// | 3D | oscillating-plate-3d, 2 → 4 (12,800 → 102,400) | ul-og 7,999; ul-enog 8,031; ul-oas 8,123 |
pub const BYTES_PER_PARTICLE_2D: u64 = 3_000;

/// Estimated peak memory of a 3D run per particle, bytes (measured with the 2D figures, see
/// [`BYTES_PER_PARTICLE_2D`]).
pub const BYTES_PER_PARTICLE_3D: u64 = 10_000;

/// Share of the available memory a run may plan to use by default.
pub const DEFAULT_MEMORY_FRACTION: f64 = 0.8;

/// The estimated peak memory per particle of a run in dimension `D`.
pub fn bytes_per_particle<D: Dim>() -> u64 {
    if D::D == 2 {
        BYTES_PER_PARTICLE_2D
    } else {
        BYTES_PER_PARTICLE_3D
    }
}

/// A memory limit for the particles of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Largest estimated peak memory of a run, bytes; `None`: no memory limit (only
    /// [`MAX_PARTICLES`]).
    pub max_bytes: Option<u64>,
    /// Where the limit comes from, shown in the error (e.g. `80 % of the 15.3 GiB available`).
    pub origin: String,
}

impl Budget {
    /// No memory limit; only [`MAX_PARTICLES`] applies.
    pub fn unlimited() -> Self {
        Self {
            max_bytes: None,
            origin: "no memory limit".into(),
        }
    }

    /// A limit of `bytes`, described by `origin` in error messages.
    pub fn with_limit(bytes: u64, origin: impl Into<String>) -> Self {
        Self {
            max_bytes: Some(bytes),
            origin: origin.into(),
        }
    }

    /// [`DEFAULT_MEMORY_FRACTION`] of [`available_memory`], with the limit it comes from in
    /// its origin; unlimited where the available memory cannot be read (then only
    /// [`MAX_PARTICLES`] applies).
    pub fn from_available_memory() -> Self {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        Self::available_to(threads)
    }

    /// [`Budget::from_available_memory`] for a process of `threads` worker threads (each
    /// reserves address space that `ulimit -v` counts).
    pub fn available_to(threads: usize) -> Self {
        match limits::tightest(threads as u64) {
            Some((avail, what)) => Self::with_limit(
                (avail as f64 * DEFAULT_MEMORY_FRACTION) as u64,
                format!(
                    "{:.0} % of the {} {what}",
                    DEFAULT_MEMORY_FRACTION * 100.0,
                    format_bytes(avail as f64)
                ),
            ),
            None => Self::unlimited(),
        }
    }

    /// The budget outside any [`scoped`] call: [`Budget::from_available_memory`], read once
    /// per process.
    pub fn default_for_process() -> Self {
        static DEFAULT: OnceLock<Budget> = OnceLock::new();
        DEFAULT.get_or_init(Budget::from_available_memory).clone()
    }

    /// The largest particle count of dimension `D` within the limit.
    pub fn max_particles<D: Dim>(&self) -> u64 {
        match self.max_bytes {
            Some(b) => (b / bytes_per_particle::<D>()).min(MAX_PARTICLES),
            None => MAX_PARTICLES,
        }
    }
}

/// Memory this process may still use, bytes: the least of Linux's `MemAvailable`, what its
/// memory cgroups leave (at every level of its hierarchy, v2 `memory.max` minus
/// `memory.current`, v1 `memory.limit_in_bytes` minus `memory.usage_in_bytes`) and what its
/// address-space and data limits (`ulimit -v`, `ulimit -d`) leave beyond its current size and
/// its worker threads' reservations. `None` where none can be read.
pub fn available_memory() -> Option<u64> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    limits::tightest(threads as u64).map(|(bytes, _)| bytes)
}

struct Scope {
    budget: Budget,
    used_bytes: f64,
}

thread_local! {
    static SCOPE: RefCell<Option<Scope>> = const { RefCell::new(None) };
}

/// Runs `f` with `budget` on this thread; the particles generated inside add up against it.
/// The previous budget is restored afterwards (also if `f` panics). Scopes nest.
pub fn scoped<R>(budget: Budget, f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Scope>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            SCOPE.with(|s| *s.borrow_mut() = previous);
        }
    }
    let previous = SCOPE.with(|s| {
        s.borrow_mut().replace(Scope {
            budget,
            used_bytes: 0.0,
        })
    });
    let _restore = Restore(previous);
    f()
}

/// The budget in force on this thread.
pub fn current() -> Budget {
    SCOPE
        .with(|s| s.borrow().as_ref().map(|sc| sc.budget.clone()))
        .unwrap_or_else(Budget::default_for_process)
}

/// How many more particles of dimension `D` this thread may generate.
pub fn remaining<D: Dim>() -> u64 {
    let (budget, used) = SCOPE
        .with(|s| {
            s.borrow()
                .as_ref()
                .map(|sc| (sc.budget.clone(), sc.used_bytes))
        })
        .unwrap_or_else(|| (Budget::default_for_process(), 0.0));
    let used_particles = (used / bytes_per_particle::<D>() as f64).ceil() as u64;
    budget.max_particles::<D>().saturating_sub(used_particles)
}

/// Checks that `count` more particles of dimension `D` (an estimate; any value, also huge or
/// non-finite, is safe to pass) fit in the budget, and books them in the current scope.
/// `what` names the generator call in the error (e.g. `annulus_polar at dp = 0.001`).
pub fn reserve<D: Dim>(count: f64, what: &str) -> Result<(), Error> {
    if !(count.is_finite() && count >= 0.0) || count.ceil() > remaining::<D>() as f64 {
        return Err(exceeded::<D>(count, what));
    }
    book::<D>(count.ceil() as u64);
    Ok(())
}

/// Books `count` particles already generated (within [`remaining`]) in the current scope.
pub fn book<D: Dim>(count: u64) {
    SCOPE.with(|s| {
        if let Some(sc) = s.borrow_mut().as_mut() {
            sc.used_bytes += count as f64 * bytes_per_particle::<D>() as f64;
        }
    });
}

/// The error for `count` particles (an estimate) that do not fit.
pub fn exceeded<D: Dim>(count: f64, what: &str) -> Error {
    let budget = current();
    let bytes = count * bytes_per_particle::<D>() as f64;
    let limit = match budget.max_bytes {
        Some(b) => format!("{} ({})", format_bytes(b as f64), budget.origin),
        None => format!("{MAX_PARTICLES} particles (indices are 32-bit)"),
    };
    Error::TooManyParticles {
        what: what.into(),
        particles: format_count(count),
        memory: format_bytes(bytes),
        limit,
    }
}

/// `1.5 GiB`, `236 GiB`, `3.2e292 B`, `∞ B`: a byte count for people.
pub fn format_bytes(bytes: f64) -> String {
    if !bytes.is_finite() {
        return "∞ B".into();
    }
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut x = bytes;
    let mut k = 0;
    while x >= 1024.0 && k + 1 < UNITS.len() {
        x /= 1024.0;
        k += 1;
    }
    if x >= 1e6 {
        format!("{bytes:.1e} B")
    } else if x >= 100.0 || k == 0 {
        format!("{x:.0} {}", UNITS[k])
    } else {
        format!("{x:.1} {}", UNITS[k])
    }
}

/// `48,000,000` up to a billion, `3.10e300` beyond, `∞`: a count for people.
pub fn format_count(count: f64) -> String {
    if !count.is_finite() {
        return "∞".into();
    }
    if count < 1e9 {
        let s = format!("{:.0}", count.max(0.0));
        let mut out = String::new();
        for (i, c) in s.chars().enumerate() {
            if i > 0 && (s.len() - i) % 3 == 0 {
                out.push(',');
            }
            out.push(c);
        }
        out
    } else {
        format!("{count:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::{D2, D3};

    #[test]
    fn a_scope_adds_up_its_reservations_and_restores_the_previous_budget() {
        let limit = 10 * BYTES_PER_PARTICLE_2D;
        scoped(Budget::with_limit(limit, "test"), || {
            assert_eq!(remaining::<D2>(), 10);
            reserve::<D2>(6.0, "first").unwrap();
            assert_eq!(remaining::<D2>(), 4);
            let e = reserve::<D2>(5.0, "second").unwrap_err().to_string();
            assert!(e.contains("second") && e.contains("test"), "{e}");
            // 3D particles cost more: the same bytes hold fewer.
            assert!(remaining::<D3>() < 4);
            scoped(Budget::unlimited(), || {
                assert_eq!(remaining::<D2>(), MAX_PARTICLES);
            });
            assert_eq!(remaining::<D2>(), 4);
        });
    }

    #[test]
    fn huge_and_non_finite_counts_are_refused_whatever_the_budget() {
        scoped(Budget::unlimited(), || {
            for n in [1e300, f64::INFINITY, f64::NAN, -1.0, 5e9] {
                let e = reserve::<D2>(n, "g").unwrap_err();
                assert!(matches!(e, Error::TooManyParticles { .. }), "{n}: {e}");
            }
            reserve::<D3>(1e6, "g").unwrap();
        });
    }

    #[test]
    fn sizes_and_counts_read_well() {
        assert_eq!(format_bytes(512.0), "512 B");
        assert_eq!(format_bytes(1.5 * 1024.0 * 1024.0 * 1024.0), "1.5 GiB");
        assert_eq!(format_bytes(236e9), "220 GiB");
        assert_eq!(format_count(48_000_000.0), "48,000,000");
        assert_eq!(format_count(999.0), "999");
        assert_eq!(format_count(1e300), "1.00e300");
    }
}
