use super::*;
use crate::sample::stream;
use crate::sample::voronoi::{Domain, elements, noisy_grid_seeds, tessellate};

fn sample(noise: f64, n: usize) -> (Vec<VoronoiCell>, Bodies, DlsmBonds) {
    let d = Domain::Box {
        lo: Vec3::zeros(),
        hi: Vec3::new(1.0, 0.8, 0.6),
    };
    let mut rng = stream(11, 9);
    let seeds = noisy_grid_seeds(&d, n, noise, &mut rng);
    let cells = tessellate(&seeds, &d).unwrap();
    let (bodies, _) = elements(&cells, 1000.0);
    let bonds = DlsmBonds::from_cells(&cells, &bodies, 20e9, 0.3);
    (cells, bodies, bonds)
}

/// Moves every element so that its seed follows u(x) = ε x (and turns it by `rot`
/// about the origin).
fn deform(
    cells: &[VoronoiCell],
    bodies: &mut Bodies,
    eps: &Matrix3<f64>,
    rot: &UnitQuaternion<f64>,
) {
    for (i, c) in cells.iter().enumerate() {
        bodies.orientation[i] = rot * bodies.orientation[i];
        bodies.pos[i] = rot * (c.seed + eps * c.seed);
    }
}

#[test]
fn the_strain_measures_differ_at_second_order_and_linear_is_exact() {
    // A finite uniaxial stretch (e = 2e-3, ν = −0.95): Eq. 15 as printed gives the affine
    // strain to round-off; the Green strains carry O(e²) terms, e²/e = 2e-3 of it.
    let e = 2e-3;
    let eps = Matrix3::from_diagonal(&Vec3::new(e, 0.95 * e, 0.95 * e));
    let mut worst = [0.0f64; 3];
    for (k, measure) in [
        StrainMeasure::Linear,
        StrainMeasure::GreenRotated,
        StrainMeasure::GreenPushed,
    ]
    .into_iter()
    .enumerate()
    {
        let (cells, mut bodies, mut bonds) = sample(0.8, 300);
        bonds.strain_measure = measure;
        deform(&cells, &mut bodies, &eps, &UnitQuaternion::identity());
        let mut forces = Forces::new(bodies.len());
        bonds.evaluate(&bodies, &mut forces, None);
        for i in 0..cells.len() {
            let err = (mat_of(&bonds.element_strain(i)) - eps).norm() / eps.norm();
            worst[k] = worst[k].max(err);
        }
    }
    assert!(worst[0] < 1e-9, "linear: {}", worst[0]);
    assert!(worst[1] > 2e-4 && worst[2] > 2e-4, "{worst:?}");
}

#[test]
fn uniform_strain_gives_hookes_stress_and_balanced_interior_elements() {
    let (cells, mut bodies, mut bonds) = sample(0.8, 600);
    // Small enough that the geometric terms (O(ε²): current normals and lengths) stay
    // below 1e-6 of the forces.
    let eps = Matrix3::new(1.0, 0.3, -0.2, 0.3, -0.5, 0.1, -0.2, 0.1, 0.7) * 1e-7;
    deform(&cells, &mut bodies, &eps, &UnitQuaternion::identity());
    let mut forces = Forces::new(bodies.len());
    bonds.evaluate(&bodies, &mut forces, None);
    let (lambda, mu) = (bonds.lambda, 0.5 * bonds.two_mu);
    let sigma = eps * (2.0 * mu) + Matrix3::identity() * (lambda * eps.trace());
    let mean_area = bonds.area.iter().sum::<f64>() / bonds.contacts() as f64;
    let scale = sigma.norm() * mean_area;
    let mut interior = 0;
    for (i, c) in cells.iter().enumerate() {
        let s = bonds.element_strain(i);
        // Small-strain least squares of a linear field: exact but for O(ε²) terms.
        assert!(
            (mat_of(&s) - eps).norm() < 1e-6 * eps.norm(),
            "element {i}: {s:?}"
        );
        if c.faces
            .iter()
            .all(|f| matches!(f.neighbour, Neighbour::Cell(_)))
        {
            interior += 1;
            assert!(
                forces.force[i].norm() < 1e-6 * scale,
                "element {i}: {}",
                forces.force[i]
            );
        }
    }
    assert!(interior > 50);
    for c in 0..bonds.contacts() {
        let [i, j] = bonds.pair[c];
        let n = (cells[j as usize].seed - cells[i as usize].seed).normalize();
        let (_, s) = bonds.contact_state(&bodies, c);
        assert!(
            (mat_of(&s) - sigma).norm() < 1e-5 * sigma.norm(),
            "contact {c}"
        );
        let want = sigma * n * bonds.area[c];
        assert!((bonds.out[c].f - want).norm() < 1e-5 * scale);
    }
}

#[test]
fn rigid_rotation_gives_no_strain_and_no_force() {
    let (cells, mut bodies, mut bonds) = sample(0.9, 300);
    let rot = UnitQuaternion::from_scaled_axis(Vec3::new(0.4, -1.1, 0.7));
    deform(&cells, &mut bodies, &Matrix3::zeros(), &rot);
    let mut forces = Forces::new(bodies.len());
    bonds.evaluate(&bodies, &mut forces, None);
    for i in 0..bodies.len() {
        let s = bonds.element_strain(i);
        assert!(s.iter().all(|v| v.abs() < 1e-13), "{s:?}");
        assert!(forces.force[i].norm() < 1e-3, "{}", forces.force[i]);
        assert!(forces.torque[i].norm() < 1e-3);
    }
}

#[test]
fn breaking_a_contact_removes_it_from_the_least_squares() {
    let (cells, mut bodies, mut bonds) = sample(0.0, 60);
    // Regular grid: a corner cube has exactly 3 neighbours; break one of them.
    let corner = 0;
    assert_eq!(bonds.active_neighbours(corner), 3);
    let (_, c) = bonds.neighbours(corner).next().unwrap();
    bonds.break_contacts(&[c]);
    assert_eq!(bonds.active_neighbours(corner), 2);
    // Fewer than 3 neighbours: null displacement field, whatever the neighbours do.
    let eps = Matrix3::from_diagonal(&Vec3::new(1e-4, 2e-4, 3e-4));
    deform(&cells, &mut bodies, &eps, &UnitQuaternion::identity());
    let mut forces = Forces::new(bodies.len());
    bonds.evaluate(&bodies, &mut forces, None);
    assert_eq!(bonds.element_strain(corner), [0.0; 6]);
    assert_eq!(bonds.out[c].f, Vec3::zeros());
}

#[test]
fn contact_breaks_when_normal_stress_exceeds_the_strength() {
    let (cells, mut bodies, mut bonds) = sample(0.0, 60);
    // Uniaxial strain along x: σxx = (λ + 2μ) ε on x contacts, λ ε on the others.
    let e = 1e-4;
    let eps = Matrix3::from_diagonal(&Vec3::new(e, 0.0, 0.0));
    deform(&cells, &mut bodies, &eps, &UnitQuaternion::identity());
    let (lambda, two_mu) = (bonds.lambda, bonds.two_mu);
    let sxx = (lambda + two_mu) * e;
    let mut forces = Forces::new(bodies.len());
    let none = bonds.evaluate(&bodies, &mut forces, Some(sxx * 1.001));
    assert!(none.is_empty());
    let broke = bonds.evaluate(&bodies, &mut forces, Some(sxx * 0.999));
    let along_x = (0..bonds.contacts())
        .filter(|&c| {
            let [i, j] = bonds.pair[c];
            (cells[j as usize].seed - cells[i as usize].seed).x.abs() > 1e-9
        })
        .count();
    assert_eq!(broke.len(), along_x);
    assert!(broke.iter().all(|&c| bonds.broken[c]));
}

#[test]
fn rotation_vector_matches_axis_angle() {
    for angle in [1e-9, 1e-3, 0.05, 1.0, 3.0] {
        let axis = Vec3::new(0.3, -0.4, 0.5).normalize();
        let q = UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
        let v = rotation_vector(&q.into_inner());
        assert!(
            (v - axis * angle).norm() < 1e-13 * angle.max(1.0),
            "{angle}"
        );
        let minus = rotation_vector(&(-q.into_inner()));
        assert!((minus - v).norm() < 1e-13 * angle.max(1.0));
    }
}
