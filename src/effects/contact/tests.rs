use super::*;

/// The spheres' frequency estimate is gathered in the force pass: it must be what summing
/// `2 E* a` over every overlapping pair and wall, found here by brute force over all
/// pairs (no neighbour list), gives — on one thread and on a team of two (whose private
/// accumulators are merged with the forces).
#[test]
fn the_spheres_frequency_estimate_is_the_sum_over_their_overlaps() {
    let (young, poisson, density) = (60e9, 0.17, 2650.0);
    let mut bodies = Bodies::default();
    // 400 spheres on a jittered grid of spacing 0.95 mm, radii 0.45-0.55 mm: most touch
    // their neighbours, and the outer ones the walls of the box [0, 9.5 mm)^3.
    let mut seed = 12345u64;
    let mut rand = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for ix in 0..10 {
        for iy in 0..10 {
            for iz in 0..4 {
                let jitter = Vec3::new(rand(), rand(), rand()) * 0.05e-3;
                let pos = Vec3::new(ix as f64, iy as f64, iz as f64) * 0.95e-3
                    + Vec3::repeat(0.5e-3)
                    + jitter;
                let r = 0.45e-3 + 0.1e-3 * rand();
                bodies.push_sphere(pos, r, density, UnitQuaternion::identity());
            }
        }
    }
    let mut walls = Walls::new_box(Vec3::zeros(), Vec3::new(9.5e-3, 9.5e-3, 3.8e-3));
    let hertz = Hertz::new(young, poisson);
    let two_e = 2.0 * hertz.e_eff;
    let n = bodies.len();
    let mut sums = vec![0.0; n];
    for i in 0..n {
        for j in i + 1..n {
            let (ri, rj) = (bodies.radius[i], bodies.radius[j]);
            let delta = ri + rj - (bodies.pos[i] - bodies.pos[j]).norm();
            if delta > 0.0 {
                let k = two_e * (ri * rj / (ri + rj) * delta).sqrt();
                sums[i] += k;
                sums[j] += k;
            }
        }
        for wall in &walls.walls {
            let delta = bodies.radius[i] - wall.distance(&bodies.pos[i]);
            if delta > 0.0 {
                sums[i] += two_e * (bodies.radius[i] * delta).sqrt();
            }
        }
    }
    let expected = (0..n)
        .map(|i| (2.0 * sums[i] * bodies.inv_mass[i]).sqrt())
        .fold(0.0, f64::max);
    let touching = sums.iter().filter(|&&k| k > 0.0).count();
    assert!(touching > n / 2, "{touching} of {n} touch");
    for team in [None, Some(crate::parallel::Team::new(2).unwrap())] {
        for friction in [None, Some(Mindlin::new(young, poisson, 0.5))] {
            let mut effect = build_contact(ContactParams {
                hertz,
                damping: Some(ViscousDamping::from_restitution(0.5)),
                mindlin: friction,
                wall_friction: None,
                sleeve_friction: None,
                skin: None,
                shapes: false,
            });
            let mut forces = Forces::new(n);
            let ctx = StepContext {
                dt: 1e-9,
                update_history: false,
            };
            let mut evaluate = || effect.accumulate(&ctx, &bodies, &mut walls, &mut forces);
            match &team {
                Some(t) => t.awake_for(&mut evaluate),
                None => evaluate(),
            }
            let got = effect.max_frequency(&bodies, &walls);
            assert!(
                (got - expected).abs() <= 1e-12 * expected,
                "team {}: {got} against {expected}",
                team.is_some()
            );
        }
    }
}

/// A saved contact history names its bodies by index; restored into a state of fewer
/// bodies (a forged or mismatched checkpoint) it is refused naming the body, where the
/// first step after it indexed a row that does not exist; within the bodies it is taken.
#[test]
fn a_history_naming_a_body_past_the_state_is_refused() {
    for shapes in [false, true] {
        let params = ContactParams {
            hertz: Hertz::new(60e9, 0.17),
            damping: None,
            mindlin: Some(Mindlin::new(60e9, 0.17, 0.5)),
            wall_friction: None,
            sleeve_friction: None,
            skin: None,
            shapes,
        };
        let saved = SavedHistory {
            pairs: vec![(0, 5, [1e-9, 0.0, 0.0])],
            walls: vec![(0, 2, [0.0; 3])],
            normals: Vec::new(),
            wall_radii: Vec::new(),
        };
        let data = postcard::to_stdvec(&saved).unwrap();
        let mut effect = build_contact(params);
        let err = effect.restore(&data, 5).unwrap_err().to_string();
        assert!(err.contains("names body 5 of a state of 5 bodies"), "{err}");
        effect.restore(&data, 6).unwrap();
    }
}
