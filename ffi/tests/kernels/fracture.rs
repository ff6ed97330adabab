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
            &c_body(&b),
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
            particle_strength: 0,
            comminution_limit: 0.0,
            ..fracture_law(4, d.flag(), d.flag())
        };
        let p = law_params(&law);
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
            &c_body(&b),
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
        let p = law_params(&law);
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
            &c_body(&b),
            force.as_ptr(),
            torque.as_ptr(),
            &ft,
            jitter.as_ref().map_or(null(), |j| j.as_ptr()),
            &mut out,
        );
        assert_eq!(s, FRACTUM_OK);
        // Asked first, the shape test agrees with the split.
        let mut can = -1;
        assert_eq!(fractum_kernel_can_break(&c_body(&b), &mut can), FRACTUM_OK);
        assert_eq!(can, i32::from(out.axis >= 0));
        forbidden += usize::from(can == 0);
        let Some(split) = lib else {
            assert_eq!(out.axis, -1);
            continue;
        };
        splits += 1;
        assert_eq!(out.axis as usize, split.axis);
        assert_eq!(body_bits(&out.plus), body_bits(&c_body(&split.plus)));
        assert_eq!(body_bits(&out.minus), body_bits(&c_body(&split.minus)));
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
            &c_body(&pa),
            &c_body(&pb),
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
            assert_eq!(spring_bits(&fsprings[k]), spring_bits(&c_spring(&m.spring)));
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
                    &c_body(&a),
                    &c_body(&bb),
                    f.as_mut_ptr(),
                    ta.as_mut_ptr(),
                    tb.as_mut_ptr(),
                    &mut w,
                    &mut br,
                );
                assert_eq!(s, FRACTUM_OK);
                assert_eq!(spring_bits(&fs), spring_bits(&c_spring(&lib)));
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
                        &c_body(&a),
                        &c_body(&bb),
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

/// The halves of a split, each field of both FractumBodies against the number the split's
/// docs give for it, written out by hand: [`hand_body`] broken by contacts whose plane is
/// normal to world y, its shape frame's x axis, so it splits normal to x through its octant
/// origin (fractum::fracture::subdivision: the + half's semi-axes 0.9 a+ and 0.1 a+ along x,
/// the others times r_c = sqrt(0.9), its octant origin 0.1 a+ ahead of the parent's; the -
/// half's 0.1 a- and 0.9 a-, 0.1 a- behind; the masses in the volumes' proportion 1 : 0.9;
/// both shifted to keep the centre of mass; moving as the parent did, v = v_P + omega x
/// (x - x_P), the same omega). Lopsided along x only, each half's principal frame is its
/// shape frame, the parent's: body to world 120 degrees about (1, 1, 1) after 180 degrees
/// about x, w x y z = -0.5 0.5 0.5 -0.5, and shape to body the identity.
#[test]
fn split_halves_fields_by_hand() {
    let law = fracture_law(0, false, false);
    let trigger = FractumTrigger {
        kind: 2,
        normal: [0.0, 1.0, 0.0],
        ..Default::default()
    };
    let (force, torque) = ([20.0, 30.0, 40.0], [0.0; 3]);
    let mut out = FractumSplit::default();
    let s = fractum_kernel_split(
        &law,
        &hand_body(),
        force.as_ptr(),
        torque.as_ptr(),
        &trigger,
        null(),
        &mut out,
    );
    assert_eq!(s, FRACTUM_OK);
    assert_eq!(out.axis, 0);
    let rc = 0.9f64.sqrt();
    let across = [rc * 0.3, rc * 0.3, rc * 0.2, rc * 0.2];
    let semi = |ap: f64, am: f64| [ap, am, across[0], across[1], across[2], across[3]];
    // Along world y, from the parent's octant origin at 2 - 0.0375: the + half's centroid
    // 0.1 + 3/8 (0.9 - 0.1) = 0.4 ahead, the - half's 0.09 + 3/8 (0.81 - 0.09) = 0.36 behind;
    // the shift -0.0025 brings their centre of mass, (2.3625 + 0.9 x 1.6025) / 1.9, to 2.
    // Each half's bounding radius: the tip of its long x semi-axis from its centroid.
    for (half, semi, mass, y, x_bar, radius) in [
        (
            &out.plus,
            semi(0.9 * 1.0, (1.0 - 0.9) * 1.0),
            10.0 / 1.9,
            2.36,
            0.3,
            0.9 - 0.3,
        ),
        (
            &out.minus,
            semi((1.0 - 0.9) * 0.9, 0.9 * 0.9),
            9.0 / 1.9,
            1.6,
            -0.27,
            0.81 - 0.27,
        ),
    ] {
        near(&half.pos, &[1.0, y, 3.0]);
        // (4, 5, 6) + (7, 8, 9) x (0, y - 2, 0)
        let dy = y - 2.0;
        near(&half.vel, &[4.0 - 9.0 * dy, 5.0, 6.0 + 7.0 * dy]);
        assert_eq!(half.omega, [7.0, 8.0, 9.0]);
        near(&half.quat, &[-0.5, 0.5, 0.5, -0.5]);
        near(&[half.mass], &[mass]);
        assert!((half.radius / radius - 1.0).abs() < 2e-9, "{}", half.radius);
        near(&half.semi, &semi);
        near(&half.origin, &[-x_bar, 0.0, 0.0]);
        assert_eq!(half.to_body, [1.0, 0.0, 0.0, 0.0]);
        near(&half.inertia, &moments_lopsided_x(&semi, mass));
        assert_eq!(half.sphere, 0);
    }
    assert_eq!(out.plus.mass + out.minus.mass, 10.0, "the mass, exactly");
    assert_eq!(out.pending.centroid, [1.0, 2.0, 3.0]);
    near(&out.pending.accel, &[2.0, 3.0, 4.0]);
    assert_eq!(out.pending.omega, [7.0, 8.0, 9.0]);
    assert_eq!(out.pending.count, 0, "no cohesion");
}

/// One evaluation of a spring written out field by field, against the numbers the header's
/// docs and Eq. 35 (the force f_i - k opening, along the direction turned with A) give: A
/// and B unturned, the ends (0.06, 0, 0.08) apart, 0.1, beyond the largest elongation so far
/// 0.05. Then the same spring broken: it does nothing and comes back as it was.
#[test]
fn spring_fields_by_hand() {
    let sphere_at = |pos| FractumBody {
        pos,
        quat: [1.0, 0.0, 0.0, 0.0],
        mass: 1.0,
        radius: 1.0,
        semi: [1.0; 6],
        to_body: [1.0, 0.0, 0.0, 0.0],
        inertia: [0.4; 3],
        sphere: 1,
        ..Default::default()
    };
    let spring = FractumSpring {
        on_a: [0.1, 0.2, 0.3],
        on_b: [-0.4, -0.5, -0.6],
        direction: [0.0, 0.6, 0.8],
        f0: 7.0,
        k: 11.0,
        opening: 0.05,
        last_gap: [0.01, 0.02, 0.03],
        last_force: [1.5, 2.5, 3.5],
        broken: 0,
    };
    let a = sphere_at([1.0, 2.0, 3.0]);
    // B's centre: A's end minus the gap minus B's end.
    let b = sphere_at([1.1 - 0.06 + 0.4, 2.2 + 0.5, 3.3 - 0.08 + 0.6]);
    let mut s = spring;
    let (mut f, mut ta, mut tb, mut w, mut br) = ([9.0; 3], [9.0; 3], [9.0; 3], 9.0, -1);
    let status = fractum_kernel_spring(
        &mut s,
        &a,
        &b,
        f.as_mut_ptr(),
        ta.as_mut_ptr(),
        tb.as_mut_ptr(),
        &mut w,
        &mut br,
    );
    assert_eq!(status, FRACTUM_OK);
    // (7 - 11 x 0.1) (0, 0.6, 0.8)
    let force = [0.0, 3.54, 4.72];
    assert_eq!(s.on_a, [0.1, 0.2, 0.3]);
    assert_eq!(s.on_b, [-0.4, -0.5, -0.6]);
    assert_eq!(s.direction, [0.0, 0.6, 0.8]);
    assert_eq!((s.f0, s.k), (7.0, 11.0));
    near(&[s.opening], &[0.1]);
    near(&s.last_gap, &[0.06, 0.0, 0.08]);
    near(&s.last_force, &force);
    assert_eq!(s.broken, 0);
    near(&f, &force);
    // on_a x force, and -(on_b x force)
    near(&ta, &[-0.118, -0.472, 0.354]);
    near(&tb, &[0.236, -1.888, 1.416]);
    // (force + last force) / 2 . (gap - last gap)
    near(&[w], &[0.5 * (1.5 * 0.05 - 6.04 * 0.02 + 8.22 * 0.05)]);
    assert_eq!(br, 0);

    let broken = FractumSpring {
        broken: 1,
        ..spring
    };
    let mut s = broken;
    let status = fractum_kernel_spring(
        &mut s,
        &a,
        &b,
        f.as_mut_ptr(),
        ta.as_mut_ptr(),
        tb.as_mut_ptr(),
        &mut w,
        &mut br,
    );
    assert_eq!(status, FRACTUM_OK);
    assert_eq!(s, broken, "a broken spring comes back as it was");
    assert_eq!((f, ta, tb, w, br), ([0.0; 3], [0.0; 3], [0.0; 3], 0.0, 0));
}

/// A grain load's moment is row-major, element 1 the (0, 1) entry: the sum of force_i
/// lever_j, force (1, 2, 3) at lever (4, 5, 6) and force (-1, 0, 0) at lever (-1, 1, -1), a
/// matrix that is not symmetric. Its critical contacts come largest first: the second, of
/// the larger Hertz force.
#[test]
fn grain_load_fields_by_hand() {
    let mut load = FractumGrainLoad::default();
    let centre = [10.0, 20.0, 30.0];
    let contacts = [
        ([1.0, 2.0, 3.0], [14.0, 25.0, 36.0], 2.0),
        ([-1.0, 0.0, 0.0], [9.0, 21.0, 29.0], 8.0),
    ];
    for (force, point, hertz) in &contacts {
        let s = fractum_kernel_grain_load_add(
            &mut load,
            centre.as_ptr(),
            force.as_ptr(),
            point.as_ptr(),
            *hertz,
            1e-4,
            0.2,
            0.0,
        );
        assert_eq!(s, FRACTUM_OK);
    }
    #[rustfmt::skip]
    let rows = [
        4.0 + 1.0, 5.0 - 1.0, 6.0 + 1.0,
        8.0, 10.0, 12.0,
        12.0, 15.0, 18.0,
    ];
    assert_eq!(load.moment, rows);
    // Element 1 is the (0, 1) entry, 4; element 3 the (1, 0) entry, 8.
    assert_eq!((load.moment[1], load.moment[3]), (4.0, 8.0));
    assert_eq!(load.count, 2);
    let st = |hertz| criteria::contact_tensile_stress(hertz, 1e-4, 0.2);
    assert_eq!(load.stress, [st(8.0), st(2.0), 0.0]);
    assert_eq!(
        load.point,
        [[9.0, 21.0, 29.0], [14.0, 25.0, 36.0], [0.0; 3]]
    );
}

/// A law of distinct values, each field reaching the library as its doc says: the
/// critical-contact count and the Weibull switch decide breaks the test predicts by hand,
/// the spring count the split's spring points; and the check, the split and the bond are the
/// library's under the law's constants taken by name (`law_params`), bit for bit, with the
/// slight rotation's angles given and `plane_jitter` 0.
#[test]
fn fracture_law_fields_by_hand() {
    let law = FractumFractureLaw {
        mi: 11.5,
        sigma_c: 3.25e8,
        sigma_f: 7.75e8,
        poisson: 0.21,
        critical_contacts: 5,
        ideal_plane: 1,
        plane_jitter: 0,
        springs: 7,
        gc: 13.5,
        weibull_sigma_c: 1,
        particle_strength: 0,
        comminution_limit: 0.0,
    };
    let mut bodies = Bodies::default();
    let q = UnitQuaternion::from_scaled_axis(Vec3::new(0.3, -0.2, 0.1));
    bodies.push_sphere(Vec3::new(1e-3, 2e-3, 3e-3), 1e-3, 2650.0, q);
    let b = bodies.body(0);
    let check =
        |law: &FractumFractureLaw, strength, m: &Matrix3<f64>, n: usize, pts: &[[f64; 3]]| {
            let mut out = FractumTrigger::default();
            let s = fractum_kernel_check(
                law,
                &c_body(&b),
                strength,
                c_rows(m).as_ptr(),
                [0.0; 3].as_ptr(),
                n,
                if pts.is_empty() { null() } else { pts.as_ptr() },
                9e8,
                &mut out,
            );
            assert_eq!(s, FRACTUM_OK);
            let v: Vec<Vec3> = pts.iter().map(|p| Vec3::from(*p)).collect();
            let lib = grain_fails(
                &law_params(law),
                &b,
                strength,
                m,
                &Vec3::zeros(),
                n,
                &v,
                9e8,
            );
            same_trigger(&out, &lib);
            (out, lib)
        };
    // Critical contacts: 4 are fewer than the law's 5; 5 break the grain along their plane.
    let pts = [[0.0; 3], [1e-3, 0.0, 0.0], [0.0, 1e-3, 0.0]];
    let unloaded = Matrix3::zeros();
    assert_eq!(check(&law, 1.0, &unloaded, 4, &pts).0.kind, 0);
    let (out, _) = check(&law, 1.0, &unloaded, 5, &pts);
    assert_eq!((out.kind, out.value), (2, 9e8));
    near(
        &[out.normal[0], out.normal[1], out.normal[2].abs()],
        &[0.0, 0.0, 1.0],
    );
    // Squeezed at 3/4 of sigma_c: a grain of Weibull factor 0.5 fails by Hoek-Brown where the
    // factor scales sigma_c (weibull_sigma_c), not where it scales sigma_f only.
    let f = 0.75 * law.sigma_c * 2.0 * std::f64::consts::PI * b.radius * b.radius / 3.0;
    let squeezed = squeeze(&b, Vec3::x(), f);
    let sigma_f_only = FractumFractureLaw {
        weibull_sigma_c: 0,
        particle_strength: 0,
        comminution_limit: 0.0,
        ..law
    };
    assert_eq!(check(&sigma_f_only, 0.5, &squeezed, 0, &[]).0.kind, 0);
    let (out, lib) = check(&law, 0.5, &squeezed, 0, &[]);
    assert_eq!(out.kind, 1);

    // The split (the sphere turned to the ideal plane, the angles not used) and its bond.
    let p = law_params(&law);
    let (trigger, _, _) = lib.unwrap();
    let (force, torque, jitter) = (
        Vec3::new(3.0, -2.0, 1.0),
        Vec3::new(1e-4, 2e-4, -1e-4),
        [0.1; 3],
    );
    let split = split_grain(&p, &b, &force, &torque, &trigger, Some(jitter)).unwrap();
    let mut fs = FractumSplit::default();
    let s = fractum_kernel_split(
        &law,
        &c_body(&b),
        force.as_ptr(),
        torque.as_ptr(),
        &out,
        jitter.as_ptr(),
        &mut fs,
    );
    assert_eq!(s, FRACTUM_OK);
    assert_eq!((fs.axis, fs.pending.count), (0, 7));
    assert_eq!(body_bits(&fs.plus), body_bits(&c_body(&split.plus)));
    assert_eq!(body_bits(&fs.minus), body_bits(&c_body(&split.minus)));
    same_pending(&fs.pending, &split.pending);
    let loads = [
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1e-4, 0.0, 0.0),
        Vec3::new(-2.0, 1.0, 0.5),
        Vec3::new(0.0, -1e-4, 0.0),
    ];
    let mut made = Vec::new();
    let (gc, _) = p.cohesion.unwrap();
    bond_split(
        gc,
        &split.plus,
        &split.minus,
        [&loads[0], &loads[1], &loads[2], &loads[3]],
        &split.pending,
        |m| made.push(m),
    );
    let mut springs = [FractumSpring::default(); 16];
    let mut n_made = -1;
    let s = fractum_kernel_bond(
        &law,
        &fs.plus,
        &fs.minus,
        loads[0].as_ptr(),
        loads[1].as_ptr(),
        loads[2].as_ptr(),
        loads[3].as_ptr(),
        &fs.pending,
        springs.as_mut_ptr(),
        &mut n_made,
    );
    assert_eq!(s, FRACTUM_OK);
    assert_eq!(n_made as usize, made.len());
    assert!(n_made > 0);
    for (s, m) in springs.iter().zip(&made) {
        assert_eq!(spring_bits(s), spring_bits(&c_spring(&m.spring)));
    }
}

/// The strength draws are the library's for the same grain, generation and seed: Eq. 18's
/// size law (`fractum_kernel_grain_strength`) and a given size exponent
/// (`fractum_kernel_grain_strength_sized`, the same draw at beta = 2/w); a negative exponent
/// is refused.
#[test]
fn strength_draws_are_the_librarys_with_and_without_a_size_exponent() {
    let mut d = Draw::new(41);
    for k in 0..20u64 {
        let b = random_body(&mut d, k % 2 == 0);
        let v = b.volume();
        let (w, xm, beta) = (d.range(0.5, 4.0), d.range(1e-4, 5e-4), d.range(0.0, 3.0));
        let (mut plain, mut sized, mut eq18) = (0.0, 0.0, 0.0);
        let generation = (k % 4) as u32;
        assert_eq!(
            fractum_kernel_grain_strength(7, k + 1, generation, &c_body(&b), w, xm, &mut plain),
            FRACTUM_OK
        );
        assert_eq!(
            fractum_kernel_grain_strength_sized(
                7,
                k + 1,
                generation,
                &c_body(&b),
                w,
                beta,
                xm,
                &mut sized
            ),
            FRACTUM_OK
        );
        assert_eq!(
            fractum_kernel_grain_strength_sized(
                7,
                k + 1,
                generation,
                &c_body(&b),
                w,
                2.0 / w,
                xm,
                &mut eq18
            ),
            FRACTUM_OK
        );
        let lib = fractum::fracture::grain_strength_sized(7, k + 1, generation, v, w, beta, xm);
        assert_eq!(sized.to_bits(), lib.to_bits());
        assert_eq!(
            plain.to_bits(),
            fractum::fracture::grain_strength(7, k + 1, generation, v, w, xm).to_bits()
        );
        assert_eq!(eq18.to_bits(), plain.to_bits());
    }
    let b = c_body(&random_body(&mut d, true));
    let mut f = 0.0;
    assert_eq!(
        fractum_kernel_grain_strength_sized(7, 1, 0, &b, 2.0, -0.5, 1e-4, &mut f),
        FRACTUM_ERR_INPUT
    );
}

/// A piece below the law's comminution limit is never found failing, however it is loaded;
/// one just above it fails as without the limit (the library's `below_comminution_limit` on
/// its equivalent radius); a negative or infinite limit is refused.
#[test]
fn the_check_leaves_pieces_below_the_comminution_limit_whole() {
    let law = FractumFractureLaw {
        mi: 11.5,
        sigma_c: 3.25e8,
        sigma_f: 7.75e8,
        poisson: 0.21,
        critical_contacts: 3,
        ideal_plane: 1,
        plane_jitter: 0,
        springs: 0,
        gc: 0.0,
        weibull_sigma_c: 0,
        particle_strength: 0,
        comminution_limit: 0.0,
    };
    let mut bodies = Bodies::default();
    bodies.push_sphere(Vec3::zeros(), 1e-4, 2650.0, UnitQuaternion::identity());
    let b = bodies.body(0);
    let f = 2.0 * law.sigma_c * 2.0 * std::f64::consts::PI * b.radius * b.radius / 3.0;
    let squeezed = squeeze(&b, Vec3::x(), f);
    let kind = |limit: f64| {
        let mut out = FractumTrigger::default();
        let l = FractumFractureLaw {
            comminution_limit: limit,
            ..law
        };
        let s = fractum_kernel_check(
            &l,
            &c_body(&b),
            1.0,
            c_rows(&squeezed).as_ptr(),
            [0.0; 3].as_ptr(),
            0,
            null(),
            0.0,
            &mut out,
        );
        (s, out.kind)
    };
    assert_eq!(kind(0.0), (FRACTUM_OK, 1));
    assert_eq!(kind(1.01e-4), (FRACTUM_OK, 0));
    assert_eq!(kind(0.99e-4), (FRACTUM_OK, 1));
    assert_eq!(kind(-1e-4).0, FRACTUM_ERR_INPUT);
    assert_eq!(kind(f64::INFINITY).0, FRACTUM_ERR_INPUT);
}
