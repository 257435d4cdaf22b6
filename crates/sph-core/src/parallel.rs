//! When a loop over particles is split over threads, in one place for every method.
//!
//! The loops of a time step run on the [`crate::team`] (helpers that wait actively between
//! loops, so consecutive loops cost no system call); set-up work (reference pair data, sorted
//! neighbour lists) stays on rayon. A parallel loop still costs a hand-off: splitting,
//! claiming, joining (measured on the 2D plate, 1,612 particles: a TL step is ~110 µs of
//! physics in about twenty loops). Loops over fewer than twice [`MIN_PARTICLES_PER_TASK`]
//! particles therefore stay on the calling thread, and a loop splits only into tasks of at
//! least that many particles. The value is measured: at 1,024 per task the 1,612-particle UL
//! plate ran serially and took 24.4 s instead of 15.0 s on two threads (`sph run
//! oscillating-plate-2d --method ul-enog --set h_over_dp=1.3 --threads 2 --no-output`). Every
//! loop that uses these helpers is a gather (each task writes only its own entries, sums in
//! neighbour-list order), so the results are identical for any thread count and any split.
//!
//! Each task's rows run through [`crate::wide::dispatch`]: compiled with AVX2 and FMA where the
//! CPU has them, with the same results. A hot loop passes its per-particle closure as
//! `#[inline(always)] |i, out| …`, so that the closure is compiled into both copies.

/// The fewest particles a parallel task gets: loops over fewer than twice this many particles
/// run on the calling thread.
pub const MIN_PARTICLES_PER_TASK: usize = 512;

/// Whether a loop over `n` particles is split over threads at all.
#[inline]
pub fn worth_splitting(n: usize) -> bool {
    n >= 2 * MIN_PARTICLES_PER_TASK
}

/// `f(i, &mut out[i])` for every `i`, in tasks of at least [`MIN_PARTICLES_PER_TASK`] entries
/// on the [`crate::team`].
#[inline]
pub fn gather<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    let rows = |start: usize, part: &mut [T]| {
        crate::wide::dispatch(
            #[inline(always)]
            || {
                for (k, o) in part.iter_mut().enumerate() {
                    f(start + k, o);
                }
            },
        )
    };
    let n = out.len();
    if !worth_splitting(n) {
        return rows(0, out);
    }
    let tasks = task_count(n);
    let out = SharedMut::new(out);
    crate::team::run_tasks(tasks, &|k| {
        let range = k * n / tasks..(k + 1) * n / tasks;
        let start = range.start;
        // SAFETY: the tasks' ranges are disjoint and within `out`.
        rows(start, unsafe { out.slice(range) });
    });
}

/// `f(i, &mut a[i], &mut b[i])` for every `i`: [`gather`] into two arrays at once.
///
/// # Panics
/// If `a.len() != b.len()`.
#[inline]
pub fn gather2<A: Send, B: Send>(
    a: &mut [A],
    b: &mut [B],
    f: impl Fn(usize, &mut A, &mut B) + Sync + Send,
) {
    assert_eq!(a.len(), b.len(), "gather2 lengths");
    let rows = |start: usize, pa: &mut [A], pb: &mut [B]| {
        crate::wide::dispatch(
            #[inline(always)]
            || {
                for (k, (a, b)) in pa.iter_mut().zip(pb.iter_mut()).enumerate() {
                    f(start + k, a, b);
                }
            },
        )
    };
    let n = a.len();
    if !worth_splitting(n) {
        return rows(0, a, b);
    }
    let tasks = task_count(n);
    let (a, b) = (SharedMut::new(a), SharedMut::new(b));
    crate::team::run_tasks(tasks, &|k| {
        let range = k * n / tasks..(k + 1) * n / tasks;
        // SAFETY: the tasks' ranges are disjoint and within both arrays.
        let (pa, pb) = unsafe { (a.slice(range.clone()), b.slice(range.clone())) };
        rows(range.start, pa, pb);
    });
}

/// The largest `f(i)` over `0..n` (`init` when `n == 0`), on the [`crate::team`]. Exact in any
/// order, hence the same for every thread count (a NaN is dropped, as by `f64::max`).
pub fn max_over(n: usize, init: f64, f: impl Fn(usize) -> f64 + Sync + Send) -> f64 {
    fold_chunks(
        n,
        #[inline(always)]
        |rows| rows.map(&f).fold(init, f64::max),
    )
    .into_iter()
    .fold(init, f64::max)
}

/// The smallest `i < n` with `pred(i)`, on the [`crate::team`] (the same for every thread count).
pub fn first_index(n: usize, pred: impl Fn(usize) -> bool + Sync + Send) -> Option<usize> {
    fold_chunks(
        n,
        #[inline(always)]
        |rows| {
            // A loop, not `Iterator::find`: `find`'s own closure would not be inlined into
            // the AVX2 copy (crate::wide).
            #[allow(clippy::manual_find)]
            for i in rows {
                if pred(i) {
                    return Some(i);
                }
            }
            None
        },
    )
    .into_iter()
    .flatten()
    .next()
}

/// How many equal tasks a loop over `n` particles (`n` ≥ 2 × [`MIN_PARTICLES_PER_TASK`]) is cut
/// into: a multiple of the thread count, each of at least [`MIN_PARTICLES_PER_TASK`] particles.
/// On the 1,612-particle plate with two threads that is one task per thread (three tasks of
/// 537 left one thread with two: 4 % slower).
fn task_count(n: usize) -> usize {
    let threads = rayon::current_num_threads().max(1);
    let rounds = (n / (MIN_PARTICLES_PER_TASK * threads)).max(1);
    (rounds * threads).min(n / MIN_PARTICLES_PER_TASK)
}

/// `[f(0), …, f(tasks − 1)]`, one task each on the [`crate::team`] (for work already cut into
/// blocks, e.g. the neighbour search's blocks of rows). The result is in task order.
pub fn map_tasks<R: Send>(tasks: usize, f: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
    let mut out: Vec<Option<R>> = (0..tasks).map(|_| None).collect();
    let slots = SharedMut::new(&mut out);
    crate::team::run_tasks(tasks, &|k| {
        // SAFETY: task `k` alone writes slot `k`.
        let slot = unsafe { slots.slice(k..k + 1) };
        slot[0] = Some(crate::wide::dispatch(
            #[inline(always)]
            || f(k),
        ));
    });
    out.into_iter()
        .map(|r| r.expect("every task ran"))
        .collect()
}

/// `fold(rows)` for consecutive ranges of rows covering `0..n`, in order: one range on the
/// calling thread below the splitting size, else one per task of the [`crate::team`]. For
/// reductions: combine the results in order and the sum is the same for a given thread count;
/// exact ones (max, min) are the same for every thread count.
pub fn fold_chunks<R: Send>(
    n: usize,
    fold: impl Fn(std::ops::Range<usize>) -> R + Sync + Send,
) -> Vec<R> {
    if !worth_splitting(n) {
        return vec![crate::wide::dispatch(
            #[inline(always)]
            || fold(0..n),
        )];
    }
    let tasks = task_count(n);
    map_tasks(
        tasks,
        #[inline(always)]
        |k| fold(k * n / tasks..(k + 1) * n / tasks),
    )
}

/// Per-particle arrays one loop writes together: a tuple of mutable slices, each either one
/// entry per particle or empty (a field the scene does not carry, e.g. UL's `τ` when it is not
/// integrated). [`fold_columns`] hands each task its rows of every array, so a loop that
/// updates several fields of a particle (a drift of `x`, `ρ` and `τ` with the pressure of the
/// new `ρ`) is one pass instead of one per field.
pub trait Columns<'a>: Sized {
    /// The arrays while the tasks of one loop share them.
    #[doc(hidden)]
    type Shared: Sync;
    /// One task's rows of every array (an empty array gives an empty slice).
    type Part;
    /// # Panics
    /// If an array is neither `n` long nor empty.
    #[doc(hidden)]
    fn share(self, n: usize) -> Self::Shared;
    /// # Safety
    /// `rows` within `0..n`, and no two live parts of the same shared arrays overlap.
    #[doc(hidden)]
    unsafe fn part(shared: &Self::Shared, rows: std::ops::Range<usize>) -> Self::Part;
}

macro_rules! columns_for_tuple {
    ($($name:ident : $t:ident),+) => {
        impl<'a, $($t: Send + 'a),+> Columns<'a> for ($(&'a mut [$t],)+) {
            type Shared = ($(SharedMut<$t>,)+);
            type Part = ($(&'a mut [$t],)+);
            fn share(self, n: usize) -> Self::Shared {
                let ($($name,)+) = self;
                $(assert!(
                    $name.len() == n || $name.is_empty(),
                    "a column of {} entries in a loop over {n} particles",
                    $name.len()
                );)+
                ($(SharedMut::new($name),)+)
            }
            unsafe fn part(shared: &Self::Shared, rows: std::ops::Range<usize>) -> Self::Part {
                let ($($name,)+) = shared;
                // SAFETY: the caller's contract (disjoint rows within every non-empty array).
                unsafe {
                    ($(if $name.len == 0 { $name.slice(0..0) } else { $name.slice(rows.clone()) },)+)
                }
            }
        }
    };
}
columns_for_tuple!(a: A);
columns_for_tuple!(a: A, b: B);
columns_for_tuple!(a: A, b: B, c: C);
columns_for_tuple!(a: A, b: B, c: C, d: E);
columns_for_tuple!(a: A, b: B, c: C, d: E, e: G);
columns_for_tuple!(a: A, b: B, c: C, d: E, e: G, f: H);
columns_for_tuple!(a: A, b: B, c: C, d: E, e: G, f: H, g: I);
columns_for_tuple!(a: A, b: B, c: C, d: E, e: G, f: H, g: I, h: J);

/// `fold(rows, part)` for consecutive ranges of rows covering `0..n`, where `part` holds those
/// rows of every array of `columns` ([`Columns`]); the results in order. The same ranges as
/// [`fold_chunks`]: one on the calling thread below the splitting size, else one per task of
/// the [`crate::team`]. Each task writes only its own rows, so the arrays come out the same
/// for every thread count; a reduction over the results is as deterministic as with
/// [`fold_chunks`].
///
/// ```
/// let (mut x, mut y) = (vec![1.0; 3000], vec![0.0; 3000]);
/// let largest = sph_core::parallel::fold_columns(3000, (&mut x[..], &mut y[..]), |rows, (x, y)| {
///     let mut m = 0.0f64;
///     for (k, i) in rows.enumerate() {
///         x[k] += i as f64;
///         y[k] = 2.0 * x[k];
///         m = m.max(y[k]);
///     }
///     m
/// });
/// assert_eq!(largest.into_iter().fold(0.0, f64::max), 6000.0);
/// assert!(x.iter().enumerate().all(|(i, &v)| v == 1.0 + i as f64));
/// ```
pub fn fold_columns<'a, C: Columns<'a>, R: Send>(
    n: usize,
    columns: C,
    fold: impl Fn(std::ops::Range<usize>, C::Part) -> R + Sync + Send,
) -> Vec<R> {
    let shared = columns.share(n);
    // SAFETY (both): the ranges are disjoint and within `0..n`; each is one task's.
    if !worth_splitting(n) {
        let part = unsafe { C::part(&shared, 0..n) };
        return vec![crate::wide::dispatch(
            #[inline(always)]
            || fold(0..n, part),
        )];
    }
    let tasks = task_count(n);
    map_tasks(
        tasks,
        #[inline(always)]
        |k| {
            let rows = k * n / tasks..(k + 1) * n / tasks;
            fold(rows.clone(), unsafe { C::part(&shared, rows) })
        },
    )
}

/// [`fold_columns`] without a result: `update(rows, part)` for the rows of every task.
pub fn gather_columns<'a, C: Columns<'a>>(
    n: usize,
    columns: C,
    update: impl Fn(std::ops::Range<usize>, C::Part) + Sync + Send,
) {
    let shared = columns.share(n);
    // SAFETY (both): the ranges are disjoint and within `0..n`; each is one task's.
    let rows = |rows: std::ops::Range<usize>, part: C::Part| {
        crate::wide::dispatch(
            #[inline(always)]
            || update(rows, part),
        )
    };
    if !worth_splitting(n) {
        return rows(0..n, unsafe { C::part(&shared, 0..n) });
    }
    let tasks = task_count(n);
    crate::team::run_tasks(tasks, &|k| {
        let range = k * n / tasks..(k + 1) * n / tasks;
        rows(range.clone(), unsafe { C::part(&shared, range) });
    });
}

/// A slice shared by the tasks of one loop, each of which takes a disjoint part.
#[doc(hidden)]
pub struct SharedMut<T> {
    ptr: *mut T,
    len: usize,
}

// SAFETY: only disjoint parts are handed out (callers' contract of `slice`), each to one task.
unsafe impl<T: Send> Sync for SharedMut<T> {}

impl<T> SharedMut<T> {
    fn new(s: &mut [T]) -> Self {
        Self {
            ptr: s.as_mut_ptr(),
            len: s.len(),
        }
    }

    /// # Safety
    /// `r` within the slice, and no two live parts overlap.
    #[allow(clippy::mut_from_ref)]
    unsafe fn slice<'b>(&self, r: std::ops::Range<usize>) -> &'b mut [T] {
        assert!(r.start <= r.end && r.end <= self.len);
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(r.start), r.end - r.start) }
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
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    gather_blocks(
        offsets,
        out,
        #[inline(always)]
        |rows, mut block: &mut [T]| {
            for i in rows {
                let (slots, tail) =
                    std::mem::take(&mut block).split_at_mut(offsets[i + 1] - offsets[i]);
                f(i, slots);
                block = tail;
            }
        },
    );
}

/// `f(rows, block)` for the blocks of particles [`gather_slices`] hands to one task each, where
/// `block = &mut out[offsets[rows.start]..offsets[rows.end]]`: for work that needs a task's
/// rows together. The blocks depend only on the particle count ([`blocks`] names them),
/// never on the thread count.
///
/// # Panics
/// If `out.len() != offsets[last] - offsets[0]`.
pub fn gather_blocks<T: Send>(
    offsets: &[usize],
    out: &mut [T],
    f: impl Fn(std::ops::Range<usize>, &mut [T]) + Sync,
) {
    let n = offsets.len().saturating_sub(1);
    if n == 0 {
        return;
    }
    assert_eq!(out.len(), offsets[n] - offsets[0], "pair buffer length");
    split_blocks(offsets, out, &f);
}

/// The blocks of [`gather_blocks`] over `n` particles, in order: `0..n` halved until a part
/// is too small to split ([`worth_splitting`]). They depend only on `n`, never on the thread
/// count, so work cut along them (e.g. [`crate::pairs::PairSymmetry`]) is the same on every
/// thread count.
pub fn blocks(n: usize) -> Vec<std::ops::Range<usize>> {
    fn halve(rows: std::ops::Range<usize>, out: &mut Vec<std::ops::Range<usize>>) {
        if worth_splitting(rows.len()) {
            // The same halving as `split_blocks`.
            let mid = rows.start + rows.len() / 2;
            halve(rows.start..mid, out);
            halve(mid..rows.end, out);
        } else {
            out.push(rows);
        }
    }
    let mut out = Vec::new();
    if n > 0 {
        halve(0..n, &mut out);
    }
    out
}

/// `[f(rows) for rows in blocks(n)]`: one task per block of [`blocks`] on the [`crate::team`],
/// the results in block order. A sum cut this way (each block summed in particle order, the
/// blocks' sums added in block order) is the same for every thread count. `f` should be an
/// `#[inline(always)]` closure (see [`crate::wide::dispatch`]).
pub fn map_blocks<R: Send>(
    n: usize,
    f: impl Fn(std::ops::Range<usize>) -> R + Sync + Send,
) -> Vec<R> {
    let blocks = blocks(n);
    map_tasks(
        blocks.len(),
        #[inline(always)]
        |b| f(blocks[b].clone()),
    )
}

/// [`map_blocks`] with each block's rows of `columns` ([`Columns`]): `[f(rows, part) for rows
/// in blocks(n)]`, one task per block, the results in block order. For a pass that sums per
/// block (the same bits for every thread count, as with [`map_blocks`]) and updates its rows in
/// the same task.
pub fn map_block_columns<'a, C: Columns<'a>, R: Send>(
    n: usize,
    columns: C,
    f: impl Fn(std::ops::Range<usize>, C::Part) -> R + Sync + Send,
) -> Vec<R> {
    let shared = columns.share(n);
    let blocks = blocks(n);
    map_tasks(
        blocks.len(),
        #[inline(always)]
        |b| {
            let rows = blocks[b].clone();
            // SAFETY: the blocks are disjoint ranges within `0..n`, one per task.
            f(rows.clone(), unsafe { C::part(&shared, rows) })
        },
    )
}

/// The blocks of [`gather_blocks`] as tasks of the team: the halving tree is walked to the depth
/// of its largest leaf, and task `k` follows the bits of `k` down it; a leaf reached above
/// that depth belongs to the task whose remaining bits are zero.
fn split_blocks<T: Send>(
    offsets: &[usize],
    out: &mut [T],
    f: &(impl Fn(std::ops::Range<usize>, &mut [T]) + Sync),
) {
    let n = offsets.len() - 1;
    let mut depth = 0;
    while worth_splitting(n.div_ceil(1 << depth)) {
        depth += 1;
    }
    let base = offsets[0];
    let out = SharedMut::new(out);
    crate::team::run_tasks(1 << depth, &|k| {
        let (mut start, mut end) = (0, n);
        for bit in (0..depth).rev() {
            if !worth_splitting(end - start) {
                if k & ((1 << (bit + 1)) - 1) != 0 {
                    return;
                }
                break;
            }
            // The same halving as `blocks`.
            let mid = start + (end - start) / 2;
            if (k >> bit) & 1 == 0 {
                end = mid;
            } else {
                start = mid;
            }
        }
        // SAFETY: the leaves of the tree are disjoint row ranges, each run by one task.
        let block = unsafe { out.slice(offsets[start] - base..offsets[end] - base) };
        crate::wide::dispatch(
            #[inline(always)]
            || f(start..end, block),
        );
    });
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
            gather_slices(&offsets, &mut out, |i, slots: &mut [usize]| {
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
    fn gather_blocks_runs_the_blocks_that_blocks_names() {
        for n in [1usize, 1023, 1024, 3000, 5000, 70_001] {
            let offsets: Vec<usize> = (0..=n).collect();
            let mut out = vec![usize::MAX; n];
            gather_blocks(&offsets, &mut out, |rows, block: &mut [usize]| {
                assert_eq!(block.len(), rows.len());
                block.iter_mut().for_each(|b| *b = rows.start);
            });
            let named = blocks(n);
            assert_eq!(named.first().map(|b| b.start), Some(0));
            assert_eq!(named.last().map(|b| b.end), Some(n));
            for pair in named.windows(2) {
                assert_eq!(pair[0].end, pair[1].start, "{n} particles");
            }
            for b in &named {
                assert!(n < 2 * MIN_PARTICLES_PER_TASK || b.len() >= MIN_PARTICLES_PER_TASK);
                assert!(out[b.clone()].iter().all(|&s| s == b.start), "{b:?} of {n}");
            }
        }
        assert!(blocks(0).is_empty());
    }

    #[test]
    fn columns_give_each_task_its_own_rows_of_every_array_and_skip_empty_ones() {
        use crate::team::in_pool;
        for n in [0usize, 5, 1023, 1024, 5000] {
            for threads in 1..=3 {
                in_pool(threads, || {
                    let (mut a, mut b, mut none) =
                        (vec![0usize; n], vec![0.0f64; n], Vec::<u8>::new());
                    let sums = fold_columns(
                        n,
                        (&mut a[..], &mut b[..], &mut none[..]),
                        |rows, (a, b, none)| {
                            assert!(none.is_empty());
                            assert_eq!((a.len(), b.len()), (rows.len(), rows.len()));
                            for (k, i) in rows.clone().enumerate() {
                                assert_eq!(a[k], 0, "row {i} written twice");
                                a[k] = i + 1;
                                b[k] = 0.5 * i as f64;
                            }
                            rows.len()
                        },
                    );
                    assert_eq!(sums.iter().sum::<usize>(), n);
                    assert!(a.iter().enumerate().all(|(i, &x)| x == i + 1));
                    assert!(b.iter().enumerate().all(|(i, &x)| x == 0.5 * i as f64));
                    gather_columns(n, (&mut a[..],), |rows, (a,)| {
                        for (k, i) in rows.enumerate() {
                            a[k] += i;
                        }
                    });
                    assert!(a.iter().enumerate().all(|(i, &x)| x == 2 * i + 1));
                });
            }
        }
    }

    #[test]
    #[should_panic(expected = "a column of 3 entries in a loop over 4 particles")]
    fn a_column_of_another_length_is_refused() {
        let (mut a, mut b) = (vec![0u8; 4], vec![0u8; 3]);
        gather_columns(4, (&mut a[..], &mut b[..]), |_, _| {});
    }

    #[test]
    fn gather_writes_each_entry_from_its_index() {
        for n in [0usize, 5, 3000] {
            let mut out = vec![0usize; n];
            gather(&mut out, |i, o| *o = 3 * i + 1);
            assert!(out.iter().enumerate().all(|(i, &o)| o == 3 * i + 1));
        }
    }

    #[test]
    fn reductions_and_maps_are_the_same_on_every_thread_count() {
        use crate::team::in_pool;
        for n in [0usize, 3, 1023, 1024, 5000, 70_001] {
            let v: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1013) as f64 - 500.0).collect();
            let serial_max = v.iter().copied().fold(-1e300, f64::max);
            let serial_first = v.iter().position(|&x| x > 505.0);
            for threads in 1..=3 {
                in_pool(threads, || {
                    assert_eq!(max_over(n, -1e300, |i| v[i]), serial_max);
                    assert_eq!(first_index(n, |i| v[i] > 505.0), serial_first);
                    let chunks = fold_chunks(n, |r| r.clone());
                    let mut next = 0;
                    for r in &chunks {
                        assert_eq!(r.start, next);
                        next = r.end;
                    }
                    assert_eq!(next, n);
                    assert_eq!(map_tasks(7, |k| k * k), vec![0, 1, 4, 9, 16, 25, 36]);
                    let (mut a, mut b) = (vec![0usize; n], vec![0.0; n]);
                    gather2(&mut a, &mut b, |i, a, b| {
                        *a = 2 * i;
                        *b = v[i];
                    });
                    assert!(a.iter().enumerate().all(|(i, &x)| x == 2 * i));
                    assert_eq!(b, v);
                });
            }
        }
    }
}
