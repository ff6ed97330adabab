//! The status every export returns: its own file, which carries nothing but the enum, so the
//! kernel tests (ffi/tests/kernels/) compile the very definition the library exports.

/// Status codes returned by every function.
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FractumStatus {
    /// Success.
    FRACTUM_OK = 0,
    /// A pointer argument was null.
    FRACTUM_ERR_NULL = 1,
    /// The handle is unknown: never created, or already freed.
    FRACTUM_ERR_HANDLE = 2,
    /// Bad input: a scene, a key, a value out of range, a file that cannot be read, an unknown
    /// series column.
    FRACTUM_ERR_INPUT = 3,
    /// The simulation failed (instability, a state that cannot be restored, a time that a
    /// fixed-step integrator cannot land on).
    FRACTUM_ERR_RUN = 4,
    /// A caller buffer is too small; the needed size is in the last-error message (and in
    /// `*needed` for text).
    FRACTUM_ERR_BUFFER = 5,
    /// An internal error (a caught panic). The handle should be freed.
    FRACTUM_ERR_INTERNAL = 6,
    /// The call does not apply to this run's model (face calls on a model without driven
    /// faces, radii of a model without grains); the message names the model. Nothing changed.
    FRACTUM_ERR_MODEL = 7,
    /// `fractum_advance` / `fractum_advance_to` stopped early, before a step, because a bound
    /// of `fractum_set_call_limits` ran out or `fractum_cancel` was called; the message says
    /// which and where. The run is consistent: call again to go on.
    FRACTUM_INTERRUPTED = 8,
}
