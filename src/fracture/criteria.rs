//! The fracture criteria of a grain (granular paper, Section 3.1–3.2): the
//! particle average stress with its dynamic terms (Eq. 8–13), Hoek–Brown on it (Eq. 14), the
//! maximum tensile stress of a Hertz contact (Eq. 17) and the Weibull strength (Eq. 18).
//!
//! Sign conventions: [`average_stress`] is tension positive, like every other stress in
//! Fractum; Hoek–Brown takes compression positive, as the paper does, and
//! [`principal_compressions`] converts at that boundary.

use nalgebra::{Matrix3, SymmetricEigen};

use crate::linalg::symmetric3_eigenvalues;
pub use crate::linalg::symmetric3_largest_eigenvalue;
use crate::state::Vec3;

/// One force acting on a grain: the force (N) and its point of application relative to the
/// grain's centre of mass (m), both in the world frame.
#[derive(Debug, Clone, Copy)]
pub struct AppliedForce {
    pub force: Vec3,
    pub lever: Vec3,
}

/// The particle average stress (Pa, tension positive, world frame), Eq. 8–13:
///
/// ```text
/// σ = (1/V) [ Σ_α f^α ⊗ x^α  −  ∫ ρ a ⊗ x dV  +  g ⊗ ∫ ρ x dV ]
/// ```
///
/// with x measured from the centre of mass, where `∫ ρ x dV = 0` (no gravity term) and, for
/// the rigid-body acceleration `a = a_o + α × x + ω × (ω × x)` (Eq. 10),
/// `∫ ρ a ⊗ x dV = (W(α) + ω ωᵀ − |ω|² 1) M` (Eq. 13), `W(α)` the cross-product matrix of α
/// and `M = ∫ ρ x xᵀ dV` the grain's second mass moment about its centre of mass (world
/// frame, see [`mass_moment`]). When the forces and the motion agree (angular momentum
/// balance) the result is symmetric; [`principal_compressions`] uses its symmetric part.
pub fn average_stress(
    volume: f64,
    forces: impl IntoIterator<Item = AppliedForce>,
    mass_moment: &Matrix3<f64>,
    alpha: &Vec3,
    omega: &Vec3,
) -> Matrix3<f64> {
    let mut s = Matrix3::zeros();
    for f in forces {
        s += f.force * f.lever.transpose();
    }
    average_stress_from_moment(volume, &s, mass_moment, alpha, omega)
}

/// [`average_stress`] from the summed moment `Σ f ⊗ x` of the forces.
pub fn average_stress_from_moment(
    volume: f64,
    moment: &Matrix3<f64>,
    mass_moment: &Matrix3<f64>,
    alpha: &Vec3,
    omega: &Vec3,
) -> Matrix3<f64> {
    let inertial = (alpha.cross_matrix() + omega * omega.transpose()
        - Matrix3::identity() * omega.norm_squared())
        * mass_moment;
    (moment - inertial) / volume
}

/// The second mass moment `M = ∫ ρ x xᵀ dV` about the centre of mass (world frame) of a body
/// with principal moments of inertia `inertia` in its body frame, turned by `rotation` (body
/// to world): in the body frame `M = tr(I)/2 · 1 − I`.
pub fn mass_moment(inertia: &Vec3, rotation: &Matrix3<f64>) -> Matrix3<f64> {
    let half_trace = 0.5 * (inertia.x + inertia.y + inertia.z);
    let body = Matrix3::from_diagonal(&(Vec3::repeat(half_trace) - inertia));
    rotation * body * rotation.transpose()
}

/// Principal stresses of a tension-positive stress in the Hoek–Brown convention,
/// compression positive, ordered σ1 ≥ σ2 ≥ σ3, with their unit directions.
pub fn principal_compressions(stress: &Matrix3<f64>) -> ([f64; 3], [Vec3; 3]) {
    let eig = SymmetricEigen::new(-(stress + stress.transpose()) * 0.5);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let values = order.map(|k| eig.eigenvalues[k]);
    let dirs = order.map(|k| eig.eigenvectors.column(k).into_owned());
    (values, dirs)
}

/// The principal values of [`principal_compressions`] without the directions, in closed form
/// (the trigonometric solution of the characteristic cubic): the check every grain takes
/// every step.
pub fn principal_compression_values(stress: &Matrix3<f64>) -> [f64; 3] {
    symmetric3_eigenvalues(&(-(stress + stress.transpose()) * 0.5))
}

/// Whether the tension-positive `stress` may fail Hoek–Brown (σc `sigma_c`, `mi`): false only
/// when it certainly does not, from bounds on its principal values that need no eigenvalues.
/// With q the mean and p = ‖dev‖_F / √6 of the compression-positive stress, the principal values
/// lie in [q − 2p, q + 2p] and σ1 − σ3 ≤ 2√3 p; Hoek–Brown holds when σ3 ≥ q − 2p stays above
/// the tensile cut-off and 2√3 p stays below σc sqrt(m_i (q − 2p) / σc + 1), both with margins
/// far above the rounding of the closed-form values, so skipping [`hoek_brown_fails`] when this
/// is false never changes a decision.
pub fn hoek_brown_may_fail(stress: &Matrix3<f64>, sigma_c: f64, mi: f64) -> bool {
    let a = -(stress + stress.transpose()) * 0.5;
    let q = a.trace() / 3.0;
    let p2 = (a.m11 - q).powi(2)
        + (a.m22 - q).powi(2)
        + (a.m33 - q).powi(2)
        + 2.0 * (a.m12 * a.m12 + a.m13 * a.m13 + a.m23 * a.m23);
    let p = (p2 / 6.0).sqrt() * (1.0 + 1e-9) + 1e-12 * q.abs();
    let s = mi * (q - 2.0 * p) / sigma_c + 1.0;
    let holds = s > 0.0 && 2.0 * 3f64.sqrt() * p * (1.0 + 1e-9) < sigma_c * s.sqrt();
    !holds
}

/// Hoek–Brown (Eq. 14), compression positive: a grain fails when
/// `σ1 ≥ σ3 + σc sqrt(m_i σ3 / σc + 1)`. Below the tensile cut-off `σ3 < −σc / m_i` the root
/// has no real value: the grain fails in tension.
pub fn hoek_brown_fails(sigma1: f64, sigma3: f64, sigma_c: f64, mi: f64) -> bool {
    let s = mi * sigma3 / sigma_c + 1.0;
    s < 0.0 || sigma1 >= sigma3 + sigma_c * s.sqrt()
}

/// The largest σ1 Hoek–Brown allows for a given σ3 (compression positive; −∞ below the
/// tensile cut-off).
pub fn hoek_brown_limit(sigma3: f64, sigma_c: f64, mi: f64) -> f64 {
    let s = mi * sigma3 / sigma_c + 1.0;
    if s < 0.0 {
        f64::NEG_INFINITY
    } else {
        sigma3 + sigma_c * s.sqrt()
    }
}

/// The maximum tensile stress (Pa) of a Hertz contact (Eq. 17, Timoshenko & Goodier): at the
/// edge of the contact circle, `σt = (1 − 2ν)/3 · q0`, with the peak pressure
/// `q0 = 3F / (2π a²)` of normal force `F` (N) over a contact of radius `a` (m).
///
/// `F` is the elastic (Hertz) force `4/3 E* a δ` whose pressure distribution the formula
/// describes, so that `q0 = 2 E* a / (π R)`. The contact's viscous damping force is not a
/// Hertz pressure over `a`: at the first instants of an impact (δ → 0 at a finite approach
/// speed) it would give `σt ∝ a^(−3/2)` → ∞, and every impact broke both grains at its first
/// step, the more of them the shorter the step (the main job: 12, 18 and 32 grains at its
/// second step at safety 0.4, 0.1 and 0.025).
pub fn contact_tensile_stress(normal_force: f64, contact_radius: f64, poisson: f64) -> f64 {
    let q0 = 3.0 * normal_force / (2.0 * std::f64::consts::PI * contact_radius * contact_radius);
    (1.0 - 2.0 * poisson) / 3.0 * q0
}

/// The Weibull strength factor of Eq. 18, `ln(1/P)^(1/w) (x/x_M)^(−2/w)`, for a uniform
/// variate `p` in (0, 1), Weibull modulus `w`, equivalent radius `x` and reference radius
/// `x_m`: a grain's strengths are the reference ones times this. It is 1 for a grain of the
/// reference radius with P = 1/e.
///
/// The paper prints the size exponent as −2w. Its source (Ben-Nun, Einav and Tordesillas
/// 2010, after Weibull 1951) derives the law from the survival probability of a grain of
/// flawed area A ∝ x², `P = exp(−(A/A_M) (σ/σ_M)^w)`: solving for σ gives
/// `σ = σ_M ln(1/P)^(1/w) (x/x_M)^(−2/w)`, so the exponent is −2/w (the strength falls more
/// slowly with size the larger the modulus, the less the scatter). The two agree at w = 1, the
/// paper's only value; they give opposite trends otherwise.
pub fn weibull_factor(p: f64, w: f64, x: f64, x_m: f64) -> f64 {
    weibull_factor_sized(p, w, 2.0 / w, x, x_m)
}

/// [`weibull_factor`] with its size exponent `beta` given: `ln(1/P)^(1/w) (x/x_M)^(−β)`.
/// Single-grain crushing tests measure the scatter (w) and the size effect (β) of a grain's
/// strength separately; Eq. 18 ties them (β = 2/w), which holds only when the flaws that
/// break a grain lie on its surface and follow Weibull's weakest link.
pub fn weibull_factor_sized(p: f64, w: f64, beta: f64, x: f64, x_m: f64) -> f64 {
    (1.0 / p).ln().powf(1.0 / w) * (x / x_m).powf(-beta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Uniform variates in [-0.5, 0.5) from a linear congruential generator seeded `seed`.
    fn centred_uniforms(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    /// The largest eigenvalue alone is the first of the three, bit for bit.
    #[test]
    fn the_largest_eigenvalue_alone_is_the_first_of_the_three() {
        let mut draw = centred_uniforms(11);
        for case in 0..10_000 {
            let mut m = Matrix3::from_fn(|_, _| draw());
            m = (m + m.transpose()) * 0.5;
            if case % 3 == 0 {
                m = Matrix3::identity() * draw();
            }
            let all = symmetric3_eigenvalues(&m);
            let top = symmetric3_largest_eigenvalue(&m);
            assert_eq!(top.to_bits(), all[0].to_bits(), "{m}");
        }
    }

    /// The bound never says "cannot fail" of a stress that fails: random stresses around the
    /// Hoek–Brown surface (hydrostatic to deviatoric, compressive to past the tensile cut-off,
    /// and right at the surface), against the closed-form principal values; and it does skip
    /// most stresses well inside the surface.
    #[test]
    fn hoek_brown_bound_never_hides_a_failure() {
        let (sc, mi) = (592e6, 20.56);
        let mut draw = centred_uniforms(7);
        let (mut failing, mut skipped, mut inside) = (0, 0, 0);
        for case in 0..200_000 {
            let scale = sc * [0.01, 0.1, 0.5, 1.0, 3.0][case % 5];
            let mut m = Matrix3::from_fn(|_, _| draw() * scale);
            m = (m + m.transpose()) * 0.5 - Matrix3::identity() * (draw() + 0.3) * scale;
            // Scale some onto the surface itself: σ1 − σ3 at the limit for their σ3.
            let [s1, _, s3] = principal_compression_values(&m);
            if case % 7 == 0 && s1 > s3 {
                let limit = hoek_brown_limit(s3, sc, mi);
                if limit.is_finite() {
                    let dev = m - Matrix3::identity() * (m.trace() / 3.0);
                    m = Matrix3::identity() * (m.trace() / 3.0) + dev * ((limit - s3) / (s1 - s3));
                }
            }
            let [s1, _, s3] = principal_compression_values(&m);
            let fails = hoek_brown_fails(s1, s3, sc, mi);
            let may = hoek_brown_may_fail(&m, sc, mi);
            assert!(
                may || !fails,
                "case {case}: a failing stress was skipped: {m}"
            );
            failing += usize::from(fails);
            if !fails && s1 - s3 < 0.3 * (hoek_brown_limit(s3, sc, mi) - s3) {
                inside += 1;
                skipped += usize::from(!may);
            }
        }
        assert!(failing > 10_000, "{failing}");
        assert!(
            skipped * 2 > inside,
            "{skipped} of {inside} well inside skipped"
        );
    }

    /// A sphere squeezed between two opposite forces F along z: σ_zz = −2rF/V = −3F/(2πr²)
    /// (the 3D counterpart of Eq. 15), nothing else.
    #[test]
    fn uniaxial_average_stress() {
        let (r, f): (f64, f64) = (0.3e-3, 20.0);
        let v = 4.0 / 3.0 * PI * r.powi(3);
        let forces = [
            AppliedForce {
                force: Vec3::new(0.0, 0.0, -f),
                lever: Vec3::new(0.0, 0.0, r),
            },
            AppliedForce {
                force: Vec3::new(0.0, 0.0, f),
                lever: Vec3::new(0.0, 0.0, -r),
            },
        ];
        let s = average_stress(v, forces, &Matrix3::zeros(), &Vec3::zeros(), &Vec3::zeros());
        let expected = -3.0 * f / (2.0 * PI * r * r);
        assert!((s[(2, 2)] / expected - 1.0).abs() < 1e-14);
        assert!(s.iter().enumerate().all(|(k, v)| k == 8 || v.abs() < 1e-6));
        let (p, d) = principal_compressions(&s);
        assert!((p[0] / -expected - 1.0).abs() < 1e-14 && p[1].abs() < 1e-6);
        assert!((d[0].z.abs() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn closed_form_principal_values_match_the_eigen_solver() {
        let mut rng = crate::sample::stream(3, 5);
        use rand::RngExt;
        for _ in 0..1000 {
            let mut m = Matrix3::<f64>::zeros();
            for a in 0..3 {
                for b in a..3 {
                    let v = 1e8 * (rng.random::<f64>() - 0.5);
                    m[(a, b)] = v;
                    m[(b, a)] = v;
                }
            }
            let (full, _) = principal_compressions(&m);
            let fast = principal_compression_values(&m);
            for k in 0..3 {
                assert!((full[k] - fast[k]).abs() < 1e-6, "{full:?} {fast:?}");
            }
        }
        let iso = Matrix3::identity() * -3e6;
        assert_eq!(principal_compression_values(&iso), [3e6; 3]);
    }

    /// A free body accelerating under one force has zero average stress only once the
    /// inertial term is counted: a force F at the centre of mass alone leaves Σ f⊗x = 0, but a
    /// force off the centre spins the body and the dynamic terms (Eq. 13) balance the moment.
    #[test]
    fn dynamic_terms_balance_a_free_spinning_body() {
        let (r, rho): (f64, f64) = (1e-3, 2650.0);
        let v = 4.0 / 3.0 * PI * r.powi(3);
        let m = rho * v;
        let i = 0.4 * m * r * r;
        let inertia = Vec3::repeat(i);
        let mm = mass_moment(&inertia, &Matrix3::identity());
        // Solid sphere: M = diag(m r²/5).
        assert!((mm[(0, 0)] / (m * r * r / 5.0) - 1.0).abs() < 1e-14);
        // Tangential force at the equator: it accelerates and spins the sphere.
        let f = AppliedForce {
            force: Vec3::new(0.0, 1.0, 0.0),
            lever: Vec3::new(r, 0.0, 0.0),
        };
        let alpha = f.lever.cross(&f.force) / i;
        // Without the dynamic terms Σ f⊗x = r F e_y e_xᵀ is not symmetric: the moment is not
        // balanced. With the angular acceleration α = r F / I the inertial term W(α) M takes
        // out the antisymmetric part exactly, leaving the shear r F / (2V) on both sides.
        let static_only = average_stress(v, [f], &mm, &Vec3::zeros(), &Vec3::zeros());
        let with_dynamics = average_stress(v, [f], &mm, &alpha, &Vec3::zeros());
        assert!((static_only[(1, 0)] - r / v).abs() < 1e-9 * r / v);
        assert_eq!(static_only[(0, 1)], 0.0);
        for (a, b) in [(0, 1), (1, 0)] {
            assert!((with_dynamics[(a, b)] / (0.5 * r / v) - 1.0).abs() < 1e-12);
        }
        // Spinning at ω about z adds the centripetal term: −(ωωᵀ − |ω|²) M / V, an isotropic
        // tension in the xy plane of ω² m r² / (5V).
        let w = Vec3::new(0.0, 0.0, 100.0);
        let spin = average_stress(v, [], &mm, &Vec3::zeros(), &w);
        let t = w.z * w.z * m * r * r / 5.0 / v;
        assert!((spin[(0, 0)] / t - 1.0).abs() < 1e-12 && spin[(2, 2)].abs() < 1e-6 * t);
    }

    /// Fig. 6: with m_i = 20.56 and σc = 592 MPa, uniaxial compression fails at σ1 = σc with
    /// σ3 = 0, while σ1 = σ3 (the blue dot) never fails; the tensile cut-off is −σc/m_i.
    #[test]
    fn hoek_brown_of_fig6() {
        let (sc, mi) = (592e6, 20.56);
        assert!(!hoek_brown_fails(0.999 * sc, 0.0, sc, mi));
        assert!(hoek_brown_fails(sc, 0.0, sc, mi));
        for s in [0.1, 1.0, 5.0] {
            assert!(!hoek_brown_fails(s * sc, s * sc, sc, mi));
        }
        // σ3/σc = 0.2: σ1 limit = σc (0.2 + sqrt(20.56 * 0.2 + 1)) = 2.4614 σc.
        let lim = hoek_brown_limit(0.2 * sc, sc, mi) / sc;
        assert!((lim - (0.2 + (20.56f64 * 0.2 + 1.0).sqrt())).abs() < 1e-12);
        assert!(hoek_brown_fails(0.0, -1.01 * sc / mi, sc, mi));
        assert!(!hoek_brown_fails(0.0, -0.99 * sc / mi, sc, mi));
    }

    #[test]
    fn contact_tensile_stress_of_eq17() {
        // F = 10 N over a = 30 µm, ν = 0.25: q0 = 30 / (2π 9e-10) = 5.305e9 Pa, σt = q0 / 6.
        let s = contact_tensile_stress(10.0, 30e-6, 0.25);
        let q0 = 30.0 / (2.0 * PI * 9e-10);
        assert!((s / (q0 / 6.0) - 1.0).abs() < 1e-14);
        assert_eq!(contact_tensile_stress(10.0, 30e-6, 0.5), 0.0);
    }

    #[test]
    fn weibull_factor_of_eq18() {
        let e = std::f64::consts::E;
        assert!((weibull_factor(1.0 / e, 1.0, 2e-3, 2e-3) - 1.0).abs() < 1e-15);
        // Half the size, w = 1: four times stronger (Fig. 9's size effect).
        assert!((weibull_factor(1.0 / e, 1.0, 1e-3, 2e-3) - 4.0).abs() < 1e-14);
    }

    /// w = 3 against the closed form of the area-weighted weakest link: a grain survives σ
    /// with probability P = exp(−(x/x_M)² (σ/σ_M)^w), so the σ at which it fails for its drawn
    /// P is σ_M (ln(1/P) (x_M/x)²)^(1/w). Checked at several sizes and P, to 1e-12 relative;
    /// and the survival probability of that σ, recomputed, is P again.
    #[test]
    fn weibull_factor_at_w3_is_the_weakest_link_closed_form() {
        let w = 3.0;
        for &(p, x) in &[(0.5, 1.1), (0.05, 0.3), (0.9, 2.0), (1.0 / 3.0, 1.0)] {
            let closed = ((1.0f64 / p).ln() * (1.0 / x) * (1.0 / x)).powf(1.0 / w);
            let f = weibull_factor(p, w, x, 1.0);
            assert!(
                (f / closed - 1.0).abs() < 1e-12,
                "P {p} x {x}: {f} vs {closed}"
            );
            let survival = (-(x * x) * f.powf(w)).exp();
            assert!((survival / p - 1.0).abs() < 1e-12);
        }
        // Twice the size at w = 3: 2^(-2/3) = 0.63 of the strength (the printed -2w would give
        // 2^-6 = 0.016).
        let ratio = weibull_factor(0.5, w, 2.0, 1.0) / weibull_factor(0.5, w, 1.0, 1.0);
        assert!((ratio - 2f64.powf(-2.0 / 3.0)).abs() < 1e-14);
    }
}
