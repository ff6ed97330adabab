//! The FMI 2.0 co-simulation layer, the part Reference-FMUs keep in `fmi2Functions.c`: the
//! 34 exported fmi2 functions, the instance's phases and which calls each allows, pointer
//! and argument checks, the registries of live instances and FMU states, logging, the
//! resource location, and a catch for every panic so none crosses the boundary. The model
//! (`crate::FmuModel`) is reached only through [`Model`]: variables by value reference,
//! its build at the end of initialisation, a communication step, and its saved state.

// The fmi2 functions are C entry points: their pointer arguments are defined by the FMI
// standard, and each is checked for null (and instances and states against the live
// registries) before it is read or written.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use fmi_sys::fmi2::*;
use fractum::output::sealed;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::FmuModel;

/// An error: one sentence, logged as `"<fmi2 function>: <sentence>"`.
pub type Failure = String;

/// What the FMI layer needs of a model (what Reference-FMUs put in each `model.c`). One
/// model is exported per library: `crate::FmuModel`.
pub trait Model: Default {
    /// The GUID of modelDescription.xml; fmi2Instantiate refuses any other.
    const GUID: &'static str;
    /// The modelIdentifier; also the instance name when the host passes none.
    const MODEL_IDENTIFIER: &'static str;
    /// The phases in which fmi2SetReal, fmi2SetInteger, fmi2SetBoolean and fmi2SetString are
    /// allowed at all; the setters then check each variable (a parameter only before
    /// running...).
    const SET_REAL_IN: &'static [Phase];
    const SET_INTEGER_IN: &'static [Phase];
    const SET_BOOLEAN_IN: &'static [Phase] = &[];
    const SET_STRING_IN: &'static [Phase];
    /// Whether the model has Boolean variables; without, fmi2GetBoolean and fmi2SetBoolean
    /// refuse any non-empty call and [`Model::boolean`] and [`Model::set_boolean`] are unused.
    const HAS_BOOLEANS: bool = false;
    /// What a saved FMU state holds of the model.
    type Saved: Serialize + DeserializeOwned;

    /// The communication time (s). The model keeps it, so that its saved state holds it;
    /// fmi2SetupExperiment sets the start time, fmi2DoStep checks each step against it.
    fn time(&self) -> f64;
    fn set_time(&mut self, time: f64);
    /// Builds the model from its parameters and the FMU's resources folder, at the end of
    /// initialisation.
    fn build(&mut self, resources: &Path) -> Result<(), Failure>;
    /// A progress sentence after [`Physics::build`], logged when debug logging is on.
    fn built(&self) -> String;
    /// The value of a Real variable (any phase).
    fn real(&self, vr: u32) -> Result<f64, Failure>;
    /// Sets a Real variable; `phase` is the instance's, for per-variable checks.
    fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), Failure>;
    fn integer(&self, vr: u32) -> Result<i32, Failure>;
    fn set_integer(&mut self, vr: u32, value: i32, phase: Phase) -> Result<(), Failure>;
    fn boolean(&self, vr: u32) -> Result<bool, Failure> {
        Err(format!(
            "{vr} is not the value reference of a Boolean variable"
        ))
    }
    fn set_boolean(&mut self, vr: u32, _value: bool, _phase: Phase) -> Result<(), Failure> {
        Err(format!(
            "{vr} is not the value reference of a Boolean variable"
        ))
    }
    fn string(&self, vr: u32) -> Result<String, Failure>;
    /// Sets a String variable; `value` is None where the host passed a null pointer.
    fn set_string(&mut self, vr: u32, value: Option<String>, phase: Phase) -> Result<(), Failure>;
    /// The most work one fmi2DoStep may take, in words ("1e9 solver steps"), for
    /// fmi2CancelStep's message: [`Model::do_step`] refuses a longer step up front, so that
    /// no synchronous step runs for days.
    fn step_bound() -> String;
    /// Advances from `current` (the model's time, checked) to `current + h` (h > 0 finite,
    /// checked) and sets the model's time to `current + h`.
    fn do_step(&mut self, current: f64, h: f64) -> Result<(), StepError>;
    fn save(&self) -> Self::Saved;
    /// Returns to a saved state; on an error the model is unchanged.
    fn restore(&mut self, saved: &Self::Saved, resources: &Path) -> Result<(), Failure>;
}

/// Why a communication step did not happen.
#[derive(Debug)]
pub enum StepError {
    /// Refused before anything changed: the instance stays usable.
    Refused(Failure),
    /// The step failed part way: the instance goes to [`Phase::Failed`].
    Failed(Failure),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    Instantiated,
    Initialization,
    Running,
    Terminated,
    /// A step or the initialisation failed: only Terminate, Reset, FreeInstance and getters
    /// are allowed.
    Failed,
}

impl Phase {
    /// Ok if this phase is one of `allowed`, else why `call` is refused.
    pub fn expect(self, allowed: &[Phase], call: &str) -> Result<(), Failure> {
        if allowed.contains(&self) {
            Ok(())
        } else {
            Err(format!(
                "{call} is not allowed in the {self:?} state of the FMU"
            ))
        }
    }
}

struct Instance {
    name: CString,
    logger: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    logging: bool,
    resources: PathBuf,
    phase: Phase,
    model: FmuModel,
}

// SAFETY: what keeps Instance from being Send is the host's `componentEnvironment` pointer
// and logger, which this library never dereferences: it hands the pointer back to the host's
// logger. FMI 2.0 leaves the host free to call an instance from any thread, and the
// instance's lock keeps its calls from overlapping.
unsafe impl Send for Instance {}

/// A saved FMU state (fmi2GetFMUstate).
#[derive(Serialize, Deserialize)]
struct Saved {
    phase: Phase,
    model: <FmuModel as Model>::Saved,
}

/// A live instance. The lock serialises calls on it, as the C API's lock on each handle does
/// (ffi/src/lib.rs): a host that calls one instance from two threads at once gets one call
/// after the other, never two threads inside the solver. The registry holds it by an `Arc`,
/// so that fmi2FreeInstance during another thread's call frees it when that call ends.
type Slot = Arc<Mutex<Instance>>;

/// The live instances, by the address the host holds as its `fmi2Component` (the address of
/// the instance's lock: a key, never dereferenced).
fn live() -> &'static Mutex<HashMap<usize, Slot>> {
    static LIVE: OnceLock<Mutex<HashMap<usize, Slot>>> = OnceLock::new();
    LIVE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The live FMU states, by the address the host holds as its `fmi2FMUstate`, shared as the
/// instances are: a state freed by one thread while another restores it lives until that ends.
fn live_states() -> &'static Mutex<HashMap<usize, Arc<Saved>>> {
    static LIVE: OnceLock<Mutex<HashMap<usize, Arc<Saved>>>> = OnceLock::new();
    LIVE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Registers a state and gives its address, the host's `fmi2FMUstate`.
fn register_state(saved: Saved) -> Result<fmi2FMUstate, Failure> {
    let saved = Arc::new(saved);
    let key = Arc::as_ptr(&saved) as usize;
    live_states()
        .lock()
        .map_err(|_| "state registry poisoned".to_string())?
        .insert(key, saved);
    Ok(key as fmi2FMUstate)
}

impl Instance {
    fn log(&self, status: fmi2Status, category: &str, message: &str) {
        if let Some(logger) = self.logger {
            let cat = CString::new(category).unwrap_or_default();
            let msg =
                CString::new(message.replace('\0', " ").replace('%', "%%")).unwrap_or_default();
            // SAFETY: the host gave this logger; all strings are NUL-terminated.
            unsafe {
                logger(
                    self.environment,
                    self.name.as_ptr(),
                    status,
                    cat.as_ptr(),
                    msg.as_ptr(),
                )
            };
        }
    }

    fn expect(&self, allowed: &[Phase], call: &str) -> Result<(), Failure> {
        self.phase.expect(allowed, call)
    }

    fn save(&self) -> Saved {
        Saved {
            phase: self.phase,
            model: self.model.save(),
        }
    }

    fn restore(&mut self, saved: &Saved) -> Result<(), Failure> {
        self.model.restore(&saved.model, &self.resources)?;
        self.phase = saved.phase;
        Ok(())
    }
}

/// Runs `f` on the instance `c`, catching panics and reporting failures to the logger.
fn with_instance(
    c: fmi2Component,
    call: &str,
    f: impl FnOnce(&mut Instance) -> Result<fmi2Status, Failure>,
) -> fmi2Status {
    let slot = live()
        .lock()
        .ok()
        .and_then(|l| l.get(&(c as usize)).cloned());
    let Some(slot) = slot else {
        return fmi2Status_fmi2Error;
    };
    // Waits for a call of another thread on this instance to end. Panics are caught inside
    // the lock, so none poisons it.
    let mut guard = slot.lock().unwrap_or_else(PoisonError::into_inner);
    let inst = &mut *guard;
    match catch_unwind(AssertUnwindSafe(|| f(inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            // Shortened as the library's own errors are: a parameter of 10 MB came back whole.
            inst.log(
                fmi2Status_fmi2Error,
                "logStatusError",
                &fractum::error::shorten(&format!("{call}: {message}")),
            );
            fmi2Status_fmi2Error
        }
        Err(_) => {
            inst.phase = Phase::Failed;
            inst.log(
                fmi2Status_fmi2Fatal,
                "logStatusFatal",
                &format!("{call}: internal error in Fractum"),
            );
            fmi2Status_fmi2Fatal
        }
    }
}

fn c_str(p: fmi2String) -> Option<String> {
    if p.is_null() {
        return None;
    }
    // SAFETY: FMI strings are NUL-terminated.
    Some(unsafe { CStr::from_ptr(p) }.to_string_lossy().to_string())
}

/// Why `fmi2Instantiate` refuses the GUID `given` (NULL: none). The value itself, not the
/// `Some("...")` of its Rust option, which hosts' logs showed.
fn guid_mismatch(given: Option<&str>) -> String {
    let given = match given {
        Some(g) => format!("\"{g}\""),
        None => "none".to_string(),
    };
    format!("GUID {given} does not match this FMU's {}", FmuModel::GUID)
}

/// The folder of a `file:` resource URI, percent-decoded.
pub fn resource_dir(uri: &str) -> Option<PathBuf> {
    let rest = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))?;
    // file:///abs/path or file://localhost/abs/path
    let rest = rest.strip_prefix("localhost").unwrap_or(rest);
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' {
            let hex = std::str::from_utf8(bytes.get(k + 1..k + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    Some(PathBuf::from(String::from_utf8(out).ok()?))
}

/// The resources folder of the unpacked FMU this library was loaded from
/// (`binaries/linux64/fractum_shpb.so` -> `resources/`).
fn own_resources() -> Option<PathBuf> {
    let mut info: libc::Dl_info = unsafe { std::mem::zeroed() };
    // SAFETY: dladdr only reads the address of one of this library's functions.
    let ok = unsafe { libc::dladdr(fmi2GetVersion as *const c_void, &mut info) };
    if ok == 0 || info.dli_fname.is_null() {
        return None;
    }
    // SAFETY: dladdr returned a NUL-terminated file name.
    let so = PathBuf::from(
        unsafe { CStr::from_ptr(info.dli_fname) }
            .to_string_lossy()
            .to_string(),
    );
    Some(so.parent()?.parent()?.parent()?.join("resources"))
}

// ---- the 34 FMI 2.0 functions ------------------------------------------------------------

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    _n: usize,
    _categories: *const fmi2String,
) -> fmi2Status {
    with_instance(c, "fmi2SetDebugLogging", |i| {
        i.logging = logging_on != 0;
        Ok(fmi2Status_fmi2OK)
    })
}

/// # Safety
/// `functions` must point to valid callbacks as the FMI standard requires.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let callbacks = if functions.is_null() {
            None
        } else {
            // SAFETY: checked non-null; the host passes a valid struct.
            Some(unsafe { *functions })
        };
        let name = c_str(instance_name).unwrap_or_else(|| FmuModel::MODEL_IDENTIFIER.to_string());
        let mut inst = Instance {
            name: CString::new(name.replace('\0', " ")).unwrap_or_default(),
            logger: callbacks.and_then(|c| c.logger),
            environment: callbacks.map_or(std::ptr::null_mut(), |c| c.componentEnvironment),
            logging: logging_on != 0,
            resources: PathBuf::new(),
            phase: Phase::Instantiated,
            model: FmuModel::default(),
        };
        let fail = |inst: &Instance, message: String| {
            inst.log(
                fmi2Status_fmi2Error,
                "logStatusError",
                &format!("fmi2Instantiate: {message}"),
            );
            std::ptr::null_mut()
        };
        if fmu_type != fmi2Type_fmi2CoSimulation {
            return fail(&inst, "this FMU supports co-simulation only".to_string());
        }
        match c_str(guid) {
            Some(g) if g == FmuModel::GUID => {}
            g => return fail(&inst, guid_mismatch(g.as_deref())),
        }
        let uri = c_str(resource_location).unwrap_or_default();
        let resources = if uri.is_empty() {
            own_resources()
        } else {
            resource_dir(&uri)
        };
        match resources {
            Some(dir) => inst.resources = dir,
            None => {
                return fail(
                    &inst,
                    format!("cannot use the resource location {uri:?} (a file: URI is expected)"),
                );
            }
        }
        let slot = Arc::new(Mutex::new(inst));
        let key = Arc::as_ptr(&slot) as usize;
        match live().lock() {
            Ok(mut l) => {
                l.insert(key, slot);
                key as fmi2Component
            }
            Err(_) => std::ptr::null_mut(),
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // Dropped here, or when a call of another thread on it ends.
        let removed = live().lock().ok().and_then(|mut l| l.remove(&(c as usize)));
        drop(removed);
    }));
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _tolerance_defined: fmi2Boolean,
    _tolerance: fmi2Real,
    start_time: fmi2Real,
    _stop_time_defined: fmi2Boolean,
    _stop_time: fmi2Real,
) -> fmi2Status {
    with_instance(c, "fmi2SetupExperiment", |i| {
        i.expect(&[Phase::Instantiated], "fmi2SetupExperiment")?;
        if !start_time.is_finite() {
            return Err(format!("start time {start_time} is not finite"));
        }
        i.model.set_time(start_time);
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2EnterInitializationMode", |i| {
        i.expect(&[Phase::Instantiated], "fmi2EnterInitializationMode")?;
        i.phase = Phase::Initialization;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2ExitInitializationMode", |i| {
        i.expect(&[Phase::Initialization], "fmi2ExitInitializationMode")?;
        // The build takes seconds: its start and end are logged whatever the debug logging
        // setting, so that a master's user sees why the call takes long.
        i.log(
            fmi2Status_fmi2OK,
            "logBuild",
            "building the specimen (packing and settling the grains; a few seconds)",
        );
        let started = std::time::Instant::now();
        if let Err(why) = i.model.build(&i.resources) {
            // Only Terminate, Reset, FreeInstance and getters from here.
            i.phase = Phase::Failed;
            return Err(why);
        }
        i.log(
            fmi2Status_fmi2OK,
            "logBuild",
            &format!(
                "{} in {:.1} s",
                i.model.built(),
                started.elapsed().as_secs_f64()
            ),
        );
        i.phase = Phase::Running;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Terminate", |i| {
        // After a failed step or initialisation too: masters (OMSimulator) terminate every
        // instance they initialised, and refusing it only repeated the first error.
        i.expect(&[Phase::Running, Phase::Failed], "fmi2Terminate")?;
        i.phase = Phase::Terminated;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Reset", |i| {
        i.model = FmuModel::default();
        i.phase = Phase::Instantiated;
        Ok(fmi2Status_fmi2OK)
    })
}

fn slices<'a, T>(
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *const T,
) -> Result<(&'a [u32], &'a [T]), Failure> {
    if n == 0 {
        return Ok((&[], &[]));
    }
    if vrs.is_null() || values.is_null() {
        return Err("null value-reference or value array".to_string());
    }
    // SAFETY: the host passes arrays of `n` elements.
    Ok(unsafe {
        (
            std::slice::from_raw_parts(vrs, n),
            std::slice::from_raw_parts(values, n),
        )
    })
}

fn out_slices<'a, T>(
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *mut T,
) -> Result<(&'a [u32], &'a mut [T]), Failure> {
    if n == 0 {
        return Ok((&[], &mut []));
    }
    if vrs.is_null() || values.is_null() {
        return Err("null value-reference or value array".to_string());
    }
    // SAFETY: the host passes arrays of `n` elements.
    Ok(unsafe {
        (
            std::slice::from_raw_parts(vrs, n),
            std::slice::from_raw_parts_mut(values, n),
        )
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *mut fmi2Real,
) -> fmi2Status {
    with_instance(c, "fmi2GetReal", |i| {
        let (vrs, values) = out_slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values.iter_mut()) {
            *v = i.model.real(*r)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *mut fmi2Integer,
) -> fmi2Status {
    with_instance(c, "fmi2GetInteger", |i| {
        let (vrs, values) = out_slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values.iter_mut()) {
            *v = i.model.integer(*r)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2GetBoolean", |i| {
        if n == 0 {
            return Ok(fmi2Status_fmi2OK);
        }
        if !FmuModel::HAS_BOOLEANS {
            return Err("this FMU has no Boolean variables".to_string());
        }
        let (vrs, values) = out_slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values.iter_mut()) {
            *v = fmi2Boolean::from(i.model.boolean(*r)?);
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetString(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *mut fmi2String,
) -> fmi2Status {
    with_instance(c, "fmi2GetString", |i| {
        let (vrs, values) = out_slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values.iter_mut()) {
            // The string outlives the call: it is kept among the last 65 returned by any
            // instance of this library.
            static STRINGS: OnceLock<Mutex<Vec<CString>>> = OnceLock::new();
            let s = CString::new(i.model.string(*r)?).unwrap_or_default();
            let ptr = s.as_ptr();
            let store = STRINGS.get_or_init(|| Mutex::new(Vec::new()));
            if let Ok(mut v) = store.lock() {
                if v.len() > 64 {
                    v.remove(0);
                }
                v.push(s);
            }
            *v = ptr;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *const fmi2Real,
) -> fmi2Status {
    with_instance(c, "fmi2SetReal", |i| {
        i.expect(FmuModel::SET_REAL_IN, "fmi2SetReal")?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            i.model.set_real(*r, *v, i.phase)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *const fmi2Integer,
) -> fmi2Status {
    with_instance(c, "fmi2SetInteger", |i| {
        i.expect(FmuModel::SET_INTEGER_IN, "fmi2SetInteger")?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            i.model.set_integer(*r, *v, i.phase)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *const fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2SetBoolean", |i| {
        if n == 0 {
            return Ok(fmi2Status_fmi2OK);
        }
        if !FmuModel::HAS_BOOLEANS {
            return Err("this FMU has no Boolean variables".to_string());
        }
        i.expect(FmuModel::SET_BOOLEAN_IN, "fmi2SetBoolean")?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            i.model.set_boolean(*r, *v != 0, i.phase)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetString(
    c: fmi2Component,
    vrs: *const fmi2ValueReference,
    n: usize,
    values: *const fmi2String,
) -> fmi2Status {
    with_instance(c, "fmi2SetString", |i| {
        i.expect(FmuModel::SET_STRING_IN, "fmi2SetString")?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            i.model.set_string(*r, c_str(*v), i.phase)?;
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2GetFMUstate", |i| {
        if state.is_null() {
            return Err("the state pointer is null".to_string());
        }
        // A state the host passes back in is replaced, not leaked.
        // SAFETY: checked non-null.
        let old = unsafe { *state };
        let fresh = register_state(i.save())?;
        if let Ok(mut l) = live_states().lock() {
            l.remove(&(old as usize));
        }
        // SAFETY: checked non-null.
        unsafe { *state = fresh };
        Ok(fmi2Status_fmi2OK)
    })
}

fn saved_of(state: fmi2FMUstate) -> Result<Arc<Saved>, Failure> {
    live_states()
        .lock()
        .ok()
        .and_then(|l| l.get(&(state as usize)).cloned())
        .ok_or_else(|| "the FMU state is null, freed or not from this FMU".to_string())
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2SetFMUstate", |i| {
        let saved = saved_of(state)?;
        i.restore(&saved)?;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2FreeFMUstate", |_| {
        if state.is_null() {
            return Ok(fmi2Status_fmi2OK);
        }
        // SAFETY: checked non-null.
        let s = unsafe { *state };
        if s.is_null() {
            return Ok(fmi2Status_fmi2OK);
        }
        let removed = live_states()
            .lock()
            .ok()
            .and_then(|mut l| l.remove(&(s as usize)));
        if removed.is_none() {
            return Err("the FMU state is not from this FMU or already freed".to_string());
        }
        // SAFETY: checked non-null.
        unsafe { *state = std::ptr::null_mut() };
        Ok(fmi2Status_fmi2OK)
    })
}

/// What a serialized FMU state starts with, and its format version (sealed: length and
/// checksum too, so a damaged state is refused before it is decoded).
const STATE_MAGIC: &[u8; 8] = b"FRACTUMF";
/// 2: the `fracture` parameter joined the saved variables.
const STATE_VERSION: u32 = 2;

fn serialize(saved: &Saved) -> Vec<u8> {
    sealed::seal(
        STATE_MAGIC,
        STATE_VERSION,
        &postcard::to_stdvec(saved).expect("FMU state serialises"),
    )
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with_instance(c, "fmi2SerializedFMUstateSize", |_| {
        let saved = saved_of(state)?;
        if size.is_null() {
            return Err("the size pointer is null".to_string());
        }
        // SAFETY: checked non-null.
        unsafe { *size = serialize(&saved).len() };
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    state: fmi2FMUstate,
    bytes: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with_instance(c, "fmi2SerializeFMUstate", |_| {
        let saved = saved_of(state)?;
        let data = serialize(&saved);
        if bytes.is_null() || size < data.len() {
            return Err(format!(
                "the buffer holds {size} bytes, the state needs {}",
                data.len()
            ));
        }
        // SAFETY: the host's buffer holds `size >= data.len()` bytes.
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), bytes as *mut u8, data.len()) };
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    bytes: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    with_instance(c, "fmi2DeSerializeFMUstate", |_| {
        if bytes.is_null() || state.is_null() {
            return Err("null bytes or state pointer".to_string());
        }
        // SAFETY: the host passes `size` readable bytes.
        let data = unsafe { std::slice::from_raw_parts(bytes as *const u8, size) };
        let data = sealed::open(data, STATE_MAGIC, STATE_VERSION)
            .map_err(|why| format!("the serialized FMU state is not usable: it {why}"))?;
        let saved: Saved = postcard::from_bytes(data)
            .map_err(|e| format!("the serialized FMU state is damaged ({e})"))?;
        let fresh = register_state(saved)?;
        // SAFETY: checked non-null.
        unsafe { *state = fresh };
        Ok(fmi2Status_fmi2OK)
    })
}

/// The arguments of fmi2DoStep against the FMU's time `now`: a finite positive step that moves
/// the clock, from where the last step ended.
fn check_step(current: f64, h: f64, now: f64) -> Result<(), String> {
    // Written so that NaN fails them: a NaN step or time once passed both checks.
    if !(h.is_finite() && h > 0.0) {
        return Err(format!(
            "communicationStepSize = {h:e} s is outside the allowed range (0, inf) s"
        ));
    }
    // The master's clock may carry the round-off of summing its steps.
    let tolerance = 1e-9 * h.max(now.abs());
    if !(current.is_finite() && (current - now).abs() <= tolerance) {
        return Err(format!(
            "currentCommunicationPoint = {current:e} s is outside the allowed range: the \
             FMU's time {now:e} s, where its last step ended (within {tolerance:.1e} s)"
        ));
    }
    // A step below the resolution of the clock at `current` (h = 5e-324, or any step at
    // t = 1e300) advanced nothing and returned fmi2OK.
    if current + h == current {
        return Err(format!(
            "communicationStepSize = {h:e} s is below the resolution of the time at \
             currentCommunicationPoint = {current:e} s (t + h == t): it would advance nothing; \
             the allowed range is a step with t + h > t"
        ));
    }
    Ok(())
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2DoStep(
    c: fmi2Component,
    current: fmi2Real,
    h: fmi2Real,
    _no_set_prior: fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2DoStep", |i| {
        i.expect(&[Phase::Running], "fmi2DoStep")?;
        check_step(current, h, i.model.time())?;
        match i.model.do_step(current, h) {
            Ok(()) => Ok(fmi2Status_fmi2OK),
            Err(StepError::Refused(message)) => Err(message),
            Err(StepError::Failed(message)) => {
                i.phase = Phase::Failed;
                Err(message)
            }
        }
    })
}

fn unsupported(c: fmi2Component, call: &str) -> fmi2Status {
    with_instance(c, call, |_| {
        Err("is not supported by this co-simulation FMU".to_string())
    })
}

/// Nothing to cancel: fmi2DoStep runs to its end before it returns (canRunAsynchronuously is
/// false) and never returns fmi2Pending, and the model bounds each step
/// ([`Model::step_bound`]).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2CancelStep", |_| {
        Err(format!(
            "no step to cancel: fmi2DoStep is synchronous (it never returns fmi2Pending) and \
             refuses up front a step that needs more than {}",
            FmuModel::step_bound()
        ))
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    _v: *mut fmi2Status,
) -> fmi2Status {
    unsupported(c, "fmi2GetStatus (steps are synchronous)")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    v: *mut fmi2Real,
) -> fmi2Status {
    with_instance(c, "fmi2GetRealStatus", |i| {
        if s == fmi2StatusKind_fmi2LastSuccessfulTime && !v.is_null() {
            // SAFETY: checked non-null.
            unsafe { *v = i.model.time() };
            Ok(fmi2Status_fmi2OK)
        } else {
            Err("only fmi2LastSuccessfulTime is available".to_string())
        }
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    _v: *mut fmi2Integer,
) -> fmi2Status {
    unsupported(c, "fmi2GetIntegerStatus")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    _v: *mut fmi2Boolean,
) -> fmi2Status {
    unsupported(c, "fmi2GetBooleanStatus")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    _s: fmi2StatusKind,
    _v: *mut fmi2String,
) -> fmi2Status {
    unsupported(c, "fmi2GetStringStatus")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _vu: *const fmi2ValueReference,
    _nu: usize,
    _vk: *const fmi2ValueReference,
    _nk: usize,
    _dvk: *const fmi2Real,
    _dvu: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetDirectionalDerivative")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsupported(
        c,
        "fmi2SetRealInputDerivatives (inputs are not interpolated)",
    )
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetRealOutputDerivatives")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_below_the_clocks_resolution_is_refused() {
        // doStep(t, h) with t + h == t returned fmi2OK and did nothing.
        for (t, h) in [(0.0, 1e-6), (1e-6, 1e-6), (1e300, 1e300)] {
            assert_eq!(check_step(t, h, t), Ok(()), "{t} {h}");
        }
        for (t, h) in [(1e-6, 5e-324), (2e-6, 1e-30), (1e300, 1e-6)] {
            let e = check_step(t, h, t).unwrap_err();
            assert!(
                e.starts_with("communicationStepSize = ")
                    && e.contains("t + h == t")
                    && e.contains("allowed"),
                "{t} {h}: {e}"
            );
        }
        // The other arguments are named first.
        assert!(
            check_step(f64::INFINITY, 1.0, 0.0)
                .unwrap_err()
                .starts_with("currentCommunicationPoint = ")
        );
    }

    #[test]
    fn resource_uris_are_percent_decoded() {
        assert_eq!(
            resource_dir("file:///tmp/my%20fmu/resources"),
            Some(PathBuf::from("/tmp/my fmu/resources"))
        );
        assert_eq!(resource_dir("file:/a/b"), Some(PathBuf::from("/a/b")));
        assert_eq!(
            resource_dir("file://localhost/a%2Fb"),
            Some(PathBuf::from("/a/b"))
        );
        assert_eq!(resource_dir("http://x/y"), None);
    }

    #[test]
    fn a_wrong_guid_is_quoted_as_given_and_a_missing_one_is_none() {
        let wrong = guid_mismatch(Some("{not-the-guid}"));
        assert!(
            wrong.starts_with("GUID \"{not-the-guid}\" does not match"),
            "{wrong}"
        );
        assert!(!wrong.contains("Some("), "{wrong}");
        assert!(wrong.ends_with(FmuModel::GUID), "{wrong}");
        let missing = guid_mismatch(None);
        assert!(missing.starts_with("GUID none does not match"), "{missing}");
    }
}
