use super::*;

#[test]
fn sphere_sphere_is_exact() {
    let (ra, rb) = (0.3e-3, 0.2e-3);
    let ca = Vector3::new(1e-3, 2e-3, -0.5e-3);
    let dir = Vector3::new(0.3, -0.8, 0.52).normalize();
    for overlap in [1e-9, 1e-6, 1e-5, 1e-4] {
        let cb = ca - dir * (ra + rb - overlap);
        let a = Placed::sphere(ra, ca);
        let b = Placed::sphere(rb, cb);
        let c = contact(&a, &b, &(ca - cb)).unwrap();
        assert!(
            (c.depth - overlap).abs() < 1e-12 * (ra + rb),
            "{} vs {overlap}",
            c.depth
        );
        assert!((c.normal - dir).norm() < 1e-12);
        assert!((c.r_eff - ra * rb / (ra + rb)).abs() < 1e-12 * ra);
        assert!((c.point_a - (ca - dir * ra)).norm() < 1e-12 * ra);
        assert!((c.point_b - (cb + dir * rb)).norm() < 1e-12 * ra);
        assert_eq!(c.iterations, 0);
        // Zero guess: the centre-to-centre fallback gives the same contact.
        let z = contact(&a, &b, &Vector3::zeros()).unwrap();
        assert!((z.depth - c.depth).abs() < 1e-15 && (z.normal - c.normal).norm() < 1e-15);
        let nan = contact(&a, &b, &Vector3::new(f64::NAN, 0.0, 1.0)).unwrap();
        assert_eq!(nan, z);
        // A poor guess converges too.
        let off = contact(&a, &b, &(dir + Vector3::new(0.3, 0.2, -0.1))).unwrap();
        assert!((off.depth - overlap).abs() < 1e-12 * (ra + rb));
        assert!((off.normal - dir).norm() < 1e-11);
    }
    let far = Placed::sphere(rb, ca - dir * (ra + rb + 1e-9));
    assert!(contact(&Placed::sphere(ra, ca), &far, &dir).is_none());
}

#[test]
fn sphere_wall_is_exact() {
    let r = 0.3e-3;
    let n = Vector3::new(0.1, 0.2, 1.0).normalize();
    let x_w = Vector3::new(0.4e-3, -0.1e-3, 0.2e-3);
    for overlap in [1e-9, 1e-6, 1e-4] {
        let c = x_w + n * (r - overlap) + Vector3::new(-n.y, n.x, 0.0) * 1e-3;
        let hit = wall_contact(&Placed::sphere(r, c), &n, &x_w).unwrap();
        assert!((hit.depth - overlap).abs() < 1e-12 * r);
        assert!((hit.r_eff - r).abs() < 1e-12 * r);
        assert_eq!(hit.normal, n);
        assert!((hit.point_a - (c - r * n)).norm() < 1e-12 * r);
        assert!((hit.point_b - hit.point_a - overlap * n).norm() < 1e-12 * r);
    }
    assert!(wall_contact(&Placed::sphere(r, x_w + n * (r + 1e-12)), &n, &x_w).is_none());
}
