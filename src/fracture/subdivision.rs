//! Subdivision of a grain into two sub-poly-ellipsoids (granular paper,
//! Section 3.3.2) that carry on its motion.
//!
//! Split normal to axis k of the shape frame, through the octant origin O, each half becomes a
//! poly-ellipsoid with the parent's principal directions: on the + side, `s'+ = 0.9 s+` and
//! `s'− = 0.1 s+` along k with its octant origin moved to `O + 0.1 s+ e_k`, so it spans the
//! parent's half exactly along k; across k the semi-axes shrink by `r_c = 0.9486833` (Eq. 28),
//! the largest ratio that keeps the half inside the parent. Likewise on the − side.
//!
//! The halves hold 90% of the parent's volume. Mass is conserved: each half gets the parent's
//! mass in proportion to its volume (a density 1/0.9 times the parent's after the first
//! split). Both halves are then shifted by the same small vector so that their common centre
//! of mass is the parent's (it differs by `(1 − r_c) 3/8 (b+ − b−)` across k for a lopsided
//! parent). They move as the parent did: `v = v_P + ω × (x − x_P)`, the same `ω`.

use nalgebra::UnitQuaternion;

use crate::shape::PolyEllipsoid;
use crate::state::Vec3;

/// `r_a` of Eq. 24: the half's long semi-axis along the split axis over the parent's.
pub const LENGTH_RATIO: f64 = 0.9;
/// `r_c` of Eq. 28: `sqrt(0.9)`, the largest cross-section ratio that keeps the half inside.
pub const SIDE_RATIO: f64 = 0.948_683_298_050_513_8;

/// The semi-axes of the + and − halves of a split normal to axis `k`, and the shift of each
/// half's octant origin along k from the parent's (m).
pub fn halves(semi: &[f64; 6], k: usize) -> [([f64; 6], f64); 2] {
    let mut plus = semi.map(|s| s * SIDE_RATIO);
    let mut minus = plus;
    let (sp, sm) = (semi[2 * k], semi[2 * k + 1]);
    plus[2 * k] = LENGTH_RATIO * sp;
    plus[2 * k + 1] = (1.0 - LENGTH_RATIO) * sp;
    minus[2 * k + 1] = LENGTH_RATIO * sm;
    minus[2 * k] = (1.0 - LENGTH_RATIO) * sm;
    [
        (plus, (1.0 - LENGTH_RATIO) * sp),
        (minus, -(1.0 - LENGTH_RATIO) * sm),
    ]
}

/// One half, placed in the world.
#[derive(Debug, Clone, Copy)]
pub struct Half {
    pub pe: PolyEllipsoid,
    pub mass: f64,
    /// Centre of mass (m) and velocity (m/s).
    pub centroid: Vec3,
    pub velocity: Vec3,
}

/// The parent as the split sees it: its semi-axes and shape frame in the world, mass, centre
/// of mass, velocity and angular velocity.
#[derive(Debug, Clone, Copy)]
pub struct Parent {
    pub semi: [f64; 6],
    /// World position of the octant origin and shape-to-world rotation.
    pub origin: Vec3,
    pub frame: UnitQuaternion<f64>,
    pub mass: f64,
    pub centroid: Vec3,
    pub velocity: Vec3,
    pub omega: Vec3,
}

/// The two halves of `parent` split normal to its axis `k`: (+ side, − side).
pub fn split(parent: &Parent, k: usize) -> [Half; 2] {
    let [(sp, shift_p), (sm, shift_m)] = halves(&parent.semi, k);
    let place = |semi: [f64; 6], shift: f64| {
        let pe = PolyEllipsoid::new(semi).expect("halves of a valid grain are valid");
        let mut along = Vec3::zeros();
        along[k] = shift;
        let centroid = parent.origin + parent.frame * (along + pe.centroid());
        (pe, centroid)
    };
    let (pe_p, cp) = place(sp, shift_p);
    let (pe_m, cm) = place(sm, shift_m);
    let (vp, vm) = (pe_p.volume(), pe_m.volume());
    // The larger half's mass from its volume share, the smaller's as the rest: M − m_large
    // is exact in floating point (m_large lies in [M/2, M]), so the halves' masses add up to
    // the parent's exactly and repeated splits never drift the sample's mass.
    let (mp, mm) = if vp >= vm {
        let mp = parent.mass * vp / (vp + vm);
        (mp, parent.mass - mp)
    } else {
        let mm = parent.mass * vm / (vp + vm);
        (parent.mass - mm, mm)
    };
    let shift = parent.centroid - (cp * mp + cm * mm) / parent.mass;
    let half = |pe: PolyEllipsoid, mass: f64, c: Vec3| {
        let centroid = c + shift;
        Half {
            pe,
            mass,
            centroid,
            velocity: parent.velocity + parent.omega.cross(&(centroid - parent.centroid)),
        }
    };
    [half(pe_p, mp, cp), half(pe_m, mm, cm)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rc_is_the_largest_ratio_inside_the_parent() {
        // Eq. 28: max rc = min over α of sqrt((0.99 − 0.81 sin²α − 0.18 sin α) / cos²α).
        let rc = (0..100_000)
            .map(|i| {
                let a = 0.9999 * std::f64::consts::FRAC_PI_2 * i as f64 / 100_000.0;
                ((0.99 - 0.81 * a.sin().powi(2) - 0.18 * a.sin()) / a.cos().powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!((rc - 0.9486833).abs() < 1e-6, "{rc}");
        assert!((SIDE_RATIO - 0.9f64.sqrt()).abs() < 1e-16);
    }

    /// A split conserves mass exactly (in floating point), keeps the centre of mass and the momentum,
    /// and both halves lie inside the parent.
    #[test]
    fn split_conserves_mass_centre_and_momentum() {
        let parent = Parent {
            semi: [1.0e-3, 0.7e-3, 0.9e-3, 0.6e-3, 1.2e-3, 0.8e-3],
            origin: Vec3::new(0.1, 0.2, 0.3),
            frame: UnitQuaternion::from_euler_angles(0.4, -0.2, 1.3),
            mass: 5.5e-6,
            centroid: Vec3::zeros(),
            velocity: Vec3::new(0.5, -0.1, 0.2),
            omega: Vec3::new(30.0, -10.0, 5.0),
        };
        let pe = PolyEllipsoid::new(parent.semi).unwrap();
        let parent = Parent {
            centroid: parent.origin + parent.frame * pe.centroid(),
            ..parent
        };
        for k in 0..3 {
            let [a, b] = split(&parent, k);
            assert_eq!(a.mass + b.mass, parent.mass);
            for m in [1.0, 3.3e-9, 7.77e-7, 0.1 + 0.2] {
                let [a, b] = split(&Parent { mass: m, ..parent }, k);
                assert_eq!(a.mass + b.mass, m, "axis {k}, mass {m}");
            }
            let com = (a.centroid * a.mass + b.centroid * b.mass) / parent.mass;
            assert!((com - parent.centroid).norm() < 1e-15);
            let p = a.velocity * a.mass + b.velocity * b.mass;
            let p0 = parent.velocity * parent.mass;
            assert!(
                (p - p0).norm() < 1e-13 * p0.norm(),
                "{}",
                (p - p0).norm() / p0.norm()
            );
            // 90% of the parent's volume.
            assert!(((a.pe.volume() + b.pe.volume()) / pe.volume() - 0.9).abs() < 1e-12);
        }
    }
}
