//! A fork–join team whose idle members wait actively: the parallel loops of a time step.
//!
//! A step of a small 2D body is a handful of parallel loops of 10–50 µs each. Handed to the
//! rayon pool, every loop wakes a worker that, once the loop is done, waits for the next one by
//! calling `sched_yield` about thirty times and then sleeps on a futex: on the 1,612-particle
//! plate with two threads that was ~20 system calls per step and a system time of 14–22 % of
//! the user time (`strace -f -c`, docs/performance.md). The team does what OpenMP runtimes do
//! with an active wait policy: its helpers spin in user space (`std::hint::spin_loop`) for
//! [`SPIN`] after a loop and only then park, so a step's loops follow each other without a
//! system call, and a helper that has parked is woken once per stretch of steps.
//!
//! [`run_tasks`] runs `task(k)` for `k in 0..tasks` on the calling thread and up to
//! `rayon::current_num_threads() - 1` helpers, each task claimed by exactly one thread. Which
//! thread runs a task is not deterministic; callers make the result independent of it (every
//! task writes its own entries, [`crate::parallel`]). Calls from inside a task, and calls
//! while another thread leads a loop, run their tasks on the calling thread: one loop at a
//! time, never nested.

use std::cell::{Cell, UnsafeCell};
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::*};
use std::sync::{Condvar, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// How long an idle helper spins before it parks. Longer than the gaps between the loops of
/// a step (serial work between two loops: a few µs to tens of µs on the 2D plate), short
/// enough that a helper does not hold a core while the rest of the program runs on rayon.
pub const SPIN: Duration = Duration::from_micros(200);

/// A loop as the helpers read it: the task (lifetime erased: valid while the leader waits in
/// [`run_tasks`]), the task count and how many helpers may join.
#[derive(Clone, Copy)]
struct Region {
    task: Option<*const (dyn Fn(usize) + Sync + 'static)>,
    tasks: usize,
    helpers: usize,
}

/// Most contiguous shares a loop is cut into (participants beyond this only help).
const SHARES: usize = 64;

/// A cursor on its own cache line (the participants update different cursors).
#[repr(align(128))]
struct Padded(AtomicUsize);

struct Team {
    /// Even: a loop is open (or none since the last one); odd: the leader is writing `region`.
    epoch: AtomicUsize,
    /// Written by the leader only while `epoch` is odd and no helper is `active`.
    region: UnsafeCell<Region>,
    /// Claim cursors: the tasks are cut into one contiguous share per participant (at most
    /// [`SHARES`]); cursor `q` counts the claimed tasks of share `q`.
    cursors: [Padded; SHARES],
    /// Tasks not yet finished.
    pending: AtomicUsize,
    /// Helpers that may be reading `region`.
    active: AtomicUsize,
    /// A task panicked in a helper (the leader re-raises it).
    panicked: AtomicBool,
    /// One leader at a time.
    leader: Mutex<()>,
    /// Helpers spawned so far (grows to the largest thread count asked for).
    spawned: Mutex<usize>,
    /// Parked helpers and the condition they wait on.
    sleepers: AtomicUsize,
    parked: Mutex<()>,
    wake: Condvar,
}

// SAFETY: `region` is the only non-Sync field; the epoch protocol of `run_tasks` and
// `help` makes its writes (leader, odd epoch, no active helper) and reads (helpers, even
// epoch, counted in `active`) exclusive. The task it points to is `Sync`.
unsafe impl Sync for Team {}
// SAFETY: as above; the team lives in a static and is never moved between threads.
unsafe impl Send for Team {}

thread_local! {
    /// Set while this thread runs a team task or leads a loop: nested calls run inline.
    static IN_TEAM: Cell<bool> = const { Cell::new(false) };
}

fn team() -> &'static Team {
    static TEAM: OnceLock<Team> = OnceLock::new();
    TEAM.get_or_init(|| Team {
        epoch: AtomicUsize::new(0),
        region: UnsafeCell::new(Region {
            task: None,
            tasks: 0,
            helpers: 0,
        }),
        cursors: std::array::from_fn(|_| Padded(AtomicUsize::new(0))),
        pending: AtomicUsize::new(0),
        active: AtomicUsize::new(0),
        panicked: AtomicBool::new(false),
        leader: Mutex::new(()),
        spawned: Mutex::new(0),
        sleepers: AtomicUsize::new(0),
        parked: Mutex::new(()),
        wake: Condvar::new(),
    })
}

/// `task(k)` for every `k in 0..tasks`, spread over the calling thread and up to
/// `rayon::current_num_threads() - 1` team helpers; returns when every task has finished.
/// A panic in a task is re-raised here after the other tasks have finished.
///
/// ```
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// let hits: Vec<AtomicUsize> = (0..100).map(|_| AtomicUsize::new(0)).collect();
/// sph_core::team::run_tasks(100, &|k| {
///     hits[k].fetch_add(1, Ordering::Relaxed);
/// });
/// assert!(hits.iter().all(|h| h.load(Ordering::Relaxed) == 1));
/// ```
pub fn run_tasks(tasks: usize, task: &(dyn Fn(usize) + Sync)) {
    let helpers = rayon::current_num_threads().saturating_sub(1);
    if tasks <= 1 || helpers == 0 || IN_TEAM.with(Cell::get) {
        (0..tasks).for_each(task);
        return;
    }
    let team = team();
    let _lead = match team.leader.try_lock() {
        Ok(g) => g,
        // A loop that panicked before: the team itself is intact (see `claim`).
        Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner(),
        Err(std::sync::TryLockError::WouldBlock) => {
            // Another thread leads a loop (e.g. a test running beside this one).
            (0..tasks).for_each(task);
            return;
        }
    };
    team.spawn_helpers(helpers);
    IN_TEAM.with(|f| f.set(true));
    let e = team.epoch.load(Relaxed);
    debug_assert!(e.is_multiple_of(2));
    team.epoch.store(e + 1, SeqCst);
    // Helpers still leaving the previous loop read `region`: wait for them.
    let mut spins = 0u32;
    while team.active.load(SeqCst) != 0 {
        backoff(&mut spins);
    }
    // SAFETY: the lifetime is erased only for the helpers, which call the task while
    // `pending > 0`, and this function does not return before `pending == 0`.
    let erased: *const (dyn Fn(usize) + Sync + 'static) =
        unsafe { std::mem::transmute(task as *const (dyn Fn(usize) + Sync)) };
    // SAFETY: epoch odd and no helper active: no one reads `region` (see `help`).
    unsafe {
        *team.region.get() = Region {
            task: Some(erased),
            tasks,
            helpers,
        }
    };
    for c in &team.cursors[..shares(helpers)] {
        c.0.store(0, Relaxed);
    }
    team.pending.store(tasks, Relaxed);
    team.panicked.store(false, Relaxed);
    team.epoch.store(e + 2, SeqCst);
    if team.sleepers.load(SeqCst) > 0 {
        let _g = team.parked.lock().unwrap_or_else(|p| p.into_inner());
        team.wake.notify_all();
    }
    let mine = catch_unwind(AssertUnwindSafe(|| team.claim(0, helpers, tasks, task)));
    // The task must outlive every call of it.
    spins = 0;
    while team.pending.load(Acquire) != 0 {
        backoff(&mut spins);
    }
    IN_TEAM.with(|f| f.set(false));
    if let Err(p) = mine {
        resume_unwind(p);
    }
    if team.panicked.load(Acquire) {
        panic!("a parallel task panicked on a team helper (its message is above)");
    }
}

/// How many contiguous shares a loop with `helpers` helpers is cut into.
fn shares(helpers: usize) -> usize {
    (helpers + 1).min(SHARES)
}

/// Spin, then yield the core now and then (a helper may have been descheduled mid-task).
fn backoff(spins: &mut u32) {
    *spins += 1;
    if *spins < 1 << 14 {
        std::hint::spin_loop();
    } else {
        std::thread::yield_now();
    }
}

impl Team {
    /// Claims and runs tasks until none is left: first those of participant `p`'s own share
    /// (the leader is 0, helper `id` is `id + 1`), then what is left of the others', in
    /// order. The same participant gets the same rows in every loop of a step, so each thread
    /// keeps working on the particles its cache holds (claiming any free task instead was
    /// about 5 % slower on the 6,100-particle twisting column with two threads: TL-HF 3.52
    /// against 3.32 s, TL-GM 6.36 against 6.04 s to t = 0.1 s, median of 3 interleaved).
    fn claim(&self, p: usize, helpers: usize, tasks: usize, task: impl Fn(usize)) {
        let parts = shares(helpers);
        for q in (0..parts).map(|q| (p + q) % parts) {
            let (lo, hi) = (q * tasks / parts, (q + 1) * tasks / parts);
            loop {
                let k = lo + self.cursors[q].0.fetch_add(1, Relaxed);
                if k >= hi {
                    break;
                }
                let done = catch_unwind(AssertUnwindSafe(|| task(k)));
                if done.is_err() {
                    self.panicked.store(true, Release);
                }
                self.pending.fetch_sub(1, AcqRel);
            }
        }
    }

    fn spawn_helpers(&'static self, wanted: usize) {
        let mut spawned = self.spawned.lock().unwrap_or_else(|p| p.into_inner());
        while *spawned < wanted {
            let id = *spawned;
            let started = std::thread::Builder::new()
                .name(format!("sph-team-{id}"))
                .spawn(move || self.help(id));
            if started.is_err() {
                // No more threads: the loop runs on those there are.
                return;
            }
            *spawned += 1;
        }
    }

    /// A helper's life: wait for a loop, join it if the leader asked for this many helpers,
    /// claim tasks until none is left, wait for the next.
    fn help(&self, id: usize) {
        IN_TEAM.with(|f| f.set(true));
        let mut seen = self.epoch.load(SeqCst) & !1;
        loop {
            let e = self.wait_for_loop(seen);
            seen = e;
            self.active.fetch_add(1, SeqCst);
            if self.epoch.load(SeqCst) == e {
                // SAFETY: counted in `active` under an even epoch: the leader does not write
                // `region` until `active` is zero.
                let r = unsafe { *self.region.get() };
                if let (Some(task), true) = (r.task, id < r.helpers) {
                    // SAFETY: the leader keeps the task alive while tasks are pending, and the
                    // pointer is dereferenced only after claiming an index below `tasks` (a
                    // helper arriving after the loop ended claims none).
                    self.claim(id + 1, r.helpers, r.tasks, |k| unsafe { (*task)(k) });
                }
            }
            self.active.fetch_sub(1, SeqCst);
        }
    }

    /// Waits until the epoch is even and differs from `seen`: spins for [`SPIN`], then parks.
    fn wait_for_loop(&self, seen: usize) -> usize {
        let open = |e: usize| e.is_multiple_of(2) && e != seen;
        let start = Instant::now();
        let mut i = 0u32;
        loop {
            let e = self.epoch.load(Acquire);
            if open(e) {
                return e;
            }
            std::hint::spin_loop();
            i = i.wrapping_add(1);
            if i.is_multiple_of(64) && start.elapsed() > SPIN {
                break;
            }
        }
        let mut g = self.parked.lock().unwrap_or_else(|p| p.into_inner());
        self.sleepers.fetch_add(1, SeqCst);
        loop {
            let e = self.epoch.load(SeqCst);
            if open(e) {
                self.sleepers.fetch_sub(1, SeqCst);
                return e;
            }
            g = self.wake.wait(g).unwrap_or_else(|p| p.into_inner());
        }
    }
}

/// `f` inside a rayon pool of `threads` threads (tests of the team and its users).
#[cfg(test)]
pub(crate) fn in_pool<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicU64;

    #[test]
    fn every_task_runs_exactly_once_on_any_thread_count() {
        for threads in 1..=4 {
            in_pool(threads, || {
                for tasks in [0usize, 1, 2, 3, 17, 1000] {
                    for _ in 0..50 {
                        let hits: Vec<AtomicU64> = (0..tasks).map(|_| AtomicU64::new(0)).collect();
                        run_tasks(tasks, &|k| {
                            hits[k].fetch_add(1, Relaxed);
                        });
                        assert!(
                            hits.iter().all(|h| h.load(Relaxed) == 1),
                            "{threads} {tasks}"
                        );
                    }
                }
            });
        }
    }

    #[test]
    fn the_helpers_take_part() {
        // With two threads, over loops whose tasks wait a little, some task runs off the
        // calling thread. Other tests lead loops at the same time (one leader at a time: the
        // others run inline), so keep trying for a while.
        in_pool(2, || {
            let me = std::thread::current().id();
            let elsewhere = AtomicU64::new(0);
            let start = Instant::now();
            while elsewhere.load(Relaxed) == 0 && start.elapsed() < Duration::from_secs(20) {
                run_tasks(4, &|_| {
                    let t = Instant::now();
                    while t.elapsed() < Duration::from_micros(50) {
                        std::hint::spin_loop();
                    }
                    if std::thread::current().id() != me {
                        elsewhere.fetch_add(1, Relaxed);
                    }
                });
            }
            assert!(elsewhere.load(Relaxed) > 0);
        });
    }

    #[test]
    fn nested_loops_run_inline_and_complete() {
        in_pool(3, || {
            let sum = AtomicU64::new(0);
            run_tasks(8, &|k| {
                run_tasks(8, &|j| {
                    sum.fetch_add((k * 8 + j) as u64, Relaxed);
                });
            });
            assert_eq!(sum.load(Relaxed), (0..64).sum::<u64>());
        });
    }

    #[test]
    fn a_panicking_task_is_re_raised_after_the_others_finish() {
        in_pool(2, || {
            let done = AtomicU64::new(0);
            let r = catch_unwind(AssertUnwindSafe(|| {
                run_tasks(16, &|k| {
                    if k == 5 {
                        panic!("task 5");
                    }
                    done.fetch_add(1, Relaxed);
                })
            }));
            assert!(r.is_err());
            assert_eq!(done.load(Relaxed), 15);
            // The team still works afterwards.
            let n = AtomicU64::new(0);
            run_tasks(10, &|_| {
                n.fetch_add(1, Relaxed);
            });
            assert_eq!(n.load(Relaxed), 10);
        });
    }

    #[test]
    fn loops_led_from_several_threads_at_once_all_complete() {
        std::thread::scope(|s| {
            for _ in 0..3 {
                s.spawn(|| {
                    in_pool(2, || {
                        for _ in 0..200 {
                            let n = AtomicU64::new(0);
                            run_tasks(7, &|_| {
                                n.fetch_add(1, Relaxed);
                            });
                            assert_eq!(n.load(Relaxed), 7);
                        }
                    })
                });
            }
        });
    }
}
