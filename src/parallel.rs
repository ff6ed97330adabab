//! How many threads the calling code may use, and the run's own pool.
//!
//! A run with several threads executes inside its own rayon pool; a single-threaded run, and
//! any library call from a plain thread, runs on the caller's thread. Parallel loops ask
//! [`threads_here`] rather than rayon's global count, so code called outside a pool never
//! hands work to rayon's global pool (threads the user did not ask for, and a cross-thread
//! hand-off per call).
//!
//! Beside the pool a run has a [`Team`]: threads that stay awake while the run advances and
//! take the granular step's regions (pair loop, force merge, integrator, fracture check,
//! neighbour rows) through [`on_team`]. Rayon's workers sleep between regions and took tens of
//! microseconds to wake on the CI machine, which made a second thread useless at 1000 bodies.

use std::any::Any;
use std::cell::{Cell, UnsafeCell};
use std::ops::Range;
use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// The size of the rayon pool the caller runs in, or 1 outside any pool.
pub fn threads_here() -> usize {
    if rayon::current_thread_index().is_some() {
        rayon::current_num_threads()
    } else {
        1
    }
}

/// A pool of `threads` workers (0: one per core), or none for a single thread: then the run
/// stays on the caller's thread and never hands work across threads.
///
/// More threads than the machine has cores is refused (a request for 100,000 made rayon start
/// them and the run hang): more threads than cores only adds hand-offs, and results depend on
/// the thread count, so it is not silently clamped either.
pub fn thread_pool(threads: usize) -> Result<Option<Arc<rayon::ThreadPool>>> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if threads > cores {
        return Err(Error::input(
            "--threads",
            format!(
                "{threads} is more than the {cores} cores of this machine: use 1 to {cores} (0: every core)"
            ),
        ));
    }
    let threads = if threads == 0 { cores } else { threads };
    if threads <= 1 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(|p| Some(Arc::new(p)))
        .map_err(|e| Error::run(format!("cannot start {threads} worker threads ({e})")))
}

/// Runs `f` on the pool's threads, or right here without one.
fn on_threads<R: Send>(pool: &Option<Arc<rayon::ThreadPool>>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// A run's threads: the rayon pool (dlsm, beam2d, and anything else written with rayon) and
/// the worker team (the granular step's regions). Both `None` on one thread.
#[derive(Clone, Default)]
pub struct Threads {
    pool: Option<Arc<rayon::ThreadPool>>,
    team: Option<Arc<Team>>,
}

impl Threads {
    /// `threads` workers (0: one per core); see [`thread_pool`].
    pub fn new(threads: usize) -> Result<Self> {
        let pool = thread_pool(threads)?;
        let team = match &pool {
            Some(p) => Some(Arc::new(Team::new(p.current_num_threads())?)),
            None => None,
        };
        Ok(Threads { pool, team })
    }

    pub fn count(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    /// Runs `f` on the pool, with the team awake (spinning between jobs) if `team`, or right
    /// here. A model whose regions use rayon runs without it: team members spinning beside
    /// rayon's workers would take their cores.
    pub fn run<R: Send>(&self, team: bool, f: impl FnOnce() -> R + Send) -> R {
        on_threads(&self.pool, || match &self.team {
            Some(t) if team => t.awake_for(f),
            _ => f(),
        })
    }
}

/// How long a team worker spins for its next job before it sleeps. Between the regions of a
/// step the caller works alone for a few microseconds (the walls, the integrator's serial
/// part); between steps for tens. Waking a sleeping thread took tens of microseconds on the
/// 2-core CI machine, twice per step, which is why the pair loop did not go parallel below
/// 1500 bodies per thread with rayon.
const SPIN: Duration = Duration::from_micros(500);

type Job = dyn Fn(usize) + Sync;

/// A fixed team of threads that stays awake while a run advances: [`Team::run`] hands the same
/// job to every member (the caller is member 0) and returns when all have finished. Members
/// spin for the next job for [`SPIN`], then sleep; outside [`Team::awake_for`] they sleep at
/// once. Work is split by member index only, so for a given team size every sum has a fixed
/// order and runs repeat bit for bit.
pub struct Team {
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
}

struct Shared {
    size: usize,
    /// Bumped once per job; a member runs the job when it sees a new value.
    epoch: AtomicU64,
    /// The current job, valid while `pending` > 0 (written only by the caller of
    /// [`Team::run`], before it bumps `epoch`; read by members after they see the bump).
    job: UnsafeCell<Option<*const Job>>,
    /// Members that have not finished the current job.
    pending: AtomicUsize,
    /// A job is being handed out (a second caller at the same time runs its job alone).
    busy: AtomicBool,
    /// Whether members spin between jobs.
    awake: AtomicBool,
    quit: AtomicBool,
    sleeping: AtomicUsize,
    lock: Mutex<()>,
    bell: Condvar,
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

// SAFETY: `job` is written only while no member reads it (before the epoch bump that
// publishes it, and after `pending` reached 0); every other field is a sync type.
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

thread_local! {
    /// The team of the run this thread is advancing, while it advances.
    static TEAM: Cell<*const Team> = const { Cell::new(std::ptr::null()) };
}

impl Team {
    /// A team of `size` members: `size - 1` new threads and the caller of [`Team::run`].
    pub fn new(size: usize) -> Result<Self> {
        let shared = Arc::new(Shared {
            size: size.max(1),
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            pending: AtomicUsize::new(0),
            busy: AtomicBool::new(false),
            awake: AtomicBool::new(false),
            quit: AtomicBool::new(false),
            sleeping: AtomicUsize::new(0),
            lock: Mutex::new(()),
            bell: Condvar::new(),
            panic: Mutex::new(None),
        });
        let mut team = Team {
            shared,
            workers: Vec::new(),
        };
        for member in 1..team.shared.size {
            let shared = team.shared.clone();
            let handle = std::thread::Builder::new()
                .name(format!("fractum-team-{member}"))
                .spawn(move || shared.serve(member))
                .map_err(|e| Error::run(format!("cannot start worker thread {member} ({e})")))?;
            team.workers.push(handle);
        }
        Ok(team)
    }

    pub fn size(&self) -> usize {
        self.shared.size
    }

    /// Runs `f` with this team as the calling thread's team and its members spinning between
    /// jobs; they sleep again when `f` returns (or unwinds).
    pub fn awake_for<R>(&self, f: impl FnOnce() -> R) -> R {
        struct Restore<'a>(&'a Shared, *const Team);
        impl Drop for Restore<'_> {
            fn drop(&mut self) {
                self.0.awake.store(false, Ordering::Relaxed);
                TEAM.with(|t| t.set(self.1));
            }
        }
        let _restore = Restore(&self.shared, TEAM.with(|t| t.replace(self)));
        self.shared.awake.store(true, Ordering::Relaxed);
        f()
    }

    /// Runs `job(member)` for every member, member 0 on this thread, and returns when all have
    /// finished. A panic in any member is raised here after all have finished.
    pub fn run<'a>(&self, job: &'a (dyn Fn(usize) + Sync + 'a)) {
        let s = &*self.shared;
        // One job at a time. A run owns its team, so a second caller does not happen in the
        // library; were it to, its members' shares run here, in order (which member computes
        // a share changes no result).
        if s.busy.swap(true, Ordering::Acquire) {
            for member in 0..s.size {
                job(member);
            }
            return;
        }
        struct Done<'a>(&'a AtomicBool);
        impl Drop for Done<'_> {
            fn drop(&mut self) {
                self.0.store(false, Ordering::Release);
            }
        }
        let _done = Done(&s.busy);
        // SAFETY: the job outlives its use: this function returns only after every member has
        // finished with it (`pending` = 0), unwinding included. No member reads `job` now:
        // the last job's `pending` reached 0 before the last call returned.
        unsafe {
            *s.job.get() = Some(std::mem::transmute::<
                &'a (dyn Fn(usize) + Sync + 'a),
                *const Job,
            >(job));
        }
        s.pending.store(s.size - 1, Ordering::SeqCst);
        s.epoch.fetch_add(1, Ordering::SeqCst);
        if s.sleeping.load(Ordering::SeqCst) > 0 {
            let _guard = s.lock.lock().unwrap_or_else(|e| e.into_inner());
            s.bell.notify_all();
        }
        // Work on this thread runs without the team: a nested region runs here, in order.
        let outer = TEAM.with(|t| t.replace(std::ptr::null()));
        let mine = panic::catch_unwind(AssertUnwindSafe(|| job(0)));
        TEAM.with(|t| t.set(outer));
        let mut spins = 0u32;
        while s.pending.load(Ordering::Acquire) != 0 {
            spins = spins.saturating_add(1);
            if spins < 1 << 16 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
        // SAFETY: every member has finished with the job.
        unsafe {
            *s.job.get() = None;
        }
        if let Err(p) = mine {
            panic::resume_unwind(p);
        }
        if let Some(p) = s.panic.lock().unwrap_or_else(|e| e.into_inner()).take() {
            panic::resume_unwind(p);
        }
    }
}

impl Drop for Team {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::SeqCst);
        {
            let _guard = self.shared.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.shared.bell.notify_all();
        }
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}

impl Shared {
    /// A member's life: wait for a job, run its share, report, again.
    fn serve(&self, member: usize) {
        let mut seen = 0;
        while let Some(epoch) = self.next_job(seen) {
            seen = epoch;
            // SAFETY: published before the epoch bump just seen, valid until `pending` = 0.
            let job = unsafe { (*self.job.get()).expect("a job is posted before the bump") };
            let done = panic::catch_unwind(AssertUnwindSafe(|| unsafe { (*job)(member) }));
            if let Err(p) = done {
                self.panic
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .get_or_insert(p);
            }
            self.pending.fetch_sub(1, Ordering::Release);
        }
    }

    /// The next job's epoch after `seen`, or `None` when the team is dropped: spins while the
    /// team is awake (for at most [`SPIN`]), then sleeps until the caller rings.
    fn next_job(&self, seen: u64) -> Option<u64> {
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            if self.quit.load(Ordering::Acquire) {
                return None;
            }
            let epoch = self.epoch.load(Ordering::Acquire);
            if epoch != seen {
                return Some(epoch);
            }
            spins = spins.wrapping_add(1);
            if self.awake.load(Ordering::Relaxed) && (spins % 256 != 0 || start.elapsed() < SPIN) {
                std::hint::spin_loop();
                continue;
            }
            let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.sleeping.fetch_add(1, Ordering::SeqCst);
            while self.epoch.load(Ordering::SeqCst) == seen && !self.quit.load(Ordering::SeqCst) {
                guard = self.bell.wait(guard).unwrap_or_else(|e| e.into_inner());
            }
            self.sleeping.fetch_sub(1, Ordering::SeqCst);
        }
    }
}

/// The members of the team of the run this thread advances (1 without one, and inside a
/// team's job).
pub fn team_size() -> usize {
    TEAM.with(|t| {
        let team = t.get();
        // SAFETY: set by `awake_for` for the duration of a borrow of the team.
        (!team.is_null()).then(|| unsafe { (*team).size() })
    })
    .unwrap_or(1)
}

/// Runs `f(k, part)` for every part: part k on team member k mod size when this thread
/// advances a run with a team, here in order otherwise; the results in part order. Parts are
/// assigned by index only, so a given team size always computes each part on the same member
/// with the same inputs.
pub fn on_team<P: Send, R: Send>(parts: Vec<P>, f: impl Fn(usize, P) -> R + Sync) -> Vec<R> {
    let team = TEAM.with(|t| t.get());
    if team.is_null() || parts.len() <= 1 {
        return parts
            .into_iter()
            .enumerate()
            .map(|(k, p)| f(k, p))
            .collect();
    }
    // SAFETY: set by `awake_for` for the duration of a borrow of the team.
    let team = unsafe { &*team };
    let n = parts.len();
    let size = team.size();
    let inputs: Vec<Mutex<Option<P>>> = parts.into_iter().map(|p| Mutex::new(Some(p))).collect();
    let outputs: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    team.run(&|member| {
        for k in (member..n).step_by(size) {
            let part = inputs[k].lock().map(|mut p| p.take()).ok().flatten();
            if let Some(part) = part {
                let r = f(k, part);
                if let Ok(mut out) = outputs[k].lock() {
                    *out = Some(r);
                }
            }
        }
    });
    outputs
        .into_iter()
        .map(|m| {
            m.into_inner()
                .ok()
                .flatten()
                .expect("every part ran (a panic would have been raised)")
        })
        .collect()
}

/// Bodies per block of [`blocks`].
const BLOCK: usize = 32;

/// Fewer bodies than this run a per-body pass on the caller alone.
const TEAM_MIN_BODIES: usize = 256;

/// `0..n` as parts for [`on_team`]: with a team and at least [`TEAM_MIN_BODIES`] items, blocks
/// of [`BLOCK`] consecutive items, dealt to the members in turn (block k to member k mod
/// size); otherwise one part. Dealt blocks balance items of uneven cost (the pieces appended
/// by splits cost twice an initial grain in the integrator: contiguous halves made the caller
/// wait half the time), and each member gets the same blocks in every pass of a step, so their
/// data stays in its core's cache.
#[allow(clippy::single_range_in_vec_init)] // one part: the whole range
pub fn blocks(n: usize) -> Vec<Range<usize>> {
    if team_size() == 1 || n < TEAM_MIN_BODIES {
        return vec![0..n];
    }
    (0..n.div_ceil(BLOCK))
        .map(|k| k * BLOCK..((k + 1) * BLOCK).min(n))
        .collect()
}

/// Disjoint mutable pieces of `data`, one per range (ranges in order, not overlapping).
pub fn split_ranges<'a, T>(mut data: &'a mut [T], ranges: &[Range<usize>]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(ranges.len());
    let mut at = 0;
    for r in ranges {
        let (_, rest) = data.split_at_mut(r.start - at);
        let (piece, rest) = rest.split_at_mut(r.end - r.start);
        out.push(piece);
        data = rest;
        at = r.end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_run_on_their_members_and_results_come_back_in_part_order() {
        let team = Team::new(2).unwrap();
        team.awake_for(|| {
            assert_eq!(team_size(), 2);
            // 0..1000 in blocks of 32: 32 parts, dealt to this thread and the worker in turn.
            let ranges = blocks(1000);
            assert_eq!(ranges.len(), 32);
            assert_eq!((ranges[0].clone(), ranges[31].clone()), (0..32, 992..1000));
            let who = on_team(ranges, |k, r| {
                (k, r.start, std::thread::current().name().map(str::to_owned))
            });
            for (k, (part, start, name)) in who.iter().enumerate() {
                assert_eq!((*part, *start), (k, 32 * k));
                // Odd parts on the worker, even ones on this thread.
                assert_eq!(name.as_deref() == Some("fractum-team-1"), k % 2 == 1);
            }
            // Disjoint mutable pieces: each element written once, by index.
            let mut data = vec![0usize; 1000];
            let ranges = blocks(data.len());
            let parts: Vec<_> = ranges
                .iter()
                .zip(split_ranges(&mut data, &ranges))
                .collect();
            on_team(parts, |_, (r, piece)| {
                for (x, i) in piece.iter_mut().zip(r.clone()) {
                    *x = i;
                }
            });
            assert!(data.iter().enumerate().all(|(i, &x)| i == x));
        });
        // Outside `awake_for` the caller has no team: one part, run here.
        assert_eq!(team_size(), 1);
        assert_eq!(blocks(1000), vec![0..1000]);
    }

    #[test]
    fn a_panic_in_a_member_reaches_the_caller_after_all_finish_and_the_team_goes_on() {
        let team = Team::new(2).unwrap();
        let finished = AtomicUsize::new(0);
        let caught = panic::catch_unwind(AssertUnwindSafe(|| {
            team.run(&|member| {
                if member == 1 {
                    panic!("member 1 fails");
                }
                std::thread::sleep(Duration::from_millis(20));
                finished.fetch_add(1, Ordering::SeqCst);
            })
        }));
        let msg = caught.expect_err("the member's panic is raised on the caller");
        assert_eq!(msg.downcast_ref::<&str>(), Some(&"member 1 fails"));
        // The caller's share had finished before the panic was raised.
        assert_eq!(finished.load(Ordering::SeqCst), 1);
        let sum = AtomicUsize::new(0);
        team.run(&|member| {
            sum.fetch_add(member + 1, Ordering::SeqCst);
        });
        assert_eq!(sum.load(Ordering::SeqCst), 3);
    }

    #[test]
    fn a_region_inside_a_job_runs_on_the_member_in_order() {
        let team = Team::new(2).unwrap();
        team.awake_for(|| {
            let inner = on_team(vec![0, 1], |_, k| {
                on_team(vec![10 * k, 10 * k + 1], |_, x| x)
            });
            assert_eq!(inner, vec![vec![0, 1], vec![10, 11]]);
        });
    }

    #[test]
    fn two_callers_at_once_each_get_every_share_run() {
        let team = Team::new(2).unwrap();
        let total = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| {
                    for _ in 0..2000 {
                        team.run(&|m| {
                            total.fetch_add(m + 1, Ordering::SeqCst);
                        });
                    }
                });
            }
        });
        // Each run adds 1 + 2 for its two shares, whoever ran them.
        assert_eq!(total.load(Ordering::SeqCst), 2 * 2000 * 3);
    }

    #[test]
    fn a_sleeping_team_wakes_for_each_job() {
        let team = Team::new(2).unwrap();
        // Not awake: the worker sleeps between jobs, and each run still completes.
        for n in 0..50 {
            let seen = AtomicUsize::new(0);
            team.run(&|m| {
                seen.fetch_add(m + n, Ordering::SeqCst);
            });
            assert_eq!(seen.load(Ordering::SeqCst), 2 * n + 1);
            if n % 10 == 0 {
                std::thread::sleep(Duration::from_millis(2));
            }
        }
    }
}
