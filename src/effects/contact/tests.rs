use super::*;

/// 400 spheres on a jittered grid of spacing 0.95 mm, radii 0.45-0.55 mm, in the box
/// [0, 9.5 mm)² × [0, 3.8 mm): most touch their neighbours, and the outer ones the walls.
fn grid_of_spheres() -> (Bodies, Walls) {
    let density = 2650.0;
    let mut bodies = Bodies::default();
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
    let walls = Walls::new_box(Vec3::zeros(), Vec3::new(9.5e-3, 9.5e-3, 3.8e-3));
    (bodies, walls)
}

/// A pair loop cut by rows (sample preparation's) gives the same bits alone and on teams of
/// two and three, over steps that carry friction histories; and the sums it adds in another
/// order than the plain loop agree with the plain loop's to rounding.
#[test]
fn parts_by_rows_give_the_same_bits_on_any_team() {
    let (bodies, walls) = grid_of_spheres();
    let run = |parts: PairParts, team: Option<crate::parallel::Team>| {
        let mut effect = build_contact(ContactParams {
            hertz: Hertz::new(60e9, 0.17),
            damping: Some(ViscousDamping::from_restitution(0.5)),
            mindlin: Some(Mindlin::new(60e9, 0.17, 0.5)),
            wall_friction: None,
            sleeve_friction: None,
            skin: None,
            shapes: false,
            parts,
        });
        let (mut b, mut w) = (bodies.clone(), walls.clone());
        let mut forces = Forces::new(b.len());
        let ctx = StepContext {
            dt: 1e-8,
            update_history: true,
        };
        let mut steps = || {
            for _ in 0..3 {
                forces.clear();
                effect.accumulate(&ctx, &b, &mut w, &mut forces);
                // Move the bodies a little along their forces, so that histories grow.
                for i in 0..b.len() {
                    let dv = forces.force[i] * b.inv_mass[i] * ctx.dt;
                    b.pos[i] += dv * ctx.dt;
                }
            }
            (forces.force.clone(), forces.torque.clone())
        };
        match &team {
            Some(t) => t.awake_for(&mut steps),
            None => steps(),
        }
    };
    let alone = run(PairParts::PerRows(64), None);
    for size in [2, 3] {
        let team = crate::parallel::Team::new(size).unwrap();
        assert!(
            run(PairParts::PerRows(64), Some(team)) == alone,
            "a team of {size} changed the bits"
        );
    }
    let plain = run(PairParts::PerThread, None);
    let scale = plain.0.iter().map(|f| f.norm()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    for (a, b) in alone.0.iter().zip(&plain.0) {
        assert!((a - b).norm() <= 1e-12 * scale, "{a} against {b}");
    }
}

/// The spheres' frequency estimate is gathered in the force pass: it must be what summing
/// `2 E* a` over every overlapping pair and wall, found here by brute force over all
/// pairs (no neighbour list), gives — on one thread and on a team of two (whose private
/// accumulators are merged with the forces).
#[test]
fn the_spheres_frequency_estimate_is_the_sum_over_their_overlaps() {
    let (young, poisson) = (60e9, 0.17);
    let (bodies, mut walls) = grid_of_spheres();
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
                parts: PairParts::PerThread,
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
            parts: PairParts::PerThread,
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
