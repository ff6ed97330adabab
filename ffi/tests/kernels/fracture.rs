//! The fracture exports against the library: the counting keys' ranges, the criteria, the
//! check, the split, bonds and springs, the jitter and the uniforms, bit for bit.

use super::*;

/// Each counting fracture key is refused by the kernels at the bounds the library gives
/// (the scene's checks take the same constants; tests/bad_input.rs and the plugin's
/// tests check those layers).
#[test]
fn fracture_ranges_are_the_librarys_and_bound_the_kernels() {
    let (mut lo, mut hi) = (0.0, 0.0);
    for (key, range) in [
        (c"critical_contacts", fractum::fracture::CRITICAL_CONTACTS),
        (c"springs", fractum::fracture::SPRINGS),
    ] {
        assert_eq!(
            fractum_kernel_fracture_range(key.as_ptr(), &mut lo, &mut hi),
            FRACTUM_OK
        );
        assert_eq!((lo, hi), (range.0 as f64, range.1 as f64));
    }
    assert_eq!(
        fractum_kernel_fracture_range(c"mi".as_ptr(), &mut lo, &mut hi),
        FRACTUM_ERR_INPUT
    );
    let ok = |critical: i32, springs: i32| {
        let mut l = fracture_law(springs, true, true);
        l.critical_contacts = critical;
        // The law is read first: a law taken, the null grain after it is refused as null.
        let no_grain =
            fractum_kernel_check(&l, null(), 0.0, null(), null(), 0, null(), 0.0, null_mut());
        no_grain == FRACTUM_ERR_NULL
    };
    let (c, s) = (
        fractum::fracture::CRITICAL_CONTACTS,
        fractum::fracture::SPRINGS,
    );
    assert!(ok(c.0 as i32, 0) && ok(c.1 as i32, 0));
    assert!(!ok(c.0 as i32 - 1, 0) && !ok(c.1 as i32 + 1, 0));
    assert!(ok(3, s.0 as i32) && ok(3, s.1 as i32));
    assert!(!ok(3, s.0 as i32 - 1) && !ok(3, s.1 as i32 + 1));
}

#[test]
fn criteria_give_the_library_bits() {
    let mut d = Draw::new(6);
    for case in 0..100 {
        let b = random_body(&mut d, case % 2 == 0);
        let moment: [f64; 9] = std::array::from_fn(|_| d.range(-1e-2, 1e-2));
        let torque = d.vec(1e-3);
        let mut stress = [0.0; 9];
        let s = fractum_kernel_average_stress(
            &body_out(&b),
            moment.as_ptr(),
            torque.as_ptr(),
            stress.as_mut_ptr(),
        );
        assert_eq!(s, FRACTUM_OK);
        let m = grain_average_stress(&b, &Matrix3::from_row_slice(&moment), &torque);
        let rows: Vec<f64> = (0..9).map(|k| m[(k / 3, k % 3)]).collect();
        assert_eq!(bits(&stress), bits(&rows));
        let mut p = [0.0; 3];
        let s = fractum_kernel_principal_compressions(stress.as_ptr(), p.as_mut_ptr());
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(bits(&p), bits(&criteria::principal_compression_values(&m)));
        let (s1, s3, sc, mi) = (
            d.range(-1e8, 1e9),
            d.range(-1e8, 1e8),
            d.range(1e8, 1e9),
            d.range(5.0, 25.0),
        );
        let mut fails = -1;
        let s = fractum_kernel_hoek_brown_fails(s1, s3, sc, mi, &mut fails);
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(fails, i32::from(criteria::hoek_brown_fails(s1, s3, sc, mi)));
        let (f, a, nu) = (d.range(0.0, 50.0), d.range(1e-6, 1e-4), d.range(0.1, 0.4));
        let mut st = 0.0;
        let s = fractum_kernel_contact_tensile_stress(f, a, nu, &mut st);
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(
            st.to_bits(),
            criteria::contact_tensile_stress(f, a, nu).to_bits()
        );
        let (pr, w, x, xm) = (d.u(), d.range(1.0, 5.0), d.range(1e-4, 1e-3), 5e-4);
        let mut wf = 0.0;
        assert_eq!(
            fractum_kernel_weibull_factor(pr, w, x, xm, &mut wf),
            FRACTUM_OK
        );
        assert_eq!(
            wf.to_bits(),
            criteria::weibull_factor(pr, w, x, xm).to_bits()
        );
        let n = case % 6;
        let pts: Vec<[f64; 3]> = (0..n).map(|_| d.vec(1e-3).into()).collect();
        let (mut normal, mut found) = ([9.0; 3], -1);
        let s =
            fractum_kernel_contacts_plane_normal(pts.as_ptr(), n, normal.as_mut_ptr(), &mut found);
        assert_eq!(s, FRACTUM_OK);
        let v: Vec<Vec3> = pts.iter().map(|p| Vec3::from(*p)).collect();
        match break_plane::contacts_plane_normal(&v) {
            Some(nrm) => {
                assert_eq!(found, 1);
                assert_eq!(bits(&normal), vb(&nrm));
            }
            None => assert_eq!((found, normal), (0, [0.0; 3])),
        }
    }
    let line = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let (mut normal, mut found) = ([0.0; 3], -1);
    let s = fractum_kernel_contacts_plane_normal(line.as_ptr(), 3, normal.as_mut_ptr(), &mut found);
    assert_eq!((s, found), (FRACTUM_OK, 0));
}

#[test]
fn check_gives_the_library_bits() {
    let mut d = Draw::new(7);
    let mut kinds = [0usize; 3];
    for case in 0..200 {
        let law = FractumFractureLaw {
            weibull_sigma_c: i32::from(d.flag()),
            ..fracture_law(4, d.flag(), d.flag())
        };
        let p = fracture_params_in(&law);
        let b = random_body(&mut d, case % 2 == 0);
        // Up to 2.5 times the force that fails a sphere in uniaxial compression.
        let f = d.range(0.0, 2.5) * law.sigma_c * 2.0 * std::f64::consts::PI * b.radius * b.radius
            / 3.0;
        let m = squeeze(&b, d.unit(), f);
        let torque = d.vec(1e-4);
        let strength = d.range(0.5, 2.0);
        let n_critical = case % 6;
        let pts: Vec<[f64; 3]> = (0..n_critical).map(|_| d.vec(1e-3).into()).collect();
        let top = d.range(1e9, 5e9);
        let v: Vec<Vec3> = pts.iter().take(3).map(|p| Vec3::from(*p)).collect();
        let t = grain_fails(&p, &b, strength, &m, &torque, n_critical, &v, top);
        let rows: Vec<f64> = (0..9).map(|k| m[(k / 3, k % 3)]).collect();
        let mut out = FractumTrigger::default();
        let s = fractum_kernel_check(
            &law,
            &body_out(&b),
            strength,
            rows.as_ptr(),
            torque.as_ptr(),
            n_critical,
            if n_critical == 0 {
                null()
            } else {
                pts.as_ptr()
            },
            top,
            &mut out,
        );
        assert_eq!(s, FRACTUM_OK);
        same_trigger(&out, &t);
        kinds[out.kind as usize] += 1;
    }
    assert!(kinds.iter().all(|&k| k > 20), "{kinds:?}");
}

/// Splits of spheres (ideal plane or not, with and without the slight rotation) and
/// poly-ellipsoids (well and badly shaped) by either trigger, with and without
/// cohesion; then the bond of each split and its springs' evaluations as the halves
/// part, until they break.
#[test]
fn split_bond_and_springs_give_the_library_bits() {
    let mut d = Draw::new(8);
    let (mut splits, mut springs_made, mut broke, mut forbidden) = (0, 0, 0, 0);
    for case in 0..120 {
        let springs = [0, 3, 4, 16][case % 4];
        let law = fracture_law(springs, d.flag(), d.flag());
        let p = fracture_params_in(&law);
        let mut b = random_body(&mut d, case % 3 != 0);
        if case % 12 == 5 {
            let pe = PolyEllipsoid::new([1e-3, 0.1e-3, 1e-3, 0.1e-3, 1e-3, 0.1e-3]).unwrap();
            b = Body::poly_ellipsoid(pe, 1e-6, b.pos, d.quat());
        }
        let trigger = if d.flag() {
            let m = squeeze(&b, d.unit(), 50.0);
            Trigger::HoekBrown {
                stress: m / b.volume() + Matrix3::from_fn(|_, _| d.range(-1e6, 1e6)),
            }
        } else {
            Trigger::Contacts { normal: d.unit() }
        };
        let ft = match trigger {
            Trigger::HoekBrown { stress } => FractumTrigger {
                kind: 1,
                stress: std::array::from_fn(|k| stress[(k / 3, k % 3)]),
                ..Default::default()
            },
            Trigger::Contacts { normal } => FractumTrigger {
                kind: 2,
                normal: normal.into(),
                ..Default::default()
            },
        };
        let (force, torque) = (d.vec(30.0), d.vec(1e-3));
        let u: [f64; 6] = std::array::from_fn(|_| d.u());
        let jitter = d.flag().then(|| break_plane::jitter_angles(&u));
        let lib = split_grain(&p, &b, &force, &torque, &trigger, jitter);
        let mut out = FractumSplit::default();
        let s = fractum_kernel_split(
            &law,
            &body_out(&b),
            force.as_ptr(),
            torque.as_ptr(),
            &ft,
            jitter.as_ref().map_or(null(), |j| j.as_ptr()),
            &mut out,
        );
        assert_eq!(s, FRACTUM_OK);
        // Asked first, the shape test agrees with the split.
        let mut can = -1;
        assert_eq!(
            fractum_kernel_can_break(&body_out(&b), &mut can),
            FRACTUM_OK
        );
        assert_eq!(can, i32::from(out.axis >= 0));
        forbidden += usize::from(can == 0);
        let Some(split) = lib else {
            assert_eq!(out.axis, -1);
            continue;
        };
        splits += 1;
        assert_eq!(out.axis as usize, split.axis);
        assert_eq!(body_bits(&out.plus), body_bits(&body_out(&split.plus)));
        assert_eq!(body_bits(&out.minus), body_bits(&body_out(&split.minus)));
        same_pending(&out.pending, &split.pending);

        // The bond, under the halves' own forces after the split.
        let (pa, pb) = (split.plus, split.minus);
        let loads = [d.vec(10.0), d.vec(1e-3), d.vec(10.0), d.vec(1e-3)];
        let mut made: Vec<MadeSpring> = Vec::new();
        if let Some((gc, _)) = p.cohesion {
            let [fa, ta, fb_, tb] = &loads;
            bond_split(gc, &pa, &pb, [fa, ta, fb_, tb], &split.pending, |m| {
                made.push(m)
            });
        }
        let mut fsprings = [FractumSpring::default(); 16];
        let mut n_made = -1;
        let s = fractum_kernel_bond(
            &law,
            &body_out(&pa),
            &body_out(&pb),
            loads[0].as_ptr(),
            loads[1].as_ptr(),
            loads[2].as_ptr(),
            loads[3].as_ptr(),
            &out.pending,
            fsprings.as_mut_ptr(),
            &mut n_made,
        );
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(n_made as usize, made.len());
        springs_made += made.len();
        for (k, m) in made.iter().enumerate() {
            assert_eq!(
                spring_bits(&fsprings[k]),
                spring_bits(&spring_out(&m.spring))
            );
            assert_eq!(bits(&fsprings[k].last_force), vb(&m.force));
        }

        // Each spring as the halves part: evaluated until it breaks.
        let (mut a, mut bb) = (pa, pb);
        let apart = (pa.pos - pb.pos).normalize();
        for (k, m) in made.iter().enumerate() {
            let mut lib = m.spring.clone();
            let mut fs = fsprings[k];
            for step in 0..400 {
                a.pos += apart * (1e-9 * step as f64);
                bb.pos -= apart * (1e-9 * step as f64);
                bb.orientation = UnitQuaternion::from_scaled_axis(d.vec(1e-4)) * bb.orientation;
                let act = lib.act(&a.pos, &a.orientation, &bb.pos, &bb.orientation);
                let (mut f, mut ta, mut tb, mut w, mut br) =
                    ([9.0; 3], [9.0; 3], [9.0; 3], 9.0, -1);
                let s = fractum_kernel_spring(
                    &mut fs,
                    &body_out(&a),
                    &body_out(&bb),
                    f.as_mut_ptr(),
                    ta.as_mut_ptr(),
                    tb.as_mut_ptr(),
                    &mut w,
                    &mut br,
                );
                assert_eq!(s, FRACTUM_OK);
                assert_eq!(spring_bits(&fs), spring_bits(&spring_out(&lib)));
                assert_eq!(bits(&f), vb(&act.force));
                assert_eq!(bits(&ta), vb(&act.torque_a));
                assert_eq!(bits(&tb), vb(&act.torque_b));
                assert_eq!(
                    (w.to_bits(), br),
                    (act.work.to_bits(), i32::from(act.broke))
                );
                if act.broke {
                    broke += 1;
                    // A broken spring does nothing more.
                    let s = fractum_kernel_spring(
                        &mut fs,
                        &body_out(&a),
                        &body_out(&bb),
                        f.as_mut_ptr(),
                        ta.as_mut_ptr(),
                        tb.as_mut_ptr(),
                        &mut w,
                        &mut br,
                    );
                    assert_eq!((s, br, w, f), (FRACTUM_OK, 0, 0.0, [0.0; 3]));
                    break;
                }
            }
        }
    }
    assert!(
        splits > 60 && springs_made > 200 && broke > 100 && forbidden > 5,
        "{splits} {springs_made} {broke} {forbidden}"
    );
}

#[test]
fn spring_initial_forces_give_the_library_bits() {
    let mut d = Draw::new(9);
    for n in [0usize, 3, 4, 7, 16] {
        let pts: Vec<[f64; 3]> = (0..n).map(|_| d.vec(1e-3).into()).collect();
        let demand: [f64; 15] =
            std::array::from_fn(|k| d.range(-1.0, 1.0) * [10.0, 1e-3, 10.0, 1e-3, 1e-3][k / 3]);
        let v = |k: usize| Vec3::new(demand[3 * k], demand[3 * k + 1], demand[3 * k + 2]);
        let lib = cohesion::initial_forces(
            &pts.iter().map(|p| Vec3::from(*p)).collect::<Vec<_>>(),
            &Demand {
                force_a: v(0),
                torque_a: v(1),
                force_b: v(2),
                torque_b: v(3),
                b_offset: v(4),
            },
        );
        let mut forces = vec![[9.0; 3]; n];
        let s = fractum_kernel_spring_initial_forces(
            if n == 0 { null() } else { pts.as_ptr() },
            n,
            demand.as_ptr(),
            if n == 0 {
                null_mut()
            } else {
                forces.as_mut_ptr()
            },
        );
        assert_eq!(s, FRACTUM_OK);
        for (f, l) in forces.iter().zip(&lib) {
            assert_eq!(bits(f), vb(l));
        }
    }
}

#[test]
fn jitter_angles_and_uniforms_give_the_library_bits() {
    let mut d = Draw::new(10);
    for _ in 0..100 {
        let u: [f64; 6] = std::array::from_fn(|_| d.u());
        let mut angles = [0.0; 3];
        let s = fractum_kernel_jitter_angles(u.as_ptr(), angles.as_mut_ptr());
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(bits(&angles), bits(&break_plane::jitter_angles(&u)));
    }
    for (seed, key, counter, n) in [(1u64, 2u64, 0u64, 10usize), (1, 2, 1, 10), (7, 0, 12345, 3)] {
        let mut out = vec![0.0; n];
        let s = fractum_kernel_uniforms(seed, key, counter, n, out.as_mut_ptr());
        assert_eq!(s, FRACTUM_OK);
        let mut lib = vec![0.0; n];
        uniforms(seed, key, counter, &mut lib);
        assert_eq!(bits(&out), bits(&lib));
        assert!(out.iter().all(|&x| x > 0.0 && x <= 1.0));
    }
    let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
    fractum_kernel_uniforms(1, 2, 0, 4, a.as_mut_ptr());
    fractum_kernel_uniforms(1, 2, 1, 4, b.as_mut_ptr());
    assert_ne!(a, b);
    let mut x = 0.0;
    let s = fractum_kernel_uniforms(1, 2, UNIFORM_COUNTERS, 1, &mut x);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    assert_eq!(fractum_kernel_uniforms(1, 2, 0, 0, null_mut()), FRACTUM_OK);
    assert_eq!(
        fractum_kernel_uniforms(1, 2, 0, 1, null_mut()),
        FRACTUM_ERR_NULL
    );
}
