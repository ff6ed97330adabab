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
