//! How many threads the calling code may use, and the run's own pool.
//!
//! A run with several threads executes inside its own rayon pool; a single-threaded run, and
//! any library call from a plain thread, runs on the caller's thread. Parallel loops ask
//! [`threads_here`] rather than rayon's global count, so code called outside a pool never
//! hands work to rayon's global pool (threads the user did not ask for, and a cross-thread
//! hand-off per call).

use std::sync::Arc;

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
pub fn on_threads<R: Send>(
    pool: &Option<Arc<rayon::ThreadPool>>,
    f: impl FnOnce() -> R + Send,
) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}
