//! Particle fracture of the granular model (granular paper, Section 3):
//! the criteria on loaded spheres, the split's conservation and kinematics, and the energy of
//! breaking springs.

mod common;

use fractum::effects::{ContactRecord, ContactRecords, WALL};
use fractum::fracture::Criterion;
use fractum::fracture::break_plane::Trigger;
use fractum::models::granular::Simulation;
use fractum::state::{Bodies, Forces, Vec3, Walls};
use nalgebra::UnitQuaternion;
use std::f64::consts::PI;

const R: f64 = 0.3e-3;
const SIGMA_C: f64 = 592e6;
const SIGMA_F: f64 = 2e9;
const NU: f64 = 0.17;

/// One sphere of radius R at the origin with the fracture effect (m_i = 20.56, σc = 592 MPa,
/// contact strength 2 GPa) and no contacts of its own: the tests hand it contacts.
fn one_sphere(effects: &str) -> Simulation {
    let scene = common::scene(
        effects,
        &format!("[fracture]\nreference_strength = {SIGMA_F:e}\nsigma_c = {SIGMA_C:e}\n"),
        1e-3,
        1e-9,
    );
    let mut b = Bodies::default();
    b.push_sphere(Vec3::zeros(), R, 2650.0, UnitQuaternion::identity());
    Simulation::from_sample(scene, common::sample(b, Walls::default()), 1).unwrap()
}

/// Contacts pressing on the sphere with force `f` along each of `dirs` (unit vectors to the
/// contact points), over contact radius `a`; the forces balance.
fn pressed(dirs: &[Vec3], f: f64, a: f64) -> ContactRecords {
    let list = dirs
        .iter()
        .enumerate()
        .map(|(w, d)| ContactRecord {
            i: 0,
            j: WALL | w as u32,
            point: d * R,
            normal: -d,
            force: -d * f,
            normal_force: f,
            hertz_force: f,
            radius: a,
            stiffness: 0.0,
            energy: 0.0,
        })
        .collect();
    ContactRecords {
        list,
        dissipated: 0.0,
    }
}

fn check(sim: &Simulation, records: &ContactRecords) -> Vec<fractum::fracture::Breaking> {
    let forces = Forces::new(1);
    let mut fracture = sim.model.state.fracture.clone().unwrap();
    fracture.check(&sim.model.state.bodies, &forces, records)
}

/// The contact radius at which force `f` gives the contact tensile stress `st` (Eq. 17).
fn radius_for_tensile_stress(f: f64, st: f64) -> f64 {
    ((1.0 - 2.0 * NU) * f / (2.0 * PI * st)).sqrt()
}

/// Uniaxial: two opposite contacts give σ1 = 3F/(2πr²), σ3 = 0, and Hoek–Brown breaks the
/// sphere exactly when σ1 reaches σc (the red dot of Fig. 6).
#[test]
fn sphere_under_uniaxial_load_breaks_by_hoek_brown_at_sigma_c() {
    let sim = one_sphere("\"contact\", \"fracture\"");
    let f_c = SIGMA_C * 2.0 * PI * R * R / 3.0;
    let dirs = [Vec3::z(), -Vec3::z()];
    // Contacts far from their tensile strength: only Hoek–Brown can act.
    let a = radius_for_tensile_stress(f_c, 0.1 * SIGMA_F);
    let below = check(&sim, &pressed(&dirs, f_c * (1.0 - 1e-9), a));
    assert!(below.is_empty(), "no break just below σc");
    let above = check(&sim, &pressed(&dirs, f_c * (1.0 + 1e-9), a));
    assert_eq!(above.len(), 1);
    assert_eq!(above[0].2, Criterion::HoekBrown);
    assert!(
        (above[0].3 / SIGMA_C - 1.0).abs() < 1e-8,
        "σ1 = {}",
        above[0].3
    );
    // The break plane contains the load axis: its normal is perpendicular to z.
    let Trigger::HoekBrown { stress } = above[0].1 else {
        panic!("Hoek–Brown trigger");
    };
    let n = Trigger::HoekBrown { stress }.ideal_normal();
    assert!(n.z.abs() < 1e-9, "{n}");
}

/// Equal loads in the Hoek–Brown sense, σ1 = σ3 (the blue dot of Fig. 6; in 3D the sphere is
/// pressed equally along x, y and z), never break by Hoek–Brown, even at twice σc; the contact
/// criterion breaks the sphere once three (here six) contacts exceed the tensile strength.
/// Loaded along x and y only, σ3 = 0 in 3D, and Hoek–Brown breaks it at σc as in uniaxial.
#[test]
fn sphere_under_equal_loads_breaks_by_contacts_not_hoek_brown() {
    let sim = one_sphere("\"contact\", \"fracture\"");
    let six = [
        Vec3::x(),
        -Vec3::x(),
        Vec3::y(),
        -Vec3::y(),
        Vec3::z(),
        -Vec3::z(),
    ];
    let f = 2.0 * SIGMA_C * 2.0 * PI * R * R / 3.0;
    let a = radius_for_tensile_stress(f, SIGMA_F);
    let below = check(&sim, &pressed(&six, f, a * (1.0 + 1e-6)));
    assert!(below.is_empty(), "σ1 = σ3 = 2σc: no Hoek–Brown failure");
    let above = check(&sim, &pressed(&six, f, a * (1.0 - 1e-6)));
    assert_eq!(above.len(), 1);
    assert_eq!(above[0].2, Criterion::Contacts);
    assert!((above[0].3 / SIGMA_F - 1.0).abs() < 1e-5);
    // Only two contacts above the strength: not enough.
    let mut two = pressed(&six, f, a * (1.0 + 1e-6));
    for r in &mut two.list[..2] {
        r.radius = a * (1.0 - 1e-6);
    }
    assert!(check(&sim, &two).is_empty());
    let mut three = two.clone();
    three.list[4].radius = a * (1.0 - 1e-6);
    let broke = check(&sim, &three);
    assert_eq!(broke.len(), 1);
    // The plane through the contacts at +x, -x and +z is normal to y.
    let Trigger::Contacts { normal } = broke[0].1 else {
        panic!("contact trigger");
    };
    assert!((normal.y.abs() - 1.0).abs() < 1e-12, "{normal}");
    // Biaxial in 3D: σ3 = 0 along z, so Hoek–Brown acts at σc as under uniaxial load.
    let four = &six[..4];
    let f_c = SIGMA_C * 2.0 * PI * R * R / 3.0;
    let a_far = radius_for_tensile_stress(f_c, 0.1 * SIGMA_F);
    assert!(check(&sim, &pressed(four, f_c * (1.0 - 1e-9), a_far)).is_empty());
    let b = check(&sim, &pressed(four, f_c * (1.0 + 1e-9), a_far));
    assert_eq!(b[0].2, Criterion::HoekBrown);
}

/// Angular acceleration of body k in the world frame, `I⁻¹ (T − ω × I ω)`.
fn angular_acceleration(sim: &Simulation, k: usize) -> Vec3 {
    let b = &sim.model.state.bodies;
    let q = b.orientation[k];
    let w = q.inverse_transform_vector(&b.omega[k]);
    let t = q.inverse_transform_vector(&sim.model.state.forces.torque[k]);
    let i = b.inertia[k];
    q * (t - w.cross(&w.component_mul(&i))).component_div(&i)
}

/// A lopsided grain spinning in free fall, split with cohesion: mass is conserved to 1e-12,
/// and the initial cohesive forces (Eq. 40–43) make each half accelerate exactly as the
/// parent's material did at its centre, `a_P + α_P × r + ω × (ω × r)`, centripetal part
/// included. Spinning about an axis of symmetry of the split, the angular accelerations agree
/// too. In general they cannot all agree: the halves hold the parent's mass in 90% of its
/// volume, so their inertia differs from the parent's by about 10%, the moments the springs
/// must supply for α_A = α_B = α_P are not equal and opposite, and as Eq. 43 does for the
/// forces each half gets the mean; the lopsided grain's halves turn within 10% of the parent.
#[test]
fn split_conserves_mass_and_halves_accelerate_as_the_parent() {
    use fractum::shape::PolyEllipsoid;
    let scene = common::scene(
        "\"contact\", \"gravity\", \"fracture\", \"cohesion\"",
        &format!("[fracture]\nreference_strength = {SIGMA_F:e}\n"),
        1e-3,
        1e-9,
    );
    let cases: [([f64; 6], Vec3, usize); 2] = [
        // A lopsided grain spinning about a skew axis.
        (
            [0.32e-3, 0.25e-3, 0.30e-3, 0.27e-3, 0.35e-3, 0.28e-3],
            Vec3::new(300.0, -200.0, 500.0),
            3,
        ),
        // A sphere spinning about the normal of its break plane: both halves are bodies of
        // revolution about it, so no gyroscopic term differs.
        ([R; 6], Vec3::new(800.0, 0.0, 0.0), 0),
    ];
    for (semi, omega, _) in cases {
        let pe = PolyEllipsoid::new(semi).unwrap();
        let mut b = Bodies::default();
        let q = UnitQuaternion::from_euler_angles(0.3, 0.2, -0.4);
        let mass = 2650.0 * pe.volume();
        b.push_poly_ellipsoid(pe, mass, Vec3::new(1e-3, 2e-3, 3e-3), q);
        b.vel[0] = Vec3::new(0.1, 0.0, -0.2);
        b.omega[0] = q * omega;
        let mut sim =
            Simulation::from_sample(scene.clone(), common::sample(b, Walls::default()), 1).unwrap();
        let (x_p, w) = (
            sim.model.state.bodies.pos[0],
            sim.model.state.bodies.omega[0],
        );
        let a_p = sim.model.state.forces.force[0] / mass;
        assert!((a_p - Vec3::new(0.0, 0.0, -9.81)).norm() < 1e-12);
        let alpha_p = angular_acceleration(&sim, 0);
        // Break along the grain's x axis (a Hoek–Brown stress most tensile along it).
        let x = sim.model.state.bodies.shape_placement(0).1 * Vec3::x();
        let stress = x * x.transpose() * 1e8;
        let made =
            sim.break_grains(&[(0, Trigger::HoekBrown { stress }, Criterion::HoekBrown, 0.0)]);
        assert_eq!(made, 1);
        let b = &sim.model.state.bodies;
        assert_eq!(b.len(), 2);
        assert!(((b.mass[0] + b.mass[1]) / mass - 1.0).abs() < 1e-12);
        let f = sim.model.state.fracture.as_ref().unwrap();
        assert!(f.springs.len() >= 3, "springs {}", f.springs.len());
        for k in 0..2 {
            let r = b.pos[k] - x_p;
            let want = a_p + alpha_p.cross(&r) + w.cross(&w.cross(&r));
            let got = sim.model.state.forces.force[k] / b.mass[k];
            assert!(
                (got - want).norm() < 1e-9 * want.norm(),
                "half {k}: a = {got}, parent field {want}"
            );
            let alpha = angular_acceleration(&sim, k);
            let dev = (alpha - alpha_p).norm() / alpha_p.norm().max(w.norm_squared());
            println!("half {k}: α {alpha:?} parent {alpha_p:?} relative deviation {dev:e}");
            let bound = if semi == [R; 6] { 1e-9 } else { 0.1 };
            assert!(dev < bound, "half {k}: α deviates by {dev:e}");
        }
    }
}

/// Section 3.4.2: a cohesive spring's force falls to zero as it opens, so breaking it releases
/// no force: the step in which it breaks changes the kinetic energy by less than 1% of the
/// energy the spring held (G_c A), and the halves flying apart lose exactly G_c A to it.
#[test]
fn breaking_a_spring_injects_no_energy() {
    use fractum::fracture::cohesion::{Spring, cohesive_energy};
    let scene = common::scene(
        "\"contact\", \"fracture\", \"cohesion\"",
        &format!("[fracture]\nreference_strength = {SIGMA_F:e}\n"),
        1e-6,
        1e-10,
    );
    let mut b = Bodies::default();
    let gap = 0.1e-3;
    for x in [-(R + 0.5 * gap), R + 0.5 * gap] {
        b.push_sphere(
            Vec3::new(x, 0.0, 0.0),
            R,
            2650.0,
            UnitQuaternion::identity(),
        );
    }
    let mut sim = Simulation::from_sample(scene, common::sample(b, Walls::default()), 1).unwrap();
    let gc = cohesive_energy(1.77e6, 60e9, 0.17);
    let area = PI * R * R / 4.0;
    let f0 = 10.0;
    // One spring at the midpoint, pulling A (at -x) towards B.
    let spring = Spring {
        a: 0,
        b: 1,
        on_a: Vec3::new(R + 0.5 * gap, 0.0, 0.0),
        on_b: Vec3::new(-(R + 0.5 * gap), 0.0, 0.0),
        direction: Vec3::x(),
        f0,
        k: f0 * f0 / (2.0 * gc * area),
        opening: 0.0,
        last_gap: Vec3::zeros(),
        last_force: Vec3::x() * f0,
        broken: false,
    };
    let stored = spring.stored_energy();
    assert!((stored / (gc * area) - 1.0).abs() < 1e-12);
    {
        let f = sim.model.state.fracture.as_mut().unwrap();
        f.springs.push(spring);
        f.bonds[0] = 1;
        f.bonds[1] = 1;
    }
    sim.model.state.forces.force[0] += Vec3::x() * f0;
    sim.model.state.forces.force[1] -= Vec3::x() * f0;
    // The halves fly apart with twice the energy the spring holds.
    let v = (2.0 * stored / (2.0 * sim.model.state.bodies.mass[0])).sqrt() * 2f64.sqrt();
    sim.model.state.bodies.vel[0] = Vec3::new(-v, 0.0, 0.0);
    sim.model.state.bodies.vel[1] = Vec3::new(v, 0.0, 0.0);
    let k0 = sim.model.state.bodies.kinetic_energy();
    assert!((k0 / (2.0 * stored) - 1.0).abs() < 1e-12);
    let mut last = k0;
    let mut jump = None;
    for _ in 0..5000 {
        sim.advance(1).unwrap();
        let k = sim.model.state.bodies.kinetic_energy();
        if jump.is_none() && sim.model.state.fracture.as_ref().unwrap().springs[0].broken {
            jump = Some(k - last);
        }
        last = k;
    }
    let jump = jump.expect("the spring broke");
    println!(
        "break step: ΔK = {jump:e} J, stored {stored:e} J; spent {:e}",
        k0 - sim.model.state.bodies.kinetic_energy()
    );
    assert!(
        jump.abs() < 0.01 * stored,
        "kinetic energy jumped by {jump:e} J at the break, {:.3}% of the stored {stored:e} J",
        100.0 * jump.abs() / stored
    );
    // The energy spent in fracture is G_c A (Eq. 36), taken from the halves' motion.
    let spent = k0 - sim.model.state.bodies.kinetic_energy();
    assert!(
        (spent / stored - 1.0).abs() < 0.01,
        "spent {spent:e} J of {stored:e} J"
    );
    let work = sim.model.state.fracture.as_ref().unwrap().spring_work;
    assert!(
        (-work / stored - 1.0).abs() < 0.01,
        "spring work {work:e} J"
    );
}

/// `fractum explain` on the main job names fracture, its criteria and constants, Weibull and
/// cohesion, and the step adaptation (it mentioned none of them); without
/// cohesion and Weibull it says so.
#[test]
fn explain_names_fracture_weibull_cohesion_and_the_step_rule() {
    let file = common::repo().join("scenes/shpb_sand.toml");
    let o = common::fractum(&common::repo(), &["explain", file.to_str().unwrap()]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for want in [
        "after each step: fracture:",
        "Hoek-Brown (m_i = 20.56, sigma_c = 5.92e8 Pa)",
        "sigma_fM = 3e9 Pa",
        "+ weibull:",
        "+ cohesion: the halves held by 4 springs",
        "omega dt <= 1.200 (3 x 0.4)",
    ] {
        assert!(s.contains(want), "missing `{want}`: {s}");
    }
    let o = common::fractum(
        &common::repo(),
        &[
            "explain",
            file.to_str().unwrap(),
            "--set",
            "effects=[\"contact\", \"fracture\"]",
        ],
    );
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        s.contains("(no weibull)") && s.contains("(no cohesion)"),
        "{s}"
    );
}

/// crush_grain with each piece's strength drawn afresh at its size (Weibull on the particle
/// strength, size exponent 1): the list of bodies per generation of the summary.
fn crushed(extra: &[&str]) -> (Vec<u64>, u64, serde_json::Value) {
    let mut args = vec![
        "--set",
        r#"effects=["contact","damping","friction","fracture","cohesion","weibull"]"#,
        "--set",
        r#"fracture.weibull_on="particle""#,
        "--set",
        "fracture.reference_radius=0.15e-3",
        "--set",
        "fracture.weibull_modulus=3",
        "--set",
        "fracture.size_exponent=1",
    ];
    args.extend_from_slice(extra);
    let (_dir, s, _) = common::run_scene("scenes/crush_grain.toml", &args);
    let c = &s["comminution"];
    let generations = c["generations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g.as_u64().unwrap())
        .collect();
    (generations, c["at_comminution_limit"].as_u64().unwrap(), s)
}

/// Comminution goes on: between the platens a fragment of a fragment breaks again, each
/// piece with its own Weibull strength at its own size (three generations or more).
#[test]
fn a_fragment_of_a_fragment_breaks_between_platens() {
    let (generations, at_limit, s) = crushed(&[]);
    assert!(generations.len() >= 4, "{generations:?}");
    assert!(generations[3..].iter().sum::<u64>() > 0, "{generations:?}");
    assert_eq!(at_limit, 0);
    let bodies: u64 = generations.iter().sum();
    assert_eq!(bodies, s["particles_final"].as_u64().unwrap());
}

/// A piece below the comminution limit never splits: with the limit between the grain's
/// equivalent radius (0.2915 mm: semi-axes sums 0.59, 0.56, 0.60 mm, V = π/6 × their product)
/// and its halves' (about 0.23 mm), the grain splits once and neither half again, however far
/// the platens go.
#[test]
fn pieces_below_the_comminution_limit_never_split() {
    let v = PI / 6.0 * 0.59e-3 * 0.56e-3 * 0.60e-3;
    let r = (3.0 * v / (4.0 * PI)).cbrt();
    assert!((r - 0.2915e-3).abs() < 1e-7, "{r}");
    let (generations, at_limit, s) = crushed(&["--set", "fracture.comminution_limit=0.27e-3"]);
    assert_eq!(generations, vec![0, 2], "{s}");
    assert_eq!(at_limit, 2);
    assert_eq!(s["splits"]["total"].as_u64().unwrap(), 1);
}
