//! Which instruction set the particle loops run with, chosen once at run time.
//!
//! The release build targets plain x86-64 (SSE2), so a binary runs on any x86-64 machine. The
//! loops of a time step are compiled a second time with AVX2 and FMA enabled, and the
//! [`crate::parallel`] helpers run that copy when the CPU has both (Intel Core since Haswell,
//! 2013, AMD since Excavator, 2015, and every x86-64 server CPU since). On the performance
//! anchors it executes 11–22 % fewer instructions (docs/performance.md).
//!
//! **The results are the same bits on either copy.** Rust never contracts `a * b + c` into a
//! fused multiply-add on its own (only `f64::mul_add` does, which is exactly rounded on either
//! copy), and LLVM vectorises floating-point code only where the order of the operations stays
//! the same, so wider registers change how many instructions run, not what they compute. The
//! tests run scenes on both copies and compare every field bit for bit.
//!
//! How a loop takes part: the helpers of [`crate::parallel`] run each task's rows through
//! [`dispatch`]. The per-particle closure given to a helper is then called from both copies, so
//! a hot loop marks it `#[inline(always)]` to have it compiled into each; a closure without the
//! mark is still correct, it just runs as plain x86-64 code.

use std::sync::atomic::{AtomicU8, Ordering};

/// 0: not decided yet; 1: plain x86-64; 2: AVX2 + FMA.
static MODE: AtomicU8 = AtomicU8::new(0);

/// Whether the particle loops run their AVX2 + FMA copy: the CPU has both, and
/// [`set_enabled`] has not turned the copy off.
#[inline]
pub fn enabled() -> bool {
    match MODE.load(Ordering::Relaxed) {
        0 => {
            let on = cpu_has_avx2_fma();
            MODE.store(if on { 2 } else { 1 }, Ordering::Relaxed);
            on
        }
        mode => mode == 2,
    }
}

/// Whether this CPU can run the AVX2 + FMA copy.
pub fn cpu_has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Turns the AVX2 + FMA copy on (where the CPU has it) or off, for every thread from the next
/// loop on. For comparisons: the results are the same either way.
pub fn set_enabled(on: bool) {
    let mode = if on && cpu_has_avx2_fma() { 2 } else { 1 };
    MODE.store(mode, Ordering::Relaxed);
}

/// The name of the instruction set the loops run with: `"avx2+fma"` or `"x86-64"` (another
/// architecture: its baseline, `"baseline"`).
pub fn instruction_set() -> &'static str {
    if enabled() {
        "avx2+fma"
    } else if cfg!(target_arch = "x86_64") {
        "x86-64"
    } else {
        "baseline"
    }
}

/// `body()`, compiled with AVX2 and FMA when [`enabled`]. `body` should be an
/// `#[inline(always)]` closure, so that its code (and what it inlines) is compiled into each
/// copy; the copies give the same results.
#[inline(always)]
pub fn dispatch<R>(body: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    {
        if enabled() {
            // SAFETY: `enabled` is true only on a CPU with AVX2 and FMA.
            return unsafe { with_avx2_fma(body) };
        }
    }
    body()
}

/// `body()` in a function compiled with AVX2 and FMA, into which `body` is inlined.
///
/// # Safety
/// The CPU must have AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn with_avx2_fma<R>(body: impl FnOnce() -> R) -> R {
    body()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_copies_compute_the_same_bits() {
        let x: Vec<f64> = (0..1000).map(|i| (i as f64 * 0.37).sin() * 1e3).collect();
        let sum = |x: &[f64]| {
            x.iter()
                .zip(x.iter().skip(1))
                .map(|(a, b)| (a * b + a / (b.abs() + 1.0)).sqrt().max(0.0) + a.mul_add(*b, 1.0))
                .fold(0.0, |s, v| s + v)
        };
        let plain = sum(&x);
        // SAFETY: only where the CPU has the features.
        #[cfg(target_arch = "x86_64")]
        if cpu_has_avx2_fma() {
            let wide = unsafe { with_avx2_fma(|| sum(&x)) };
            assert_eq!(wide.to_bits(), plain.to_bits());
        }
        assert_eq!(dispatch(|| sum(&x)).to_bits(), plain.to_bits());
    }

    #[test]
    fn the_choice_can_be_switched_off_and_back() {
        set_enabled(false);
        assert!(!enabled());
        assert_ne!(instruction_set(), "avx2+fma");
        set_enabled(true);
        assert_eq!(enabled(), cpu_has_avx2_fma());
    }
}
