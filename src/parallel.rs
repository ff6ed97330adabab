//! How many threads the calling code may use, and the run's own pool.
//!
//! A run with several threads executes inside its own rayon pool; a single-threaded run, and
//! any library call from a plain thread, runs on the caller's thread. Parallel loops ask
//! [`threads_here`] rather than rayon's global count, so code called outside a pool never
//! hands work to rayon's global pool (threads the user did not ask for, and a cross-thread
//! hand-off per call).
//!
//! Beside the pool a run has a [`Team`]: threads that stay awake while the run advances and
//! take the granular step's regions (pair loop, force merge, integrator, placements, wall
//! contacts, fracture check, springs, frequency bound, neighbour rows) through [`on_team`]. Rayon's workers sleep between regions and took tens of
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

    /// Runs `f` on the pool, with the first `members` of the team awake (spinning between
    /// jobs) if that is more than one, or right here. A model whose regions use rayon runs
    /// without it (`members` 1): team members spinning beside rayon's workers would take
    /// their cores.
    pub fn run<R: Send>(&self, members: usize, f: impl FnOnce() -> R + Send) -> R {
        on_threads(&self.pool, || match &self.team {
            Some(t) if members > 1 => t.awake_with(members, f),
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

/// A fixed team of threads that stays awake while a run advances: [`Team::run`] posts a job
/// that the caller (member 0) runs and every member that comes in time joins. Members spin for
/// the next job for `SPIN`, then sleep; outside [`Team::awake_for`] they sleep at once.
///
/// A job is a loop that claims parts of the work ([`on_team`]), so it is done whoever comes:
/// the caller closes the job when its loop ends and waits only for the members that joined
/// before that. A member that is not running (the machine has more busy threads than cores)
/// then costs nothing: its parts are taken by the caller. Before, each member had a fixed
/// share and the caller waited for it: on a machine whose cores were busy with another
/// program, the main job to 0.25 strain took 190 s on two threads against 32 s on one.
pub struct Team {
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
}

/// Bits of [`Shared::gate`]: the members that joined the current job (low bits), closed,
/// and the job's epoch above.
const JOINED: u64 = (1 << 15) - 1;
const CLOSED: u64 = 1 << 15;
const EPOCH_SHIFT: u32 = 16;

struct Shared {
    size: usize,
    /// The members that take part while the team is awake ([`Team::awake_with`]): member
    /// `m` joins jobs only if `m < active`; the others sleep.
    active: AtomicUsize,
    /// Bumped once per job; a member tries to join the job when it sees a new value.
    epoch: AtomicU64,
    /// The current job, valid until the members that joined it have finished (written only by
    /// the caller of [`Team::run`], before it opens the gate; read by members that joined).
    job: UnsafeCell<Option<*const Job>>,
    /// The current job's epoch, whether it is closed, and how many members joined it.
    gate: AtomicU64,
    /// Members that joined the current job and have finished it.
    finished: AtomicUsize,
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

// SAFETY: `job` is written only while no member reads it (before the gate that lets members
// join opens, and after every member that joined has finished); every other field is a sync
// type.
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

thread_local! {
    /// The team of the run this thread is advancing, while it advances.
    static TEAM: Cell<*const Team> = const { Cell::new(std::ptr::null()) };
}

impl Team {
    /// A team of `size` members: `size - 1` new threads and the caller of [`Team::run`].
    pub fn new(size: usize) -> Result<Self> {
        let size = size.clamp(1, JOINED as usize);
        let shared = Arc::new(Shared {
            size,
            active: AtomicUsize::new(size),
            epoch: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            gate: AtomicU64::new(CLOSED),
            finished: AtomicUsize::new(0),
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

    /// The members that take part in its jobs: all of them, or fewer while
    /// [`Team::awake_with`] says so.
    pub fn size(&self) -> usize {
        self.shared.active.load(Ordering::Relaxed)
    }

    /// Runs `f` with this team as the calling thread's team and its members spinning between
    /// jobs; they sleep again when `f` returns (or unwinds).
    pub fn awake_for<R>(&self, f: impl FnOnce() -> R) -> R {
        self.awake_with(self.shared.size, f)
    }

    /// [`Team::awake_for`] with only the first `members` members (the caller counted; at
    /// least one, at most the team): the others sleep, and the work is dealt to these. A step
    /// whose work pays for fewer threads than the run has keeps that many, instead of none.
    pub fn awake_with<R>(&self, members: usize, f: impl FnOnce() -> R) -> R {
        struct Restore<'a>(&'a Shared);
        impl Drop for Restore<'_> {
            fn drop(&mut self) {
                self.0.awake.store(false, Ordering::Relaxed);
                self.0.set_active(self.0.size);
            }
        }
        // Set while no job is posted (a job runs inside `f` only): no member is inside one.
        let _restore = Restore(&self.shared);
        self.shared.set_active(members.clamp(1, self.shared.size));
        self.shared.awake.store(true, Ordering::Relaxed);
        with_team(self, f)
    }

    /// Runs `job(0)` here and `job(member)` on every member that comes before `job(0)` has
    /// returned, and returns when those have finished: `job` must be a loop that claims the
    /// work it does (each piece once, whoever runs it), as [`on_team`]'s is. A panic in any of
    /// them is raised here after all have finished.
    pub fn run<'a>(&self, job: &'a (dyn Fn(usize) + Sync + 'a)) {
        let s = &*self.shared;
        // One job at a time. A run owns its team, so a second caller does not happen in the
        // library; were it to, the job's loop runs here alone.
        if s.busy.swap(true, Ordering::Acquire) {
            job(0);
            return;
        }
        struct Done<'a>(&'a AtomicBool);
        impl Drop for Done<'_> {
            fn drop(&mut self) {
                self.0.store(false, Ordering::Release);
            }
        }
        let _done = Done(&s.busy);
        // SAFETY: the job outlives its use: this function returns only after every member that
        // joined it has finished with it, unwinding included; no member reads `job` now (the
        // last job's gate was closed and its members finished before the last call returned).
        unsafe {
            *s.job.get() = Some(std::mem::transmute::<
                &'a (dyn Fn(usize) + Sync + 'a),
                *const Job,
            >(job));
        }
        s.finished.store(0, Ordering::SeqCst);
        let epoch = s.epoch.load(Ordering::SeqCst) + 1;
        s.gate.store(epoch << EPOCH_SHIFT, Ordering::SeqCst);
        s.epoch.store(epoch, Ordering::SeqCst);
        if s.sleeping.load(Ordering::SeqCst) > 0 {
            let _guard = s.lock.lock().unwrap_or_else(|e| e.into_inner());
            s.bell.notify_all();
        }
        // Work on this thread runs without the team: a nested region runs here, in order.
        let outer = TEAM.with(|t| t.replace(std::ptr::null()));
        let mine = panic::catch_unwind(AssertUnwindSafe(|| job(0)));
        TEAM.with(|t| t.set(outer));
        // The work is claimed: who has not joined by now stays out; wait for who did.
        let joined = (s.gate.fetch_or(CLOSED, Ordering::AcqRel) & JOINED) as usize;
        let mut spins = 0u32;
        while s.finished.load(Ordering::Acquire) != joined {
            spins = spins.saturating_add(1);
            if spins < 1 << 16 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
        // SAFETY: every member that joined has finished with the job.
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
    /// Lets the first `members` members take part from the next job on, waking those that
    /// slept out (under the lock, so that none misses the change on its way to sleep).
    fn set_active(&self, members: usize) {
        if self.active.swap(members, Ordering::SeqCst) < members {
            let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.bell.notify_all();
        }
    }

    /// A member's life: wait for a job, join it if it is still open, run it, report, again.
    fn serve(&self, member: usize) {
        let mut seen = 0;
        while let Some(epoch) = self.next_job(seen, member) {
            seen = epoch;
            if member >= self.active.load(Ordering::Acquire) || !self.join(epoch) {
                continue;
            }
            // SAFETY: published before the gate opened, valid until the joined have finished.
            let job = unsafe { (*self.job.get()).expect("a job is posted before the gate opens") };
            let done = panic::catch_unwind(AssertUnwindSafe(|| unsafe { (*job)(member) }));
            if let Err(p) = done {
                self.panic
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .get_or_insert(p);
            }
            self.finished.fetch_add(1, Ordering::Release);
        }
    }

    /// Joins the job of `epoch` unless the caller has closed it (or posted a later one).
    fn join(&self, epoch: u64) -> bool {
        let mut gate = self.gate.load(Ordering::Acquire);
        loop {
            if gate >> EPOCH_SHIFT != epoch || gate & CLOSED != 0 {
                return false;
            }
            match self.gate.compare_exchange_weak(
                gate,
                gate + 1,
                Ordering::AcqRel,
                Ordering::Acquire,
            ) {
                Ok(_) => return true,
                Err(now) => gate = now,
            }
        }
    }

    /// The next job's epoch after `seen`, or `None` when the team is dropped: spins while the
    /// team is awake (for at most [`SPIN`]), then sleeps until the caller rings. A member that
    /// does not take part (`member` not below [`Shared::active`]) sleeps until it does, uncounted
    /// by [`Shared::sleeping`], so that jobs do not ring for it.
    fn next_job(&self, seen: u64, member: usize) -> Option<u64> {
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            if self.quit.load(Ordering::Acquire) {
                return None;
            }
            if member >= self.active.load(Ordering::Acquire) {
                let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
                while member >= self.active.load(Ordering::SeqCst)
                    && !self.quit.load(Ordering::SeqCst)
                {
                    guard = self.bell.wait(guard).unwrap_or_else(|e| e.into_inner());
                }
                continue;
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
            while self.epoch.load(Ordering::SeqCst) == seen
                && !self.quit.load(Ordering::SeqCst)
                && member < self.active.load(Ordering::SeqCst)
            {
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

/// Runs `f` with `team` as this thread's team (null: none), the one before it restored when
/// `f` returns or unwinds.
fn with_team<R>(team: *const Team, f: impl FnOnce() -> R) -> R {
    struct Restore(*const Team);
    impl Drop for Restore {
        fn drop(&mut self) {
            TEAM.with(|t| t.set(self.0));
        }
    }
    let _restore = Restore(TEAM.with(|t| t.replace(team)));
    f()
}

/// Runs `f` with no team on this thread, whatever the run it advances has: its passes run
/// here, as on one thread (the team's members, awake, spin out their wait and sleep).
pub fn alone<R>(f: impl FnOnce() -> R) -> R {
    with_team(std::ptr::null(), f)
}

/// Runs `f(k, part)` for every part, and returns the results in part order: with a team
/// (this thread advances a run that has one), member m's own parts are the m-th of `size`
/// contiguous runs of the parts (the first `n mod size` runs one part longer), taken from
/// their front, and a member done with its own takes the others' from their far end;
/// otherwise here, in order. Each part is computed once, by whoever takes it, from the same
/// inputs, so results do not depend on which thread ran what, and for a given team size (which
/// fixes the parts) runs repeat bit for bit. Own runs keep each member on the same parts in
/// every pass when the members keep pace, and on the bodies of the rows it takes in the pair
/// loop (the pair loop's `size` parts: one each), so their data stays in its core's cache;
/// taking the rest balances uneven parts and a member that does not come at all. Parts dealt
/// in turn (part k to member k mod size) had each member integrate every other block of
/// bodies and then read half of the other's in the pair loop. Measured on the main job's
/// 12 mm box to 2% strain on two threads (same series): a gain within a noisy machine's
/// spread, 12.1 s mean of seven runs dealt in turn against 11.7 s of four in runs.
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
    // Member m's parts are a contiguous run: its front and back of what is left of them.
    let count = |m: usize| n / size + usize::from(m < n % size);
    let start: Vec<usize> = (0..size)
        .scan(0, |at, m| {
            let s = *at;
            *at += count(m);
            Some(s)
        })
        .collect();
    let dealt: Vec<Dealt> = (0..size).map(|m| Dealt::new(count(m))).collect();
    let run = |k: usize| {
        let part = inputs[k].lock().map(|mut p| p.take()).ok().flatten();
        if let Some(part) = part {
            let r = f(k, part);
            if let Ok(mut out) = outputs[k].lock() {
                *out = Some(r);
            }
        }
    };
    team.run(&|member| {
        while let Some(i) = dealt[member].take(true) {
            run(start[member] + i);
        }
        for other in (1..size).map(|d| (member + d) % size) {
            while let Some(i) = dealt[other].take(false) {
                run(start[other] + i);
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

/// What is left of one member's parts in [`on_team`]: the next index from the front (its
/// own) and the end from the back (where the others take), one word, on a cache line of its
/// own so that members taking their own parts do not contend.
#[repr(align(64))]
struct Dealt(AtomicU64);

impl Dealt {
    fn new(count: usize) -> Self {
        Dealt(AtomicU64::new(count as u64))
    }

    /// Takes the next part from the front (`front`) or the back, or `None` when none is left.
    fn take(&self, front: bool) -> Option<usize> {
        let mut now = self.0.load(Ordering::Acquire);
        loop {
            let (next, end) = (now >> 32, now & u64::from(u32::MAX));
            if next >= end {
                return None;
            }
            let (taken, after) = if front {
                (next, ((next + 1) << 32) | end)
            } else {
                (end - 1, (next << 32) | (end - 1))
            };
            match self
                .0
                .compare_exchange_weak(now, after, Ordering::AcqRel, Ordering::Acquire)
            {
                Ok(_) => return Some(taken as usize),
                Err(seen) => now = seen,
            }
        }
    }
}

/// Bodies per block of [`blocks`].
const BLOCK: usize = 32;

/// Fewer bodies than this run a per-body pass on the caller alone.
const TEAM_MIN_BODIES: usize = 256;

/// `0..n` as parts for [`on_team`] when this thread has a team and there are at least
/// `TEAM_MIN_BODIES` items: blocks of `BLOCK` consecutive items, each member's own a
/// contiguous run ([`on_team`]); `None` otherwise, when the caller runs the pass here,
/// without building parts (nothing is allocated per step on one thread). Small blocks let a
/// member done early take the other's last ones, which balances items of uneven cost (the
/// pieces appended by splits cost twice an initial grain in the integrator: fixed contiguous
/// halves made the caller wait half the time), and each member gets the same blocks in every
/// pass of a step, so their data stays in its core's cache.
pub fn team_blocks(n: usize) -> Option<Vec<Range<usize>>> {
    if n < TEAM_MIN_BODIES {
        return None;
    }
    team_parts(n, BLOCK)
}

/// `0..n` in parts of `per_part` consecutive items for [`on_team`] when this thread has a
/// team and there are at least two parts; `None` otherwise (the caller runs the pass here).
/// For passes over items cheap enough that a part must hold more than [`team_blocks`]' 32.
pub fn team_parts(n: usize, per_part: usize) -> Option<Vec<Range<usize>>> {
    let per_part = per_part.max(1);
    if team_size() == 1 || n <= per_part {
        return None;
    }
    Some(
        (0..n.div_ceil(per_part))
            .map(|k| k * per_part..((k + 1) * per_part).min(n))
            .collect(),
    )
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
mod tests;
