use super::*;

fn params(on: WeibullOn, beta: Option<f64>, limit: Option<f64>) -> FractureParams {
    let spec = FractureSpec {
        reference_strength: Some(1.5e9),
        reference_radius: Some(0.15e-3),
        weibull_modulus: 3.0,
        size_exponent: beta,
        weibull_on: on,
        comminution_limit: limit,
        sigma_c: 200e6,
        ..FractureSpec::default()
    };
    FractureParams::new(&spec, 95e9, 0.18, true, false)
}

/// The particle reading: a grain whose crushing force is S times the reference grain's
/// has σc S and a contact strength S^(1/3), because the Hertz edge stress at a force F
/// is (1 - 2ν)/3 · 3F/(2πa²) with a ∝ F^(1/3), i.e. ∝ F^(1/3). Checked here on the Hertz
/// formula itself: the edge stress at S F_c equals S^(1/3) times that at F_c.
#[test]
fn particle_strength_scales_sigma_c_and_the_contact_strength_by_its_cube_root() {
    let p = params(WeibullOn::Particle, Some(0.9), None);
    let s = 2.7;
    assert_eq!(p.compressive_strength(s), 200e6 * s);
    assert!((p.contact_strength(s) / 1.5e9 - s.cbrt()).abs() < 1e-15);
    let (e_star, r, nu) = (95e9 / (2.0 * (1.0 - 0.18 * 0.18)), 0.15e-3, 0.18);
    let edge = |f: f64| {
        let a = (3.0 * f * r / (4.0 * e_star)).cbrt();
        criteria::contact_tensile_stress(f, a, nu)
    };
    assert!((edge(s * 9.4) / edge(9.4) - s.cbrt()).abs() < 1e-12);
    // The paper's reading scales the contact strength by the factor itself, and "both"
    // σc too.
    let c = params(WeibullOn::Contact, None, None);
    assert_eq!(c.contact_strength(s), 1.5e9 * s);
    assert_eq!(c.compressive_strength(s), 200e6);
    let b = params(WeibullOn::Both, None, None);
    assert_eq!(b.compressive_strength(s), 200e6 * s);
}

/// The size exponent defaults to Eq. 18's 2/w (the same draws, bit for bit, as before it
/// was a key); given, a grain twice the reference radius with P = 1/e has 2^(−β).
#[test]
fn size_exponent_defaults_to_two_over_w_and_sets_the_size_effect() {
    assert_eq!(
        params(WeibullOn::Contact, None, None).size_exponent,
        2.0 / 3.0
    );
    let v = 4.0 / 3.0 * std::f64::consts::PI * (0.3e-3f64).powi(3);
    for grain in 1..50 {
        assert_eq!(
            grain_strength(7, grain, 2, v, 3.0, 0.15e-3),
            grain_strength_sized(7, grain, 2, v, 3.0, 2.0 / 3.0, 0.15e-3)
        );
    }
    let e = std::f64::consts::E;
    let f = criteria::weibull_factor_sized(1.0 / e, 3.0, 0.9, 0.3e-3, 0.15e-3);
    assert!((f - 2f64.powf(-0.9)).abs() < 1e-15, "{f}");
}

/// The comminution limit compares the piece's equivalent radius (3V/4π)^⅓ with the limit;
/// no limit: nothing is below it.
#[test]
fn comminution_limit_reads_the_equivalent_radius() {
    let v = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let p = params(WeibullOn::Particle, None, Some(0.1e-3));
    assert!(p.below_comminution_limit(v(0.099e-3)));
    assert!(!p.below_comminution_limit(v(0.101e-3)));
    let none = params(WeibullOn::Particle, None, None);
    assert!(!none.below_comminution_limit(v(1e-9)));
}

/// The grain load keeps what the check used to select by sorting all of a grain's critical
/// contacts (stable, largest stress first): the count, the three largest in that order
/// (equal stresses in the order they came), and the moment; on random contacts with ties.
#[test]
fn grain_load_keeps_the_three_largest_as_a_stable_sort_would() {
    let centre = Vec3::new(1e-3, -2e-3, 0.5e-3);
    let mut u = [0.0; 4000];
    crate::sample::uniforms(5, 77, 0, &mut u);
    let mut v = u.iter().copied();
    let mut next = move || v.next().unwrap();
    for case in 0..100 {
        let mut load = GrainLoad::default();
        let mut all = Vec::new();
        let mut moment = Matrix3::zeros();
        for _ in 0..(case % 9) {
            let force = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            let point = centre + Vec3::new(next(), next(), next()) * 1e-4;
            // Hertz forces from a few values, so that stresses tie.
            let hertz = [0.5, 1.0, 1.0, 2.0][(next() * 4.0) as usize % 4];
            load.add(&centre, &force, &point, hertz, 1e-4, 0.2, 2e4);
            moment += force * (point - centre).transpose();
            let st = criteria::contact_tensile_stress(hertz, 1e-4, 0.2);
            if st > 2e4 {
                all.push((st, point));
            }
        }
        all.sort_by(|a, b| b.0.total_cmp(&a.0));
        assert_eq!(load.count, all.len(), "case {case}");
        assert_eq!(load.moment, moment);
        let kept: Vec<(f64, Vec3)> = (0..load.count.min(3))
            .map(|k| (load.stress[k], load.point[k]))
            .collect();
        assert_eq!(kept, all[..all.len().min(3)].to_vec(), "case {case}");
        assert_eq!(load.top(), all.first().map_or(0.0, |x| x.0));
    }
}

/// The fracture check's loads and verdicts, the cohesive springs and the frequency bound over
/// the contact records run in parts across a team, with their sums added in the order one
/// thread adds them: on a team of two they must give the same bits as on one thread. 600
/// grains on a jittered grid with contacts between neighbours and with a wall, loaded hard
/// enough that some fail, and about 1500 springs, some stretched past breaking.
#[test]
fn a_team_checks_grains_acts_springs_and_bounds_frequencies_bit_for_bit() {
    use crate::contact::records::{ContactRecord, RecordsByBody, WALL, records_max_frequency};
    use crate::parallel::Team;
    let mut seed = 987654321u64;
    let mut rand = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut bodies = Bodies::default();
    let spacing = 0.3e-3;
    let (nx, ny, nz) = (10, 10, 6);
    for ix in 0..nx {
        for iy in 0..ny {
            for iz in 0..nz {
                let pos = Vec3::new(ix as f64, iy as f64, iz as f64) * spacing
                    + Vec3::new(rand(), rand(), rand()) * 0.01e-3;
                let q = UnitQuaternion::from_euler_angles(rand(), rand(), rand());
                bodies.push_sphere(pos, 0.14e-3 + 0.02e-3 * rand(), 2650.0, q);
            }
        }
    }
    let n = bodies.len();
    let mut records = Vec::new();
    let index = |ix: usize, iy: usize, iz: usize| (ix * ny + iy) * nz + iz;
    for ix in 0..nx {
        for iy in 0..ny {
            for iz in 0..nz {
                let i = index(ix, iy, iz);
                let mut partners = Vec::new();
                if ix + 1 < nx {
                    partners.push(index(ix + 1, iy, iz) as u32);
                }
                if iz + 1 < nz {
                    partners.push(index(ix, iy, iz + 1) as u32);
                }
                if iz == 0 {
                    partners.push(WALL | 4);
                }
                for j in partners {
                    let other = if j & WALL != 0 {
                        bodies.pos[i] - Vec3::z() * spacing
                    } else {
                        bodies.pos[j as usize]
                    };
                    let normal = (bodies.pos[i] - other).normalize();
                    let hertz = 0.5 + 10.0 * rand();
                    records.push(ContactRecord {
                        i: i as u32,
                        j,
                        point: (bodies.pos[i] + other) * 0.5,
                        normal,
                        force: normal * hertz + Vec3::new(rand(), rand(), rand()) * 2.0,
                        normal_force: hertz,
                        hertz_force: hertz,
                        radius: 15e-6 + 30e-6 * rand(),
                        stiffness: 1e6 + 1e7 * rand(),
                        energy: 0.0,
                    });
                }
            }
        }
    }
    let mut forces = Forces::new(n);
    for k in 0..n {
        forces.torque[k] = Vec3::new(rand(), rand(), rand()) * 1e-4;
    }
    let mut fracture = GrainFracture::new(params(WeibullOn::Particle, None, None), 7, &bodies);
    for _ in 0..8000 {
        let a = (rand() * n as f64) as usize % n;
        let b = (a + 1 + (rand() * 5.0) as usize) % n;
        fracture.springs.push(Spring {
            a: a as u32,
            b: b as u32,
            on_a: Vec3::new(rand(), rand(), rand()) * 0.1e-3,
            on_b: Vec3::new(rand(), rand(), rand()) * 0.1e-3,
            direction: Vec3::new(rand(), rand(), rand()).normalize(),
            f0: 1.0 + rand(),
            // Critical openings f0/k from 0.01 to 0.5 mm: the springs spanning the grid
            // spacing break.
            k: 2e3 + 2e5 * rand(),
            opening: 0.0,
            last_gap: Vec3::zeros(),
            last_force: Vec3::zeros(),
            broken: false,
        });
        fracture.bonds[a] += 1;
        fracture.bonds[b] += 1;
    }
    // Half the grains free of springs, so that the check reads them.
    for k in (0..n).step_by(2) {
        fracture.bonds[k] = 0;
    }
    fracture.springs.retain(|s| s.a % 2 == 1 && s.b % 2 == 1);
    let team = Team::new(2).unwrap();
    let list = ContactRecords {
        list: records.clone(),
        dissipated: 0.0,
    };

    let (mut one, mut two) = (fracture.clone(), fracture);
    let checked_one = one.check(&bodies, &forces, &list);
    let checked_two = team.awake_for(|| two.check(&bodies, &forces, &list));
    let free = n / 2;
    assert!(
        !checked_one.is_empty() && checked_one.len() < free,
        "{} of {free} fail",
        checked_one.len()
    );
    assert_eq!(format!("{checked_one:?}"), format!("{checked_two:?}"));
    assert_eq!(one.loads(), two.loads());

    let (mut f_one, mut f_two) = (forces.clone(), forces.clone());
    let springs = one.springs.len();
    // More than two parts of the team's split (512 springs a part).
    assert!(springs > 1024, "{springs} springs");
    one.add_spring_forces(&bodies, &mut f_one);
    team.awake_for(|| two.add_spring_forces(&bodies, &mut f_two));
    let broke = one.springs.iter().filter(|s| s.broken).count();
    assert!(broke > 0 && broke < springs, "{broke} of {springs} broke");
    assert_eq!(f_one.force, f_two.force);
    assert_eq!(f_one.torque, f_two.torque);
    assert_eq!(one.bonds, two.bonds);
    assert_eq!(one.spring_work.to_bits(), two.spring_work.to_bits());
    assert_eq!(format!("{:?}", one.springs), format!("{:?}", two.springs));

    for tangential in [0.0, 0.8] {
        let serial = records_max_frequency(&records, &bodies, tangential);
        let teamed = team.awake_for(|| records_max_frequency(&records, &bodies, tangential));
        assert!(serial > 0.0);
        assert_eq!(serial.to_bits(), teamed.to_bits());
    }

    // The index by body lists each body's records, in record order, once each.
    let mut by_body = RecordsByBody::default();
    by_body.build(n, &records);
    for b in 0..n {
        let expected: Vec<u32> = (0..records.len() as u32)
            .filter(|&k| {
                let r = &records[k as usize];
                r.i as usize == b || (r.j & WALL == 0 && r.j as usize == b)
            })
            .collect();
        assert_eq!(by_body.of(b), &expected[..], "body {b}");
    }
}
