//! The Hertz–Mindlin contact against closed-form theory: head-on impact (duration, maximum
//! overlap), restitution with damping, and a sphere sliding on a wall (Coulomb limit, then
//! rolling at 5/7 of the initial speed).

mod common;

use fractum::models::granular::Simulation;
use fractum::state::{Bodies, BoxFace, Vec3, Walls};
use nalgebra::UnitQuaternion;

const E: f64 = 60e9;
const NU: f64 = 0.17;
const RHO: f64 = 2650.0;

fn e_eff() -> f64 {
    E / (2.0 * (1.0 - NU * NU))
}

/// Two equal spheres of radius `r` approaching head-on at `v` each, with restitution `e`
/// when `effects` include damping. Returns the contact duration (s), the maximum overlap (m)
/// and the rebound speed of each sphere (m/s).
fn head_on(effects: &str, e: f64, r: f64, v: f64) -> (f64, f64, f64) {
    let mut b = Bodies::default();
    b.push_sphere(
        Vec3::new(-r - 1e-9, 0.0, 0.0),
        r,
        RHO,
        UnitQuaternion::identity(),
    );
    b.push_sphere(
        Vec3::new(r + 1e-9, 0.0, 0.0),
        r,
        RHO,
        UnitQuaternion::identity(),
    );
    b.vel[0].x = v;
    b.vel[1].x = -v;
    let m = b.mass[0];
    let m_eff = 0.5 * m;
    let r_eff = 0.5 * r;
    let t_c = 2.87 * (m_eff * m_eff / (r_eff * e_eff().powi(2) * 2.0 * v)).powf(0.2);
    let dt = t_c / 4000.0;
    let mut scene = common::scene(effects, "", 3.0 * t_c, dt);
    fractum::scene::apply_override(&mut scene.tables, &format!("material.restitution={e:e}"))
        .unwrap();
    let mut sim = Simulation::from_sample(scene, common::sample(b, Walls::default()), 1).unwrap();
    let overlap = |s: &Simulation| {
        2.0 * r - (s.model.state.bodies.pos[1] - s.model.state.bodies.pos[0]).norm()
    };
    let (mut start, mut end, mut max_overlap) = (None, None, 0.0_f64);
    let mut prev = (sim.clock.time, overlap(&sim));
    while !sim.finished() {
        sim.advance(1).unwrap();
        let now = (sim.clock.time, overlap(&sim));
        // Interpolate the instants where the overlap changes sign.
        let cross = prev.0 + (now.0 - prev.0) * prev.1 / (prev.1 - now.1);
        if prev.1 <= 0.0 && now.1 > 0.0 && start.is_none() {
            start = Some(cross);
        }
        if prev.1 > 0.0 && now.1 <= 0.0 && end.is_none() {
            end = Some(cross);
        }
        max_overlap = max_overlap.max(now.1);
        prev = now;
    }
    let duration = end.expect("spheres separate") - start.expect("spheres touch");
    (duration, max_overlap, -sim.model.state.bodies.vel[0].x)
}

#[test]
fn head_on_impact_matches_hertz_duration_and_overlap() {
    let (r, v) = (1e-3, 1.0);
    let (duration, max_overlap, rebound) = head_on("\"contact\"", 1.0, r, v);
    let m_eff = 0.5 * fractum::shape::sphere_mass(r, RHO);
    let r_eff = 0.5 * r;
    let vrel = 2.0 * v;
    let t_theory = 2.87 * (m_eff * m_eff / (r_eff * e_eff().powi(2) * vrel)).powf(0.2);
    let d_theory = (15.0 * m_eff * vrel * vrel / (16.0 * e_eff() * r_eff.sqrt())).powf(0.4);
    assert!(
        (duration / t_theory - 1.0).abs() < 0.01,
        "contact time {duration:e} s, Hertz {t_theory:e} s"
    );
    assert!(
        (max_overlap / d_theory - 1.0).abs() < 0.01,
        "maximum overlap {max_overlap:e} m, Hertz {d_theory:e} m"
    );
    // Without damping the collision is elastic.
    assert!((rebound / v - 1.0).abs() < 1e-6, "rebound {rebound}");
}

#[test]
fn damped_impact_gives_the_requested_restitution() {
    for e in [0.2, 0.5, 0.8] {
        let v = 2.0;
        let (_, _, rebound) = head_on("\"contact\", \"damping\"", e, 0.3e-3, v);
        let measured = rebound / v;
        assert!(
            (measured / e - 1.0).abs() < 0.02,
            "requested e = {e}, measured {measured}"
        );
    }
}

#[test]
fn sliding_sphere_saturates_at_mu_n_then_rolls_at_five_sevenths() {
    let r = 1e-3;
    let v0 = 0.5;
    let mu = 0.3;
    let g = 9.81;
    let mut b = Bodies::default();
    let m = fractum::shape::sphere_mass(r, RHO);
    // Start at the static Hertz overlap under the sphere's weight, so it does not bounce.
    let delta0 = (m * g / (4.0 / 3.0 * e_eff() * r.sqrt())).powf(2.0 / 3.0);
    b.push_sphere(
        Vec3::new(0.0, 0.0, r - delta0),
        r,
        RHO,
        UnitQuaternion::identity(),
    );
    b.vel[0].x = v0;
    let walls = Walls::new_box(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 1.0));
    // Sliding decelerates at mu g; rolling starts after t = 2 v0 / (7 mu g).
    let t_roll = 2.0 * v0 / (7.0 * mu * g);
    let mut scene = common::scene(
        "\"contact\", \"damping\", \"friction\", \"gravity\"",
        "",
        2.0 * t_roll,
        2e-7,
    );
    fractum::scene::apply_override(&mut scene.tables, &format!("material.friction={mu:e}"))
        .unwrap();
    let mut sim = Simulation::from_sample(scene, common::sample(b, walls), 1).unwrap();
    let mut saturated = 0;
    let mut worst: f64 = 0.0;
    while sim.clock.time < 0.8 * t_roll {
        sim.advance(1).unwrap();
        let f = sim.model.state.walls.face(BoxFace::ZMin).force;
        let normal = -f.z;
        let tangential = (f.x * f.x + f.y * f.y).sqrt();
        let slip = sim.model.state.bodies.vel[0].x - r * sim.model.state.bodies.omega[0].y;
        if slip > 1e-3 {
            worst = worst.max((tangential / (mu * normal) - 1.0).abs());
            saturated += 1;
        }
    }
    assert!(
        saturated > 1000,
        "the sphere slides for a while ({saturated} steps)"
    );
    assert!(
        worst < 1e-9,
        "|F_t| / (mu F_n) - 1 reached {worst:e} while sliding"
    );
    sim.advance(u64::MAX).unwrap();
    let v_end = sim.model.state.bodies.vel[0].x;
    assert!(
        (v_end / (5.0 / 7.0 * v0) - 1.0).abs() < 0.01,
        "rolling speed {v_end}, theory {}",
        5.0 / 7.0 * v0
    );
    let rolling = sim.model.state.bodies.omega[0].y * r;
    assert!((rolling / v_end - 1.0).abs() < 0.01, "rolls without slip");
}
