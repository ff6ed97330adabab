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
