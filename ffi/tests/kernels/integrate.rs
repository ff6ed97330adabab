//! The step exports against the run: the step check's verdicts, the frequency shares and the
//! adapted step.

use super::*;

/// The step check's verdicts at Fractum's limits (omega dt 2: stop, 1.6: warn), and bad
/// arguments refused.
#[test]
fn step_check_gives_the_runs_verdicts() {
    let (mut x, mut v) = (0.0, -1);
    // omega = 1e6 rad/s (sum 1e12): dt 1e-6 gives omega dt 1.
    for (dt, expect) in [(1e-6, 0), (1.7e-6, 1), (2.1e-6, 2)] {
        assert_eq!(
            fractum_kernel_step_check(1e12, dt, &mut x, &mut v),
            FRACTUM_OK
        );
        assert_eq!(v, expect, "dt {dt}");
        assert!((x - dt * 1e6).abs() <= 1e-12 * x);
    }
    assert_eq!(
        fractum_kernel_step_check(f64::NAN, 1e-6, &mut x, &mut v),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_step_check(1.0, 0.0, &mut x, &mut v),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_step_check(1.0, 1.0, null_mut(), &mut v),
        FRACTUM_ERR_NULL
    );
}

/// The frequency shares of pair contacts as the run's estimate sums them (over a Bodies,
/// as `records_max_frequency` reads it), and the adapted step.
#[test]
fn frequency_share_and_adapted_step_give_the_library_bits() {
    use fractum::contact::records::{
        ContactRecord, WALL, frequency_bound, records_max_frequency, tangential_ratio,
    };
    let mut d = Draw::new(9);
    let (mut shortened, mut touching) = (0, 0);
    for fric in [false, true] {
        let (law, k) = laws(true, fric, 0.4);
        let tangential = if fric {
            tangential_ratio(k.eight_g, k.two_e)
        } else {
            0.0
        };
        for case in 0..40 {
            let a = random_body(&mut d, case % 2 == 0);
            let mut b = random_body(&mut d, case % 3 == 0);
            b.pos = a.pos - d.unit() * (0.9 * (a.radius + b.radius));
            let mut mem = FractumPairMemory::default();
            let mut c = FractumContact::default();
            let s =
                fractum_kernel_pair(&law, &c_body(&a), &c_body(&b), &mut mem, 2e-8, 1, 1, &mut c);
            assert_eq!(s, FRACTUM_OK);
            if c.touching == 0 {
                continue;
            }
            touching += 1;
            let (bodies, _) = run_pair(&a, &b);
            // The run's bound over this one contact, between the bodies and against a wall.
            let record = |j| ContactRecord {
                i: 0,
                j,
                point: Vec3::from(c.point),
                normal: Vec3::from(c.normal),
                force: Vec3::from(c.force),
                normal_force: c.normal_force,
                hertz_force: c.hertz_force,
                radius: c.radius,
                stiffness: c.stiffness,
                energy: c.energy,
            };
            let (fa, fb_) = (c_body(&a), c_body(&b));
            let mut shares = [f64::NAN; 2];
            for (k, (own, other)) in [(&fa, &fb_), (&fb_, &fa)].into_iter().enumerate() {
                let s = fractum_kernel_frequency_share(&law, &c, own, other, &mut shares[k]);
                assert_eq!(s, FRACTUM_OK);
            }
            let mut both = [f64::NAN; 2];
            let s =
                fractum_kernel_frequency_shares(&law, &c, &fa, &fb_, &mut both[0], &mut both[1]);
            assert_eq!(s, FRACTUM_OK);
            assert_eq!(bits(&both), bits(&shares));
            let sum = shares[0].max(shares[1]);
            let lib = records_max_frequency(&[record(1)], &bodies, tangential);
            assert_eq!(frequency_bound(sum).to_bits(), lib.to_bits());
            let mut wall = f64::NAN;
            let s = fractum_kernel_frequency_share(&law, &c, &fa, null(), &mut wall);
            assert_eq!(s, FRACTUM_OK);
            let lib = records_max_frequency(&[record(WALL)], &bodies, tangential);
            assert_eq!(frequency_bound(wall).to_bits(), lib.to_bits());
            let omega = frequency_bound(sum);
            for dt in [0.5, 1.5, 3.0].map(|f| f * 0.6 / omega) {
                let mut next = f64::NAN;
                assert_eq!(
                    fractum_kernel_adapted_step(sum, dt, 0.6, &mut next),
                    FRACTUM_OK
                );
                let lib = fractum::integrate::adapted_step(omega, dt, 0.6);
                assert_eq!(next.to_bits(), lib.unwrap_or(dt).to_bits());
                shortened += usize::from(lib.is_some());
            }
        }
    }
    assert!(touching > 20, "{touching}");
    assert_eq!(
        shortened,
        2 * touching,
        "the steps above 0.6 / omega are shortened"
    );
    let mut next = 0.0;
    assert_eq!(
        fractum_kernel_adapted_step(-1.0, 1e-8, 0.6, &mut next),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_adapted_step(1.0, 0.0, 0.6, &mut next),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_adapted_step(1.0, 1e-8, f64::NAN, &mut next),
        FRACTUM_ERR_INPUT
    );
}

/// Per-atom arrays in a host's layout (row pointers, as LAMMPS's `atom->x` and its
/// `fix property/atom` arrays): rows of the width LAMMPS's Fractum arrays have.
struct Rows {
    x: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    omega: Vec<[f64; 3]>,
    force: Vec<[f64; 3]>,
    torque: Vec<[f64; 3]>,
    mass: Vec<f64>,
    radius: Vec<f64>,
    quat: Vec<[f64; 7]>,
    inertia: Vec<[f64; 7]>,
    travel: Vec<[f64; 1]>,
    mask: Vec<i32>,
}

/// Row pointers of `rows`, kept alive by the caller while the kernel runs.
fn pointers<const N: usize>(rows: &mut [[f64; N]]) -> Vec<*mut f64> {
    rows.iter_mut().map(|r| r.as_mut_ptr()).collect()
}

/// The bulk integrator kernels give the per-atom kernels' bits on every atom of the group
/// (kick-drift with the travel of `fractum_kernel_travel`, then the kick), over spheres and
/// poly-ellipsoids, with and without orientations tracked, and leave the atoms outside the
/// group as they were.
#[test]
fn bulk_integrator_gives_the_per_atom_kernels_bits() {
    let mut d = Draw::new(21);
    let dt = 3e-8;
    for tracked in [true, false] {
        let n = 24;
        let bodies: Vec<Body> = (0..n)
            .map(|k| random_body(&mut d, !tracked || k % 3 == 0))
            .collect();
        let mut c: Vec<FractumBody> = bodies.iter().map(c_body).collect();
        if !tracked {
            // A sphere without shape arrays, as the plugin's fractum_body makes it.
            for b in &mut c {
                let moment = 0.4 * b.mass * b.radius * b.radius;
                b.inertia = [moment; 3];
                b.quat = [1.0, 0.0, 0.0, 0.0];
            }
        }
        let force: Vec<[f64; 3]> = (0..n).map(|_| c_vec(&d.vec(1e-3))).collect();
        let torque: Vec<[f64; 3]> = (0..n).map(|_| c_vec(&d.vec(1e-7))).collect();
        let mask: Vec<i32> = (0..n).map(|k| if k % 5 == 2 { 1 } else { 1 | 4 }).collect();
        let mut r = Rows {
            x: c.iter().map(|b| b.pos).collect(),
            v: c.iter().map(|b| b.vel).collect(),
            omega: c.iter().map(|b| b.omega).collect(),
            force: force.clone(),
            torque: torque.clone(),
            mass: c.iter().map(|b| b.mass).collect(),
            radius: c.iter().map(|b| b.radius).collect(),
            quat: c
                .iter()
                .map(|b| {
                    let mut row = [0.0; 7];
                    row[..4].copy_from_slice(&b.quat);
                    row[4..].copy_from_slice(&b.origin);
                    row
                })
                .collect(),
            inertia: c
                .iter()
                .map(|b| {
                    let mut row = [0.0; 7];
                    row[..3].copy_from_slice(&b.inertia);
                    row[3..].copy_from_slice(&b.to_body);
                    row
                })
                .collect(),
            travel: (0..n).map(|k| [1e-6 * k as f64]).collect(),
            mask,
        };
        let before_travel = r.travel.clone();
        // The per-atom path on copies.
        let mut expect = c.clone();
        let mut expect_travel: Vec<f64> = before_travel.iter().map(|t| t[0]).collect();
        for k in 0..n {
            if r.mask[k] & 4 == 0 {
                continue;
            }
            let before = expect[k];
            let s = fractum_kernel_kick_drift(
                &mut expect[k],
                force[k].as_ptr(),
                torque[k].as_ptr(),
                dt,
            );
            assert_eq!(s, FRACTUM_OK);
            if tracked {
                assert_eq!(
                    fractum_kernel_travel(&before, &expect[k], &mut expect_travel[k]),
                    FRACTUM_OK
                );
            }
        }
        let (mut x, mut v, mut w) = (
            pointers(&mut r.x),
            pointers(&mut r.v),
            pointers(&mut r.omega),
        );
        let (mut q, mut ti) = (pointers(&mut r.quat), pointers(&mut r.inertia));
        let mut tr = pointers(&mut r.travel);
        let (mut f, mut t) = (pointers(&mut r.force), pointers(&mut r.torque));
        let rows = FractumAtomRows {
            n: n as i32,
            groupbit: 4,
            mask: r.mask.as_ptr(),
            x: x.as_mut_ptr(),
            v: v.as_mut_ptr(),
            omega: w.as_mut_ptr(),
            force: f.as_mut_ptr().cast(),
            torque: t.as_mut_ptr().cast(),
            mass: r.mass.as_ptr(),
            radius: r.radius.as_ptr(),
            quat: if tracked { q.as_mut_ptr() } else { null_mut() },
            inertia: if tracked {
                ti.as_mut_ptr().cast()
            } else {
                null_mut()
            },
            travel: tr.as_mut_ptr(),
        };
        assert_eq!(fractum_kernel_kick_drift_atoms(&rows, dt), FRACTUM_OK);
        let check = |r: &Rows, expect: &[FractumBody], travel: &[f64]| {
            for k in 0..n {
                assert_eq!(r.x[k], expect[k].pos, "position of atom {k}");
                assert_eq!(r.v[k], expect[k].vel, "velocity of atom {k}");
                assert_eq!(r.omega[k], expect[k].omega, "angular velocity of atom {k}");
                if tracked {
                    assert_eq!(r.quat[k][..4], expect[k].quat, "orientation of atom {k}");
                }
                // The travel only grows with orientations tracked (the pair's skip needs them).
                assert_eq!(r.travel[k][0], travel[k], "travel of atom {k}");
            }
        };
        let unchanged: Vec<f64> = before_travel.iter().map(|t| t[0]).collect();
        check(
            &r,
            &expect,
            if tracked { &expect_travel } else { &unchanged },
        );
        // The second half kick.
        for k in 0..n {
            if r.mask[k] & 4 != 0 {
                let s =
                    fractum_kernel_kick(&mut expect[k], force[k].as_ptr(), torque[k].as_ptr(), dt);
                assert_eq!(s, FRACTUM_OK);
            }
        }
        assert_eq!(fractum_kernel_kick_atoms(&rows, dt), FRACTUM_OK);
        check(
            &r,
            &expect,
            if tracked { &expect_travel } else { &unchanged },
        );
        // Something moved, and the atoms outside the group did not.
        assert!((0..n).any(|k| r.x[k] != c[k].pos));
        for k in (0..n).filter(|k| r.mask[*k] & 4 == 0) {
            assert_eq!(
                (r.x[k], r.v[k], r.omega[k]),
                (c[k].pos, c[k].vel, c[k].omega)
            );
        }
    }
    // A table missing, and a negative count, refused.
    let bad = FractumAtomRows {
        n: 1,
        groupbit: 1,
        mask: null(),
        x: null_mut(),
        v: null_mut(),
        omega: null_mut(),
        force: null_mut(),
        torque: null_mut(),
        mass: null(),
        radius: null(),
        quat: null_mut(),
        inertia: null_mut(),
        travel: null_mut(),
    };
    assert_eq!(fractum_kernel_kick_atoms(&bad, dt), FRACTUM_ERR_NULL);
    assert_eq!(
        fractum_kernel_kick_drift_atoms(&FractumAtomRows { n: -1, ..bad }, dt),
        FRACTUM_ERR_INPUT
    );
    assert_eq!(
        fractum_kernel_kick_drift_atoms(&FractumAtomRows { n: 0, ..bad }, dt),
        FRACTUM_OK
    );
}
