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
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    const SPLIT: [f64; 6] = [0.9, 0.1, 0.95, 0.95, 0.95, 0.95];

    /// A random vector in the cube [-0.5, 0.5]³.
    fn random_vector(rng: &mut ChaCha8Rng) -> Vector3<f64> {
        Vector3::new(
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        )
        .add_scalar(-0.5)
    }

    fn shapes() -> Vec<PolyEllipsoid> {
        vec![
            PolyEllipsoid::new([1.0, 1.5, 0.8, 1.2, 1.9, 0.7]).unwrap(),
            PolyEllipsoid::new([2.0, 1.0, 1.0, 1.0, 1.0, 1.0]).unwrap(),
            PolyEllipsoid::new(SPLIT).unwrap(),
            PolyEllipsoid::new([1.0, 0.1, 0.6, 1.3, 0.9, 0.9]).unwrap(),
        ]
    }

    /// Uniform points in the bounding box; returns (V, ∫x dV, ∫x xᵀ dV about the origin)
    /// estimates and their standard errors (per entry).
    fn monte_carlo(
        pe: &PolyEllipsoid,
        n: usize,
        seed: u64,
    ) -> (
        f64,
        Vector3<f64>,
        Matrix3<f64>,
        f64,
        Vector3<f64>,
        Matrix3<f64>,
    ) {
        let s = &pe.semi;
        let lo = Vector3::new(-s[1], -s[3], -s[5]);
        let span = Vector3::new(s[0] + s[1], s[2] + s[3], s[4] + s[5]);
        let box_v = span.x * span.y * span.z;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut v1, mut v2) = (0.0, 0.0);
        let (mut m1, mut m2) = (Vector3::zeros(), Vector3::zeros());
        let (mut s1, mut s2) = (Matrix3::zeros(), Matrix3::zeros());
        for _ in 0..n {
            let u = Vector3::new(
                rng.random::<f64>(),
                rng.random::<f64>(),
                rng.random::<f64>(),
            );
            let p = lo + span.component_mul(&u);
            if pe.implicit(&p) <= 1.0 {
                v1 += 1.0;
                v2 += 1.0;
                m1 += p;
                m2 += p.component_mul(&p);
                let pp = p * p.transpose();
                s1 += pp;
                s2 += pp.component_mul(&pp);
            }
        }
        let nf = n as f64;
        // Mean of f·box_v over uniform samples and its standard error.
        let se = |sum: f64, sum2: f64| {
            let mean = sum / nf;
            box_v * ((sum2 / nf - mean * mean) / nf).sqrt()
        };
        let vse = se(v1, v2);
        let mse = Vector3::from_fn(|i, _| se(m1[i], m2[i]));
        let sse = Matrix3::from_fn(|i, j| se(s1[(i, j)], s2[(i, j)]));
        (
            box_v * v1 / nf,
            box_v * m1 / nf,
            box_v * s1 / nf,
            vse,
            mse,
            sse,
        )
    }

    #[test]
    fn volume_centroid_second_moment_match_monte_carlo() {
        // Each estimate within 4.5 standard errors (2e6 samples; the seeds are fixed).
        let mut worst: f64 = 0.0;
        let mut check = |exact: f64, estimate: f64, se: f64, what: &str| {
            let z = (exact - estimate).abs() / se.max(1e-300);
            worst = worst.max(z);
            assert!(z < 4.5, "{what}: {exact} vs Monte Carlo {estimate} ± {se}");
        };
        for (k, pe) in shapes().iter().enumerate() {
            let (v, m, s, vse, mse, sse) = monte_carlo(pe, 2_000_000, 7 + k as u64);
            check(pe.volume(), v, vse, "volume");
            let c = pe.centroid();
            for i in 0..3 {
                check(c[i] * pe.volume(), m[i], mse[i], "first moment");
            }
            // About the origin: S_c + V c cᵀ.
            let s_origin = pe.second_moment() + pe.volume() * c * c.transpose();
            for i in 0..3 {
                for j in 0..3 {
                    check(s_origin[(i, j)], s[(i, j)], sse[(i, j)], "second moment");
                }
            }
        }
        println!("Monte Carlo: largest deviation {worst:.2} standard errors");
    }

    /// Fine midpoint quadrature in each octant (spherical coordinates of the unit ball mapped
    /// by the octant's axes) checks the closed forms far below the Monte Carlo noise.
    #[test]
    fn second_moment_matches_quadrature() {
        for pe in shapes() {
            let n = 160;
            let mut v = 0.0;
            let mut first = Vector3::zeros();
            let mut second = Matrix3::zeros();
            let h = 1.0 / n as f64;
            for sx in [1.0, -1.0] {
                for sy in [1.0, -1.0] {
                    for sz in [1.0, -1.0] {
                        let ax = pe.octant_axes(&Vector3::new(sx, sy, sz));
                        let jac = ax.x * ax.y * ax.z;
                        for i in 0..n {
                            let r = (i as f64 + 0.5) * h;
                            for j in 0..n {
                                let th = (j as f64 + 0.5) * h * PI / 2.0;
                                for k in 0..n {
                                    let ph = (k as f64 + 0.5) * h * PI / 2.0;
                                    let w = jac * r * r * th.sin() * h * h * h * PI * PI / 4.0;
                                    let p = Vector3::new(
                                        sx * ax.x * r * th.sin() * ph.cos(),
                                        sy * ax.y * r * th.sin() * ph.sin(),
                                        sz * ax.z * r * th.cos(),
                                    );
                                    v += w;
                                    first += w * p;
                                    second += w * p * p.transpose();
                                }
                            }
                        }
                    }
                }
            }
            let c = first / v;
            let sc = second - v * c * c.transpose();
            let scale = pe.volume() * pe.semi.iter().cloned().fold(0.0, f64::max).powi(2);
            println!(
                "quadrature {:?}: volume {:.1e}, centroid {:.1e}, second moment {:.1e} (relative)",
                pe.semi,
                (v - pe.volume()).abs() / v,
                (c - pe.centroid()).norm() / pe.semi[0],
                (sc - pe.second_moment()).abs().max() / scale
            );
            assert!((v - pe.volume()).abs() < 2e-5 * v, "volume");
            assert!(
                (c - pe.centroid()).norm() < 2e-5,
                "centroid {c} vs {}",
                pe.centroid()
            );
            assert!(
                (sc - pe.second_moment()).abs().max() < 2e-5 * scale,
                "second moment\n{sc}\n{}",
                pe.second_moment()
            );
        }
    }

    #[test]
    fn sphere_and_ellipsoid_closed_forms() {
        let r = 0.3e-3;
        let rho = 2650.0;
        let sp = PolyEllipsoid::sphere(r);
        let v = 4.0 / 3.0 * PI * r.powi(3);
        assert!((sp.volume() - v).abs() <= 1e-14 * v);
        assert!((sp.equivalent_radius() - r).abs() <= 1e-14 * r);
        assert_eq!(sp.centroid(), Vector3::zeros());
        let i_sphere = 0.4 * rho * v * r * r;
        let (moments, frame) = sp.principal_inertia(rho);
        for k in 0..3 {
            assert!((moments[k] - i_sphere).abs() <= 1e-14 * i_sphere);
        }
        assert_eq!(frame, UnitQuaternion::identity());
        assert_eq!(sp.bounding_radius(), r);

        let (a, b, c) = (2.0e-3, 1.3e-3, 0.7e-3);
        let el = PolyEllipsoid::new([a, a, b, b, c, c]).unwrap();
        let v = 4.0 / 3.0 * PI * a * b * c;
        let m = rho * v;
        assert!((el.volume() - v).abs() <= 1e-14 * v);
        let i = el.inertia(rho);
        let expect = Vector3::new(
            m * (b * b + c * c) / 5.0,
            m * (a * a + c * c) / 5.0,
            m * (a * a + b * b) / 5.0,
        );
        for k in 0..3 {
            assert!((i[(k, k)] - expect[k]).abs() <= 1e-14 * expect[k]);
        }
        assert!(i.m12 == 0.0 && i.m13 == 0.0 && i.m23 == 0.0);
        assert_eq!(el.bounding_radius(), a);
        // A half ellipsoid of semi-axis a along +x and a vanishing one along -x: centroid 3a/8.
        let half = PolyEllipsoid::new([a, 1e-300, b, b, c, c]).unwrap();
        assert!((half.centroid().x - 0.375 * a).abs() < 1e-15);
        assert!((half.volume() - v / 2.0).abs() < 1e-14 * v);
    }

    #[test]
    fn principal_frame_diagonalises_inertia() {
        // Split-like shapes have one asymmetric axis: diagonal tensor, identity frame.
        let split = PolyEllipsoid::new(SPLIT).unwrap();
        assert_eq!(split.principal_inertia(1.0).1, UnitQuaternion::identity());
        for pe in shapes() {
            let i = pe.inertia(2650.0);
            let (moments, frame) = pe.principal_inertia(2650.0);
            let r = frame.to_rotation_matrix().into_inner();
            let back = r * Matrix3::from_diagonal(&moments) * r.transpose();
            assert!(
                (back - i).abs().max() < 1e-12 * i.abs().max(),
                "{back}\n{i}"
            );
            assert!((r.determinant() - 1.0).abs() < 1e-12);
            // Each principal axis is the one closest to its shape axis, on its positive side.
            for k in 0..3 {
                assert!(r[(k, k)] > 0.5, "axis {k} of {:?}: {r}", pe.semi);
            }
        }
        // The first shape has three asymmetric axes: a genuinely rotated frame.
        let (_, frame) = shapes()[0].principal_inertia(1.0);
        assert!(frame.angle() > 1e-3);
    }

    #[test]
    fn support_point_matches_dense_surface_sampling() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for pe in shapes() {
            // Dense samples of the surface: rays from the octant origin on a cube grid.
            let n = 200;
            let pts: Vec<Vector3<f64>> = cube_grid(n)
                .map(|(face, s, t)| pe.surface_point(&cube_direction(face, s, t)))
                .collect();
            let rmax = pe.semi.iter().cloned().fold(0.0, f64::max);
            let rmin = pe.semi.iter().cloned().fold(f64::INFINITY, f64::min);
            // Neighbouring samples are at most about rmax · 2/n · 1.5 apart; the sampled maximum is
            // below the true one by at most (spacing/2)² / (2 ρ_min), ρ_min ≥ rmin²/rmax.
            let spacing = rmax * 3.0 / n as f64;
            let tol = 0.125 * spacing * spacing / (rmin * rmin / rmax);
            for _ in 0..200 {
                let d = random_vector(&mut rng) * 3.0;
                let s = pe.support(&d);
                let h = pe.support_value(&d);
                assert!((s.dot(&d) - h).abs() < 1e-12 * h);
                assert!((pe.implicit(&s) - 1.0).abs() < 1e-12);
                let normal = pe.normal_at(&s);
                assert!((normal - d.normalize()).norm() < 1e-12);
                let dn = d.norm();
                let sampled = pts
                    .iter()
                    .map(|p| p.dot(&d))
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!(sampled <= h + 1e-12 * h * dn, "sample beyond support");
                assert!(
                    h - sampled <= tol * dn,
                    "support {h} sampled {sampled} tol {}",
                    tol * dn
                );
            }
        }
    }

    #[test]
    fn curvature_radii_at_tips_and_of_a_sphere() {
        let r = 0.7;
        let sp = PolyEllipsoid::sphere(r);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..50 {
            let n = random_vector(&mut rng).normalize();
            let (radii, dirs) = sp.principal_curvatures(&n);
            assert!((radii[0] - r).abs() < 1e-14 && (radii[1] - r).abs() < 1e-14);
            assert!(dirs[0].dot(&n).abs() < 1e-14 && dirs[1].dot(&n).abs() < 1e-14);
            let hs = sp.support_hessian(&n);
            assert!(
                (hs - r * (Matrix3::identity() - n * n.transpose()))
                    .abs()
                    .max()
                    < 1e-14
            );
        }
        // Poly-ellipsoid tips: the octants on the tip's side decide (a+ at +x, ...).
        let pe = PolyEllipsoid::new([1.0, 1.5, 0.8, 1.2, 1.9, 0.7]).unwrap();
        let s = pe.semi;
        // At the +x tip the four octants with x > 0 meet; the radii in the y and z directions
        // on the side y > 0, z > 0 are b+²/a+ and c+²/a+ (the support Hessian uses the octant of
        // n with its zero components counted as positive).
        let (radii, dirs) = pe.principal_curvatures(&Vector3::x());
        let mut expect = [s[2] * s[2] / s[0], s[4] * s[4] / s[0]];
        expect.sort_by(f64::total_cmp);
        assert!((radii[0] - expect[0]).abs() < 1e-14 && (radii[1] - expect[1]).abs() < 1e-14);
        assert!(dirs[0].x.abs() < 1e-14);
        let (radii, _) = pe.principal_curvatures(&(-Vector3::z()));
        let mut expect = [s[0] * s[0] / s[5], s[2] * s[2] / s[5]];
        expect.sort_by(f64::total_cmp);
        assert!((radii[0] - expect[0]).abs() < 1e-14 && (radii[1] - expect[1]).abs() < 1e-14);
        // Just off the -y tip into the octant x < 0, z < 0: a-²/b- and c-²/b-.
        let n = Vector3::new(-1e-9, -1.0, -1e-9).normalize();
        let (radii, _) = pe.principal_curvatures(&n);
        let mut expect = [s[1] * s[1] / s[3], s[5] * s[5] / s[3]];
        expect.sort_by(f64::total_cmp);
        assert!((radii[0] - expect[0]).abs() < 1e-8 && (radii[1] - expect[1]).abs() < 1e-8);
    }

    /// The curvature radii agree with the second derivative of the surface measured by
    /// finite differences of support points: moving the normal by a small angle ε along a
    /// principal direction moves the support point by ρ ε along it.
    #[test]
    fn curvature_radii_match_finite_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for pe in shapes() {
            for _ in 0..50 {
                let n = random_vector(&mut rng).normalize();
                let (radii, dirs) = pe.principal_curvatures(&n);
                let eps = 1e-6;
                for k in 0..2 {
                    let up = pe.support(&(n + eps * dirs[k]).normalize());
                    let down = pe.support(&(n - eps * dirs[k]).normalize());
                    let fd = (up - down).dot(&dirs[k]) / (2.0 * eps);
                    // A sample within ε of an octant plane straddles the curvature jump.
                    if n.abs().min() > 1e-4 {
                        assert!(
                            (fd - radii[k]).abs() < 1e-6 * radii[1],
                            "{fd} vs {}",
                            radii[k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn surface_points_normals_and_implicit() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for pe in shapes() {
            for _ in 0..200 {
                let d = random_vector(&mut rng);
                let p = pe.surface_point(&d);
                assert!((pe.implicit(&p) - 1.0).abs() < 1e-13);
                assert!(p.normalize().dot(&d.normalize()) > 1.0 - 1e-14);
                // The normal at p has p as its support point.
                let n = pe.normal_at(&p);
                assert!((pe.support(&n) - p).norm() < 1e-12);
                assert!(pe.implicit(&(0.999 * p)) < 1.0 && pe.implicit(&(1.001 * p)) > 1.0);
            }
        }
    }

    #[test]
    fn tangent_basis_is_orthonormal_and_right_handed() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let mut dirs = vec![Vector3::z(), -Vector3::z(), Vector3::x()];
        for _ in 0..1000 {
            let v = random_vector(&mut rng);
            dirs.push(v.normalize());
        }
        for n in dirs {
            let (t1, t2) = tangent_basis(&n);
            assert!((t1.norm() - 1.0).abs() < 1e-14 && (t2.norm() - 1.0).abs() < 1e-14);
            assert!(t1.dot(&t2).abs() < 1e-14 && t1.dot(&n).abs() < 1e-14);
            assert!((t1.cross(&t2) - n).norm() < 1e-14);
        }
    }

    #[test]
    fn constructor_rejects_bad_semi_axes() {
        assert!(
            PolyEllipsoid::new([1.0, 1.0, 0.0, 1.0, 1.0, 1.0])
                .unwrap_err()
                .contains("b+")
        );
        assert!(
            PolyEllipsoid::new([1.0, f64::NAN, 1.0, 1.0, 1.0, 1.0])
                .unwrap_err()
                .contains("a-")
        );
        assert!(PolyEllipsoid::new([1.0, 1.0, 1.0, 1.0, 1.0, -2.0]).is_err());
    }
}
