//! Where a grain breaks (granular paper, Section 3.3): always through its
//! octant origin, along one of its three principal planes; which one depends on why it broke
//! and on how well shaped it is (cases (1)–(5), Algorithm 1). Spheres may first turn their
//! principal directions to the ideal plane and, with a random slight rotation (Eq. 19–23),
//! away from it again.

use nalgebra::{Matrix3, Rotation3, SymmetricEigen, UnitQuaternion};

use crate::state::Vec3;

/// Why a grain breaks, which decides its break plane.
#[derive(Debug, Clone, Copy)]
pub enum Trigger {
    /// Hoek–Brown on the average stress (tension positive, world frame): the break plane is
    /// the principal plane with the largest tensile normal stress; its ideal orientation is
    /// normal to the minor principal (least compressive) direction.
    HoekBrown { stress: Matrix3<f64> },
    /// Critical contacts: the ideal break plane is parallel to the plane through them (its
    /// unit normal here, world frame), shifted to the centroid.
    Contacts { normal: Vec3 },
}

impl Trigger {
    /// How well the plane normal to the unit axis `e` (world) suits this trigger: the normal
    /// stress on it (tension positive) or its alignment with the contacts' plane.
    fn score(&self, e: &Vec3) -> f64 {
        match self {
            Trigger::HoekBrown { stress } => e.dot(&(stress * e)),
            Trigger::Contacts { normal } => normal.dot(e).abs(),
        }
    }

    /// The unit normal of the ideal break plane (world).
    pub fn ideal_normal(&self) -> Vec3 {
        match self {
            Trigger::HoekBrown { stress } => {
                let eig = SymmetricEigen::new((stress + stress.transpose()) * 0.5);
                // Tension positive: the largest eigenvalue is the least compressive.
                let k = eig.eigenvalues.imax();
                eig.eigenvectors.column(k).into_owned()
            }
            Trigger::Contacts { normal } => *normal,
        }
    }
}

/// A semi-axis ratio below this is "bad" (Section 3.3.3).
const BAD_RATIO: f64 = 0.2;
/// The length ratio that lets a poorly shaped grain still break (cases 3–5).
const LENGTH_RATIO: f64 = 1.2;

/// The axis (0, 1, 2 for the grain's x, y, z) normal to the plane the grain breaks along, or
/// `None` when its shape forbids breaking. `semi` = [a+, a-, b+, b-, c+, c-]; `axes` are the
/// grain's principal directions in the world frame.
///
/// * (1) no bad ratio: the candidate the trigger prefers, among all three;
/// * (2) three bad ratios: never;
/// * (3) two bad ratios and the good axis longer than 1.2 × the larger bad semi-axes: along
///   the plane of the two bad axes; (4) otherwise never;
/// * (5) one bad ratio (Algorithm 1): normal to the longer of the two good axes when it is
///   1.2 × the other; else the candidate the trigger prefers among the two. (Algorithm 1's
///   "σy > σz then break along xz" reads with the tension-positive stress of case 1: the
///   plane with the larger tensile normal stress.)
pub fn break_axis(semi: &[f64; 6], axes: &[Vec3; 3], trigger: &Trigger) -> Option<usize> {
    let max = |k: usize| semi[2 * k].max(semi[2 * k + 1]);
    let length = |k: usize| semi[2 * k] + semi[2 * k + 1];
    let bad = bad_axes(semi);
    let best = |candidates: &[usize]| {
        candidates
            .iter()
            .copied()
            .max_by(|&a, &b| trigger.score(&axes[a]).total_cmp(&trigger.score(&axes[b])))
    };
    match bad.len() {
        0 => best(&[0, 1, 2]),
        1 => {
            let a = bad[0];
            let (p, q) = ((a + 1) % 3, (a + 2) % 3);
            if length(p) > LENGTH_RATIO * length(q) {
                Some(p)
            } else if length(q) > LENGTH_RATIO * length(p) {
                Some(q)
            } else {
                best(&[p.min(q), p.max(q)])
            }
        }
        2 => {
            let good = 3 - bad[0] - bad[1];
            (length(good) > LENGTH_RATIO * max(bad[0]).max(max(bad[1]))).then_some(good)
        }
        _ => None,
    }
}

/// The axes whose two semi-axes have a bad ratio (the shorter below [`BAD_RATIO`] times the
/// longer), in order.
fn bad_axes(semi: &[f64; 6]) -> Vec<usize> {
    let max = |k: usize| semi[2 * k].max(semi[2 * k + 1]);
    let min = |k: usize| semi[2 * k].min(semi[2 * k + 1]);
    (0..3).filter(|&k| min(k) < BAD_RATIO * max(k)).collect()
}

/// True when a grain of semi-axes `semi` cannot break whatever triggers it: [`break_axis`]
/// is `None` for it, which depends on the shape alone (cases 2 and 4 of Section 3.3.3; every
/// other case breaks along some axis). A host can skip such a grain's split before it asks.
pub fn shape_forbids_breaking(semi: &[f64; 6]) -> bool {
    let axes = [Vec3::x(), Vec3::y(), Vec3::z()];
    break_axis(semi, &axes, &Trigger::Contacts { normal: Vec3::x() }).is_none()
}

/// The unit normal of the plane through the critical contact points (world): for three, the
/// plane through them; for more, the least-squares plane. `None` when they are collinear.
pub fn contacts_plane_normal(points: &[Vec3]) -> Option<Vec3> {
    if points.len() < 3 {
        return None;
    }
    let c = points.iter().sum::<Vec3>() / points.len() as f64;
    let mut scatter = Matrix3::zeros();
    for p in points {
        let d = p - c;
        scatter += d * d.transpose();
    }
    let eig = SymmetricEigen::new(scatter);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    // Collinear points spread along one direction only: no plane.
    if eig.eigenvalues[order[1]] <= 1e-12 * eig.eigenvalues[order[2]] {
        return None;
    }
    Some(eig.eigenvectors.column(order[0]).into_owned())
}

/// The largest random slight rotation of the break plane, θmax = arctan(1/5) (Section 3.3.1).
pub fn max_jitter_angle() -> f64 {
    (0.2f64).atan()
}

/// Eq. 19–20: `R(α, β, γ) = Rx(α) Ry(β) Rz(γ)` in the paper's convention; its columns are the
/// rotated principal directions a', b', c' of Eq. 21–23 (local frame).
pub fn jitter_rotation(alpha: f64, beta: f64, gamma: f64) -> Matrix3<f64> {
    let (sa, ca) = alpha.sin_cos();
    let (sb, cb) = beta.sin_cos();
    let (sg, cg) = gamma.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, ca, sa, 0.0, -sa, ca);
    let ry = Matrix3::new(cb, 0.0, -sb, 0.0, 1.0, 0.0, sb, 0.0, cb);
    let rz = Matrix3::new(cg, sg, 0.0, -sg, cg, 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

/// The angles (rad) of the random slight rotation from six uniform variates in [0, 1]: per
/// angle k, the magnitude `θmax (0.5 + 0.5 u[2k])` and the sign `+` when `u[2k+1] >= 0.5`,
/// else `−`.
pub fn jitter_angles(u: &[f64; 6]) -> [f64; 3] {
    let t = max_jitter_angle();
    [0, 1, 2].map(|k| {
        let magnitude = t * (0.5 + 0.5 * u[2 * k]);
        if u[2 * k + 1] >= 0.5 {
            magnitude
        } else {
            -magnitude
        }
    })
}

/// A sphere's orientation turned so that its x axis lies along the ideal break-plane normal
/// `n` (world), by the smallest rotation from the body axis closest to ±n (a purely
/// geometric turn: a sphere's physics does not see it). Returns the orientation and the axis
/// that now lies along n (always 0, x).
pub fn turn_to_ideal(q: &UnitQuaternion<f64>, n: &Vec3) -> UnitQuaternion<f64> {
    let x = q * Vec3::x();
    let target = if x.dot(n) >= 0.0 { *n } else { -n };
    let turn = UnitQuaternion::rotation_between(&x, &target)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&(q * Vec3::y_axis()), 0.0));
    turn * q
}

/// The orientation after the random slight rotation (Eq. 19–23) of the local principal
/// directions.
pub fn jittered(q: &UnitQuaternion<f64>, angles: [f64; 3]) -> UnitQuaternion<f64> {
    let r = Rotation3::from_matrix_unchecked(jitter_rotation(angles[0], angles[1], angles[2]));
    q * UnitQuaternion::from_rotation_matrix(&r)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> [Vec3; 3] {
        [Vec3::x(), Vec3::y(), Vec3::z()]
    }

    fn uniaxial_z() -> Trigger {
        Trigger::HoekBrown {
            stress: Matrix3::from_diagonal(&Vec3::new(0.0, -1e6, -5e6)),
        }
    }

    /// Whether a shape breaks does not depend on the trigger or the axes: for shapes of each
    /// case (no, one, two and three bad ratios, the two-bad case on both sides of the 1.2
    /// length ratio), `shape_forbids_breaking` is `break_axis` being `None` under every one of
    /// several triggers and rotated frames.
    #[test]
    fn a_shape_forbids_breaking_whatever_the_trigger() {
        let shapes = [
            [1.0, 0.8, 1.0, 0.9, 1.1, 1.0], // no bad ratio
            [1.0, 0.1, 1.0, 0.9, 1.1, 1.0], // one
            [1.0, 0.1, 1.0, 0.1, 3.0, 3.0], // two, the good axis long: breaks
            [1.0, 0.1, 1.0, 0.1, 0.6, 0.5], // two, the good axis short: never
            [1.0, 0.1, 1.0, 0.1, 1.0, 0.1], // three: never
        ];
        let forbidden: Vec<bool> = shapes.iter().map(shape_forbids_breaking).collect();
        assert_eq!(forbidden, [false, false, false, true, true]);
        let q = UnitQuaternion::from_euler_angles(0.4, -1.2, 2.2);
        let turned = [q * Vec3::x(), q * Vec3::y(), q * Vec3::z()];
        let triggers = [
            uniaxial_z(),
            Trigger::Contacts {
                normal: Vec3::new(0.3, -0.2, 0.93).normalize(),
            },
            Trigger::Contacts { normal: Vec3::y() },
        ];
        for (semi, &never) in shapes.iter().zip(&forbidden) {
            for frame in [&axes(), &turned] {
                for t in &triggers {
                    assert_eq!(break_axis(semi, frame, t).is_none(), never, "{semi:?}");
                }
            }
        }
    }

    #[test]
    fn normal_grain_splits_parallel_to_the_load() {
        // Compression along z (and a little along y): the most tensile principal plane is
        // normal to x, a plane that contains the load axis.
        let semi = [1.0, 0.8, 1.0, 0.9, 1.1, 1.0];
        assert_eq!(break_axis(&semi, &axes(), &uniaxial_z()), Some(0));
        let ideal = uniaxial_z().ideal_normal();
        assert!((ideal.x.abs() - 1.0).abs() < 1e-12);
        // Contacts in a plane tilted 10° from the xy plane pick the z axis.
        let t = 10f64.to_radians();
        let n = Vec3::new(t.sin(), 0.0, t.cos());
        assert_eq!(
            break_axis(&semi, &axes(), &Trigger::Contacts { normal: n }),
            Some(2)
        );
    }

    #[test]
    fn poorly_shaped_cases() {
        let t = uniaxial_z();
        // (2) three bad ratios: never.
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.0, 0.1, 1.0, 0.1], &axes(), &t),
            None
        );
        // (3) a and b bad, c long: break along the xy plane (normal z), whatever the stress.
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.0, 0.1, 1.0, 1.0], &axes(), &t),
            Some(2)
        );
        // (4) a and b bad, c short: never.
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.0, 0.1, 0.5, 0.5], &axes(), &t),
            None
        );
        // (5) a bad: b much longer -> xz plane (normal y); c much longer -> xy (normal z).
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.5, 1.5, 1.0, 1.0], &axes(), &t),
            Some(1)
        );
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.0, 1.0, 1.5, 1.5], &axes(), &t),
            Some(2)
        );
        // (5) b and c alike: the stress decides between y and z: y is the more tensile.
        assert_eq!(
            break_axis(&[1.0, 0.1, 1.0, 1.0, 1.0, 1.0], &axes(), &t),
            Some(1)
        );
    }

    #[test]
    fn contact_plane_and_jitter() {
        let pts = [
            Vec3::new(1.0, 0.0, 0.3),
            Vec3::new(0.0, 1.0, 0.3),
            Vec3::new(-1.0, -1.0, 0.3),
        ];
        let n = contacts_plane_normal(&pts).unwrap();
        assert!((n.z.abs() - 1.0).abs() < 1e-12);
        let line = [Vec3::zeros(), Vec3::x(), Vec3::x() * 2.0];
        assert!(contacts_plane_normal(&line).is_none());
        // Eq. 21–23: the columns of R are a', b', c'.
        let (a, b, g) = (0.1, -0.15, 0.2);
        let r = jitter_rotation(a, b, g);
        let a_prime = Vec3::new(
            b.cos() * g.cos(),
            g.cos() * a.sin() * b.sin() - a.cos() * g.sin(),
            a.sin() * g.sin() + a.cos() * g.cos() * b.sin(),
        );
        assert!((r.column(0) - a_prime).norm() < 1e-15);
        let c_prime = Vec3::new(-b.sin(), b.cos() * a.sin(), a.cos() * b.cos());
        assert!((r.column(2) - c_prime).norm() < 1e-15);
        assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
        let tmax = max_jitter_angle();
        assert!((tmax - 0.19739555984988078).abs() < 1e-15);
        for grain in 1..=100 {
            for x in crate::fracture::grain_jitter(1, grain, 0) {
                assert!(x.abs() >= 0.5 * tmax && x.abs() <= tmax);
            }
        }
    }

    #[test]
    fn sphere_turns_its_x_axis_to_the_ideal_normal() {
        let q = UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0);
        let n = Vec3::new(1.0, 2.0, -0.5).normalize();
        let turned = turn_to_ideal(&q, &n);
        let x = turned * Vec3::x();
        assert!((x.dot(&n).abs() - 1.0).abs() < 1e-14);
    }
}
