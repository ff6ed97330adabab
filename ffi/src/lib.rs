//! C ABI for Fractum: `libfractum.so` and `include/fractum.h`.
//!
//! A thin layer: it checks arguments and handles, translates errors into status codes and a
//! last-error message, and keeps panics from crossing the boundary. The physics is the
//! library's: every handle holds one run of any model (`granular`, `dlsm`, `beam2d`), built
//! by the library's registry from the scene's `model.kind` and driven through
//! `fractum::Run`. The few calls that only some models answer (the driven faces of a
//! granular box, grain radii) return `FRACTUM_ERR_MODEL` on the others.
//!
//! Handles are opaque numbers, never addresses: a freed or forged handle is recognised and
//! rejected (`FRACTUM_ERR_HANDLE`) instead of being dereferenced.
//!
//! The kernel exports (`fractum_kernel_*`, in `kernels/`) need no handle: they are the
//! per-contact and per-grain functions of the granular model, for hosts that keep their own
//! particles (a LAMMPS plugin), each the library function Fractum's own run calls.

use std::cell::RefCell;
use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use fractum::run::CallLimits;
use fractum::{Error, Run, Scene};

mod kernels;
mod status;
pub use kernels::*;
pub use status::FractumStatus;

use FractumStatus::*;

/// An opaque simulation handle (0 is never a valid handle).
pub type FractumHandle = u64;

/// One run behind a handle: any model's, built and restored by the registry.
struct Sim(Box<dyn Run>);

impl Sim {
    fn build(scene: Scene, threads: usize) -> fractum::Result<Sim> {
        Ok(Sim(fractum::build(scene, threads, &mut |_| {})?))
    }

    fn restore(scene: Scene, bytes: &[u8], threads: usize) -> fractum::Result<Sim> {
        Ok(Sim(fractum::restore(scene, bytes, threads)?))
    }

    fn run(&self) -> &dyn Run {
        &*self.0
    }

    fn run_mut(&mut self) -> &mut dyn Run {
        &mut *self.0
    }

    /// The run over again from `bytes` (a saved state of this run's scene), on its threads.
    fn replaced(&self, bytes: &[u8]) -> fractum::Result<Sim> {
        let run = self.run();
        Sim::restore(run.scene().clone(), bytes, run.threads())
    }
}

struct Entry {
    sim: Sim,
    /// The state right after creation, for `fractum_reset`.
    initial: Vec<u8>,
    /// The bounds on each advance call (`fractum_set_call_limits`, `fractum_cancel`), handed
    /// to the run before each call (a restored run starts without them).
    limits: CallLimits,
}

/// A live simulation: its entry, and its cancel flag outside the entry's lock, so
/// `fractum_cancel` reaches it while another thread holds the entry in an advance call.
struct Slot {
    entry: Mutex<Entry>,
    cancel: Arc<AtomicBool>,
}

type Failure = (FractumStatus, String);

/// The live simulations by handle.
type Registry = Mutex<HashMap<u64, Arc<Slot>>>;

fn registry() -> &'static Registry {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
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
fn guard(f: impl FnOnce() -> Result<(), Failure>) -> FractumStatus {
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

fn from_error(e: Error) -> Failure {
    let status = match e {
        Error::Input { .. } => FRACTUM_ERR_INPUT,
        Error::Run(_) => FRACTUM_ERR_RUN,
        Error::Interrupted(_) => FRACTUM_INTERRUPTED,
    };
    (status, e.to_string())
}

fn null(what: &str) -> Failure {
    (FRACTUM_ERR_NULL, format!("{what} is a null pointer"))
}

/// `FRACTUM_ERR_MODEL` for `call` on `run`, saying what it needs.
fn not_for_model(call: &str, run: &dyn Run, needs: &str) -> Failure {
    (
        FRACTUM_ERR_MODEL,
        format!(
            "{call} does not apply to this {} run (scene {}): {needs}",
            run.model(),
            run.scene().name
        ),
    )
}

fn poisoned() -> Failure {
    (
        FRACTUM_ERR_INTERNAL,
        "the handle registry is poisoned".to_string(),
    )
}

fn string_arg(p: *const c_char, what: &str) -> Result<String, Failure> {
    if p.is_null() {
        return Err(null(what));
    }
    // SAFETY: the caller passes a NUL-terminated string (documented in the header).
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map(str::to_string)
        .map_err(|_| (FRACTUM_ERR_INPUT, format!("{what} is not valid UTF-8")))
}

fn overrides_arg(overrides: *const *const c_char, count: usize) -> Result<Vec<String>, Failure> {
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

fn register(scene: Scene, threads: i32, out: *mut FractumHandle) -> Result<(), Failure> {
    if out.is_null() {
        return Err(null("handle"));
    }
    // A negative count was taken as 0 (every core).
    if threads < 0 {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        return Err(from_error(fractum::Error::input(
            "threads",
            format!("{threads} is outside the allowed range [0, {cores}] (0: every core)"),
        )));
    }
    let sim = Sim::build(scene, threads as usize).map_err(from_error)?;
    let initial = sim.run().save_state();
    let handle = NEXT_HANDLE.fetch_add(1, Ordering::Relaxed);
    let cancel = Arc::new(AtomicBool::new(false));
    let limits = CallLimits {
        cancel: Some(cancel.clone()),
        ..CallLimits::default()
    };
    let entry = Mutex::new(Entry {
        sim,
        initial,
        limits,
    });
    registry()
        .lock()
        .map_err(|_| poisoned())?
        .insert(handle, Arc::new(Slot { entry, cancel }));
    // SAFETY: checked non-null above.
    unsafe { *out = handle };
    Ok(())
}

/// The live simulation behind `handle`.
fn slot(handle: FractumHandle) -> Result<Arc<Slot>, Failure> {
    registry()
        .lock()
        .map_err(|_| poisoned())?
        .get(&handle)
        .cloned()
        .ok_or_else(|| {
            (
                FRACTUM_ERR_HANDLE,
                format!(
                    "handle {handle} is not a live Fractum simulation (never created, or freed)"
                ),
            )
        })
}

/// Runs `f` on the simulation behind `handle`.
fn with_sim<T>(
    handle: FractumHandle,
    f: impl FnOnce(&mut Entry) -> Result<T, Failure>,
) -> Result<T, Failure> {
    let slot = slot(handle)?;
    let mut entry = slot.entry.lock().map_err(|_| {
        (
            FRACTUM_ERR_INTERNAL,
            "this simulation failed earlier; free it".to_string(),
        )
    })?;
    f(&mut entry)
}

/// Runs `f` on the run behind `handle`, read only.
fn with_run<T>(handle: FractumHandle, f: impl FnOnce(&dyn Run) -> T) -> Result<T, Failure> {
    with_sim(handle, |e| Ok(f(e.sim.run())))
}

/// Writes `value` through `out`.
fn put<T>(out: *mut T, value: T, what: &str) -> Result<(), Failure> {
    if out.is_null() {
        return Err(null(what));
    }
    // SAFETY: checked non-null; the caller provides a valid pointer.
    unsafe { *out = value };
    Ok(())
}

/// Copies `values` into the caller's buffer of `len` elements (`unit` names them in the
/// message when the buffer is too small).
fn copy_out<T: Copy>(values: &[T], buf: *mut T, len: usize, unit: &str) -> Result<(), Failure> {
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

/// Copies `text` and a final NUL into the caller's buffer of `len` bytes; `*needed` receives
/// the bytes it takes (with the NUL) in every case, so a call with `len` = 0 (and `buf` null)
/// asks for the size.
fn copy_text(text: &str, buf: *mut c_char, len: usize, needed: *mut usize) -> Result<(), Failure> {
    let size = text.len() + 1;
    put(needed, size, "needed")?;
    if len < size {
        return Err((
            FRACTUM_ERR_BUFFER,
            format!("the buffer holds {len} bytes, {size} are needed (with the final NUL)"),
        ));
    }
    if buf.is_null() {
        return Err(null("buffer"));
    }
    // SAFETY: `buf` holds at least `len >= size` bytes; the text has no NUL of its own (JSON
    // escapes control characters, column names have none).
    unsafe {
        std::ptr::copy_nonoverlapping(text.as_ptr().cast::<c_char>(), buf, text.len());
        *buf.add(text.len()) = 0;
    }
    Ok(())
}

/// The caller's `len` bytes at `buf`.
fn bytes_arg(buf: *const u8, len: usize) -> Result<Vec<u8>, Failure> {
    if buf.is_null() {
        return Err(null("buffer"));
    }
    // SAFETY: the caller passes `len` readable bytes (documented in the header).
    Ok(unsafe { std::slice::from_raw_parts(buf, len) }.to_vec())
}

/// A NUL-terminated copy of `s` that lives as long as the process (one per distinct string:
/// the model kinds).
fn static_c_str(s: &'static str) -> Result<*const c_char, Failure> {
    type Names = Mutex<HashMap<&'static str, &'static CStr>>;
    static NAMES: OnceLock<Names> = OnceLock::new();
    let mut names = NAMES
        .get_or_init(|| Mutex::new(HashMap::new()))
        .lock()
        .map_err(|_| poisoned())?;
    let name = names
        .entry(s)
        .or_insert_with(|| Box::leak(CString::new(s).unwrap_or_default().into_boxed_c_str()));
    Ok(name.as_ptr())
}

/// Creates a simulation from a scene file, of whatever model its `model.kind` names.
/// `overrides` are `count` strings `KEY=VALUE` as for `fractum run --set`; `threads` = 0 uses
/// every core, a negative count or more than the machine has is refused (FRACTUM_ERR_INPUT). On success `*handle` is
/// set.
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
/// An advance call in progress on it in another thread stops before its next step (it returns
/// FRACTUM_INTERRUPTED) and the run is dropped when it has.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_free(handle: FractumHandle) -> FractumStatus {
    guard(|| {
        let removed = registry().lock().map_err(|_| poisoned())?.remove(&handle);
        match removed {
            Some(slot) => {
                // An advance call in progress on another thread holds the run until it ends:
                // stop it before its next step, or an unbounded `fractum_advance_to` went on
                // for ever on a handle nobody could reach any more.
                slot.cancel.store(true, Ordering::Release);
                Ok(())
            }
            None => Err((
                FRACTUM_ERR_HANDLE,
                format!(
                    "handle {handle} is not a live Fractum simulation (never created, or freed)"
                ),
            )),
        }
    })
}

/// The scene's model (`model.kind`: "granular", "dlsm" or "beam2d") into `*kind`: a static
/// string, valid for the life of the process.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_model(handle: FractumHandle, kind: *mut *const c_char) -> FractumStatus {
    guard(|| {
        let name = with_run(handle, |run| run.model())?;
        put(kind, static_c_str(name)?, "kind")
    })
}

/// Takes up to `steps` steps of the run's own time step, never past the scene's end (so
/// `UINT64_MAX` runs to the end, also where the run shortens its step on the way; see
/// `fractum_finished`). A run without an end of its own (faces driven from outside) refuses
/// more than 1e9 steps in one call unless `fractum_set_call_limits` bounds it
/// (FRACTUM_ERR_RUN). Series rows are recorded on the way
/// as in `fractum run`: chunking a run into calls does not change it.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_advance(handle: FractumHandle, steps: u64) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            e.sim.run_mut().set_call_limits(e.limits.clone());
            e.sim.run_mut().advance(steps).map_err(from_error)
        })
    })
}

/// Advances to exactly `time` (s), sub-stepping at the simulation's own time step and
/// shortening the last sub-step to land on `time`; never past the scene's end, as
/// `fractum_advance` (a time beyond it stops there: `fractum_finished` says so). A run whose integrator takes whole steps
/// only (beam2d with Gear5) refuses a time off its grid with FRACTUM_ERR_RUN before taking any step.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_advance_to(handle: FractumHandle, time: f64) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            e.sim.run_mut().set_call_limits(e.limits.clone());
            e.sim.run_mut().advance_to(time).map_err(from_error)
        })
    })
}

/// Bounds each later `fractum_advance` / `fractum_advance_to` call on this simulation: it
/// stops with `FRACTUM_INTERRUPTED`, before a step, once it has taken `max_steps` steps or run
/// `max_seconds` seconds of wall time (0 for either: no bound; both 0, the default: no
/// bounds). A call may end with `FRACTUM_OK` short of its target only where the run ends
/// (`fractum_finished`). The bounds are not part of the saved state. Negative or non-finite
/// `max_seconds` is refused with `FRACTUM_ERR_INPUT`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_set_call_limits(
    handle: FractumHandle,
    max_steps: u64,
    max_seconds: f64,
) -> FractumStatus {
    guard(|| {
        if !(max_seconds.is_finite() && max_seconds >= 0.0) {
            return Err((
                FRACTUM_ERR_INPUT,
                format!(
                    "fractum_set_call_limits: max_seconds = {max_seconds} is outside [0, ∞) (0: no bound)"
                ),
            ));
        }
        with_sim(handle, |e| {
            e.limits.max_steps = max_steps;
            e.limits.max_seconds = max_seconds;
            Ok(())
        })
    })
}

/// Asks the `fractum_advance` / `fractum_advance_to` call in progress on this simulation (in
/// another thread), or else the next one, to stop before its next step with
/// `FRACTUM_INTERRUPTED`; that stop clears the request. Safe to call from any thread at any
/// time: it does not wait for the call in progress.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_cancel(handle: FractumHandle) -> FractumStatus {
    guard(|| {
        slot(handle)?.cancel.store(true, Ordering::Release);
        Ok(())
    })
}

/// `*finished` = 1 once the run has reached the scene's end (or the model stopped it, e.g.
/// after failure), else 0. A run whose faces are driven from outside has no end.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_finished(handle: FractumHandle, finished: *mut i32) -> FractumStatus {
    guard(|| {
        let f = with_run(handle, |run| run.finished())?;
        put(finished, i32::from(f), "finished")
    })
}

/// The time (s).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_time(handle: FractumHandle, time: *mut f64) -> FractumStatus {
    guard(|| put(time, with_run(handle, |run| run.time())?, "time"))
}

/// The number of steps taken.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_steps(handle: FractumHandle, steps: *mut u64) -> FractumStatus {
    guard(|| put(steps, with_run(handle, |run| run.step())?, "steps"))
}

/// The run's time step (s); a granular run may shorten it as grains break.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_dt(handle: FractumHandle, dt: *mut f64) -> FractumStatus {
    guard(|| put(dt, with_run(handle, |run| run.dt())?, "dt"))
}

/// The number of bodies (particles, elements or polygons): what the per-body copies need.
/// It can grow between steps (granular grains break).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_bodies(handle: FractumHandle, bodies: *mut u64) -> FractumStatus {
    guard(|| {
        put(
            bodies,
            with_run(handle, |run| run.bodies() as u64)?,
            "bodies",
        )
    })
}

/// Drives the top (z+) and bottom (z-) faces from now on at `top` and `bottom` m/s into the
/// sample (compression positive). The scene's own loading stops and the run has no end of its
/// own. Granular samples in a box only: FRACTUM_ERR_MODEL on other runs.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_set_face_speeds(
    handle: FractumHandle,
    top: f64,
    bottom: f64,
) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            let run = e.sim.run_mut();
            if run.faces().is_none() {
                return Err(not_for_model("fractum_set_face_speeds", run, FACES_NEEDED));
            }
            run.set_face_speeds(top, bottom).map_err(from_error)
        })
    })
}

const FACES_NEEDED: &str = "only granular samples in a box have driven faces";

/// Compressive normal forces (N) on the top (z+) and bottom (z-) faces. Granular samples in a
/// box only: FRACTUM_ERR_MODEL on other runs.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_face_forces(
    handle: FractumHandle,
    top: *mut f64,
    bottom: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (t, b) = with_sim(handle, |e| {
            let run = e.sim.run();
            let faces = run
                .faces()
                .ok_or_else(|| not_for_model("fractum_face_forces", run, FACES_NEEDED))?;
            Ok(faces.face_forces())
        })?;
        put(top, t, "top")?;
        put(bottom, b, "bottom")
    })
}

/// Compressive normal stresses (Pa) on the top (z+) and bottom (z-) faces, and their area (m²).
/// Granular samples in a box only: FRACTUM_ERR_MODEL on other runs.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_face_stresses(
    handle: FractumHandle,
    top: *mut f64,
    bottom: *mut f64,
    area: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (t, b, a) = with_sim(handle, |e| {
            let run = e.sim.run();
            let faces = run
                .faces()
                .ok_or_else(|| not_for_model("fractum_face_stresses", run, FACES_NEEDED))?;
            let (t, b) = faces.face_stresses();
            Ok((t, b, faces.face_area()))
        })?;
        put(top, t, "top")?;
        put(bottom, b, "bottom")?;
        put(area, a, "area")
    })
}

/// Time (s), axial strain and the number of steps taken. The strain is that of the box
/// between driven faces (a granular sample in a box; compression positive) and NaN for runs
/// without them, whose own strain columns `fractum_scalar` reads.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_progress(
    handle: FractumHandle,
    time: *mut f64,
    strain: *mut f64,
    steps: *mut u64,
) -> FractumStatus {
    guard(|| {
        let (t, s, n) = with_sim(handle, |e| {
            let run = e.sim.run();
            let strain = run.faces().map_or(f64::NAN, |f| f.axial_strain());
            Ok((run.time(), strain, run.step()))
        })?;
        put(time, t, "time")?;
        put(strain, s, "strain")?;
        put(steps, n, "steps")
    })
}

/// Numbers of bodies and of body–body contacts, and the kinetic energy (J), now. Contacts are 0
/// for a model that does not count them (dlsm: its cohesive contacts are bonds).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_counts(
    handle: FractumHandle,
    bodies: *mut u64,
    contacts: *mut u64,
    kinetic_energy: *mut f64,
) -> FractumStatus {
    guard(|| {
        let (n, c, k) = with_sim(handle, |e| {
            let run = e.sim.run();
            let n = run.bodies() as u64;
            let contacts = run.contacts().map_or(0, |c| c as u64);
            Ok((n, contacts, run.kinetic_energy()))
        })?;
        put(bodies, n, "bodies")?;
        put(contacts, c, "contacts")?;
        put(kinetic_energy, k, "kinetic_energy")
    })
}

/// The value of the series column `name` (a column of the run's series.csv, e.g. "stress",
/// "kinetic_energy") in its last row, recorded at the last output step (every `output.every`
/// steps and at the end). An unknown name gives FRACTUM_ERR_INPUT with the columns listed.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_scalar(
    handle: FractumHandle,
    name: *const c_char,
    value: *mut f64,
) -> FractumStatus {
    guard(|| {
        let name = string_arg(name, "name")?;
        let v = with_run(handle, |run| {
            let series = run.series();
            let k = series.index(&name).ok_or_else(|| {
                (
                    FRACTUM_ERR_INPUT,
                    format!(
                        "\"{name}\" is not a series column of this {} run (scene {}); its columns are: {}",
                        run.model(),
                        run.scene().name,
                        series.columns.join(", ")
                    ),
                )
            })?;
            let row = series.rows.last().ok_or_else(|| {
                (
                    FRACTUM_ERR_RUN,
                    "the run has recorded no series row yet".to_string(),
                )
            })?;
            Ok(row[k])
        })??;
        put(value, v, "value")
    })
}

/// The series columns (those `fractum_scalar` reads) as one comma-separated NUL-terminated
/// text into `buf` of `len` bytes. `*needed` receives the size with the NUL; a short buffer
/// (or `len` = 0 to ask) gives FRACTUM_ERR_BUFFER.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_columns(
    handle: FractumHandle,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> FractumStatus {
    guard(|| {
        let text = with_run(handle, |run| run.series().columns.join(","))?;
        copy_text(&text, buf, len, needed)
    })
}

/// The run's summary so far as NUL-terminated JSON text into `buf` of `len` bytes: the keys
/// and numbers of `fractum run`'s summary.json for the same scene and thread count, less
/// `wall_seconds`, in the same (pretty-printed) layout. `*needed` receives the size with the
/// NUL; a short buffer (or `len` = 0 to ask) gives FRACTUM_ERR_BUFFER.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_summary_json(
    handle: FractumHandle,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> FractumStatus {
    guard(|| {
        let summary = with_run(handle, |run| run.summary())?;
        let text = serde_json::to_string_pretty(&summary).map_err(|e| {
            (
                FRACTUM_ERR_INTERNAL,
                format!("the summary does not serialise: {e}"),
            )
        })?;
        copy_text(&text, buf, len, needed)
    })
}

/// Copies per-body values (taken from the run by `values`) into the caller's buffer.
fn copy_body_values(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
    values: impl FnOnce(&Sim) -> Result<Vec<f64>, Failure>,
) -> FractumStatus {
    guard(|| {
        let v = with_sim(handle, |e| values(&e.sim))?;
        copy_out(&v, buf, len, "doubles")
    })
}

fn flatten(v: &[fractum::state::Vec3]) -> Vec<f64> {
    v.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// Copies the positions (m) as x0 y0 z0 x1 ... into `buf` of `len` doubles (3 per body; z = 0
/// for beam2d's 2D polygons).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_positions(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| Ok(flatten(&sim.run().positions())))
}

/// Copies the velocities (m/s) as vx0 vy0 vz0 vx1 ... into `buf` of `len` doubles (3 per
/// body).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_velocities(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| Ok(flatten(&sim.run().velocities())))
}

/// Copies the orientations as unit quaternions w0 x0 y0 z0 w1 ... into `buf` of `len` doubles
/// (4 per body; beam2d's polygons turn about z only).
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_orientations(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| {
        Ok(sim.run().orientations().into_iter().flatten().collect())
    })
}

/// Copies the radii (m; the bounding radius of non-spherical bodies) into `buf` of `len`
/// doubles (1 per body). Granular runs only: FRACTUM_ERR_MODEL on other runs.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_radii(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| match sim.run().radii() {
        Some(r) => Ok(r),
        None => Err(not_for_model(
            "fractum_copy_radii",
            sim.run(),
            "only granular runs have grain radii",
        )),
    })
}

/// Copies each grain's load at the last fracture check into `buf` of `len` doubles (22 per
/// body, FractumGrainLoad's fields in its order: the moment of the contact forces about the
/// grain's centre, 9 doubles row-major (N m); the number of critical contacts; the three
/// largest contact tensile stresses (Pa) and their points (m, 3 x 3), largest first, zeros
/// past the count): what the check compared with the grain's strength, after the force
/// evaluation of the last step. Zeros for grains held by intact springs (not checked), for
/// halves made by that check's splits, and before the first step (and after a restore, until
/// the next step). Granular runs with the `fracture` effect only: FRACTUM_ERR_MODEL otherwise.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_copy_grain_loads(
    handle: FractumHandle,
    buf: *mut f64,
    len: usize,
) -> FractumStatus {
    copy_body_values(handle, buf, len, |sim| match sim.run().grain_loads() {
        Some(loads) => Ok(loads.iter().flat_map(kernels::grain_load_row).collect()),
        None => Err(not_for_model(
            "fractum_copy_grain_loads",
            sim.run(),
            "only granular runs with the \"fracture\" effect check grain loads",
        )),
    })
}

/// The size (bytes) of the saved state, for sizing the buffer of `fractum_save_state`.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_state_size(handle: FractumHandle, size: *mut usize) -> FractumStatus {
    guard(|| {
        let n = with_run(handle, |run| run.save_state().len())?;
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
        let bytes = with_run(handle, |run| run.save_state())?;
        copy_out(&bytes, buf, len, "bytes")?;
        put(written, bytes.len(), "written")
    })
}

/// Restores a state saved by `fractum_save_state` from the same scene; the run then continues
/// bit for bit. A state carries a format version and a checksum: damaged, truncated or foreign
/// bytes are refused with `FRACTUM_ERR_RUN` and the run is left as it was.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_restore_state(
    handle: FractumHandle,
    buf: *const u8,
    len: usize,
) -> FractumStatus {
    guard(|| {
        let bytes = bytes_arg(buf, len)?;
        with_sim(handle, |e| {
            e.sim = e.sim.replaced(&bytes).map_err(from_error)?;
            Ok(())
        })
    })
}

/// Returns the simulation to the state it had right after creation.
#[unsafe(no_mangle)]
pub extern "C" fn fractum_reset(handle: FractumHandle) -> FractumStatus {
    guard(|| {
        with_sim(handle, |e| {
            e.sim = e.sim.replaced(&e.initial).map_err(from_error)?;
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

    fn last_error() -> String {
        // SAFETY: fractum_last_error returns a valid NUL-terminated string.
        unsafe { CStr::from_ptr(fractum_last_error()) }
            .to_string_lossy()
            .to_string()
    }

    #[test]
    fn a_panic_becomes_a_status_and_a_message() {
        let status = guard(|| panic!("boom"));
        assert_eq!(status, FRACTUM_ERR_INTERNAL);
        let msg = last_error();
        assert!(msg.contains("boom"), "{msg}");
    }

    #[test]
    fn unknown_handles_are_refused() {
        assert_eq!(fractum_advance_to(u64::MAX, 1.0), FRACTUM_ERR_HANDLE);
        assert_eq!(fractum_advance(u64::MAX, 1), FRACTUM_ERR_HANDLE);
        let mut kind = std::ptr::null();
        assert_eq!(fractum_model(12345, &mut kind), FRACTUM_ERR_HANDLE);
        assert_eq!(fractum_free(0), FRACTUM_ERR_HANDLE);
        let msg = last_error();
        assert!(msg.contains("not a live Fractum simulation"), "{msg}");
    }

    #[test]
    fn text_goes_out_with_its_size_and_a_short_buffer_is_refused() {
        let mut needed = 0usize;
        let status = guard(|| copy_text("abc", std::ptr::null_mut(), 0, &mut needed));
        assert_eq!((status, needed), (FRACTUM_ERR_BUFFER, 4));
        assert!(last_error().contains("4 are needed"), "{}", last_error());
        let mut buf = [1 as c_char; 4];
        let status = guard(|| copy_text("abc", buf.as_mut_ptr(), buf.len(), &mut needed));
        assert_eq!(status, FRACTUM_OK);
        // SAFETY: copy_text wrote a NUL-terminated string into buf.
        let back = unsafe { CStr::from_ptr(buf.as_ptr()) };
        assert_eq!(back.to_str(), Ok("abc"));
    }
}
