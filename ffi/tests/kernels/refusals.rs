//! What the kernels refuse: null pointers and bad input, a split of a grain without size or
//! mass; and the last-error message they leave alone.

use super::*;

#[test]
fn null_pointers_and_bad_input_are_refused() {
    let mut d = Draw::new(11);
    let (law, _) = laws(true, true, 0.3);
    let sphere = c_body(&random_body(&mut d, true));
    let poly = c_body(&random_body(&mut d, false));
    let mut bad = poly;
    bad.semi[3] = -1e-4;
    let mut nan = poly;
    nan.semi[0] = f64::NAN;
    let v = [0.0, 0.0, 1.0];
    let mut h = [0.0; 3];
    let mut mem = FractumPairMemory::default();
    let mut c = FractumContact::default();
    let mut g = FractumGeometry::default();
    let p = v.as_ptr();

    let s = fractum_kernel_hertz_mindlin(
        null(),
        p,
        1e-6,
        1e-3,
        1e-6,
        p,
        h.as_mut_ptr(),
        1e-8,
        1,
        &mut c,
    );
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_hertz_mindlin(&law, p, 1e-6, 1e-3, 1e-6, p, null_mut(), 1e-8, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_NULL);
    assert_eq!(
        fractum_kernel_convex_contact(&sphere, null(), p, &mut g),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_convex_contact(&sphere, &poly, p, null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_convex_contact(&sphere, &bad, p, &mut g),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_wall_geometry(&poly, p, null(), &mut g),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_wall_geometry(&nan, p, p, &mut g),
        FRACTUM_ERR_INPUT
    );
    let s = fractum_kernel_pair(&law, &sphere, &poly, null_mut(), 1e-8, 1, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_pair(&law, &bad, &poly, &mut mem, 1e-8, 1, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let s = fractum_kernel_pair(&law, &sphere, &bad, &mut mem, 1e-8, 1, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let mut place = FractumPlacement::default();
    assert_eq!(
        fractum_kernel_placement(&bad, &mut place),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_placement(&poly, null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(fractum_kernel_placement(&poly, &mut place), FRACTUM_OK);
    let s = fractum_kernel_pair_placed(
        &law,
        &sphere,
        null(),
        &poly,
        &place,
        &mut mem,
        1e-8,
        1,
        1,
        &mut c,
    );
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_wall(&law, &poly, p, p, null(), &mut mem, 1e-8, 1, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_wall(&law, &bad, p, p, p, &mut mem, 1e-8, 1, 1, &mut c);
    assert_eq!(s, FRACTUM_ERR_INPUT);

    let mut body = FractumBody::default();
    let q = [1.0, 0.0, 0.0, 0.0];
    let mut semi = [1e-3; 6];
    let s = fractum_kernel_poly_ellipsoid_body(semi.as_ptr(), 1e-6, p, null(), &mut body);
    assert_eq!(s, FRACTUM_ERR_NULL);
    semi[4] = 0.0;
    let s = fractum_kernel_poly_ellipsoid_body(semi.as_ptr(), 1e-6, p, q.as_ptr(), &mut body);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let mut x = 0.0;
    assert_eq!(fractum_kernel_body_volume(null(), &mut x), FRACTUM_ERR_NULL);
    assert_eq!(fractum_kernel_body_volume(&bad, &mut x), FRACTUM_ERR_INPUT);

    let m = [0.0; 9];
    let mut out9 = [0.0; 9];
    let s = fractum_kernel_average_stress(&poly, null(), p, out9.as_mut_ptr());
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_average_stress(&bad, m.as_ptr(), p, out9.as_mut_ptr());
    assert_eq!(s, FRACTUM_ERR_INPUT);
    assert_eq!(
        fractum_kernel_principal_compressions(m.as_ptr(), null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_hoek_brown_fails(1.0, 0.0, 1.0, 1.0, null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_contact_tensile_stress(1.0, 1.0, 0.2, null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_weibull_factor(0.5, 1.0, 1.0, 1.0, null_mut()),
        FRACTUM_ERR_NULL
    );
    let mut found = 0;
    let mut n3 = [0.0; 3];
    let s = fractum_kernel_contacts_plane_normal(null(), 3, n3.as_mut_ptr(), &mut found);
    assert_eq!(s, FRACTUM_ERR_NULL);

    let fl = fracture_law(4, true, true);
    let mut t = FractumTrigger::default();
    let s = fractum_kernel_check(&fl, &poly, 1.0, m.as_ptr(), p, 2, null(), 0.0, &mut t);
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_check(&fl, &bad, 1.0, m.as_ptr(), p, 0, null(), 0.0, &mut t);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let many = fracture_law(17, true, true);
    let s = fractum_kernel_check(&many, &poly, 1.0, m.as_ptr(), p, 0, null(), 0.0, &mut t);
    assert_eq!(s, FRACTUM_ERR_INPUT);

    let mut split = FractumSplit::default();
    let hb = FractumTrigger {
        kind: 1,
        ..Default::default()
    };
    let none = FractumTrigger::default();
    let s = fractum_kernel_split(&fl, &poly, p, p, null(), null(), &mut split);
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_split(&fl, &poly, p, p, &none, null(), &mut split);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let s = fractum_kernel_split(&fl, &bad, p, p, &hb, null(), &mut split);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let s = fractum_kernel_split(&fl, &sphere, p, p, &hb, null(), &mut split);
    assert_eq!(s, FRACTUM_OK);
    let mut u6 = [0.5; 6];
    assert_eq!(
        fractum_kernel_jitter_angles(u6.as_ptr(), null_mut()),
        FRACTUM_ERR_NULL
    );
    assert_eq!(
        fractum_kernel_jitter_angles(null(), u6.as_mut_ptr()),
        FRACTUM_ERR_NULL
    );

    let mut springs = [FractumSpring::default(); 16];
    let mut made = 0;
    let s = fractum_kernel_bond(
        &fl,
        &split.plus,
        &split.minus,
        p,
        p,
        p,
        p,
        &split.pending,
        null_mut(),
        &mut made,
    );
    assert_eq!(s, FRACTUM_ERR_NULL);
    let s = fractum_kernel_bond(
        &fl,
        &split.plus,
        &bad,
        p,
        p,
        p,
        p,
        &split.pending,
        springs.as_mut_ptr(),
        &mut made,
    );
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let mut pend = split.pending;
    pend.count = 17;
    let s = fractum_kernel_bond(
        &fl,
        &split.plus,
        &split.minus,
        p,
        p,
        p,
        p,
        &pend,
        springs.as_mut_ptr(),
        &mut made,
    );
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let demand = [0.0; 15];
    let s = fractum_kernel_spring_initial_forces(
        split.pending.points.as_ptr(),
        4,
        demand.as_ptr(),
        null_mut(),
    );
    assert_eq!(s, FRACTUM_ERR_NULL);
    let mut sp = FractumSpring::default();
    let (mut w, mut br) = (0.0, 0);
    let s = fractum_kernel_spring(
        &mut sp,
        &poly,
        &poly,
        h.as_mut_ptr(),
        h.as_mut_ptr(),
        null_mut(),
        &mut w,
        &mut br,
    );
    assert_eq!(s, FRACTUM_ERR_NULL);
    let mut f3 = [0.0; 3];
    let mut t3 = [0.0; 3];
    let s = fractum_kernel_spring(
        &mut sp,
        &poly,
        &bad,
        h.as_mut_ptr(),
        f3.as_mut_ptr(),
        t3.as_mut_ptr(),
        &mut w,
        &mut br,
    );
    assert_eq!(s, FRACTUM_ERR_INPUT);
}

/// A grain of zero (or negative, or non-finite) radius or mass is refused with
/// FRACTUM_ERR_INPUT: a zero-radius sphere panicked in the split (FRACTUM_ERR_INTERNAL and
/// a panic message on the host's stderr).
#[test]
fn split_of_a_grain_without_size_or_mass_is_refused_as_input() {
    let mut d = Draw::new(11);
    let fl = fracture_law(4, true, true);
    let hb = FractumTrigger {
        kind: 1,
        ..Default::default()
    };
    let v = [0.0; 3];
    for sphere in [true, false] {
        let good = c_body(&random_body(&mut d, sphere));
        for (radius, mass) in [
            (0.0, good.mass),
            (-1e-3, good.mass),
            (f64::NAN, good.mass),
            (f64::INFINITY, good.mass),
            (good.radius, 0.0),
            (good.radius, f64::NAN),
        ] {
            let mut bad = good;
            bad.radius = radius;
            bad.mass = mass;
            let mut split = FractumSplit::default();
            let s =
                fractum_kernel_split(&fl, &bad, v.as_ptr(), v.as_ptr(), &hb, null(), &mut split);
            assert_eq!(
                s, FRACTUM_ERR_INPUT,
                "sphere {sphere}, radius {radius}, mass {mass}"
            );
        }
    }
}

/// The kernels leave the handle API's last-error message alone.
#[test]
fn kernels_keep_the_last_error() {
    assert_eq!(fractum_free(u64::MAX), FRACTUM_ERR_HANDLE);
    // SAFETY: fractum_last_error returns a valid NUL-terminated string.
    let before = unsafe { std::ffi::CStr::from_ptr(fractum_last_error()) }.to_owned();
    assert!(!before.is_empty());
    let mut x = 0.0;
    assert_eq!(fractum_kernel_body_volume(null(), &mut x), FRACTUM_ERR_NULL);
    let mut law = FractumContactLaw::default();
    assert_eq!(
        fractum_kernel_contact_law(YOUNG, POISSON, 0.5, 0.3, 0, 1, &mut law),
        FRACTUM_OK
    );
    // SAFETY: as above.
    let after = unsafe { std::ffi::CStr::from_ptr(fractum_last_error()) }.to_owned();
    assert_eq!(before, after);
}
