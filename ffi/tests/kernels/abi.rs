//! The exports as a C host reaches them: each looked up by its C name in the libfractum.so
//! built from the current sources (`common::profile_dir`), then called through a pointer of
//! the signature include/fractum.h declares. The library is a cdylib only, so these tests
//! cannot link it as a Rust crate.

#![allow(clippy::too_many_arguments)]

use std::ffi::{CString, c_char, c_int, c_void};
use std::os::unix::ffi::OsStrExt;
use std::sync::OnceLock;

use crate::common;
use crate::status::FractumStatus;
use crate::types::*;

unsafe extern "C" {
    fn dlopen(file: *const c_char, mode: c_int) -> *mut c_void;
    fn dlsym(handle: *mut c_void, name: *const c_char) -> *mut c_void;
}

/// dlopen's flag: resolve every symbol now.
const RTLD_NOW: c_int = 2;

/// The address of export `name` in the freshly built libfractum.so.
fn symbol(name: &str) -> usize {
    static LIBRARY: OnceLock<usize> = OnceLock::new();
    let library = *LIBRARY.get_or_init(|| {
        let path = common::profile_dir().join("libfractum.so");
        let path = CString::new(path.as_os_str().as_bytes()).unwrap();
        // SAFETY: a NUL-terminated path; the library stays loaded for the whole process.
        let handle = unsafe { dlopen(path.as_ptr(), RTLD_NOW) };
        assert!(!handle.is_null(), "libfractum.so loads");
        handle as usize
    });
    let c_name = CString::new(name).unwrap();
    // SAFETY: a handle dlopen returned and a NUL-terminated name.
    let address = unsafe { dlsym(library as *mut c_void, c_name.as_ptr()) };
    assert!(!address.is_null(), "libfractum.so exports {name}");
    address as usize
}

/// A function of each export's name and signature that calls the export.
macro_rules! exports {
    ($(fn $name:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty;)*) => {$(
        pub fn $name($($arg: $ty),*) -> $ret {
            static ADDRESS: OnceLock<usize> = OnceLock::new();
            let address = *ADDRESS.get_or_init(|| symbol(stringify!($name)));
            // SAFETY: the export of this name has this signature (include/fractum.h).
            let f: extern "C" fn($($ty),*) -> $ret = unsafe { std::mem::transmute(address) };
            f($($arg),*)
        }
    )*};
}

exports! {
    fn fractum_free(handle: u64) -> FractumStatus;
    fn fractum_last_error() -> *const c_char;
    fn fractum_kernel_contact_law(young: f64, poisson: f64, restitution: f64, mu: f64, damping: i32, friction: i32, out: *mut FractumContactLaw) -> FractumStatus;
    fn fractum_kernel_hertz_mindlin(law: *const FractumContactLaw, n: *const f64, delta: f64, r_eff: f64, m_eff: f64, v: *const f64, hist: *mut f64, dt: f64, update: i32, out: *mut FractumContact) -> FractumStatus;
    fn fractum_kernel_convex_contact(a: *const FractumBody, b: *const FractumBody, guess: *const f64, out: *mut FractumGeometry) -> FractumStatus;
    fn fractum_kernel_wall_geometry(a: *const FractumBody, wall_normal: *const f64, wall_point: *const f64, out: *mut FractumGeometry) -> FractumStatus;
    fn fractum_kernel_pair(law: *const FractumContactLaw, a: *const FractumBody, b: *const FractumBody, memory: *mut FractumPairMemory, dt: f64, update: i32, shapes: i32, out: *mut FractumContact) -> FractumStatus;
    fn fractum_kernel_pair_placed(law: *const FractumContactLaw, a: *const FractumBody, pa: *const FractumPlacement, b: *const FractumBody, pb: *const FractumPlacement, memory: *mut FractumPairMemory, dt: f64, update: i32, shapes: i32, out: *mut FractumContact) -> FractumStatus;
    fn fractum_kernel_placement(b: *const FractumBody, out: *mut FractumPlacement) -> FractumStatus;
    fn fractum_kernel_travel(before: *const FractumBody, after: *const FractumBody, travel: *mut f64) -> FractumStatus;
    fn fractum_kernel_pair_row(law: *const FractumContactLaw, bodies: *const FractumBody, places: *const FractumPlacement, keys: *const i64, travel: *const f64, n_bodies: i32, i: i32, partners: *const i32, n: i32, index_mask: i32, memory: *mut f64, stride: i32, dt: f64, update: i32, shapes: i32, kept: *mut i32, out: *mut FractumContact, at: *mut i32, n_out: *mut i32) -> FractumStatus;
    fn fractum_kernel_pair_list(law: *const FractumContactLaw, bodies: *const FractumBody, places: *const FractumPlacement, keys: *const i64, travel: *const f64, n_bodies: i32, n_local: i32, list: *const FractumNeighbours, keep: i32, reshaped: *const i64, n_reshaped: usize, dt: f64, update: i32, shapes: i32, shares: i32, touching: *mut FractumTouching, capacity: usize, n_touching: *mut usize, sides: *mut i32, n_sides: *mut usize, energy: *mut f64) -> FractumStatus;
    fn fractum_kernel_wall(law: *const FractumContactLaw, a: *const FractumBody, wall_normal: *const f64, wall_point: *const f64, wall_velocity: *const f64, memory: *mut FractumPairMemory, dt: f64, update: i32, shapes: i32, out: *mut FractumContact) -> FractumStatus;
    fn fractum_kernel_poly_ellipsoid_body(semi: *const f64, mass: f64, centroid: *const f64, shape_quat: *const f64, out: *mut FractumBody) -> FractumStatus;
    fn fractum_kernel_body_volume(b: *const FractumBody, volume: *mut f64) -> FractumStatus;
    fn fractum_kernel_average_stress(b: *const FractumBody, moment: *const f64, torque: *const f64, stress: *mut f64) -> FractumStatus;
    fn fractum_kernel_principal_compressions(stress: *const f64, out: *mut f64) -> FractumStatus;
    fn fractum_kernel_hoek_brown_fails(s1: f64, s3: f64, sigma_c: f64, mi: f64, fails: *mut i32) -> FractumStatus;
    fn fractum_kernel_contact_tensile_stress(normal_force: f64, contact_radius: f64, poisson: f64, stress: *mut f64) -> FractumStatus;
    fn fractum_kernel_weibull_factor(p: f64, w: f64, x: f64, x_m: f64, factor: *mut f64) -> FractumStatus;
    fn fractum_kernel_contacts_plane_normal(points: *const [f64; 3], n: usize, normal: *mut f64, found: *mut i32) -> FractumStatus;
    fn fractum_kernel_check(law: *const FractumFractureLaw, b: *const FractumBody, strength: f64, moment: *const f64, torque: *const f64, n_critical: usize, critical_points: *const [f64; 3], top_stress: f64, out: *mut FractumTrigger) -> FractumStatus;
    fn fractum_kernel_fracture_range(key: *const c_char, lo: *mut f64, hi: *mut f64) -> FractumStatus;
    fn fractum_kernel_grain_load_add(load: *mut FractumGrainLoad, centre: *const f64, force: *const f64, point: *const f64, hertz_force: f64, radius: f64, poisson: f64, threshold: f64) -> FractumStatus;
    fn fractum_kernel_grain_strength(seed: u64, grain: u64, generation: u32, b: *const FractumBody, w: f64, x_m: f64, factor: *mut f64) -> FractumStatus;
    fn fractum_kernel_grain_strength_sized(seed: u64, grain: u64, generation: u32, b: *const FractumBody, w: f64, beta: f64, x_m: f64, factor: *mut f64) -> FractumStatus;
    fn fractum_kernel_grain_jitter(seed: u64, grain: u64, generation: u32, angles: *mut f64) -> FractumStatus;
    fn fractum_kernel_split(law: *const FractumFractureLaw, parent: *const FractumBody, force: *const f64, torque: *const f64, trigger: *const FractumTrigger, jitter: *const f64, out: *mut FractumSplit) -> FractumStatus;
    fn fractum_kernel_jitter_angles(u: *const f64, angles: *mut f64) -> FractumStatus;
    fn fractum_kernel_uniforms(seed: u64, key: u64, counter: u64, n: usize, out: *mut f64) -> FractumStatus;
    fn fractum_kernel_bond(law: *const FractumFractureLaw, a: *const FractumBody, b: *const FractumBody, force_a: *const f64, torque_a: *const f64, force_b: *const f64, torque_b: *const f64, pending: *const FractumPending, springs: *mut FractumSpring, made: *mut i32) -> FractumStatus;
    fn fractum_kernel_spring_initial_forces(points: *const [f64; 3], n: usize, demand: *const f64, forces: *mut [f64; 3]) -> FractumStatus;
    fn fractum_kernel_spring(s: *mut FractumSpring, a: *const FractumBody, b: *const FractumBody, force_a: *mut f64, torque_a: *mut f64, torque_b: *mut f64, work: *mut f64, broke: *mut i32) -> FractumStatus;
    fn fractum_kernel_can_break(b: *const FractumBody, can: *mut i32) -> FractumStatus;
    fn fractum_kernel_cohesive_energy(toughness: f64, young: f64, poisson: f64, gc: *mut f64) -> FractumStatus;
    fn fractum_kernel_kick_drift(b: *mut FractumBody, force: *const f64, torque: *const f64, dt: f64) -> FractumStatus;
    fn fractum_kernel_frequency_share(law: *const FractumContactLaw, c: *const FractumContact, a: *const FractumBody, b: *const FractumBody, share: *mut f64) -> FractumStatus;
    fn fractum_kernel_frequency_shares(law: *const FractumContactLaw, c: *const FractumContact, a: *const FractumBody, b: *const FractumBody, share_a: *mut f64, share_b: *mut f64) -> FractumStatus;
    fn fractum_kernel_adapted_step(sum: f64, dt: f64, target: f64, next: *mut f64) -> FractumStatus;
    fn fractum_kernel_step_check(sum: f64, dt: f64, omega_dt: *mut f64, verdict: *mut i32) -> FractumStatus;
    fn fractum_kernel_kick(b: *mut FractumBody, force: *const f64, torque: *const f64, dt: f64) -> FractumStatus;
    fn fractum_kernel_kick_drift_atoms(atoms: *const FractumAtomRows, dt: f64) -> FractumStatus;
    fn fractum_kernel_kick_atoms(atoms: *const FractumAtomRows, dt: f64) -> FractumStatus;
    fn fractum_kernel_sum_contacts(touching: *const FractumTouching, n_touching: usize, sides: *const i32, n_sides: usize, n_atoms: usize, force: *const *mut f64, torque: *const *mut f64, centre: *const *const f64, grain: *const *const f64, poisson: f64, sigma_f: f64, particle: i32, shares: *mut f64, loads: *mut FractumGrainLoad) -> FractumStatus;
}
