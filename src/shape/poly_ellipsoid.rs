//! Poly-ellipsoid geometry (Peters et al. 2009; paper Section 2, Eq. 1–2).
//!
//! A poly-ellipsoid is eight octants of ellipsoids glued at a common centre, the *octant
//! origin*. In its own shape frame (origin at the octant origin, axes along the principal
//! lengths) it has six semi-axis lengths `semi = [a+, a-, b+, b-, c+, c-]` along +x, -x, +y,
//! -y, +z, -z. The octant with signs (sx, sy, sz) is one eighth of the ellipsoid
//! `(x/a)² + (y/b)² + (z/c)² = 1` (Eq. 1 with x0 = y0 = z0 = 0) with `a = a_sx`, `b = b_sy`,
//! `c = c_sz` (Eq. 2). Neighbouring octants share the semi-axes that meet at their common
//! plane, so the surface is C1 and the body is convex; the curvature jumps across the three
//! coordinate planes.
//!
//! Everything here is in the shape frame and in SI units. The support function
//! `h(d) = max over the body of d·x` is the workhorse of contact detection
//! ([`crate::contact::convex`]): in the octant of `d` it is the ellipsoid's
//! `h(d) = sqrt(dᵀ M d)`, `M = diag(a², b², c²)`, with support point `s = M d / h` and
//! Hessian `(M - s sᵀ)/h`, whose restriction to the tangent plane of a unit `d` is the tensor
//! of principal radii of curvature at `s`.

use std::f64::consts::PI;

use nalgebra::{Matrix3, Rotation3, SymmetricEigen, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// A poly-ellipsoid in its shape frame (paper Eq. 1–2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PolyEllipsoid {
    /// Semi-axis lengths `[a+, a-, b+, b-, c+, c-]` (m) along +x, -x, +y, -y, +z, -z.
    pub semi: [f64; 6],
}

impl PolyEllipsoid {
    /// Checked constructor: every semi-axis length finite and positive. Cheap when they are
    /// (the C ABI's kernels check each body this way, per contact).
    #[inline]
    pub fn new(semi: [f64; 6]) -> Result<Self, String> {
        if semi.iter().all(|v| v.is_finite() && *v > 0.0) {
            Ok(PolyEllipsoid { semi })
        } else {
            Err(Self::refusal(&semi))
        }
    }

    /// The sentence for the first semi-axis that is not finite and positive.
    #[cold]
    fn refusal(semi: &[f64; 6]) -> String {
        const NAMES: [&str; 6] = ["a+", "a-", "b+", "b-", "c+", "c-"];
        let (value, name) = semi
            .iter()
            .zip(NAMES)
            .find(|(v, _)| !(v.is_finite() && **v > 0.0))
            .expect("called for a bad semi-axis");
        format!("poly-ellipsoid semi-axis {name} = {value} must be finite and > 0 (m)")
    }

    /// The sphere of radius `r` (all six semi-axes equal).
    pub fn sphere(r: f64) -> Self {
        PolyEllipsoid { semi: [r; 6] }
    }

    /// The semi-axes `(a, b, c)` of the octant that holds direction or point `d`: `a+` when
    /// `d.x >= 0`, else `a-`, and so on.
    #[inline(always)]
    pub fn octant_axes(&self, d: &Vector3<f64>) -> Vector3<f64> {
        let s = &self.semi;
        Vector3::new(
            if d.x >= 0.0 { s[0] } else { s[1] },
            if d.y >= 0.0 { s[2] } else { s[3] },
            if d.z >= 0.0 { s[4] } else { s[5] },
        )
    }

    /// Volume (m³): `V = π/6 (a+ + a-)(b+ + b-)(c+ + c-)`, the sum of the eight octants
    /// `π a b c / 6`.
    pub fn volume(&self) -> f64 {
        let s = &self.semi;
        PI / 6.0 * (s[0] + s[1]) * (s[2] + s[3]) * (s[4] + s[5])
    }

    /// Radius of the sphere of equal volume (m): `(3V / 4π)^(1/3)`.
    pub fn equivalent_radius(&self) -> f64 {
        (3.0 * self.volume() / (4.0 * PI)).cbrt()
    }

    /// Centroid relative to the octant origin (m): `x = 3/8 (a+ - a-)`, `y = 3/8 (b+ - b-)`,
    /// `z = 3/8 (c+ - c-)` (the octant of semi-axis a has its centroid at 3a/8 along x).
    pub fn centroid(&self) -> Vector3<f64> {
        let s = &self.semi;
        0.375 * Vector3::new(s[0] - s[1], s[2] - s[3], s[4] - s[5])
    }

    /// Second moment of volume about the centroid (m⁵): `S = ∫ (x - x̄)(x - x̄)ᵀ dV`.
    ///
    /// Per octant about the octant origin: `∫ x² dV = V_oct a²/5` with `V_oct = π a b c / 6`,
    /// and `∫ x y dV = sx sy a² b² c / 15` (likewise for xz and yz). Summed over the octants
    /// these factor as `S_xx = π/30 (a+³ + a-³)(b+ + b-)(c+ + c-)` and
    /// `S_xy = 1/15 (a+² - a-²)(b+² - b-²)(c+ + c-)`; the parallel-axis shift `-V x̄ x̄ᵀ`
    /// moves them to the centroid.
    pub fn second_moment(&self) -> Matrix3<f64> {
        let s = &self.semi;
        let sum = |i: usize| s[i] + s[i + 1];
        let diff2 = |i: usize| s[i] * s[i] - s[i + 1] * s[i + 1];
        let cube = |i: usize| s[i].powi(3) + s[i + 1].powi(3);
        let (ax, ay, az) = (sum(0), sum(2), sum(4));
        let xx = PI / 30.0 * cube(0) * ay * az;
        let yy = PI / 30.0 * ax * cube(2) * az;
        let zz = PI / 30.0 * ax * ay * cube(4);
        let xy = diff2(0) * diff2(2) * az / 15.0;
        let xz = diff2(0) * ay * diff2(4) / 15.0;
        let yz = ax * diff2(2) * diff2(4) / 15.0;
        let about_origin = Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        let c = self.centroid();
        about_origin - self.volume() * c * c.transpose()
    }

    /// Inertia tensor about the centroid in the shape frame (kg·m²) for density `density`
    /// (kg/m³): `I = ρ (tr(S) 1 - S)`, S the [`second_moment`](Self::second_moment).
    pub fn inertia(&self, density: f64) -> Matrix3<f64> {
        let s = self.second_moment();
        density * (Matrix3::identity() * s.trace() - s)
    }

    /// Principal moments of inertia (kg·m²) and the principal frame: `frame` rotates
    /// principal-frame vectors into the shape frame, `I = R diag(moments) Rᵀ`.
    ///
    /// When the tensor is diagonal to round-off (off-diagonal terms below 1e-12 of the largest
    /// diagonal one, as for every poly-ellipsoid with at most one asymmetric axis) the frame is
    /// the identity, so a split particle keeps its axes. Otherwise the eigenvectors are
    /// matched to the shape axes they are closest to (the permutation with the largest sum of
    /// |cosines|), each pointing along the positive side of its axis, the third completed as
    /// the cross product of the first two (right-handed); the moments follow that order.
    pub fn principal_inertia(&self, density: f64) -> (Vector3<f64>, UnitQuaternion<f64>) {
        let i = self.inertia(density);
        let largest = i.diagonal().abs().max();
        let off = i.m12.abs().max(i.m13.abs()).max(i.m23.abs());
        if off <= 1e-12 * largest {
            return (i.diagonal(), UnitQuaternion::identity());
        }
        let eig = SymmetricEigen::new(i);
        let v = eig.eigenvectors;
        const PERMUTATIONS: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let score = |p: &[usize; 3]| (0..3).map(|k| v[(k, p[k])].abs()).sum::<f64>();
        let mut best = PERMUTATIONS[0];
        for p in &PERMUTATIONS[1..] {
            if score(p) > score(&best) {
                best = *p;
            }
        }
        let axis = |k: usize| {
            let col = v.column(best[k]).into_owned();
            if col[k] < 0.0 { -col } else { col }
        };
        let (e0, e1) = (axis(0), axis(1));
        let e2 = e0.cross(&e1);
        let r = Matrix3::from_columns(&[e0, e1, e2]);
        let moments = Vector3::new(
            eig.eigenvalues[best[0]],
            eig.eigenvalues[best[1]],
            eig.eigenvalues[best[2]],
        );
        let frame = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
        (moments, frame)
    }

    /// Support point (m): the surface point maximising `d·x`, for any nonzero `d`.
    ///
    /// With `(a, b, c)` the semi-axes of `d`'s octant, `M = diag(a², b², c²)`:
    /// `s(d) = M d / sqrt(dᵀ M d)`. It lies in `d`'s own octant, so the octant ellipsoid's
    /// support point is the poly-ellipsoid's.
    #[inline(always)]
    pub fn support(&self, d: &Vector3<f64>) -> Vector3<f64> {
        self.support_at(d).point
    }

    /// Support function `h(d) = d·s(d) = sqrt(dᵀ M d)` (m for a unit `d`).
    #[inline(always)]
    pub fn support_value(&self, d: &Vector3<f64>) -> f64 {
        // Inlined, the unused division of `support_at` is dropped.
        self.support_at(d).h
    }

    /// The support value, point and octant at `d` together (one square root, one division).
    #[inline(always)]
    pub fn support_at(&self, d: &Vector3<f64>) -> Support {
        let ax = self.octant_axes(d);
        let m2 = ax.component_mul(&ax);
        let w = m2.component_mul(d);
        let h = w.dot(d).sqrt();
        let inv_h = 1.0 / h;
        Support {
            h,
            inv_h,
            point: w * inv_h,
            m2,
        }
    }

    /// Hessian of the support function at `n` (m for a unit `n`):
    /// `∇²h = M/h - (M n)(M n)ᵀ/h³ = (M - s sᵀ)/h`. It annihilates `n` (h is 1-homogeneous);
    /// on the tangent plane of a unit `n` it is the tensor of principal radii of curvature
    /// at the support point.
    pub fn support_hessian(&self, n: &Vector3<f64>) -> Matrix3<f64> {
        let sp = self.support_at(n);
        (Matrix3::from_diagonal(&sp.m2) - sp.point * sp.point.transpose()) * sp.inv_h
    }

    /// The boundary point on the ray from the octant origin along `dir` (nonzero):
    /// `t dir` with `t = 1 / sqrt((dx/a)² + (dy/b)² + (dz/c)²)` in `dir`'s octant.
    pub fn surface_point(&self, dir: &Vector3<f64>) -> Vector3<f64> {
        let ax = self.octant_axes(dir);
        let q = dir.component_div(&ax);
        dir / q.norm()
    }

    /// The octant ellipsoid's implicit function `(x/a)² + (y/b)² + (z/c)²` with `(a, b, c)`
    /// of `p`'s octant (Eq. 1): below 1 inside, 1 on the surface, above 1 outside.
    pub fn implicit(&self, p: &Vector3<f64>) -> f64 {
        let ax = self.octant_axes(p);
        p.component_div(&ax).norm_squared()
    }

    /// Outward unit normal at a surface point `p`: the normalised gradient
    /// `(x/a², y/b², z/c²)` of the octant's implicit function.
    pub fn normal_at(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let ax = self.octant_axes(p);
        p.component_div(&ax.component_mul(&ax)).normalize()
    }

    /// Principal radii of curvature (m, ascending) and their unit directions at the support
    /// point of the unit normal `n`: the eigen-decomposition of the support Hessian restricted
    /// to the tangent plane of `n`. At the tip of semi-axis a of an ellipsoid: `b²/a`, `c²/a`.
    pub fn principal_curvatures(&self, n: &Vector3<f64>) -> ([f64; 2], [Vector3<f64>; 2]) {
        let (t1, t2) = tangent_basis(n);
        let r = self.support_at(n).tangent_hessian(&t1, &t2);
        let (radii, dirs) = sym2_eigen(r);
        let dir = |v: [f64; 2]| v[0] * t1 + v[1] * t2;
        (radii, [dir(dirs[0]), dir(dirs[1])])
    }

    /// Largest distance from the centroid to the surface (m).
    ///
    /// It is `max over unit u of g(u) = h(u) - u·x̄` (the farthest point in direction u is
    /// the support point). Symmetric shapes (x̄ = 0: spheres, ellipsoids) return the largest
    /// semi-axis exactly. Otherwise `g` is maximised from the best sample of each octant on
    /// a 6 × 8 × 8 direction grid by monotone ascent: Newton's step on the sphere when the
    /// Riemannian Hessian `(∇²h)_t - g 1` is negative definite and the step increases `g`,
    /// else the fixed-point step `u ← (s(u) - x̄)/|s(u) - x̄|`, which never decreases `g`.
    /// The result is scaled by `1 + 1e-9` so that round-off cannot make it a lower bound.
    pub fn bounding_radius(&self) -> f64 {
        let c = self.centroid();
        if c == Vector3::zeros() {
            return self.semi.iter().cloned().fold(0.0, f64::max);
        }
        let g = |u: &Vector3<f64>| self.support_value(u) - u.dot(&c);
        let mut best = [(f64::NEG_INFINITY, Vector3::zeros()); 8];
        for (face, s, t) in cube_grid(8) {
            let u = cube_direction(face, s, t);
            let k =
                (u.x < 0.0) as usize | ((u.y < 0.0) as usize) << 1 | ((u.z < 0.0) as usize) << 2;
            let v = g(&u);
            if v > best[k].0 {
                best[k] = (v, u);
            }
        }
        let scale = self.semi.iter().cloned().fold(0.0, f64::max);
        let mut radius = f64::NEG_INFINITY;
        for &(_, start) in &best {
            radius = radius.max(self.farthest_from(&c, start, scale));
        }
        radius * (1.0 + 1e-9)
    }

    /// Monotone ascent of `g(u) = h(u) - u·c` from `u` (see [`bounding_radius`](Self::bounding_radius)).
    fn farthest_from(&self, c: &Vector3<f64>, mut u: Vector3<f64>, scale: f64) -> f64 {
        let mut value = self.support_value(&u) - u.dot(c);
        for _ in 0..200 {
            let sp = self.support_at(&u);
            let (t1, t2) = tangent_basis(&u);
            let r = sp.point - c;
            let grad = [t1.dot(&r), t2.dot(&r)];
            if (grad[0] * grad[0] + grad[1] * grad[1]).sqrt() <= 1e-14 * scale {
                break;
            }
            let hh = sp.tangent_hessian(&t1, &t2);
            let k = [hh[0] - value, hh[1], hh[2] - value];
            let mut next = None;
            if k[0] < 0.0 && k[0] * k[2] > k[1] * k[1] {
                let v = newton_step2(&k, &grad);
                let trial = (u + v[0] * t1 + v[1] * t2).normalize();
                let tv = self.support_value(&trial) - trial.dot(c);
                if tv >= value {
                    next = Some((trial, tv));
                }
            }
            let (trial, tv) = next.unwrap_or_else(|| {
                let trial = r.normalize();
                (trial, self.support_value(&trial) - trial.dot(c))
            });
            if tv <= value {
                break;
            }
            u = trial;
            value = tv;
        }
        value
    }
}

/// Point `(s, t)` of cube face `face` (0..6: +x, -x, +y, -y, +z, -z) projected on the unit
/// sphere; `s`, `t` in [-1, 1] cover the face, and any real values give a direction near it.
pub fn cube_direction(face: usize, s: f64, t: f64) -> Vector3<f64> {
    let v = match face {
        0 => Vector3::new(1.0, s, t),
        1 => Vector3::new(-1.0, t, s),
        2 => Vector3::new(t, 1.0, s),
        3 => Vector3::new(s, -1.0, t),
        4 => Vector3::new(s, t, 1.0),
        _ => Vector3::new(t, s, -1.0),
    };
    v.normalize()
}

/// The centres `(face, s, t)` of an `n × n` grid on each of the six cube faces (see
/// [`cube_direction`]): a direction grid of `6 n²` points for sampling the sphere.
pub fn cube_grid(n: usize) -> impl Iterator<Item = (usize, f64, f64)> {
    let at = move |i: usize| 2.0 * (i as f64 + 0.5) / n as f64 - 1.0;
    (0..6).flat_map(move |face| (0..n * n).map(move |k| (face, at(k / n), at(k % n))))
}

/// An orthonormal tangent basis `(t1, t2)` of the unit vector `n`, right-handed with `n`
/// (`t1 × t2 = n`), continuous except across `n.z = 0` and free of trigonometry (Duff et al.
/// 2017, "Building an orthonormal basis, revisited").
#[inline(always)]
pub fn tangent_basis(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vector3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// The support function of a poly-ellipsoid at one direction `d`, with what its Hessian needs.
#[derive(Debug, Clone, Copy)]
pub struct Support {
    /// `h(d) = sqrt(dᵀ M d)` (m for a unit `d`).
    pub h: f64,
    /// `1/h`.
    pub inv_h: f64,
    /// The support point `s = M d / h` (m, shape frame).
    pub point: Vector3<f64>,
    /// `diag M`: the squared semi-axes of `d`'s octant (m²).
    pub m2: Vector3<f64>,
}

impl Support {
    /// The support Hessian `(M - s sᵀ)/h` restricted to the tangent vectors `t1`, `t2` (shape
    /// frame), as the symmetric 2×2 `[r11, r12, r22]` (m): the principal radii of curvature
    /// tensor when `d` is a unit vector and `t1`, `t2` span its tangent plane.
    #[inline(always)]
    pub fn tangent_hessian(&self, t1: &Vector3<f64>, t2: &Vector3<f64>) -> [f64; 3] {
        let s = &self.point;
        let (p1, p2) = (t1.dot(s), t2.dot(s));
        let mt1 = self.m2.component_mul(t1);
        [
            (mt1.dot(t1) - p1 * p1) * self.inv_h,
            (mt1.dot(t2) - p1 * p2) * self.inv_h,
            (self.m2.component_mul(t2).dot(t2) - p2 * p2) * self.inv_h,
        ]
    }
}

/// The Newton step `v = -K⁻¹ g` of the symmetric 2×2 `K = [k11, k12, k22]` (nonsingular).
#[inline(always)]
pub fn newton_step2(k: &[f64; 3], g: &[f64; 2]) -> [f64; 2] {
    let inv = 1.0 / (k[0] * k[2] - k[1] * k[1]);
    [
        -(k[2] * g[0] - k[1] * g[1]) * inv,
        -(k[0] * g[1] - k[1] * g[0]) * inv,
    ]
}

/// Eigenvalues (ascending) and unit eigenvectors of the symmetric 2×2 `[k11, k12, k22]`,
/// in closed form.
pub fn sym2_eigen(k: [f64; 3]) -> ([f64; 2], [[f64; 2]; 2]) {
    let mean = 0.5 * (k[0] + k[2]);
    let half = 0.5 * (k[0] - k[2]);
    let d = (half * half + k[1] * k[1]).sqrt();
    let (lo, hi) = (mean - d, mean + d);
    // Two candidate eigenvectors of `hi`; the longer one is the better conditioned.
    let u = [k[1], hi - k[0]];
    let w = [hi - k[2], k[1]];
    let (nu, nw) = (
        (u[0] * u[0] + u[1] * u[1]).sqrt(),
        (w[0] * w[0] + w[1] * w[1]).sqrt(),
    );
    let v_hi = if nu == 0.0 && nw == 0.0 {
        [1.0, 0.0]
    } else if nu >= nw {
        [u[0] / nu, u[1] / nu]
    } else {
        [w[0] / nw, w[1] / nw]
    };
    ([lo, hi], [[-v_hi[1], v_hi[0]], v_hi])
}

#[cfg(test)]
mod tests;
