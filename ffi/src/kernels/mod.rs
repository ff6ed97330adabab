//! Kernel exports: the per-contact and per-grain functions of Fractum's granular model, for
//! hosts that keep their own particles (a LAMMPS plugin). Each one wraps the library
//! function that Fractum's own run calls (`fractum::contact::pair::pair_contact`,
//! `fractum::fracture::split_grain`, ...), so a host gets the same bits Fractum computes.
//!
//! Every kernel returns a `FractumStatus`: `FRACTUM_ERR_NULL` on a null pointer,
//! `FRACTUM_ERR_INPUT` on an argument the library cannot take (a poly-ellipsoid's semi-axis
//! that is not finite and positive, in any `FractumBody` passed; a count out of range),
//! `FRACTUM_ERR_INTERNAL` on a caught panic. They write their results through out pointers,
//! keep no state, hand nothing to free (split and bond use the library's temporary buffers
//! inside the call), and leave the last-error message of the handle API alone (they are
//! called per contact). Quaternions are `w x y z` and are taken as given (not
//! renormalised); 3x3 matrices are row-major. A `FractumBody`'s inverse mass and moments
//! are taken as 1/m, which is how Fractum's bodies hold them.

use std::panic::{AssertUnwindSafe, catch_unwind};

use fractum::shape::{PolyEllipsoid, Shape};
use fractum::state::{Body, Vec3};

use crate::FractumStatus::{self, *};

#[macro_use]
mod variants;

mod contact;
mod convert;
mod fracture;
mod integrate;
mod sums;
mod types;

pub use contact::*;
pub(crate) use convert::grain_load_row;
use convert::*;
pub use fracture::*;
pub use integrate::*;
pub use sums::*;
pub use types::*;

type KResult = Result<(), FractumStatus>;

/// Runs a kernel: its error as the status, a panic as FRACTUM_ERR_INTERNAL. The last-error
/// message is not touched.
fn kernel(f: impl FnOnce() -> KResult) -> FractumStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => FRACTUM_OK,
        Ok(Err(status)) => status,
        Err(_) => FRACTUM_ERR_INTERNAL,
    }
}

/// A NUL-terminated UTF-8 string argument.
fn c_str<'a>(p: *const std::ffi::c_char) -> Result<&'a str, FractumStatus> {
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: a non-null pointer from the caller is a NUL-terminated string (documented).
    unsafe { std::ffi::CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| FRACTUM_ERR_INPUT)
}

fn input_if(bad: bool) -> KResult {
    if bad { Err(FRACTUM_ERR_INPUT) } else { Ok(()) }
}

fn get<'a, T>(p: *const T) -> Result<&'a T, FractumStatus> {
    // SAFETY: a non-null pointer from the caller points to a valid T (documented).
    unsafe { p.as_ref() }.ok_or(FRACTUM_ERR_NULL)
}

fn get_mut<'a, T>(p: *mut T) -> Result<&'a mut T, FractumStatus> {
    // SAFETY: as `get`, and the caller does not alias it during the call.
    unsafe { p.as_mut() }.ok_or(FRACTUM_ERR_NULL)
}

/// The `N` doubles at `p`.
fn doubles<'a, const N: usize>(p: *const f64) -> Result<&'a [f64; N], FractumStatus> {
    get(p.cast::<[f64; N]>())
}

fn doubles_mut<'a, const N: usize>(p: *mut f64) -> Result<&'a mut [f64; N], FractumStatus> {
    get_mut(p.cast::<[f64; N]>())
}

fn vec3_at(p: *const f64) -> Result<Vec3, FractumStatus> {
    Ok(Vec3::from(*doubles::<3>(p)?))
}

/// `n` points of 3 doubles (null allowed when `n` is 0), without copying.
fn points<'a>(p: *const [f64; 3], n: usize) -> Result<&'a [Vec3], FractumStatus> {
    const _: () = assert!(std::mem::size_of::<Vec3>() == std::mem::size_of::<[f64; 3]>());
    const _: () = assert!(std::mem::align_of::<Vec3>() == std::mem::align_of::<[f64; 3]>());
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes n points; nalgebra's Vector3<f64> is a #[repr(C)] matrix over
    // a #[repr(transparent)] [[f64; 3]; 1], the layout of [f64; 3] (size and alignment
    // checked above).
    Ok(unsafe { std::slice::from_raw_parts(p.cast::<Vec3>(), n) })
}

/// The caller's `n` elements at `p`, read only (null allowed when `n` is 0).
fn slice_in<'a, T>(p: *const T, n: usize) -> Result<&'a [T], FractumStatus> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes n elements, not written during the call.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// The caller's `n` elements at `p` (null allowed when `n` is 0).
fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], FractumStatus> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(FRACTUM_ERR_NULL);
    }
    // SAFETY: the caller passes room for n elements, not aliased during the call.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// The `N` doubles a host's row pointer points to (a row of a `double **` table).
///
/// # Safety
/// `p` points to at least `N` doubles, not written during the borrow.
unsafe fn row<'a, const N: usize>(p: *const f64) -> &'a [f64; N] {
    // SAFETY: as the function's contract.
    unsafe { &*p.cast::<[f64; N]>() }
}

/// The `N` doubles a host's row pointer points to, to write.
///
/// # Safety
/// `p` points to at least `N` doubles, not otherwise referenced during the borrow.
unsafe fn row_mut<'a, const N: usize>(p: *mut f64) -> &'a mut [f64; N] {
    // SAFETY: as the function's contract.
    unsafe { &mut *p.cast::<[f64; N]>() }
}

/// The library's body from a FractumBody: the inverse mass and moments as the library makes
/// them (1/m); a poly-ellipsoid's semi-axes checked.
#[inline(always)]
fn body_in(b: &FractumBody) -> Result<Body, FractumStatus> {
    let shape = if b.sphere != 0 {
        Shape::Sphere
    } else {
        Shape::PolyEllipsoid {
            pe: PolyEllipsoid::new(b.semi).map_err(|_| FRACTUM_ERR_INPUT)?,
            origin: Vec3::from(b.origin),
            to_body: quat(&b.to_body),
        }
    };
    // Field by field rather than through Body::rigid (at rest, then moving): this runs for
    // every body of every evaluation, and the plugin's window measured 2% slower that way.
    let inertia = Vec3::from(b.inertia);
    Ok(Body {
        pos: Vec3::from(b.pos),
        vel: Vec3::from(b.vel),
        omega: Vec3::from(b.omega),
        orientation: quat(&b.quat),
        radius: b.radius,
        mass: b.mass,
        inv_mass: 1.0 / b.mass,
        inertia,
        inv_inertia: inertia.map(|m| 1.0 / m),
        shape,
    })
}

/// A grain to split: a body whose radius and mass are finite and positive. A zero-radius
/// sphere split into zero semi-axes and panicked where the halves are built.
fn grain_in(b: &FractumBody) -> Result<Body, FractumStatus> {
    let sized = |x: f64| x.is_finite() && x > 0.0;
    input_if(!(sized(b.radius) && sized(b.mass)))?;
    body_in(b)
}
