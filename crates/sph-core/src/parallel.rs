//! When a loop over particles goes to the rayon pool, in one place for every method.
//!
//! A parallel loop costs a hand-off: waking a worker, splitting, joining (measured on the 2D
//! plate, 1,612 particles: a TL step is ~110 µs of physics in about twenty loops). Loops over
//! fewer than twice [`MIN_PARTICLES_PER_TASK`] particles therefore stay on the calling thread,
//! and a loop splits only into tasks of at least that many particles. The value is measured:
//! at 1,024 per task the 1,612-particle UL plate ran serially and took 24.4 s instead of 15.0 s
//! on two threads (`sph run oscillating-plate-2d --method ul-enog --set h_over_dp=1.3
//! --threads 2 --no-output`), so 512 keeps it split in up to three tasks. Every loop that uses these helpers
//! is a gather (each task writes only its own entries, sums in neighbour-list order), so the
//! results are identical for any thread count and any split.

use rayon::prelude::*;

/// The fewest particles a parallel task gets: loops over fewer than twice this many particles
/// run on the calling thread. Use with `par_iter().with_min_len(MIN_PARTICLES_PER_TASK)`.
pub const MIN_PARTICLES_PER_TASK: usize = 512;

/// Whether a loop over `n` particles is split over the rayon pool at all.
#[inline]
pub fn worth_splitting(n: usize) -> bool {
    n >= 2 * MIN_PARTICLES_PER_TASK
}

/// `f(i, &mut out[i])` for every `i`, in tasks of at least [`MIN_PARTICLES_PER_TASK`] entries.
#[inline]
pub fn gather<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    if worth_splitting(out.len()) {
        out.par_iter_mut()
            .with_min_len(MIN_PARTICLES_PER_TASK)
            .enumerate()
            .for_each(|(i, o)| f(i, o));
    } else {
        out.iter_mut().enumerate().for_each(|(i, o)| f(i, o));
    }
}

/// `f(i, slots_i)` for every particle `i` of a neighbour-list layout, where `slots_i =
/// &mut out[offsets[i]..offsets[i + 1]]` (a pair-aligned buffer), in tasks of at least
/// [`MIN_PARTICLES_PER_TASK`] particles. Splits by recursive halving of the particle range, so
/// it allocates nothing.
///
/// # Panics
/// If `out.len() != offsets[last] - offsets[0]`.
pub fn gather_slices<T: Send>(
    offsets: &[usize],
    out: &mut [T],
    f: &(impl Fn(usize, &mut [T]) + Sync),
) {
    gather_blocks(offsets, out, &|rows, mut block: &mut [T]| {
        for i in rows {
            let (slots, tail) =
                std::mem::take(&mut block).split_at_mut(offsets[i + 1] - offsets[i]);
            f(i, slots);
            block = tail;
        }
    });
}

/// `f(rows, block)` for the blocks of particles [`gather_slices`] hands to one task each, where
/// `block = &mut out[offsets[rows.start]..offsets[rows.end]]`: for work that needs a task's
/// rows together. The blocks depend only on the particle count ([`block_of`] tells which block
/// a particle is in), never on the thread count.
///
/// # Panics
/// If `out.len() != offsets[last] - offsets[0]`.
pub fn gather_blocks<T: Send>(
    offsets: &[usize],
    out: &mut [T],
    f: &(impl Fn(std::ops::Range<usize>, &mut [T]) + Sync),
) {
    let n = offsets.len().saturating_sub(1);
    if n == 0 {
        return;
    }
    assert_eq!(out.len(), offsets[n] - offsets[0], "pair buffer length");
    split_blocks(offsets, 0, n, out, f);
}

/// The first particle of the block of [`gather_blocks`] over `n` particles that holds particle
/// `i` (`i < n`).
pub fn block_of(n: usize, i: usize) -> usize {
    let (mut start, mut end) = (0, n);
    while worth_splitting(end - start) {
        let mid = start + (end - start) / 2;
        if i < mid {
            end = mid;
        } else {
            start = mid;
        }
    }
    start
}

fn split_blocks<T: Send>(
    offsets: &[usize],
    start: usize,
    end: usize,
    out: &mut [T],
    f: &(impl Fn(std::ops::Range<usize>, &mut [T]) + Sync),
) {
    if !worth_splitting(end - start) {
        f(start..end, out);
        return;
    }
    // The same halving as `block_of`.
    let mid = start + (end - start) / 2;
    let (left, right) = out.split_at_mut(offsets[mid] - offsets[start]);
    rayon::join(
        || split_blocks(offsets, start, mid, left, f),
        || split_blocks(offsets, mid, end, right, f),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gather_slices_visits_every_particle_once_with_its_own_slots() {
        for n in [0usize, 1, 7, 2 * MIN_PARTICLES_PER_TASK + 3, 5000] {
            let mut offsets = vec![0usize];
            for i in 0..n {
                offsets.push(offsets[i] + (i * 7919) % 5);
            }
            let mut out = vec![usize::MAX; offsets[n]];
            gather_slices(&offsets, &mut out, &|i, slots: &mut [usize]| {
                for s in slots {
                    assert_eq!(*s, usize::MAX, "slot written twice");
                    *s = i;
                }
            });
            for i in 0..n {
                assert!(out[offsets[i]..offsets[i + 1]].iter().all(|&s| s == i));
            }
        }
    }

    #[test]
    fn blocks_are_those_block_of_names() {
        for n in [1usize, 1023, 1024, 5000, 70_001] {
            let offsets: Vec<usize> = (0..=n).collect();
            let mut out = vec![usize::MAX; n];
            gather_blocks(&offsets, &mut out, &|rows, block: &mut [usize]| {
                assert_eq!(block.len(), rows.len());
                block.iter_mut().for_each(|b| *b = rows.start);
            });
            for (i, &b) in out.iter().enumerate() {
                assert_eq!(b, block_of(n, i), "particle {i} of {n}");
            }
        }
    }

    #[test]
    fn gather_writes_each_entry_from_its_index() {
        for n in [0usize, 5, 3000] {
            let mut out = vec![0usize; n];
            gather(&mut out, |i, o| *o = 3 * i + 1);
            assert!(out.iter().enumerate().all(|(i, &o)| o == 3 * i + 1));
        }
    }
}
