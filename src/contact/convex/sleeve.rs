//! Contact of a body with the inside of the sleeve, a rigid circular cylinder along z: the
//! point farthest from its axis, the overlap and normal there, and the Hertz radius with the
//! cylinder's concave curvature.

use nalgebra::Vector3;

use super::{ContactGeometry, ConvexShape, Placed, Probe, at_most_zero};
use crate::shape::poly_ellipsoid::PolyEllipsoid;

/// The Hertz equivalent radius (m) of a body against the inside of a cylinder of radius
/// `radius` (m), from the body's tensor of principal radii of curvature at the contact point
/// (the support Hessian on the tangent plane), of determinant `det_h` (m²), whose component
/// along the cylinder's hoop direction is `h_hoop` (m).
///
/// The relative curvature is the body's `H⁻¹` plus the concave cylinder's `-1/R` along the
/// hoop (0 along the axis); its determinant is `(1 - h_hoop/R) / det H`, so
/// `r_eff = sqrt(det H / (1 - h_hoop/R))`: for a sphere of radius r, `r / sqrt(1 - r/R)`. A
/// body as flat as the sleeve along the hoop (`h_hoop >= R`) meets it over a band, not at a
/// point, and Hertz's law no longer holds: the radius is then taken as the sleeve's, as it is
/// wherever the formula would exceed it (a sphere above 0.62 R; the scene refuses sleeves
/// narrower than two of its largest grains).
#[inline]
pub fn sleeve_hertz_radius(det_h: f64, h_hoop: f64, radius: f64) -> f64 {
    let f = 1.0 - h_hoop / radius;
    if f > 0.0 {
        (det_h / f).sqrt().min(radius)
    } else {
        radius
    }
}

/// Newton steps of [`sleeve_contact`]'s search at most (per start).
pub const SLEEVE_ITERATIONS: u32 = 30;

/// The point of a poly-ellipsoid farthest from the sleeve's axis found from the horizontal
/// direction `e` (unit, across the axis): see [`sleeve_contact`].
struct Farthest {
    /// The radial direction there, and the hoop direction `z × e`.
    e: Vector3<f64>,
    hoop: Vector3<f64>,
    point: Vector3<f64>,
    probe: Probe,
    /// Its distance from the axis (m), and A's radius of curvature round the hoop there (m).
    rho: f64,
    h_hoop: f64,
    iterations: u32,
}

/// Newton's method on `f(θ) = h_A(e(θ)) − c·e(θ)`, the extent of A from the axis along the
/// horizontal direction `e(θ)`: `f' = (s − c)·t` (t the hoop direction, s the support point)
/// and `f'' = h_hoop − (s − c)·e`, negative at a maximum of a grain more curved round the hoop
/// than its distance from the axis; where it is not, an ascent step `f'/ρ` (the fixed point
/// `e ← radial(s)/|radial(s)|`). Stops when the step is below 1e-12 rad.
fn farthest_from_axis(
    pe: &PolyEllipsoid,
    a: &Placed,
    centre: &Vector3<f64>,
    start: Vector3<f64>,
) -> Farthest {
    let mut e = start;
    let mut iterations = 0;
    loop {
        let hoop = Vector3::z().cross(&e);
        let probe = pe.support_at(&a.rot.tr_mul(&e));
        let point = a.origin + a.rot * probe.point;
        let d = point - centre;
        let (g, rho) = (d.dot(&hoop), d.dot(&e));
        let t = a.rot.tr_mul(&hoop);
        let h_hoop = probe.tangent_hessian(&t, &t)[0];
        let curvature = rho - h_hoop;
        let step = if curvature > 0.0 {
            g / curvature
        } else {
            g / rho.abs().max(f64::MIN_POSITIVE)
        };
        let step = step.clamp(-0.5, 0.5);
        if step.abs() <= 1e-12 || step.is_nan() || iterations >= SLEEVE_ITERATIONS {
            return Farthest {
                e,
                hoop,
                point,
                probe,
                rho: Vector3::new(d.x, d.y, 0.0).norm(),
                h_hoop,
                iterations,
            };
        }
        let (sin, cos) = step.sin_cos();
        e = (e * cos + hoop * sin).normalize();
        iterations += 1;
    }
}

/// Contact of body A with the inside of a rigid circular cylinder (a sleeve) of radius
/// `radius` whose axis runs along z through `centre`, or `None` when A is clear of it.
///
/// The deepest point of A is the one farthest from the axis. Every point's distance from the
/// axis is its largest extent along a horizontal direction, so the farthest distance is the
/// largest over the horizontal directions `e(θ)` of A's extent from the axis along them,
/// `f(θ) = h_A(e) − c·e`: a search over one angle, by Newton's method from the centroid's
/// radial direction (`farthest_from_axis`; quadratic, a few steps). There A's normal is `e`,
/// the overlap is the point's distance from the axis less R, the normal `-e` (towards the
/// axis), `point_b` the foot on the cylinder, and the Hertz radius [`sleeve_hertz_radius`] of
/// A's curvature there (axis and hoop as tangents). Where A is at least as flat round the hoop
/// as its distance from the axis (a conformal contact; `f'' >= 0`), the extremum found may be
/// a minimum between two farther points: the search is then also started a grain's half-length
/// either side, and the farthest point found kept. A sphere is closed form.
pub fn sleeve_contact(a: &Placed, centre: &Vector3<f64>, radius: f64) -> Option<ContactGeometry> {
    let radial = |x: &Vector3<f64>| Vector3::new(x.x - centre.x, x.y - centre.y, 0.0);
    let (e, point_a, rho, r_eff, iterations) = match a.shape {
        ConvexShape::Sphere { radius: r } => {
            let d = radial(&a.origin);
            let rho = d.norm();
            if at_most_zero(rho) {
                // On the axis (or not finite): in a sleeve wider than the sphere, clear of it.
                return None;
            }
            let e = d / rho;
            let r_eff = sleeve_hertz_radius(r * r, r, radius);
            (e, a.origin + e * r, rho + r, r_eff, 0)
        }
        ConvexShape::PolyEllipsoid(pe) => {
            let d = radial(&a.centroid());
            let rho_c = d.norm();
            if !rho_c.is_finite() {
                return None;
            }
            let start = if rho_c > 0.0 { d / rho_c } else { Vector3::x() };
            let mut best = farthest_from_axis(pe, a, centre, start);
            if best.h_hoop >= best.rho {
                let half = pe.semi.iter().copied().fold(0.0, f64::max);
                let angle = (half / best.rho.max(half)).asin();
                let hoop = Vector3::z().cross(&start);
                for side in [-1.0, 1.0] {
                    let (sin, cos) = (side * angle).sin_cos();
                    let other = farthest_from_axis(pe, a, centre, start * cos + hoop * sin);
                    if other.rho > best.rho {
                        best = Farthest {
                            iterations: best.iterations + other.iterations,
                            ..other
                        };
                    }
                }
            }
            if at_most_zero(best.rho - radius) {
                return None;
            }
            // The curvature at the support point of `e`: tangents along the axis and the hoop.
            let axis = a.rot.tr_mul(&Vector3::z());
            let hoop = a.rot.tr_mul(&best.hoop);
            let h = best.probe.tangent_hessian(&axis, &hoop);
            let det = h[0] * h[2] - h[1] * h[1];
            (
                best.e,
                best.point,
                best.rho,
                sleeve_hertz_radius(det, h[2], radius),
                best.iterations,
            )
        }
    };
    let depth = rho - radius;
    if at_most_zero(depth) {
        return None;
    }
    let normal = -e;
    let point_b = point_a + depth * normal;
    Some(ContactGeometry {
        normal,
        depth,
        point: 0.5 * (point_a + point_b),
        point_a,
        point_b,
        r_eff,
        iterations,
    })
}
