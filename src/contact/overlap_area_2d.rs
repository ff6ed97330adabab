//! The contact of two rigid polygons that overlap (Kun et al., Section 2.2): the intersection
//! polygon's area A, the contact line through the two points where the boundaries cross, and
//! the force
//!
//! ```text
//! F_N = Y A / Lc − m_eff γ_N v_rel·n      normal to the contact line              (Eq. 2, 3)
//! |F_T| = min(m_eff γ_T |v_rel,t|, μ F_N)  against the tangential relative velocity (Eq. 4)
//! 1/Lc = (1/r_i + 1/r_j) / 2               r: diameter of the circle of the polygon's area
//! m_eff = m_i m_j / (m_i + m_j)                                                      (Eq. 6)
//! ```
//!
//! applied at the middle of the contact line. Eq. 4 as printed reads
//! `min(−m γ_T |v_t|, μ|F_N|)`, which would always pick the negative term; the intended law is
//! viscous friction capped by Coulomb's limit, directed against the sliding velocity. The
//! normal force is clamped at zero: a contact pushes, it never pulls (the beams hold the
//! solid together).

use crate::shape::polygon::{MAX_VERTICES, TaggedPolygon, Vec2, area, area_properties, perp};

/// Vertices of the intersection of two polygons of up to 16 vertices each.
const CLIP_CAPACITY: usize = 32;

const FROM_I: u32 = 0;
const FROM_J: u32 = 1;

/// The overlap of two polygons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// Area A of the intersection polygon (m²).
    pub area: f64,
    /// Where the force acts: the middle of the contact line.
    pub point: Vec2,
    /// Unit normal of the contact line, pointing from polygon i towards polygon j.
    pub normal: Vec2,
    /// Length of the contact line P1P2 (m).
    pub chord: f64,
}

/// The overlap of the convex counter-clockwise polygons `pi` and `pj` with centres of mass
/// `ci` and `cj`, or `None` when they do not overlap.
///
/// The contact line joins the two vertices of the intersection where the boundary switches
/// from one polygon to the other. When there are not exactly two such points (one polygon
/// inside the other, or two long polygons crossing), the force acts at the intersection's
/// centroid along the line between the centres.
pub fn overlap(pi: &[Vec2], pj: &[Vec2], ci: Vec2, cj: Vec2) -> Option<Overlap> {
    overlap_in(&mut ClipBuffers::default(), pi, pj, ci, cj)
}

/// Working space of [`overlap_in`], reused from pair to pair (it is large enough that
/// clearing a fresh one for every pair shows in the profile).
#[derive(Debug, Clone, Default)]
pub struct ClipBuffers {
    a: TaggedPolygon<CLIP_CAPACITY>,
    b: TaggedPolygon<CLIP_CAPACITY>,
}

/// [`overlap`] with its working space supplied.
#[inline]
pub fn overlap_in(
    buffers: &mut ClipBuffers,
    pi: &[Vec2],
    pj: &[Vec2],
    ci: Vec2,
    cj: Vec2,
) -> Option<Overlap> {
    // The edges of j that cut i; an edge with all of i outside separates them.
    let n = pj.len();
    let mut cuts = [(Vec2::zeros(), 0.0); MAX_VERTICES];
    let mut ncut = 0;
    for k in 0..n {
        let (p, q) = (pj[k], pj[if k + 1 == n { 0 } else { k + 1 }]);
        // Outward normal of the counter-clockwise edge p -> q.
        let out = Vec2::new(q.y - p.y, p.x - q.x);
        let offset = out.dot(&p);
        let outside = pi.iter().filter(|v| out.dot(v) > offset).count();
        if outside == pi.len() {
            return None;
        }
        if outside > 0 {
            cuts[ncut] = (out, offset);
            ncut += 1;
        }
    }
    let ClipBuffers { a, b: scratch } = buffers;
    a.set(pi, FROM_I);
    a.clip_all(
        scratch,
        cuts[..ncut]
            .iter()
            .map(|&(out, offset)| (out, offset, FROM_J)),
    );
    if a.len < 3 {
        return None;
    }
    let v = a.vertices();
    let area = area(v);
    // Round-off leaves slivers of touching polygons (shared edges): no force from those.
    let scale = (ci - cj).norm_squared();
    if area <= 1e-13 * scale {
        return None;
    }
    let mut crossings = [Vec2::zeros(); 2];
    let mut count = 0;
    let tags = &a.tag[..a.len];
    let mut prev = tags[tags.len() - 1];
    for (&tag, &x) in tags.iter().zip(v) {
        if prev != tag {
            if count < 2 {
                crossings[count] = x;
            }
            count += 1;
        }
        prev = tag;
    }
    let axis = cj - ci;
    if count == 2 {
        let chord = crossings[1] - crossings[0];
        let len = chord.norm();
        if len > 0.0 {
            let mut normal = perp(chord) / len;
            if normal.dot(&axis) < 0.0 {
                normal = -normal;
            }
            return Some(Overlap {
                area,
                point: 0.5 * (crossings[0] + crossings[1]),
                normal,
                chord: len,
            });
        }
    }
    let len = axis.norm();
    Some(Overlap {
        area,
        point: area_properties(v).centroid,
        normal: if len > 0.0 {
            axis / len
        } else {
            Vec2::new(1.0, 0.0)
        },
        chord: 0.0,
    })
}

/// The constants of the overlap law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OverlapLaw {
    /// Grain bulk Young's modulus Y (Pa) times the thickness of the 2D solid (m).
    pub young_thickness: f64,
    /// Normal damping γ_N (1/s); read only with the `damping` effect.
    pub gamma_n: f64,
    /// Tangential coefficient γ_T (1/s) and Coulomb coefficient μ; read only with `friction`.
    pub gamma_t: f64,
    pub mu: f64,
}

/// The characteristic length Lc of a pair from the polygons' equivalent diameters (Eq. 2).
#[inline(always)]
pub fn characteristic_length(ri: f64, rj: f64) -> f64 {
    2.0 * ri * rj / (ri + rj)
}

/// The contact force on polygon j (the force on i is its opposite) for an overlap `o`, the
/// pair's characteristic length `lc`, effective mass `m_eff` and the velocity of j relative to
/// i at the contact point, `v_rel` (Eq. 2–6). Damping and friction are compiled in only when
/// asked for.
#[inline(always)]
pub fn contact_force<const DAMP: bool, const FRIC: bool>(
    law: &OverlapLaw,
    o: &Overlap,
    lc: f64,
    m_eff: f64,
    v_rel: Vec2,
) -> Vec2 {
    let mut fn_ = law.young_thickness * o.area / lc;
    let vn = v_rel.dot(&o.normal);
    if DAMP {
        fn_ = (fn_ - m_eff * law.gamma_n * vn).max(0.0);
    }
    let mut f = o.normal * fn_;
    if FRIC {
        let vt = v_rel - o.normal * vn;
        let speed = vt.norm();
        if speed > 0.0 {
            let ft = (m_eff * law.gamma_t * speed).min(law.mu * fn_);
            f -= vt * (ft / speed);
        }
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, y0: f64, w: f64, h: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(x0, y0),
            Vec2::new(x0 + w, y0),
            Vec2::new(x0 + w, y0 + h),
            Vec2::new(x0, y0 + h),
        ]
    }

    #[test]
    fn two_squares_pressed_side_by_side() {
        // Unit squares overlapping by 0.1 along x, offset by 0.3 along y.
        let a = rect(0.0, 0.0, 1.0, 1.0);
        let b = rect(0.9, 0.3, 1.0, 1.0);
        let o = overlap(&a, &b, Vec2::new(0.5, 0.5), Vec2::new(1.4, 0.8)).unwrap();
        assert!((o.area - 0.1 * 0.7).abs() < 1e-14, "{}", o.area);
        // The boundaries cross at (1, 0.3) and (0.9, 1): the contact line joins them.
        let p1 = Vec2::new(1.0, 0.3);
        let p2 = Vec2::new(0.9, 1.0);
        assert!((o.point - 0.5 * (p1 + p2)).norm() < 1e-14);
        let t = (p2 - p1).normalize();
        assert!(o.normal.dot(&t).abs() < 1e-14);
        assert!(o.normal.x > 0.0, "points from i to j");
        assert!((o.chord - (p2 - p1).norm()).abs() < 1e-14);
    }

    #[test]
    fn apart_or_touching_gives_none_and_order_does_not_matter() {
        let a = rect(0.0, 0.0, 1.0, 1.0);
        let b = rect(1.5, 0.0, 1.0, 1.0);
        assert!(overlap(&a, &b, Vec2::new(0.5, 0.5), Vec2::new(2.0, 0.5)).is_none());
        let c = rect(1.0, 0.0, 1.0, 1.0);
        assert!(overlap(&a, &c, Vec2::new(0.5, 0.5), Vec2::new(1.5, 0.5)).is_none());
        // A triangle poking into a square: same area and opposite normal either way round.
        let tri = vec![
            Vec2::new(0.8, 0.5),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 1.0),
        ];
        let ct = Vec2::new(1.6, 0.5);
        let o1 = overlap(&a, &tri, Vec2::new(0.5, 0.5), ct).unwrap();
        let o2 = overlap(&tri, &a, ct, Vec2::new(0.5, 0.5)).unwrap();
        // The tip inside x in [0.8, 1] is a triangle of base 0.2 / 1.2 (at x = 1) and height 0.2.
        let expected = 0.5 * 0.2 * (0.2 / 1.2);
        assert!((o1.area - expected).abs() < 1e-14);
        assert!((o2.area - expected).abs() < 1e-14);
        assert!((o1.normal + o2.normal).norm() < 1e-14);
        assert!((o1.normal - Vec2::new(1.0, 0.0)).norm() < 1e-14);
        assert!((o1.point - o2.point).norm() < 1e-14);
    }

    /// Work done on square j pressed into square i while j goes once round the loop
    /// x0 -> x0 + a -> (turn by b) -> x0 -> (turn back), `steps` pieces per side, by a force of
    /// magnitude `law(overlap)` normal to the contact line at its middle.
    fn loop_work(steps: usize, law: impl Fn(&Overlap) -> f64) -> f64 {
        let fixed = rect(0.0, 0.0, 1.0, 1.0);
        let ci = Vec2::new(0.5, 0.5);
        let state = |x: f64, th: f64| {
            let c = Vec2::new(1.4 + x, 0.6);
            let (s, co) = th.sin_cos();
            let v: Vec<Vec2> = rect(-0.5, -0.5, 1.0, 1.0)
                .iter()
                .map(|p| c + Vec2::new(co * p.x - s * p.y, s * p.x + co * p.y))
                .collect();
            let o = overlap(&fixed, &v, ci, c).unwrap();
            let f = o.normal * law(&o);
            (f.x, crate::shape::polygon::cross(o.point - c, f))
        };
        let (a, b) = (-0.05, 0.1);
        let corners = [(0.0, 0.0), (a, 0.0), (a, b), (0.0, b), (0.0, 0.0)];
        let mut work = 0.0;
        for w in corners.windows(2) {
            let ((x0, t0), (x1, t1)) = (w[0], w[1]);
            for k in 0..steps {
                // Midpoint rule along the side.
                let s = (k as f64 + 0.5) / steps as f64;
                let (fx, m) = state(x0 + s * (x1 - x0), t0 + s * (t1 - t0));
                work += fx * (x1 - x0) / steps as f64 + m * (t1 - t0) / steps as f64;
            }
        }
        work
    }

    #[test]
    fn the_overlap_force_has_no_potential() {
        // Eq. 2 puts the force normal to the contact line at its middle: the direction and the
        // point of the gradient of the overlap area A (moving j by du changes A by
        // −|P1P2| n·du; turning it, by the torque of that force about its centre). A force
        // f'(A)|P1P2| there derives from the potential f(A), and its work round a closed loop
        // vanishes; Eq. 2's Y A / Lc is not of that form once the chord varies on its own, and
        // the same loop does work: an undamped packing can gain energy.
        let paper = |o: &Overlap| {
            contact_force::<false, false>(
                &OverlapLaw {
                    young_thickness: 1.0,
                    gamma_n: 0.0,
                    gamma_t: 0.0,
                    mu: 0.0,
                },
                o,
                1.0,
                0.0,
                Vec2::zeros(),
            )
            .norm()
        };
        let potential = |o: &Overlap| o.area * o.chord;
        let (coarse, fine) = (loop_work(200, paper), loop_work(400, paper));
        assert!((coarse - fine).abs() < 1e-3 * fine.abs(), "{coarse} {fine}");
        let conservative = loop_work(400, potential);
        // Scale: the work along one side of the loop, about A * 0.05.
        assert!(fine.abs() > 1e-5, "Eq. 2: {fine}");
        assert!(
            conservative.abs() < 1e-3 * fine.abs(),
            "f(A) = A²/2: {conservative} vs {fine}"
        );
    }

    #[test]
    fn force_law_damping_and_coulomb_cap() {
        let law = OverlapLaw {
            young_thickness: 1e9 * 0.01,
            gamma_n: 1e4,
            gamma_t: 1e6,
            mu: 0.5,
        };
        let o = Overlap {
            area: 1e-6,
            point: Vec2::zeros(),
            normal: Vec2::new(1.0, 0.0),
            chord: 0.01,
        };
        let lc = characteristic_length(0.01, 0.02);
        assert!((lc - 0.04 / 3.0).abs() < 1e-15);
        let elastic = 1e7 * 1e-6 / lc;
        let f = contact_force::<false, false>(&law, &o, lc, 1e-3, Vec2::new(-5.0, 3.0));
        assert!((f.x - elastic).abs() < 1e-9 && f.y == 0.0);
        // Approaching at 5 m/s adds m γ_N 5; sliding at 3 m/s is capped at μ F_N.
        let f = contact_force::<true, true>(&law, &o, lc, 1e-3, Vec2::new(-5.0, 3.0));
        let fn_ = elastic + 1e-3 * 1e4 * 5.0;
        assert!((f.x - fn_).abs() < 1e-9);
        assert!((f.y + 0.5 * fn_).abs() < 1e-9);
        // Slow sliding: viscous, below the cap.
        let f = contact_force::<true, true>(&law, &o, lc, 1e-3, Vec2::new(0.0, 1e-3));
        assert!((f.y + 1e-3 * 1e6 * 1e-3).abs() < 1e-12);
        // Separating fast: the damped normal force would pull; it is clamped at zero.
        let f = contact_force::<true, false>(&law, &o, lc, 1e-3, Vec2::new(100.0, 0.0));
        assert_eq!(f, Vec2::zeros());
    }
}
