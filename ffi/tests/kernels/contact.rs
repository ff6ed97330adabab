//! The contact exports against the library: the law, the force, the narrow phase, pairs,
//! rows, travel, walls and the poly-ellipsoid grains, bit for bit.

use super::*;

#[test]
fn contact_law_folds_the_library_constants() {
    for (damp, fric) in [(false, false), (true, false), (false, true), (true, true)] {
        let (law, k) = laws(damp, fric, 0.35);
        assert_eq!(
            bits(&[
                law.four_thirds_e,
                law.two_e,
                law.damping,
                law.eight_g,
                law.mu
            ]),
            bits(&[k.four_thirds_e, k.two_e, k.damping, k.eight_g, k.mu])
        );
        assert_eq!((law.damp, law.friction), (damp as i32, fric as i32));
    }
    let mut law = FractumContactLaw::default();
    let s = fractum_kernel_contact_law(YOUNG, POISSON, 0.0, 0.3, 1, 0, &mut law);
    assert_eq!(s, FRACTUM_ERR_INPUT);
    let s = fractum_kernel_contact_law(YOUNG, POISSON, 0.5, 0.3, 0, 0, null_mut());
    assert_eq!(s, FRACTUM_ERR_NULL);
}

#[test]
fn hertz_mindlin_gives_the_library_bits() {
    let mut d = Draw::new(1);
    for (damp, fric) in [(false, false), (true, false), (false, true), (true, true)] {
        let (law, k) = laws(damp, fric, 0.3);
        for _ in 0..50 {
            let n = d.unit();
            let (delta, r_eff, m_eff) = (
                d.range(1e-9, 1e-5),
                d.range(1e-4, 1e-3),
                d.range(1e-6, 1e-5),
            );
            let v = d.vec(2.0);
            let h0 = d.vec(1e-6);
            let (dt, update) = (d.range(1e-9, 1e-7), d.flag());
            let mut h = h0;
            let c = match (damp, fric) {
                (false, false) => hertz_mindlin::<false, false>(
                    &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                ),
                (true, false) => hertz_mindlin::<true, false>(
                    &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                ),
                (false, true) => hertz_mindlin::<false, true>(
                    &k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update,
                ),
                (true, true) => {
                    hertz_mindlin::<true, true>(&k, &n, delta, r_eff, m_eff, &v, &mut h, dt, update)
                }
            };
            let mut hist: [f64; 3] = h0.into();
            let mut out = FractumContact::default();
            let s = fractum_kernel_hertz_mindlin(
                &law,
                n.as_ptr(),
                delta,
                r_eff,
                m_eff,
                v.as_ptr(),
                hist.as_mut_ptr(),
                dt,
                i32::from(update),
                &mut out,
            );
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(bits(&hist), vb(&h));
            assert_eq!(bits(&out.force), vb(&c.force));
            assert_eq!(
                bits(&[
                    out.normal_force,
                    out.hertz_force,
                    out.radius,
                    out.stiffness,
                    out.energy,
                    out.dissipated
                ]),
                bits(&[
                    c.normal_force,
                    c.hertz_force,
                    c.radius,
                    c.stiffness,
                    c.elastic_energy,
                    c.dissipated
                ])
            );
            assert_eq!(out.touching, 1);
        }
    }
}

/// Pairs of spheres and poly-ellipsoids at separations scaled from touching bounding
/// spheres, each evaluated over a few steps as it moves (warm start, held radius,
/// tangential history), in every variant: the export's contact and memory are the
/// library's, bit for bit.
#[test]
fn pair_gives_the_library_bits() {
    let mut d = Draw::new(2);
    let mut touching = [0usize; 2];
    for &(damp, fric, poly) in &SWITCHES {
        let (law, k) = laws(damp, fric, 0.4);
        for case in 0..40 {
            let (sa, sb) = match case % 4 {
                0 => (true, true),
                1 => (true, false),
                2 => (false, true),
                _ => (false, false),
            };
            let mut a = random_body(&mut d, sa);
            let mut b = random_body(&mut d, sb);
            let u = d.unit();
            b.pos = a.pos - u * (d.range(0.4, 1.02) * (a.radius + b.radius));
            let dt = 2e-8;
            let (mut hist, mut memory) = (Vec3::zeros(), PairMemory::default());
            let mut mem = FractumPairMemory::default();
            for step in 0..4 {
                let update = step > 0;
                let (bodies, placements) = run_pair(&a, &b);
                let at = |i| BodyAt {
                    bodies: &bodies,
                    placements: &placements,
                    i,
                };
                let p = variants!(
                    damp,
                    fric,
                    poly,
                    pair_contact(&k, &at(0), &at(1), &mut hist, &mut memory, dt, update)
                );
                let mut out = FractumContact::default();
                let placed_before = mem;
                let s = fractum_kernel_pair(
                    &law,
                    &c_body(&a),
                    &c_body(&b),
                    &mut mem,
                    dt,
                    i32::from(update),
                    i32::from(poly),
                    &mut out,
                );
                assert_eq!(s, FRACTUM_OK);
                same_contact(&out, &p);
                // Placed once per body, as a caller with many pairs does: the same bits,
                // and the placement is the run's.
                let (mut pa, mut pb) = (FractumPlacement::default(), FractumPlacement::default());
                assert_eq!(fractum_kernel_placement(&c_body(&a), &mut pa), FRACTUM_OK);
                assert_eq!(fractum_kernel_placement(&c_body(&b), &mut pb), FRACTUM_OK);
                for (given, run) in [(&pa, &placements.first()), (&pb, &placements.get(1))] {
                    if let Some(run) = run {
                        assert_eq!(bits(&given.origin), vb(&run.origin));
                        assert_eq!(bits(&given.rot), bits(&c_rows(&run.rot)));
                    }
                }
                let mut placed = FractumContact::default();
                let mut placed_mem = placed_before;
                let s = fractum_kernel_pair_placed(
                    &law,
                    &c_body(&a),
                    &pa,
                    &c_body(&b),
                    &pb,
                    &mut placed_mem,
                    dt,
                    i32::from(update),
                    i32::from(poly),
                    &mut placed,
                );
                assert_eq!(s, FRACTUM_OK);
                same_contact(&placed, &p);
                for m in [&mem, &placed_mem] {
                    assert_eq!(bits(&m.hist), vb(&hist));
                    assert_eq!(bits(&m.normal), vb(&memory.normal));
                    assert_eq!(m.radius.to_bits(), memory.radius.to_bits());
                }
                touching[usize::from(sa && sb)] += usize::from(p.is_some());
                a.pos += a.vel * 1e-5;
                b.pos += b.vel * 1e-5;
                a.orientation = UnitQuaternion::from_scaled_axis(a.omega * 1e-5) * a.orientation;
            }
        }
    }
    assert!(touching[0] > 200 && touching[1] > 100, "{touching:?}");
}

/// A cluster of spheres and poly-ellipsoids moving and turning over many steps, each row
/// of its half neighbour list given to the row kernel at once (partners with a flag bit
/// the mask removes, tags that put the lower one as A in either row): the contacts and
/// memories are `fractum_kernel_pair_placed`'s bit for bit, with the separated pairs'
/// skip on (travel summed by `fractum_kernel_travel`) and off, and the skip skips.
#[test]
fn pair_row_gives_the_pair_kernels_bits_with_and_without_the_skip() {
    let mut d = Draw::new(21);
    let (mut skipped, mut touching, mut searched_apart) = (0usize, 0usize, 0usize);
    for &(damp, fric, poly) in &SWITCHES {
        let (law, _) = laws(damp, fric, 0.4);
        let n = 14;
        let mut bodies: Vec<Body> = (0..n).map(|k| random_body(&mut d, k % 3 == 0)).collect();
        for b in &mut bodies {
            b.pos *= 1.6;
        }
        // Tags out of index order.
        let keys: Vec<i64> = (0..n as i64).map(|k| (7 * k + 3) % n as i64).collect();
        let pairs: Vec<(usize, usize)> = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .collect();
        let mut reference = vec![FractumPairMemory::default(); pairs.len()];
        let mut with_skip = vec![0.0; 8 * pairs.len()];
        let mut without = vec![0.0; 7 * pairs.len()];
        let mut travel = vec![0.0; n];
        let h = 2e-5;
        let dt = 2e-8;
        for step in 0..40 {
            let update = i32::from(step > 0);
            let fbs: Vec<FractumBody> = bodies.iter().map(c_body).collect();
            let places: Vec<FractumPlacement> = fbs
                .iter()
                .map(|b| {
                    let mut p = FractumPlacement::default();
                    assert_eq!(fractum_kernel_placement(b, &mut p), FRACTUM_OK);
                    p
                })
                .collect();
            let mut expected = Vec::new();
            for (slot, &(i, j)) in pairs.iter().enumerate() {
                let (a, b) = if keys[i] > keys[j] { (j, i) } else { (i, j) };
                let mut c = FractumContact::default();
                let s = fractum_kernel_pair_placed(
                    &law,
                    &fbs[a],
                    &places[a],
                    &fbs[b],
                    &places[b],
                    &mut reference[slot],
                    dt,
                    update,
                    i32::from(poly),
                    &mut c,
                );
                assert_eq!(s, FRACTUM_OK);
                expected.push(c);
                if poly && skips(with_skip[8 * slot + 7], travel[a], travel[b]) {
                    skipped += 1;
                    assert_eq!(c.touching, 0, "a skipped pair touches");
                } else if c.touching == 0 && fbs[a].sphere * fbs[b].sphere == 0 {
                    searched_apart += 1;
                }
            }
            let mut first = 0;
            for i in 0..n {
                let row: Vec<usize> = (i + 1..n).collect();
                let partners: Vec<i32> = row
                    .iter()
                    .map(|&j| j as i32 | ((j as i32 & 1) << 29))
                    .collect();
                let m = row.len();
                for (memory, stride, t) in [
                    (&mut with_skip, 8usize, travel.as_ptr()),
                    (&mut without, 7, null()),
                ] {
                    let mut out = vec![FractumContact::default(); m];
                    let mut at = vec![-1; m];
                    let mut kept = vec![-1; m];
                    let mut count = -1;
                    let s = fractum_kernel_pair_row(
                        &law,
                        fbs.as_ptr(),
                        if poly { places.as_ptr() } else { null() },
                        keys.as_ptr(),
                        t,
                        n as i32,
                        i as i32,
                        partners.as_ptr(),
                        m as i32,
                        (1 << 29) - 1,
                        memory[first * stride..].as_mut_ptr(),
                        stride as i32,
                        dt,
                        update,
                        i32::from(poly),
                        kept.as_mut_ptr(),
                        out.as_mut_ptr(),
                        at.as_mut_ptr(),
                        &mut count,
                    );
                    assert_eq!(s, FRACTUM_OK);
                    let touching_here: Vec<usize> = (0..m)
                        .filter(|&k| expected[first + k].touching != 0)
                        .collect();
                    assert_eq!(count as usize, touching_here.len());
                    for (c, &k) in out.iter().zip(&at).take(count as usize) {
                        assert_eq!(*c, expected[first + k as usize]);
                        assert_eq!(bits(&c.force), bits(&expected[first + k as usize].force));
                    }
                    for k in 0..m {
                        let record = &memory[(first + k) * stride..(first + k + 1) * stride];
                        let r = &reference[first + k];
                        assert_eq!(bits(&record[..3]), bits(&r.hist));
                        assert_eq!(bits(&record[3..6]), bits(&r.normal));
                        assert_eq!(record[6].to_bits(), r.radius.to_bits());
                        assert_eq!(kept[k], i32::from(record.iter().any(|v| *v != 0.0)));
                    }
                }
                touching += expected[first..first + m]
                    .iter()
                    .filter(|c| c.touching != 0)
                    .count();
                first += m;
            }
            for (b, t) in bodies.iter_mut().zip(&mut travel) {
                let before = c_body(b);
                b.pos += b.vel * h;
                b.orientation = UnitQuaternion::from_scaled_axis(b.omega * h) * b.orientation;
                assert_eq!(fractum_kernel_travel(&before, &c_body(b), t), FRACTUM_OK);
            }
        }
    }
    assert!(
        skipped > 500 && touching > 500 && searched_apart > 100,
        "skipped {skipped}, touching {touching}, searched apart {searched_apart}"
    );
}

/// The travel kernel adds the library's step: a turn and a shift, summed.
#[test]
fn travel_adds_the_library_step() {
    let mut d = Draw::new(4);
    for sphere in [true, false] {
        let a = random_body(&mut d, sphere);
        let mut b = a;
        b.pos += d.vec(1e-5);
        b.orientation = UnitQuaternion::from_scaled_axis(d.vec(0.01)) * a.orientation;
        let mut t = 0.25e-3;
        assert_eq!(
            fractum_kernel_travel(&c_body(&a), &c_body(&b), &mut t),
            FRACTUM_OK
        );
        let step = travel_step(&a.pos, &a.orientation, &b.pos, &b.orientation, b.radius);
        assert_eq!(t.to_bits(), (0.25e-3 + step).to_bits());
        let angle = a.orientation.angle_to(&b.orientation);
        assert!(step >= (b.pos - a.pos).norm() + b.radius * angle);
    }
    assert_eq!(
        fractum_kernel_travel(null(), null(), null_mut()),
        FRACTUM_ERR_NULL
    );
}

/// The same pairs' geometry alone.
#[test]
fn convex_and_wall_geometry_give_the_library_bits() {
    let mut d = Draw::new(3);
    let mut touching = 0;
    for case in 0..200 {
        let a = random_body(&mut d, case % 3 == 0);
        let mut b = random_body(&mut d, case % 5 == 0);
        let u = d.unit();
        b.pos = a.pos - u * (d.range(0.4, 1.02) * (a.radius + b.radius));
        let guess = if d.flag() { d.vec(1.0) } else { Vec3::zeros() };
        let (bodies, placements) = run_pair(&a, &b);
        let at = |i| BodyAt {
            bodies: &bodies,
            placements: &placements,
            i,
        };
        let g = convex::contact(&at(0).placed(), &at(1).placed(), &guess);
        touching += usize::from(g.is_some());
        let mut out = FractumGeometry::default();
        let s = fractum_kernel_convex_contact(&c_body(&a), &c_body(&b), guess.as_ptr(), &mut out);
        assert_eq!(s, FRACTUM_OK);
        same_geometry(&out, &g);
        let wp = a.pos - u * (d.range(0.3, 1.05) * a.radius);
        let g = convex::wall_contact(&at(0).placed(), &u, &wp);
        let s = fractum_kernel_wall_geometry(&c_body(&a), u.as_ptr(), wp.as_ptr(), &mut out);
        assert_eq!(s, FRACTUM_OK);
        same_geometry(&out, &g);
    }
    assert!(touching > 80, "{touching}");
}

#[test]
fn wall_gives_the_library_bits() {
    let mut d = Draw::new(4);
    let mut touching = 0;
    for &(damp, fric, poly) in &SWITCHES {
        let (law, k) = laws(damp, fric, 0.25);
        for case in 0..40 {
            let mut a = random_body(&mut d, case % 2 == 0);
            let n = d.unit();
            let wp = a.pos - n * (d.range(0.3, 1.05) * a.radius);
            let wv = d.vec(0.5);
            let dt = 3e-8;
            let (mut hist, mut held) = (Vec3::zeros(), 0.0);
            let mut mem = FractumPairMemory::default();
            for step in 0..3 {
                let update = step > 0;
                let (bodies, placements) = run_pair(&a, &a);
                let at = BodyAt {
                    bodies: &bodies,
                    placements: &placements,
                    i: 0,
                };
                let p = variants!(
                    damp,
                    fric,
                    poly,
                    wall_contact(&k, &at, &n, &wp, &wv, &mut hist, &mut held, dt, update)
                );
                let mut out = FractumContact::default();
                let s = fractum_kernel_wall(
                    &law,
                    &c_body(&a),
                    n.as_ptr(),
                    wp.as_ptr(),
                    wv.as_ptr(),
                    &mut mem,
                    dt,
                    i32::from(update),
                    i32::from(poly),
                    &mut out,
                );
                assert_eq!(s, FRACTUM_OK);
                same_contact(&out, &p);
                assert_eq!(bits(&mem.hist), vb(&hist));
                assert_eq!(mem.radius.to_bits(), held.to_bits());
                touching += usize::from(p.is_some());
                a.pos += a.vel * 1e-5;
            }
        }
    }
    assert!(touching > 300, "{touching}");
}

#[test]
fn poly_ellipsoid_body_is_what_the_run_adds() {
    let mut d = Draw::new(5);
    for _ in 0..20 {
        let semi: [f64; 6] = std::array::from_fn(|_| d.range(0.2e-3, 1e-3));
        let (mass, c, q) = (d.range(1e-6, 1e-5), d.vec(1e-2), d.quat());
        let mut bodies = Bodies::default();
        bodies.push_poly_ellipsoid(PolyEllipsoid::new(semi).unwrap(), mass, c, q);
        let qa: [f64; 4] = [q.w, q.i, q.j, q.k];
        let mut out = FractumBody::default();
        let s = fractum_kernel_poly_ellipsoid_body(
            semi.as_ptr(),
            mass,
            c.as_ptr(),
            qa.as_ptr(),
            &mut out,
        );
        assert_eq!(s, FRACTUM_OK);
        assert_eq!(body_bits(&out), body_bits(&c_body(&bodies.body(0))));
        let mut v = 0.0;
        assert_eq!(fractum_kernel_body_volume(&out, &mut v), FRACTUM_OK);
        assert_eq!(v.to_bits(), bodies.volume(0).to_bits());
    }
    let mut bodies = Bodies::default();
    bodies.push_sphere(Vec3::zeros(), 0.7e-3, 2500.0, d.quat());
    let mut v = 0.0;
    let s = fractum_kernel_body_volume(&c_body(&bodies.body(0)), &mut v);
    assert_eq!(s, FRACTUM_OK);
    assert_eq!(v.to_bits(), bodies.volume(0).to_bits());
}

/// The body the poly-ellipsoid kernel makes, each field of the FractumBody against the number
/// its doc gives, written out by hand (no conversion on the test's side): the shape of
/// [`hand_body`] at rest at (1, 2, 3), its shape frame turned 120 degrees about (1, 1, 1).
/// Lopsided along x only, its principal frame is its shape frame, so the body frame is the
/// shape frame.
#[test]
fn poly_ellipsoid_body_fields_by_hand() {
    let (centre, shape_quat) = ([1.0, 2.0, 3.0], [0.5, 0.5, 0.5, 0.5]);
    let mut out = FractumBody::default();
    let s = fractum_kernel_poly_ellipsoid_body(
        HAND_SEMI.as_ptr(),
        10.0,
        centre.as_ptr(),
        shape_quat.as_ptr(),
        &mut out,
    );
    assert_eq!(s, FRACTUM_OK);
    assert_eq!(out.pos, [1.0, 2.0, 3.0]);
    assert_eq!(out.vel, [0.0; 3], "at rest");
    assert_eq!(out.omega, [0.0; 3], "at rest");
    assert_eq!(
        out.quat,
        [0.5, 0.5, 0.5, 0.5],
        "body to world: the shape's turn"
    );
    assert_eq!(out.mass, 10.0);
    // The tip of a+, 1 - 0.0375 from the centre of mass (the library's bound lies 1e-9 above).
    assert!((out.radius / 0.9625 - 1.0).abs() < 2e-9, "{}", out.radius);
    assert_eq!(out.semi, [1.0, 0.9, 0.3, 0.3, 0.2, 0.2]);
    near(&out.origin, &[-0.0375, 0.0, 0.0]);
    assert_eq!(
        out.to_body,
        [1.0, 0.0, 0.0, 0.0],
        "shape to body: the identity"
    );
    near(&out.inertia, &moments_lopsided_x(&HAND_SEMI, 10.0));
    assert_eq!(out.sphere, 0);
}

/// A placement's rotation is row-major, element 1 the (0, 1) entry: [`hand_body`]'s shape
/// frame (180 degrees about x in a body turned 120 degrees about (1, 1, 1)) has its x axis
/// along world y, its y along -z and its z along -x, the columns of the rotation; a
/// transposed matrix would put them in the rows. The octant origin: 0.0375 behind the centre
/// along the shape's x, world y.
#[test]
fn placement_rotation_is_row_major_by_hand() {
    let mut p = FractumPlacement::default();
    assert_eq!(fractum_kernel_placement(&hand_body(), &mut p), FRACTUM_OK);
    #[rustfmt::skip]
    let rows = [
        0.0, 0.0, -1.0,
        1.0, 0.0, 0.0,
        0.0, -1.0, 0.0,
    ];
    near(&p.rot, &rows);
    // Element 1 is the (0, 1) entry, 0; element 3 the (1, 0) entry, 1.
    near(&[p.rot[1], p.rot[3]], &[0.0, 1.0]);
    near(&p.origin, &[1.0, 2.0 - 0.0375, 3.0]);
}

/// The reference for `fractum_kernel_pair_list`: the plugin's pair as it was before the list
/// kernel, one `fractum_kernel_pair_row` call per row and the gathering around it (records
/// copied where they are not kept, reshaped records reset, the force and torques swapped back
/// to the row's atom, energies where body A is owned, both shares per contact, each owned
/// atom's sides ordered by its partners' keys).
#[allow(clippy::too_many_arguments)]
fn pair_list_by_rows(
    law: &FractumContactLaw,
    fbs: &[FractumBody],
    places: &[FractumPlacement],
    keys: &[i64],
    travel: &[f64],
    n_local: usize,
    rows: &[Vec<i32>],
    mask: i32,
    records: &mut [Vec<f64>],
    kept: &mut [Vec<i32>],
    keep: bool,
    reshaped: &[i64],
    dt: f64,
    update: i32,
    poly: bool,
) -> (Vec<FractumTouching>, Vec<i32>, [f64; 2]) {
    let mut touching = Vec::new();
    let mut sides: Vec<(usize, i64, i32)> = Vec::new();
    let mut energy = [0.0, 0.0];
    for (i, partners) in rows.iter().enumerate() {
        let m = partners.len();
        if m == 0 {
            continue;
        }
        let mut copy = records[i].clone();
        let row = if keep { &mut records[i] } else { &mut copy };
        for (jj, &p) in partners.iter().enumerate() {
            let j = (p & mask) as usize;
            if reshaped.contains(&keys[i]) || reshaped.contains(&keys[j]) {
                row[8 * jj + 6] = 0.0;
                row[8 * jj + 7] = 0.0;
            }
        }
        let mut out = vec![FractumContact::default(); m];
        let mut at = vec![-1; m];
        let mut count = -1;
        let s = fractum_kernel_pair_row(
            law,
            fbs.as_ptr(),
            if poly { places.as_ptr() } else { null() },
            keys.as_ptr(),
            if poly { travel.as_ptr() } else { null() },
            fbs.len() as i32,
            i as i32,
            partners.as_ptr(),
            m as i32,
            mask,
            row.as_mut_ptr(),
            8,
            dt,
            update,
            i32::from(poly),
            if keep {
                kept[i].as_mut_ptr()
            } else {
                null_mut()
            },
            out.as_mut_ptr(),
            at.as_mut_ptr(),
            &mut count,
        );
        assert_eq!(s, FRACTUM_OK);
        if !keep {
            for jj in 0..m {
                kept[i][jj] = i32::from(records[i][8 * jj..8 * jj + 8].iter().any(|v| *v != 0.0));
            }
        }
        for c in 0..count as usize {
            let o = &out[c];
            let j = (partners[at[c] as usize] & mask) as usize;
            let swap = keys[i] > keys[j];
            if (if swap { j } else { i }) < n_local {
                energy[0] += o.energy;
                energy[1] += o.dissipated;
            }
            let (mut si, mut sj) = (0.0, 0.0);
            let s = fractum_kernel_frequency_shares(law, o, &fbs[i], &fbs[j], &mut si, &mut sj);
            assert_eq!(s, FRACTUM_OK);
            let n = touching.len() as i32;
            touching.push(FractumTouching {
                i: i as i32,
                j: j as i32,
                force: if swap { o.force.map(|v| -v) } else { o.force },
                torque_i: if swap { o.torque_b } else { o.torque_a },
                torque_j: if swap { o.torque_a } else { o.torque_b },
                point: o.point,
                hertz_force: o.hertz_force,
                radius: o.radius,
                share_i: si,
                share_j: sj,
            });
            sides.push((i, keys[j], 2 * n));
            if j < n_local {
                sides.push((j, keys[i], 2 * n + 1));
            }
        }
    }
    // Stable: each atom's sides in the order of its partners' keys, ties as found.
    sides.sort_by_key(|s| (s.0, s.1));
    (touching, sides.iter().map(|s| s.2).collect(), energy)
}

/// `fractum_kernel_pair_list` over a whole half neighbour list (owned atoms with ghost
/// partners, flag bits the mask removes, keys out of index order) gives the row-by-row path's
/// bits, step after step: the touching contacts, the sides in summing order, the energies,
/// the records and kept flags, with records kept and (at some steps) computed on copies, and
/// with reshaped bodies' records starting afresh; and it refuses a list larger than its room.
#[test]
fn pair_list_gives_the_row_kernels_bits() {
    let mut d = Draw::new(23);
    let mut touching_seen = 0usize;
    for &(damp, fric, poly) in &SWITCHES {
        let (law, _) = laws(damp, fric, 0.4);
        let (n, n_local) = (14usize, 10usize);
        let mut bodies: Vec<Body> = (0..n).map(|k| random_body(&mut d, k % 3 == 0)).collect();
        for b in &mut bodies {
            b.pos *= 1.6;
        }
        let keys: Vec<i64> = (0..n as i64).map(|k| (5 * k + 2) % n as i64).collect();
        let mask = (1 << 29) - 1;
        // Owned rows with their later partners, ghosts included; the last owned row empty.
        let rows: Vec<Vec<i32>> = (0..n_local)
            .map(|i| {
                if i == n_local - 1 {
                    return Vec::new();
                }
                (i + 1..n)
                    .map(|j| j as i32 | ((j as i32 & 1) << 29))
                    .collect()
            })
            .collect();
        let mut ref_records: Vec<Vec<f64>> = rows.iter().map(|r| vec![0.0; 8 * r.len()]).collect();
        let mut ref_kept: Vec<Vec<i32>> = rows.iter().map(|r| vec![0; r.len()]).collect();
        let (mut records, mut kept) = (ref_records.clone(), ref_kept.clone());
        let mut travel = vec![0.0; n];
        let (h, dt) = (2e-5, 2e-8);
        for step in 0..30 {
            let update = i32::from(step > 0);
            let keep = step % 7 != 3;
            let reshaped: Vec<i64> = if step % 5 == 4 {
                vec![keys[2], keys[11]]
            } else {
                vec![]
            };
            let mut sorted = reshaped.clone();
            sorted.sort();
            let fbs: Vec<FractumBody> = bodies.iter().map(c_body).collect();
            let places: Vec<FractumPlacement> = fbs
                .iter()
                .map(|b| {
                    let mut p = FractumPlacement::default();
                    assert_eq!(fractum_kernel_placement(b, &mut p), FRACTUM_OK);
                    p
                })
                .collect();
            let (want, want_sides, want_energy) = pair_list_by_rows(
                &law,
                &fbs,
                &places,
                &keys,
                &travel,
                n_local,
                &rows,
                mask,
                &mut ref_records,
                &mut ref_kept,
                keep,
                &sorted,
                dt,
                update,
                poly,
            );
            touching_seen += want.len();

            let ilist: Vec<i32> = (0..n_local as i32).collect();
            let numneigh: Vec<i32> = rows.iter().map(|r| r.len() as i32).collect();
            let firstneigh: Vec<*const i32> = rows.iter().map(|r| r.as_ptr()).collect();
            let firstvalue: Vec<*mut f64> = records.iter_mut().map(|r| r.as_mut_ptr()).collect();
            let firsttouch: Vec<*mut i32> = kept.iter_mut().map(|r| r.as_mut_ptr()).collect();
            let list = FractumNeighbours {
                inum: n_local as i32,
                ilist: ilist.as_ptr(),
                numneigh: numneigh.as_ptr(),
                firstneigh: firstneigh.as_ptr(),
                index_mask: mask,
                firsttouch: firsttouch.as_ptr(),
                firstvalue: firstvalue.as_ptr(),
                stride: 8,
            };
            let capacity: usize = rows.iter().map(|r| r.len()).sum();
            let mut got = vec![FractumTouching::default(); capacity];
            let mut codes = vec![-1; 2 * capacity];
            let (mut n_touching, mut n_sides) = (0usize, 0usize);
            let mut energy = [0.0, 0.0];
            let call = |room: usize,
                        got: &mut Vec<FractumTouching>,
                        codes: &mut Vec<i32>,
                        n_touching: &mut usize,
                        n_sides: &mut usize,
                        energy: &mut [f64; 2]| {
                fractum_kernel_pair_list(
                    &law,
                    fbs.as_ptr(),
                    if poly { places.as_ptr() } else { null() },
                    keys.as_ptr(),
                    if poly { travel.as_ptr() } else { null() },
                    n as i32,
                    n_local as i32,
                    &list,
                    i32::from(keep),
                    sorted.as_ptr(),
                    sorted.len(),
                    dt,
                    update,
                    i32::from(poly),
                    1,
                    got.as_mut_ptr(),
                    room,
                    n_touching,
                    codes.as_mut_ptr(),
                    n_sides,
                    energy.as_mut_ptr(),
                )
            };
            if want.len() > 1 && keep {
                // Too little room: refused (the records it reached may have moved on, so the
                // refusal is checked on copies and the real call made on the originals).
                let saved = (records.clone(), kept.clone());
                let (mut nt, mut ns, mut e) = (0, 0, [0.0, 0.0]);
                let s = call(
                    want.len() - 1,
                    &mut got,
                    &mut codes,
                    &mut nt,
                    &mut ns,
                    &mut e,
                );
                assert_eq!(s, FRACTUM_ERR_INPUT);
                for (r, s) in records.iter_mut().zip(&saved.0) {
                    r.copy_from_slice(s);
                }
                for (k, s) in kept.iter_mut().zip(&saved.1) {
                    k.copy_from_slice(s);
                }
            }
            let s = call(
                capacity,
                &mut got,
                &mut codes,
                &mut n_touching,
                &mut n_sides,
                &mut energy,
            );
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(n_touching, want.len());
            assert_eq!(&got[..n_touching], &want[..]);
            for (g, w) in got.iter().zip(&want) {
                assert_eq!(bits(&g.force), bits(&w.force));
                assert_eq!(g.share_i.to_bits(), w.share_i.to_bits());
            }
            assert_eq!(&codes[..n_sides], &want_sides[..]);
            assert_eq!(bits(&energy), bits(&want_energy));
            assert_eq!(records, ref_records);
            assert_eq!(kept, ref_kept);
            for (b, t) in bodies.iter_mut().zip(&mut travel) {
                let before = c_body(b);
                b.pos += b.vel * h;
                b.orientation = UnitQuaternion::from_scaled_axis(b.omega * h) * b.orientation;
                assert_eq!(fractum_kernel_travel(&before, &c_body(b), t), FRACTUM_OK);
            }
        }
    }
    assert!(touching_seen > 300, "touching {touching_seen}");
}

/// `fractum_kernel_pair_list` refuses a null law or list, more owned atoms than bodies, a
/// record shorter than the skip's, and a row or partner out of range, before any contact.
#[test]
fn pair_list_refuses_what_it_cannot_read() {
    let mut d = Draw::new(29);
    let (law, _) = laws(true, true, 0.4);
    let fbs: Vec<FractumBody> = (0..3).map(|_| c_body(&random_body(&mut d, true))).collect();
    let keys = [0i64, 1, 2];
    let partners = [1, 2];
    let numneigh = [2, 0, 0];
    let firstneigh = [partners.as_ptr(), null(), null()];
    let mut ilist = [0];
    let mut list = FractumNeighbours {
        inum: 1,
        ilist: ilist.as_ptr(),
        numneigh: numneigh.as_ptr(),
        firstneigh: firstneigh.as_ptr(),
        index_mask: -1,
        firsttouch: null(),
        firstvalue: null(),
        stride: 8,
    };
    let run = |law: *const FractumContactLaw, list: *const FractumNeighbours, n_local: i32| {
        let mut out = [FractumTouching::default(); 2];
        let mut codes = [0; 4];
        let (mut nt, mut ns, mut e) = (0usize, 0usize, [0.0; 2]);
        fractum_kernel_pair_list(
            law,
            fbs.as_ptr(),
            null(),
            keys.as_ptr(),
            null(),
            3,
            n_local,
            list,
            1,
            null(),
            0,
            1e-8,
            1,
            0,
            0,
            out.as_mut_ptr(),
            2,
            &mut nt,
            codes.as_mut_ptr(),
            &mut ns,
            e.as_mut_ptr(),
        )
    };
    assert_eq!(run(&law, &list, 3), FRACTUM_OK);
    assert_eq!(run(null(), &list, 3), FRACTUM_ERR_NULL);
    assert_eq!(run(&law, null(), 3), FRACTUM_ERR_NULL);
    assert_eq!(run(&law, &list, 4), FRACTUM_ERR_INPUT);
    list.stride = 7;
    assert_eq!(run(&law, &list, 3), FRACTUM_ERR_INPUT);
    list.stride = 8;
    // Row 0 is not owned when no atom is, nor row 5 of three bodies.
    assert_eq!(run(&law, &list, 0), FRACTUM_ERR_INPUT);
    ilist[0] = 5;
    list.ilist = ilist.as_ptr();
    assert_eq!(run(&law, &list, 3), FRACTUM_ERR_INPUT);
}
