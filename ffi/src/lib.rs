//! C ABI for Fractum: `libfractum.so` and `include/fractum.h`.
//!
//! A thin layer: it checks arguments and handles, translates errors into status codes and a
//! last-error message, and keeps panics from crossing the boundary. The physics is the
//! library's (`fractum::Simulation`).
//!
//! Handles are opaque numbers, never addresses: a freed or forged handle is recognised and
//! rejected (`FRACTUM_ERR_HANDLE`) instead of being dereferenced.

use std::cell::RefCell;
use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use fractum::{Error, Run, Scene, Simulation};

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
    /// Bad input: a scene, a key, a value out of range, a file that cannot be read.
    FRACTUM_ERR_INPUT = 3,
    /// The simulation failed (instability, a state that cannot be restored).
    FRACTUM_ERR_RUN = 4,
    /// A caller buffer is too small; the needed size is in the last-error message.
    FRACTUM_ERR_BUFFER = 5,
    /// An internal error (a caught panic). The handle should be freed.
    FRACTUM_ERR_INTERNAL = 6,
}

use FractumStatus::*;

/// An opaque simulation handle (0 is never a valid handle).
pub type FractumHandle = u64;

struct Entry {
    sim: Simulation,
    /// The state right after creation, for `fractum_reset`.
    initial: Vec<u8>,
}

fn registry() -> &'static Mutex<HashMap<u64, Arc<Mutex<Entry>>>> {
    static REGISTRY: OnceLock<Mutex<HashMap<u64, Arc<Mutex<Entry>>>>> = OnceLock::new();
    REGISTRY.get_or_init(|| Mutex::new(HashMap::new()))
}

static NEXT_HANDLE: AtomicU64 = AtomicU64::new(1);

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(message: &str) {
    let clean = message.replace('\0', " ");
    LAST_ERROR.with(|e| *e.borrow_mut() = CString::new(clean).unwrap_or_default());
}

/// Runs `f`, turning errors into a status and a last-error message, and panics into
/// `FRACTUM_ERR_INTERNAL`.
fn guard(f: impl FnOnce() -> Result<(), (FractumStatus, String)>) -> FractumStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => {
            set_error("");
            FRACTUM_OK
        }
        Ok(Err((status, message))) => {
            set_error(&message);
            status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            set_error(&format!("internal error in Fractum: {what}"));
            FRACTUM_ERR_INTERNAL
        }
    }
}

fn from_error(e: Error) -> (FractumStatus, String) {
    let status = match e {
        Error::Input { .. } => FRACTUM_ERR_INPUT,
        Error::Run(_) => FRACTUM_ERR_RUN,
    };
    (status, e.to_string())
}

fn null(what: &str) -> (FractumStatus, String) {
    (FRACTUM_ERR_NULL, format!("{what} is a null pointer"))
}

fn string_arg(p: *const c_char, what: &str) -> Result<String, (FractumStatus, String)> {
    if p.is_null() {
        return Err(null(what));
    }
    // SAFETY: the caller passes a NUL-terminated string (documented in the header).
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map(str::to_string)
        .map_err(|_| (FRACTUM_ERR_INPUT, format!("{what} is not valid UTF-8")))
}

fn overrides_arg(
    overrides: *const *const c_char,
    count: usize,
) -> Result<Vec<String>, (FractumStatus, String)> {
    if count == 0 {
        return Ok(Vec::new());
    }
    if overrides.is_null() {
        return Err(null("overrides"));
    }
    // SAFETY: the caller passes `count` string pointers.
    let list = unsafe { std::slice::from_raw_parts(overrides, count) };
    list.iter()
        .enumerate()
        .map(|(k, &p)| string_arg(p, &format!("overrides[{k}]")))
        .collect()
}

fn register(
    scene: Scene,
    threads: i32,
    out: *mut FractumHandle,
) -> Result<(), (FractumStatus, String)> {
    if out.is_null() {
        return Err(null("handle"));
    }
    let threads = threads.max(0) as usize;
    let sim = Simulation::new(scene, threads, &mut |_| {}).map_err(from_error)?;
    let initial = sim.save_state();
    let handle = NEXT_HANDLE.fetch_add(1, Ordering::Relaxed);
    registry()
        .lock()
        .map_err(|_| {
            (
                FRACTUM_ERR_INTERNAL,
                "the handle registry is poisoned".to_string(),
            )
        })?
        .insert(handle, Arc::new(Mutex::new(Entry { sim, initial })));
    // SAFETY: checked non-null above.
    unsafe { *out = handle };
    Ok(())
}

/// Runs `f` on the simulation behind `handle`.
fn with_sim<T>(
    handle: FractumHandle,
    f: impl FnOnce(&mut Entry) -> Result<T, (FractumStatus, String)>,
) -> Result<T, (FractumStatus, String)> {
    let entry = registry()
        .lock()
        .map_err(|_| {
            (
                FRACTUM_ERR_INTERNAL,
                "the handle registry is poisoned".to_string(),
            )
        })?
        .get(&handle)
        .cloned()
        .ok_or_else(|| {
            (
                FRACTUM_ERR_HANDLE,
                format!(
                    "handle {handle} is not a live Fractum simulation (never created, or freed)"
                ),
            )
        })?;
    let mut entry = entry.lock().map_err(|_| {
        (
            FRACTUM_ERR_INTERNAL,
            "this simulation failed earlier; free it".to_string(),
        )
    })?;
    f(&mut entry)
}

/// Writes `value` through `out`.
fn put<T>(out: *mut T, value: T, what: &str) -> Result<(), (FractumStatus, String)> {
    if out.is_null() {
        return Err(null(what));
    }
    // SAFETY: checked non-null; the caller provides a valid pointer.
    unsafe { *out = value };
    Ok(())
}

/// Copies `values` into the caller's buffer of `len` elements (`unit` names them in the
/// message when the buffer is too small).
fn copy_out<T: Copy>(
    values: &[T],
    buf: *mut T,
    len: usize,
    unit: &str,
) -> Result<(), (FractumStatus, String)> {
    if buf.is_null() {
        return Err(null("buffer"));
    }
    if len < values.len() {
        return Err((
            FRACTUM_ERR_BUFFER,
            format!("the buffer holds {len} {unit}, {} are needed", values.len()),
        ));
    }
    // SAFETY: `buf` holds at least `len >= values.len()` elements.
    unsafe { std::ptr::copy_nonoverlapping(values.as_ptr(), buf, values.len()) };
    Ok(())
}

/// The caller's `len` bytes at `buf`.
fn bytes_arg(buf: *const u8, len: usize) -> Result<Vec<u8>, (FractumStatus, String)> {
    if buf.is_null() {
        return Err(null("buffer"));
    }
    // SAFETY: the caller passes `len` readable bytes (documented in the header).
    Ok(unsafe { std::slice::from_raw_parts(buf, len) }.to_vec())
}

/// Creates a simulation from a scene file. `overrides` are `count` strings `KEY=VALUE` as for
/// `fractum run --set`; `threads` = 0 uses every core. On success `*handle` is set.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_create_from_file(
    path: *const c_char,
    overrides: *const *const c_char,
    count: usize,
    threads: i32,
    handle: *mut FractumHandle,
) -> FractumStatus {
    guard(|| {
        let path = string_arg(path, "path")?;
        let overrides = overrides_arg(overrides, count)?;
        let scene = Scene::load(Path::new(&path), &overrides).map_err(from_error)?;
        register(scene, threads, handle)
    })
}

/// Creates a simulation from scene text (TOML); relative paths in it resolve against
/// `base_dir` (may be null: the current folder).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_create_from_text(
    text: *const c_char,
    base_dir: *const c_char,
    overrides: *const *const c_char,
    count: usize,
    threads: i32,
    handle: *mut FractumHandle,
) -> FractumStatus {
    guard(|| {
        let text = string_arg(text, "text")?;
        let dir = if base_dir.is_null() {
            ".".to_string()
        } else {
            string_arg(base_dir, "base_dir")?
        };
        let overrides = overrides_arg(overrides, count)?;
        let scene = Scene::from_toml(&text, "scene text", Path::new(&dir), &overrides)
            .map_err(from_error)?;
        register(scene, threads, handle)
    })
}

/// Frees a simulation. The handle is invalid afterwards (using it gives FRACTUM_ERR_HANDLE).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_free(handle: FractumHandle) -> FractumStatus {
    guard(|| {
        let removed = registry()
            .lock()
            .map_err(|_| {
                (
                    FRACTUM_ERR_INTERNAL,
                    "the handle registry is poisoned".to_string(),
                )
            })?
            .remove(&handle);
        match removed {
            Some(_) => Ok(()),
            None => Err((
                FRACTUM_ERR_HANDLE,
                format!(
                    "handle {handle} is not a live Fractum simulation (never created, or freed)"
                ),
            )),
        }
    })
}

/// Advances to exactly `time` (s), sub-stepping at the simulation's own time step and
/// shortening the last sub-step to land on `time`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_advance_to(handle: FractumHandle, time: f64) -> FractumStatus {
    guard(|| with_sim(handle, |e| e.sim.advance_to(time).map_err(from_error)))
}

/// Drives the top (z+) and bottom (z-) faces from now on at `top` and `bottom` m/s into the
/// sample (compression positive). The scene's own loading stops.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_set_face_speeds(
    handle: FractumHandle,
    top: f64,
    bottom: f64,
) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            e.sim.set_face_speeds(top, bottom).map_err(from_error)
        })
    })
}

/// Compressive normal forces (N) on the top (z+) and bottom (z-) faces.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_face_forces(
    handle: FractumHandle,
    top: *mut f64,
    bottom: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (t, b) = with_sim(handle, |e| Ok(e.sim.face_forces()))?;
        put(top, t, "top")?;
        put(bottom, b, "bottom")
    })
}

/// Compressive normal stresses (Pa) on the top (z+) and bottom (z-) faces, and their area (m²).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_face_stresses(
    handle: FractumHandle,
    top: *mut f64,
    bottom: *mut f64,
    area: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (t, b, a) = with_sim(handle, |e| {
            let (t, b) = e.sim.face_stresses();
            Ok((t, b, e.sim.face_area()))
        })?;
        put(top, t, "top")?;
        put(bottom, b, "bottom")?;
        put(area, a, "area")
    })
}

/// Time (s), axial strain (compression positive) and the number of steps taken.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_progress(
    handle: FractumHandle,
    time: *mut f64,
    strain: *mut f64,
    steps: *mut u64,
) -> FractumStatus {
    guard(|| {
        let (t, s, n) = with_sim(handle, |e| {
            Ok((e.sim.time, e.sim.axial_strain(), e.sim.step))
        })?;
        put(time, t, "time")?;
        put(strain, s, "strain")?;
        put(steps, n, "steps")
    })
}

/// Numbers of bodies and of body–body contacts, and the kinetic energy (J).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_counts(
    handle: FractumHandle,
    bodies: *mut u64,
    contacts: *mut u64,
    kinetic_energy: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (n, c, k) = with_sim(handle, |e| {
            Ok((
                e.sim.bodies.len() as u64,
                e.sim.pipeline.contacts() as u64,
                e.sim.bodies.kinetic_energy(),
            ))
        })?;
        put(bodies, n, "bodies")?;
        put(contacts, c, "contacts")?;
        put(kinetic_energy, k, "kinetic_energy")
    })
}

/// Copies per-body values (taken from the simulation by `values`) into the caller's buffer.
fn copy_body_values(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
    values: impl FnOnce(&Simulation) -> Vec<f64>,
) -> FractumStatus {
    guard(|| {
        let v = with_sim(handle, |e| Ok(values(&e.sim)))?;
        copy_out(&v, buf, len, "doubles")
    })
}

fn flatten(v: &[fractum::state::Vec3]) -> Vec<f64> {
    v.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// Copies the positions (m) as x0 y0 z0 x1 ... into `buf` of `len` doubles (3 per body).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_positions(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| flatten(&sim.bodies.pos))
}

/// Copies the velocities (m/s) as vx0 vy0 vz0 vx1 ... into `buf` of `len` doubles.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_velocities(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| flatten(&sim.bodies.vel))
}

/// Copies the radii (m; the bounding radius of non-spherical bodies) into `buf` of `len`
/// doubles (1 per body).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_radii(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| sim.bodies.radius.clone())
}

/// The size (bytes) of the saved state, for sizing the buffer of `fractum_save_state`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_state_size(handle: FractumHandle, size: *mut usize) -> FractumStatus {
    guard(|| {
        let n = with_sim(handle, |e| Ok(e.sim.save_state().len()))?;
        put(size, n, "size")
    })
}

/// Saves the whole state into `buf` of `len` bytes; `*written` receives its size.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_save_state(
    handle: FractumHandle,
    buf: *mut u8,
    len: usize,
    written: *mut usize,
) -> FractumStatus {
    guard(|| {
        let bytes = with_sim(handle, |e| Ok(e.sim.save_state()))?;
        copy_out(&bytes, buf, len, "bytes")?;
        put(written, bytes.len(), "written")
    })
}

/// Restores a state saved by `fractum_save_state` from the same scene.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_restore_state(
    handle: FractumHandle,
    buf: *const u8,
    len: usize,
) -> FractumStatus {
    guard(|| {
        let bytes = bytes_arg(buf, len)?;
        with_sim(handle, |e| {
            let threads = e.sim.threads();
            let scene = e.sim.scene.clone();
            e.sim = Simulation::restore(scene, &bytes, threads).map_err(from_error)?;
            Ok(())
        })
    })
}

/// Returns the simulation to the state it had right after creation.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_reset(handle: FractumHandle) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            let threads = e.sim.threads();
            let scene = e.sim.scene.clone();
            e.sim = Simulation::restore(scene, &e.initial, threads).map_err(from_error)?;
            Ok(())
        })
    })
}

/// The library version, e.g. "0.1.0" (a static string).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_version() -> *const c_char {
    static VERSION: OnceLock<CString> = OnceLock::new();
    VERSION
        .get_or_init(|| CString::new(env!("CARGO_PKG_VERSION")).unwrap_or_default())
        .as_ptr()
}

/// The message of the last failed call on this thread ("" after a success). Valid until the
/// next call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_a_status_and_a_message() {
        let status = guard(|| panic!("boom"));
        assert_eq!(status, FRACTUM_ERR_INTERNAL);
        // SAFETY: fractum_last_error returns a valid NUL-terminated string.
        let msg = unsafe { CStr::from_ptr(fractum_last_error()) }
            .to_string_lossy()
            .to_string();
        assert!(msg.contains("boom"), "{msg}");
    }

    #[test]
    fn unknown_handles_are_refused() {
        assert_eq!(fractum_advance_to(u64::MAX, 1.0), FRACTUM_ERR_HANDLE);
        assert_eq!(fractum_free(0), FRACTUM_ERR_HANDLE);
        let msg = unsafe { CStr::from_ptr(fractum_last_error()) }
            .to_string_lossy()
            .to_string();
        assert!(msg.contains("not a live Fractum simulation"), "{msg}");
    }
}
