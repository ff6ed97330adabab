//! FMI 2.0 co-simulation FMU of the SHPB specimen (`fractum_shpb.so`, model identifier
//! `fractum_shpb`). The bars (1D elastic wave models in Modelica, Python, Simulink...) give
//! the velocities of the two bar faces; the FMU returns the specimen's stresses and forces.
//!
//! A thin layer over `fractum::Simulation`: it checks the calling sequence, maps variables,
//! translates errors into fmi2Error with a sentence to the logger, and never lets a panic
//! cross the boundary. All 34 fmi2 functions are exported; those a co-simulation FMU of this
//! kind does not support return fmi2Error with a message.
//!
//! Variables (value references in [`vr`]):
//! * inputs `v_incident` (m/s, the incident-bar face moving into the specimen, compression
//!   positive) and `v_transmitted` (m/s, the transmitted-bar face moving along the bar axis,
//!   away from the specimen): the specimen shortens at `v_incident - v_transmitted`;
//! * outputs `stress_incident`, `stress_transmitted` (Pa, specimen axial stress at each face,
//!   compression positive), `force_incident`, `force_transmitted` (N, that stress over the
//!   specimen cross-section), `bar_stress_incident`, `bar_stress_transmitted` (Pa, the force
//!   over the bar cross-section), `strain`, `broken_particles`, `kinetic_energy` (J);
//! * parameters `scene` (a path inside resources/), `specimen_diameter`, `bar_diameter` (m),
//!   `seed`.

// The fmi2 functions are C entry points: their pointer arguments are defined by the FMI
// standard, and each is checked for null (and instances and states against the live
// registries) before it is read or written.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use std::collections::HashSet;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

use fmi_sys::fmi2::*;
use fractum::{Run, Simulation};
use serde::{Deserialize, Serialize};

/// The GUID of modelDescription.xml; Instantiate refuses any other.
pub const GUID: &str = "{5f1c6f2e-3b9a-4d57-9c1e-7a2f0d8e4b61}";
pub const MODEL_IDENTIFIER: &str = "fractum_shpb";
const DEFAULT_SCENE: &str = "shpb_sand.toml";

/// Value references.
pub mod vr {
    pub const V_INCIDENT: u32 = 0;
    pub const V_TRANSMITTED: u32 = 1;
    pub const STRESS_INCIDENT: u32 = 2;
    pub const STRESS_TRANSMITTED: u32 = 3;
    pub const FORCE_INCIDENT: u32 = 4;
    pub const FORCE_TRANSMITTED: u32 = 5;
    pub const BAR_STRESS_INCIDENT: u32 = 6;
    pub const BAR_STRESS_TRANSMITTED: u32 = 7;
    pub const STRAIN: u32 = 8;
    pub const KINETIC_ENERGY: u32 = 9;
    pub const SPECIMEN_DIAMETER: u32 = 10;
    pub const BAR_DIAMETER: u32 = 11;
    /// Integer variables.
    pub const BROKEN_PARTICLES: u32 = 12;
    pub const SEED: u32 = 13;
    /// String variable.
    pub const SCENE: u32 = 14;
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
enum Phase {
    Instantiated,
    Initialization,
    Running,
    Terminated,
    /// A step failed: only Reset, FreeInstance and getters are allowed.
    Failed,
}

/// Everything a host can set, and the time.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Variables {
    v_incident: f64,
    v_transmitted: f64,
    specimen_diameter: f64,
    bar_diameter: f64,
    seed: i32,
    scene: String,
    time: f64,
}

impl Default for Variables {
    fn default() -> Self {
        Variables {
            v_incident: 0.0,
            v_transmitted: 0.0,
            specimen_diameter: 19.05e-3,
            bar_diameter: 19.05e-3,
            seed: 1,
            scene: DEFAULT_SCENE.to_string(),
            time: 0.0,
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
    vars: Variables,
    sim: Option<Simulation>,
}

/// A saved FMU state (fmi2GetFMUstate).
#[derive(Serialize, Deserialize)]
struct Saved {
    phase: Phase,
    vars: Variables,
    sim: Option<Vec<u8>>,
}

type Failure = String;

fn live() -> &'static Mutex<HashSet<usize>> {
    static LIVE: OnceLock<Mutex<HashSet<usize>>> = OnceLock::new();
    LIVE.get_or_init(|| Mutex::new(HashSet::new()))
}

fn live_states() -> &'static Mutex<HashSet<usize>> {
    static LIVE: OnceLock<Mutex<HashSet<usize>>> = OnceLock::new();
    LIVE.get_or_init(|| Mutex::new(HashSet::new()))
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
        if allowed.contains(&self.phase) {
            Ok(())
        } else {
            Err(format!(
                "{call} is not allowed in the {:?} state of the FMU",
                self.phase
            ))
        }
    }

    fn scene_path(&self) -> Result<PathBuf, Failure> {
        let rel = Path::new(&self.vars.scene);
        if rel.is_absolute()
            || rel
                .components()
                .any(|c| matches!(c, std::path::Component::ParentDir))
        {
            return Err(format!(
                "parameter scene = \"{}\" must be a path inside the FMU's resources folder",
                self.vars.scene
            ));
        }
        Ok(self.resources.join(rel))
    }

    /// The specimen's scene: the `scene` parameter's file with `seed`, no VTK and no series
    /// rows (the host reads the outputs).
    fn scene(&self, seed: i32) -> Result<fractum::Scene, Failure> {
        let overrides = vec![
            format!("seed={seed}"),
            "output.vtk=0".to_string(),
            "output.every=1000000000".to_string(),
        ];
        fractum::Scene::load(&self.scene_path()?, &overrides).map_err(|e| e.to_string())
    }

    fn build(&mut self) -> Result<(), Failure> {
        for (name, d) in [
            ("specimen_diameter", self.vars.specimen_diameter),
            ("bar_diameter", self.vars.bar_diameter),
        ] {
            if !(d.is_finite() && d > 0.0) {
                return Err(format!(
                    "parameter {name} = {d} is outside the allowed range (0, inf) m"
                ));
            }
        }
        let scene = self.scene(self.vars.seed)?;
        let mut sim = Simulation::new(scene, 1, &mut |_| {}).map_err(|e| e.to_string())?;
        sim.set_face_speeds(self.vars.v_incident, -self.vars.v_transmitted)
            .map_err(|e| e.to_string())?;
        self.sim = Some(sim);
        Ok(())
    }

    fn real(&self, r: u32) -> Result<f64, Failure> {
        let v = &self.vars;
        let area = |d: f64| std::f64::consts::PI * d * d / 4.0;
        let (top, bottom) = self.sim.as_ref().map_or((0.0, 0.0), |s| s.face_stresses());
        Ok(match r {
            vr::V_INCIDENT => v.v_incident,
            vr::V_TRANSMITTED => v.v_transmitted,
            vr::SPECIMEN_DIAMETER => v.specimen_diameter,
            vr::BAR_DIAMETER => v.bar_diameter,
            vr::STRESS_INCIDENT => top,
            vr::STRESS_TRANSMITTED => bottom,
            vr::FORCE_INCIDENT => top * area(v.specimen_diameter),
            vr::FORCE_TRANSMITTED => bottom * area(v.specimen_diameter),
            vr::BAR_STRESS_INCIDENT => top * area(v.specimen_diameter) / area(v.bar_diameter),
            vr::BAR_STRESS_TRANSMITTED => bottom * area(v.specimen_diameter) / area(v.bar_diameter),
            vr::STRAIN => self.sim.as_ref().map_or(0.0, |s| s.axial_strain()),
            vr::KINETIC_ENERGY => self.sim.as_ref().map_or(0.0, |s| s.bodies.kinetic_energy()),
            _ => return Err(format!("{r} is not the value reference of a Real variable")),
        })
    }

    fn set_real(&mut self, r: u32, value: f64) -> Result<(), Failure> {
        if !value.is_finite() {
            return Err(format!(
                "value reference {r}: {value} is not a finite number"
            ));
        }
        let parameter_phases = [Phase::Instantiated, Phase::Initialization];
        match r {
            vr::V_INCIDENT => self.vars.v_incident = value,
            vr::V_TRANSMITTED => self.vars.v_transmitted = value,
            vr::SPECIMEN_DIAMETER | vr::BAR_DIAMETER => {
                self.expect(&parameter_phases, "setting a parameter")?;
                if r == vr::SPECIMEN_DIAMETER {
                    self.vars.specimen_diameter = value;
                } else {
                    self.vars.bar_diameter = value;
                }
            }
            _ => {
                return Err(format!(
                    "{r} is not the value reference of a settable Real variable"
                ));
            }
        }
        if let Some(sim) = &mut self.sim {
            sim.set_face_speeds(self.vars.v_incident, -self.vars.v_transmitted)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    fn save(&self) -> Saved {
        Saved {
            phase: self.phase,
            vars: self.vars.clone(),
            sim: self.sim.as_ref().map(|s| s.save_state()),
        }
    }

    fn restore(&mut self, saved: &Saved) -> Result<(), Failure> {
        self.sim = match (&saved.sim, &self.sim) {
            (None, _) => None,
            (Some(bytes), Some(current)) => Some(
                Simulation::restore(current.scene.clone(), bytes, 1).map_err(|e| e.to_string())?,
            ),
            (Some(bytes), None) => Some(
                Simulation::restore(self.scene(saved.vars.seed)?, bytes, 1)
                    .map_err(|e| e.to_string())?,
            ),
        };
        self.phase = saved.phase;
        self.vars = saved.vars.clone();
        Ok(())
    }
}

/// Runs `f` on the instance `c`, catching panics and reporting failures to the logger.
fn with_instance(
    c: fmi2Component,
    call: &str,
    f: impl FnOnce(&mut Instance) -> Result<fmi2Status, Failure>,
) -> fmi2Status {
    if c.is_null() {
        return fmi2Status_fmi2Error;
    }
    let known = live()
        .lock()
        .map(|l| l.contains(&(c as usize)))
        .unwrap_or(false);
    if !known {
        return fmi2Status_fmi2Error;
    }
    // SAFETY: `c` is a live instance created by fmi2Instantiate (checked above).
    let inst = unsafe { &mut *(c as *mut Instance) };
    match catch_unwind(AssertUnwindSafe(|| f(inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            inst.log(
                fmi2Status_fmi2Error,
                "logStatusError",
                &format!("{call}: {message}"),
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
        let name = c_str(instance_name).unwrap_or_else(|| "fractum_shpb".to_string());
        let mut inst = Instance {
            name: CString::new(name.replace('\0', " ")).unwrap_or_default(),
            logger: callbacks.and_then(|c| c.logger),
            environment: callbacks.map_or(std::ptr::null_mut(), |c| c.componentEnvironment),
            logging: logging_on != 0,
            resources: PathBuf::new(),
            phase: Phase::Instantiated,
            vars: Variables::default(),
            sim: None,
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
            Some(g) if g == GUID => {}
            g => {
                return fail(
                    &inst,
                    format!("GUID {g:?} does not match this FMU's {GUID}"),
                );
            }
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
        let ptr = Box::into_raw(Box::new(inst)) as fmi2Component;
        if let Ok(mut l) = live().lock() {
            l.insert(ptr as usize);
        }
        ptr
    }));
    result.unwrap_or(std::ptr::null_mut())
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let removed = live()
            .lock()
            .map(|mut l| l.remove(&(c as usize)))
            .unwrap_or(false);
        if removed {
            // SAFETY: `c` was created by Box::into_raw in fmi2Instantiate and is freed once.
            drop(unsafe { Box::from_raw(c as *mut Instance) });
        }
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
        i.vars.time = start_time;
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
        i.build()?;
        if i.logging {
            let n = i.sim.as_ref().map_or(0, |s| s.bodies.len());
            i.log(
                fmi2Status_fmi2OK,
                "logAll",
                &format!("specimen built: {n} grains"),
            );
        }
        i.phase = Phase::Running;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Terminate", |i| {
        i.expect(&[Phase::Running], "fmi2Terminate")?;
        i.phase = Phase::Terminated;
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Reset", |i| {
        i.sim = None;
        i.vars = Variables::default();
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
            *v = i.real(*r)?;
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
            *v = match *r {
                vr::SEED => i.vars.seed,
                vr::BROKEN_PARTICLES => i.sim.as_ref().map_or(0, |s| s.broken_particles() as c_int),
                _ => {
                    return Err(format!(
                        "{r} is not the value reference of an Integer variable"
                    ));
                }
            };
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    _vrs: *const fmi2ValueReference,
    n: usize,
    _values: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2GetBoolean", |_| {
        if n == 0 {
            Ok(fmi2Status_fmi2OK)
        } else {
            Err("this FMU has no Boolean variables".to_string())
        }
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
            if *r != vr::SCENE {
                return Err(format!(
                    "{r} is not the value reference of a String variable"
                ));
            }
            // The string lives in the instance until the next call that changes it.
            static SCENE_STRINGS: OnceLock<Mutex<Vec<CString>>> = OnceLock::new();
            let s = CString::new(i.vars.scene.clone()).unwrap_or_default();
            let ptr = s.as_ptr();
            let store = SCENE_STRINGS.get_or_init(|| Mutex::new(Vec::new()));
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
        i.expect(
            &[Phase::Instantiated, Phase::Initialization, Phase::Running],
            "fmi2SetReal",
        )?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            i.set_real(*r, *v)?;
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
        i.expect(
            &[Phase::Instantiated, Phase::Initialization],
            "fmi2SetInteger",
        )?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            match *r {
                vr::SEED if *v >= 0 => i.vars.seed = *v,
                vr::SEED => {
                    return Err(format!(
                        "parameter seed = {v} is outside the allowed range [0, inf)"
                    ));
                }
                _ => {
                    return Err(format!(
                        "{r} is not the value reference of a settable Integer variable"
                    ));
                }
            }
        }
        Ok(fmi2Status_fmi2OK)
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    _vrs: *const fmi2ValueReference,
    n: usize,
    _values: *const fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2SetBoolean", |_| {
        if n == 0 {
            Ok(fmi2Status_fmi2OK)
        } else {
            Err("this FMU has no Boolean variables".to_string())
        }
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
        i.expect(
            &[Phase::Instantiated, Phase::Initialization],
            "fmi2SetString",
        )?;
        let (vrs, values) = slices(vrs, n, values)?;
        for (r, v) in vrs.iter().zip(values) {
            if *r != vr::SCENE {
                return Err(format!(
                    "{r} is not the value reference of a String variable"
                ));
            }
            i.vars.scene = c_str(*v).ok_or("the scene string is a null pointer")?;
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
        let fresh = Box::into_raw(Box::new(i.save())) as fmi2FMUstate;
        let mut l = live_states()
            .lock()
            .map_err(|_| "state registry poisoned".to_string())?;
        if !old.is_null() && l.remove(&(old as usize)) {
            // SAFETY: `old` is a state created here and still live.
            drop(unsafe { Box::from_raw(old as *mut Saved) });
        }
        l.insert(fresh as usize);
        // SAFETY: checked non-null.
        unsafe { *state = fresh };
        Ok(fmi2Status_fmi2OK)
    })
}

fn saved_of<'a>(state: fmi2FMUstate) -> Result<&'a Saved, Failure> {
    let known = live_states()
        .lock()
        .map(|l| l.contains(&(state as usize)))
        .unwrap_or(false);
    if state.is_null() || !known {
        return Err("the FMU state is null, freed or not from this FMU".to_string());
    }
    // SAFETY: a live state created by fmi2GetFMUstate or fmi2DeSerializeFMUstate.
    Ok(unsafe { &*(state as *const Saved) })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2SetFMUstate", |i| {
        let saved = saved_of(state)?;
        i.restore(saved)?;
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
            .map(|mut l| l.remove(&(s as usize)))
            .unwrap_or(false);
        if !removed {
            return Err("the FMU state is not from this FMU or already freed".to_string());
        }
        // SAFETY: a live state created here, freed once.
        drop(unsafe { Box::from_raw(s as *mut Saved) });
        // SAFETY: checked non-null.
        unsafe { *state = std::ptr::null_mut() };
        Ok(fmi2Status_fmi2OK)
    })
}

fn serialize(saved: &Saved) -> Vec<u8> {
    postcard::to_stdvec(saved).expect("FMU state serialises")
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
        unsafe { *size = serialize(saved).len() };
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
        let data = serialize(saved_of(state)?);
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
        let saved: Saved = postcard::from_bytes(data)
            .map_err(|e| format!("the serialized FMU state is damaged ({e})"))?;
        let fresh = Box::into_raw(Box::new(saved)) as fmi2FMUstate;
        live_states()
            .lock()
            .map_err(|_| "state registry poisoned".to_string())?
            .insert(fresh as usize);
        // SAFETY: checked non-null.
        unsafe { *state = fresh };
        Ok(fmi2Status_fmi2OK)
    })
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
        if !(h > 0.0 && h.is_finite()) {
            return Err(format!("the communication step {h} must be positive"));
        }
        let now = i.vars.time;
        if (current - now).abs() > 1e-9 * h.max(now.abs()) {
            return Err(format!(
                "the step starts at t = {current:e} s but the FMU is at t = {now:e} s"
            ));
        }
        let sim = i
            .sim
            .as_mut()
            .ok_or("no specimen: initialisation did not finish")?;
        // The specimen's own clock starts at 0 when the experiment starts.
        let target = (current + h) - (now - sim.time);
        if let Err(e) = sim.advance_to(target) {
            i.phase = Phase::Failed;
            return Err(e.to_string());
        }
        i.vars.time = current + h;
        Ok(fmi2Status_fmi2OK)
    })
}

fn unsupported(c: fmi2Component, call: &str) -> fmi2Status {
    with_instance(c, call, |_| {
        Err("is not supported by this co-simulation FMU".to_string())
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsupported(c, "fmi2CancelStep (steps are synchronous)")
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
            unsafe { *v = i.vars.time };
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
}
