//! The dispatch from the runtime switches (damping, friction, shapes) to the library's
//! monomorphised contact functions; its own file, so the kernel tests (ffi/tests/kernels/)
//! dispatch the same way.

/// Calls `$f::<DAMP, FRIC, POLY>(args)` for the runtime switches.
macro_rules! variants {
    ($damp:expr, $fric:expr, $poly:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match ($damp, $fric, $poly) {
            (false, false, false) => $f::<false, false, false>($($arg),*),
            (true, false, false) => $f::<true, false, false>($($arg),*),
            (false, true, false) => $f::<false, true, false>($($arg),*),
            (true, true, false) => $f::<true, true, false>($($arg),*),
            (false, false, true) => $f::<false, false, true>($($arg),*),
            (true, false, true) => $f::<true, false, true>($($arg),*),
            (false, true, true) => $f::<false, true, true>($($arg),*),
            (true, true, true) => $f::<true, true, true>($($arg),*),
        }
    };
}
