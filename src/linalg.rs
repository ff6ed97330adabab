//! Small dense linear algebra in closed form, shared by the floors above: the eigenvalues of a
//! symmetric 3×3 matrix (the fracture criteria's principal stresses, the contact records'
//! frequency bound).

use nalgebra::Matrix3;

/// The eigenvalues of the symmetric 3×3 `a` (its upper triangle is read), largest first, in
/// closed form (the trigonometric solution of the characteristic cubic).
pub fn symmetric3_eigenvalues(a: &Matrix3<f64>) -> [f64; 3] {
    match trigonometric_form(a) {
        Err(q) => [q; 3],
        Ok((q, p, phi)) => {
            let s1 = q + 2.0 * p * phi.cos();
            let s3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
            [s1, 3.0 * q - s1 - s3, s3]
        }
    }
}

/// The largest eigenvalue of the symmetric 3×3 `a`: `symmetric3_eigenvalues(a)[0]`, the same
/// bits, without the third root's cosine (the frequency bound of the step adaptation, after
/// every step, needs only this one).
pub fn symmetric3_largest_eigenvalue(a: &Matrix3<f64>) -> f64 {
    match trigonometric_form(a) {
        Err(q) => q,
        Ok((q, p, phi)) => q + 2.0 * p * phi.cos(),
    }
}

/// The mean `q`, the deviatoric scale `p` and the angle `phi` of the eigenvalues
/// `q + 2 p cos(phi + 2πk/3)` of the symmetric `a`; `Err(q)` when `a` is isotropic to rounding
/// (all three equal `q`).
#[inline]
fn trigonometric_form(a: &Matrix3<f64>) -> std::result::Result<(f64, f64, f64), f64> {
    let p1 = a.m12 * a.m12 + a.m13 * a.m13 + a.m23 * a.m23;
    let q = a.trace() / 3.0;
    let p2 = (a.m11 - q).powi(2) + (a.m22 - q).powi(2) + (a.m33 - q).powi(2) + 2.0 * p1;
    if p2 <= 1e-30 * q * q || p2 == 0.0 {
        return Err(q);
    }
    let p = (p2 / 6.0).sqrt();
    let b = (a - Matrix3::identity() * q) / p;
    let r = (0.5 * b.determinant()).clamp(-1.0, 1.0);
    Ok((q, p, r.acos() / 3.0))
}
