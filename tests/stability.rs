//! The time-step guard: Hertz contacts stiffen as they overlap, so a run checks its highest
//! contact frequency against the velocity Verlet limit `ω dt < 2`.

mod common;

use fractum::Run;
use fractum::models::granular::Simulation;
use fractum::state::{Bodies, Vec3, Walls};
use nalgebra::UnitQuaternion;

const RHO: f64 = 2650.0;

fn pair(r: f64, overlap: f64, v: f64) -> Bodies {
    let mut b = Bodies::default();
    let x = r - 0.5 * overlap;
    b.push_sphere(Vec3::new(-x, 0.0, 0.0), r, RHO, UnitQuaternion::identity());
    b.push_sphere(Vec3::new(x, 0.0, 0.0), r, RHO, UnitQuaternion::identity());
    b.vel[0].x = v;
    b.vel[1].x = -v;
    b
}

#[test]
fn frequency_estimate_is_exact_for_two_equal_spheres() {
    let (r, delta) = (1e-3, 2e-6);
    let scene = common::scene("\"contact\"", "", 1e-6, 1e-9);
    let sim = Simulation::from_sample(
        scene,
        common::sample(pair(r, delta, 0.0), Walls::default()),
        1,
    )
    .unwrap();
    let e_eff = 60e9 / (2.0 * (1.0 - 0.17 * 0.17));
    // Normal mode of two equal masses on the contact's tangent stiffness k = 2 E* sqrt(R* δ):
    // ω² = k / m* with m* = m / 2.
    let k = 2.0 * e_eff * (0.5 * r * delta).sqrt();
    let m_eff = 0.5 * sim.bodies.mass[0];
    let omega = (k / m_eff).sqrt();
    let estimate = sim.pipeline.max_frequency(&sim.bodies, &sim.walls);
    assert!(
        (estimate / omega - 1.0).abs() < 1e-9,
        "{estimate} vs {omega}"
    );
}

#[test]
fn a_step_too_long_for_the_contacts_stops_the_run_with_a_clear_error() {
    // r = 1 mm spheres meeting at 1 m/s each: contact time about 6 µs. After one step of
    // 4 µs they overlap by 8 µm, where the contact oscillates with ω dt ≈ 3.4.
    let r = 1e-3;
    let scene = common::scene("\"contact\"", "", 2e-5, 4e-6);
    let mut sim = Simulation::from_sample(
        scene,
        common::sample(pair(r, 0.0, 1.0), Walls::default()),
        1,
    )
    .unwrap();
    let err = sim.advance(u64::MAX).unwrap_err().to_string();
    assert!(err.contains("omega dt") && err.contains("time.dt"), "{err}");
    assert_eq!(fractum::Error::run("x").exit_code(), 1);
    // The same impact at a hundredth of the step runs through and records its largest ω dt.
    let scene = common::scene("\"contact\"", "", 2e-5, 2e-8);
    let mut sim = Simulation::from_sample(
        scene,
        common::sample(pair(r, 0.0, 1.0), Walls::default()),
        1,
    )
    .unwrap();
    sim.advance(u64::MAX).unwrap();
    let max = sim.summary()["max_omega_dt"].as_f64().unwrap();
    assert!(max > 0.0 && max < 0.1, "{max}");
    assert!(sim.warnings.is_empty());
}
