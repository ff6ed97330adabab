//! Regular lattices of equal spheres in a box that fits them exactly (walls touch the outer
//! spheres).

use crate::state::Vec3;

/// Simple cubic lattice of `layers = [nx, ny, nz]` touching spheres of radius `r`. Returns
/// the centres and the box size.
pub fn simple_cubic_positions(r: f64, layers: [usize; 3]) -> (Vec<Vec3>, Vec3) {
    let [nx, ny, nz] = layers;
    let d = 2.0 * r;
    let mut pos = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                pos.push(Vec3::new(
                    r + d * i as f64,
                    r + d * j as f64,
                    r + d * k as f64,
                ));
            }
        }
    }
    (pos, Vec3::new(d * nx as f64, d * ny as f64, d * nz as f64))
}

/// Hexagonal close packing (ABAB stacking along z) of `layers = [nx, ny, nz]`: nx spheres per
/// row, ny rows per layer, nz layers. Rows are √3·r apart, layers 2·√(2/3)·r apart; odd rows
/// and odd layers shift by r along x, odd layers by r/√3 along y. For r = 0.3 mm and 10³ this
/// gives the 6.300 × 5.450 × 5.009 mm box of the paper's Table 3.
pub fn hcp_positions(r: f64, layers: [usize; 3]) -> (Vec<Vec3>, Vec3) {
    let [nx, ny, nz] = layers;
    let row = 3.0_f64.sqrt() * r;
    let layer = 2.0 * (2.0_f64 / 3.0).sqrt() * r;
    let mut pos = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        let (kx, ky) = if k % 2 == 1 {
            (r, row / 3.0)
        } else {
            (0.0, 0.0)
        };
        for j in 0..ny {
            let jx = if j % 2 == 1 { r } else { 0.0 };
            for i in 0..nx {
                pos.push(Vec3::new(
                    r + 2.0 * r * i as f64 + ((jx + kx) % (2.0 * r)),
                    r + row * j as f64 + ky,
                    r + layer * k as f64,
                ));
            }
        }
    }
    let x = 2.0 * r * nx as f64 + if ny > 1 || nz > 1 { r } else { 0.0 };
    let y = 2.0 * r + row * (ny.max(1) - 1) as f64 + if nz > 1 { row / 3.0 } else { 0.0 };
    let z = 2.0 * r + layer * (nz.max(1) - 1) as f64;
    (pos, Vec3::new(x, y, z))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn min_gap(pos: &[Vec3], r: f64) -> f64 {
        let mut g = f64::INFINITY;
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                g = g.min((pos[i] - pos[j]).norm() - 2.0 * r);
            }
        }
        g
    }

    #[test]
    fn hcp_box_matches_paper_table_3() {
        let r = 0.3e-3;
        let (pos, size) = hcp_positions(r, [10, 10, 10]);
        assert_eq!(pos.len(), 1000);
        assert!((size.x - 6.300e-3).abs() < 1e-6);
        assert!((size.y - 5.450e-3).abs() < 1e-6);
        assert!((size.z - 5.009e-3).abs() < 1e-6);
        // Touching, never overlapping, and 12 neighbours for an interior sphere.
        assert!(min_gap(&pos, r).abs() < 1e-15);
        let centre = pos
            .iter()
            .position(|p| (p - Vec3::new(3.0e-3, 2.7e-3, 2.5e-3)).norm() < 0.45e-3)
            .unwrap();
        let touching = pos
            .iter()
            .filter(|p| ((*p - pos[centre]).norm() - 2.0 * r).abs() < 1e-12)
            .count();
        assert_eq!(touching, 12);
        // Every sphere inside the box.
        assert!(
            pos.iter()
                .all(|p| (0..3).all(|a| p[a] >= r - 1e-15 && p[a] <= size[a] - r + 1e-15))
        );
    }

    #[test]
    fn simple_cubic_solid_fraction_is_pi_over_six() {
        let r = 0.3e-3;
        let (pos, size) = simple_cubic_positions(r, [10, 10, 10]);
        let phi = pos.len() as f64 * crate::shape::sphere_volume(r) / (size.x * size.y * size.z);
        assert!((phi - std::f64::consts::PI / 6.0).abs() < 1e-12);
        assert!(min_gap(&pos, r).abs() < 1e-15);
    }
}
