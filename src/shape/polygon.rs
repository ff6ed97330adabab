//! Convex polygons in the plane: area, centroid and polar moment, and clipping by half-planes
//! with every edge remembering where it came from.
//!
//! One clipping routine serves two purposes: it cuts Voronoi cells out of the plane (an edge's
//! tag is the neighbour whose bisector made it, sample/lattice2d.rs) and it intersects two
//! overlapping polygons (an edge's tag says which polygon's boundary it lies on, so the points
//! where the two boundaries cross are where the tag changes, contact/overlap_area_2d.rs).

use serde::{Deserialize, Serialize};

pub type Vec2 = nalgebra::Vector2<f64>;

/// The most vertices a polygon of the `beam2d` model may have. Cells of the vectorizable
/// random lattice have 4 to about 10; cutting to a disc adds up to about 3.
pub const MAX_VERTICES: usize = 16;

/// The z component of the cross product of two plane vectors.
#[inline(always)]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// `a` turned by +90°.
#[inline(always)]
pub fn perp(a: Vec2) -> Vec2 {
    Vec2::new(-a.y, a.x)
}

/// Area, centroid and polar second moment of area of a polygon.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AreaProperties {
    /// Area (m²), positive for counter-clockwise vertices.
    pub area: f64,
    pub centroid: Vec2,
    /// Polar second moment of area about the centroid, ∫ r² dA (m⁴).
    pub polar_moment: f64,
}

/// The area properties of a simple polygon given counter-clockwise. Sums run relative to the
/// first vertex, which keeps round-off small far from the origin.
pub fn area_properties(v: &[Vec2]) -> AreaProperties {
    let o = v[0];
    let (mut a2, mut cx, mut cy, mut j) = (0.0, 0.0, 0.0, 0.0);
    for k in 1..v.len().saturating_sub(1) {
        let (p, q) = (v[k] - o, v[k + 1] - o);
        let c = cross(p, q);
        a2 += c;
        cx += c * (p.x + q.x);
        cy += c * (p.y + q.y);
        // ∫ r² over the triangle (o, p, q), r measured from o.
        j += c * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y);
    }
    let area = 0.5 * a2;
    let c = Vec2::new(cx, cy) / (3.0 * a2);
    let j_o = j / 12.0;
    AreaProperties {
        area,
        centroid: o + c,
        polar_moment: j_o - area * c.norm_squared(),
    }
}

/// Signed area of a polygon (counter-clockwise positive).
pub fn area(v: &[Vec2]) -> f64 {
    let o = v[0];
    let mut a2 = 0.0;
    for k in 1..v.len().saturating_sub(1) {
        a2 += cross(v[k] - o, v[k + 1] - o);
    }
    0.5 * a2
}

/// A convex polygon of at most `N` vertices, counter-clockwise, on the stack. `tag[k]` belongs
/// to the edge from vertex k to vertex k + 1.
#[derive(Debug, Clone, Copy)]
pub struct TaggedPolygon<const N: usize> {
    pub len: usize,
    pub v: [Vec2; N],
    pub tag: [u32; N],
    /// Set when a clip had more vertices than fit (the result is then incomplete).
    pub overflow: bool,
}

impl<const N: usize> Default for TaggedPolygon<N> {
    fn default() -> Self {
        TaggedPolygon {
            len: 0,
            v: [Vec2::zeros(); N],
            tag: [0; N],
            overflow: false,
        }
    }
}

impl<const N: usize> TaggedPolygon<N> {
    /// The polygon `v` with every edge tagged `tag`.
    pub fn from_vertices(v: &[Vec2], tag: u32) -> Self {
        let mut p = TaggedPolygon::default();
        p.set(v, tag);
        p
    }

    /// Makes this the polygon `v` (at most N vertices) with every edge tagged `tag`.
    #[inline]
    pub fn set(&mut self, v: &[Vec2], tag: u32) {
        let n = v.len().min(N);
        self.v[..n].copy_from_slice(&v[..n]);
        self.tag[..n].fill(tag);
        self.len = n;
        self.overflow = v.len() > N;
    }

    #[inline(always)]
    fn push(&mut self, x: Vec2, tag: u32) {
        if self.len < N {
            self.v[self.len] = x;
            self.tag[self.len] = tag;
            self.len += 1;
        } else {
            self.overflow = true;
        }
    }

    pub fn vertices(&self) -> &[Vec2] {
        &self.v[..self.len]
    }

    /// Writes into `out` the part of this polygon where `normal · x <= offset`; the new edge
    /// along the cutting line gets `tag`, the others keep theirs (Sutherland–Hodgman, each
    /// vertex emitted as the start of its own edge). Returns false, leaving `out` alone, when
    /// the whole polygon is on the kept side.
    #[inline]
    pub fn clip_into(&self, normal: Vec2, offset: f64, tag: u32, out: &mut Self) -> bool {
        let n = self.len;
        let mut d = [0.0; N];
        let mut outside = 0;
        for (dk, v) in d.iter_mut().zip(&self.v[..n]) {
            *dk = normal.dot(v) - offset;
            outside += (*dk > 0.0) as usize;
        }
        if outside == 0 {
            return false;
        }
        out.len = 0;
        out.overflow = self.overflow;
        for k in 0..n {
            let next = if k + 1 == n { 0 } else { k + 1 };
            let (dc, dn) = (d[k], d[next]);
            let (cur, t) = (self.v[k], self.tag[k]);
            if dc < 0.0 {
                out.push(cur, t);
                if dn > 0.0 {
                    let b = self.v[next];
                    out.push(cur + (b - cur) * (dc / (dc - dn)), tag);
                }
            } else if dc == 0.0 {
                // On the line: if the edge leaves, the boundary from here follows the line.
                out.push(cur, if dn > 0.0 { tag } else { t });
            } else if dn < 0.0 {
                let b = self.v[next];
                out.push(cur + (b - cur) * (dc / (dc - dn)), t);
            }
        }
        true
    }

    /// Clips in place (through a copy).
    pub fn clip(&mut self, normal: Vec2, offset: f64, tag: u32) {
        let copy = *self;
        copy.clip_into(normal, offset, tag, self);
    }

    /// Clips by a sequence of half-planes `(normal, offset, tag)`, alternating between this
    /// polygon and `scratch` without copying where a half-plane cuts nothing. The result is in
    /// `self`; stops early once fewer than three vertices are left.
    pub fn clip_all(
        &mut self,
        scratch: &mut Self,
        planes: impl IntoIterator<Item = (Vec2, f64, u32)>,
    ) {
        let mut in_scratch = false;
        for (normal, offset, tag) in planes {
            let (from, to) = if in_scratch {
                (&*scratch, &mut *self)
            } else {
                (&*self, &mut *scratch)
            };
            if from.clip_into(normal, offset, tag, to) {
                in_scratch = !in_scratch;
            }
            let now = if in_scratch { &*scratch } else { &*self };
            if now.len < 3 {
                break;
            }
        }
        if in_scratch {
            self.len = scratch.len;
            self.overflow = scratch.overflow;
            self.v[..scratch.len].copy_from_slice(&scratch.v[..scratch.len]);
            self.tag[..scratch.len].copy_from_slice(&scratch.tag[..scratch.len]);
        }
    }

    /// Removes edges shorter than `tol`: the vertex that starts one is dropped, so the previous
    /// edge runs on to the next vertex with its own tag.
    pub fn remove_short_edges(&mut self, tol: f64) {
        let mut k = 0;
        while self.len > 3 && k < self.len {
            let next = (k + 1) % self.len;
            if (self.v[next] - self.v[k]).norm() < tol {
                for m in k..self.len - 1 {
                    self.v[m] = self.v[m + 1];
                    self.tag[m] = self.tag[m + 1];
                }
                self.len -= 1;
            } else {
                k += 1;
            }
        }
    }

    pub fn area(&self) -> f64 {
        if self.len < 3 {
            0.0
        } else {
            area(self.vertices())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(side: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(side, 0.0),
            Vec2::new(side, side),
            Vec2::new(0.0, side),
        ]
    }

    #[test]
    fn square_properties() {
        let p = area_properties(&square(2.0));
        assert!((p.area - 4.0).abs() < 1e-14);
        assert!((p.centroid - Vec2::new(1.0, 1.0)).norm() < 1e-14);
        // a^4 / 6 for a square of side a.
        assert!((p.polar_moment - 16.0 / 6.0).abs() < 1e-13);
    }

    #[test]
    fn triangle_far_from_origin() {
        // Right triangle with legs 3 and 4: J about the centroid = A (a² + b²) / 18.
        let o = Vec2::new(1e3, -2e3);
        let v = [o, o + Vec2::new(3.0, 0.0), o + Vec2::new(0.0, 4.0)];
        let p = area_properties(&v);
        assert!((p.area - 6.0).abs() < 1e-9);
        assert!((p.centroid - (o + Vec2::new(1.0, 4.0 / 3.0))).norm() < 1e-9);
        assert!((p.polar_moment - 6.0 * 25.0 / 18.0).abs() < 1e-6);
    }

    #[test]
    fn clip_keeps_tags_and_cuts_where_asked() {
        let mut p = TaggedPolygon::<8>::from_vertices(&square(1.0), 0);
        // Keep x <= 0.25.
        p.clip(Vec2::new(1.0, 0.0), 0.25, 7);
        assert_eq!(p.len, 4);
        assert!((p.area() - 0.25).abs() < 1e-15);
        // Exactly one edge lies on the cut and carries its tag.
        let on_cut: Vec<usize> = (0..p.len).filter(|&k| p.tag[k] == 7).collect();
        assert_eq!(on_cut.len(), 1);
        let k = on_cut[0];
        assert!((p.v[k].x - 0.25).abs() < 1e-15 && (p.v[(k + 1) % 4].x - 0.25).abs() < 1e-15);
        // Cutting along an existing edge leaves the polygon as it is.
        p.clip(Vec2::new(0.0, -1.0), 0.0, 9);
        assert_eq!(p.len, 4);
        assert!((p.area() - 0.25).abs() < 1e-15);
        // Cutting everything away leaves nothing.
        p.clip(Vec2::new(1.0, 0.0), -1.0, 3);
        assert_eq!(p.len, 0);
    }
}
