//! How many threads the calling code may use.
//!
//! A run with several threads executes inside its own rayon pool; a single-threaded run, and
//! any library call from a plain thread, runs on the caller's thread. Parallel loops ask
//! [`threads_here`] rather than rayon's global count, so code called outside a pool never
//! hands work to rayon's global pool (threads the user did not ask for, and a cross-thread
//! hand-off per call).

/// The size of the rayon pool the caller runs in, or 1 outside any pool.
pub fn threads_here() -> usize {
    if rayon::current_thread_index().is_some() {
        rayon::current_num_threads()
    } else {
        1
    }
}
