//! Beams between the centres of mass of neighbouring polygons (Kun et al., Section 2.2–2.3).
//!
//! A beam of length l, cross-section S (the shared side's length times the thickness) and
//! second moment I = t S_side³ / 12 has (Eq. 7–9, with b = 2a as in the paper)
//!
//! ```text
//! a = l / (E S),  b = 2a,  c = l³ / (E I)
//! α = 1/a,  β = 1 / (b + c/12),  δ = β (b/c + 1/3)
//! ```
//!
//! Forces and torques are taken in the beam's own frame, which turns with the line between the
//! centres (co-rotational): x along the beam, the ends' transverse displacements zero, and the
//! ends' bending angles Θ measured from the beam's line. Then (Eq. 10–12)
//!
//! ```text
//! F_x^i = α Δl                               longitudinal, Δl = l − l0
//! M^i   = −(β l0²/2) Θ^j + δ l0² (Θ^j − Θ^i)  flexural torque
//! M^j   = −(β l0²/2) Θ^i + δ l0² (Θ^i − Θ^j)
//! F_y^j = −F_y^i = −(M^i + M^j) / l           shear, ≈ (β l0/2)(Θ^i + Θ^j)
//! ```
//!
//! Eq. 12 as printed has `+ l Θ^j` inside the first bracket; that makes the stiffness matrix
//! unsymmetric and is a sign slip: the Timoshenko beam element gives `− l Θ^j`, and only then
//! does a cantilever take its closed-form deflection (see the tests). The shear force is
//! taken from the torques so that every beam conserves angular momentum exactly; it equals
//! Eq. 11's `−(β l/2)(Θ^i + Θ^j)` to first order. The forces derive from the energy
//! `α Δl²/2 + (δ l0² (Θ^i² + Θ^j²) + (β − 2δ) l0² Θ^i Θ^j) / 2` ([`beam_energy`]).
//!
//! A stretched beam breaks when (Eq. 13) `(ε/t_ε)² + max(|Θ^i|, |Θ^j|)/t_Θ ≥ 1`, ε = Δl/l0;
//! compressed beams never break, and broken beams never return.

use serde::{Deserialize, Serialize};

use crate::shape::polygon::{Vec2, cross, perp};

/// α, β and δ of one beam (Eq. 7–12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamConstants {
    pub alpha: f64,
    pub beta: f64,
    pub delta: f64,
}

impl BeamConstants {
    /// The constants of a beam of length `l` (m), Young's modulus `young` (Pa), cross-section
    /// `section` (m²) and second moment of area `second_moment` (m⁴), with b = 2a.
    pub fn new(young: f64, l: f64, section: f64, second_moment: f64) -> Self {
        let a = l / (young * section);
        let b = 2.0 * a;
        let c = l * l * l / (young * second_moment);
        let beta = 1.0 / (b + c / 12.0);
        BeamConstants {
            alpha: 1.0 / a,
            beta,
            delta: beta * (b / c + 1.0 / 3.0),
        }
    }
}

/// What a beam does to its two ends.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BeamResponse {
    /// Force on end j (N); end i gets the opposite.
    pub force_j: Vec2,
    /// Torques on the ends (N·m).
    pub torque_i: f64,
    pub torque_j: f64,
    /// Longitudinal strain ε = Δl / l0.
    pub strain: f64,
    /// Bending angles Θ of the ends relative to the beam's line (rad).
    pub theta_i: f64,
    pub theta_j: f64,
}

/// `x` brought into (−π, π].
#[inline(always)]
pub fn wrap_angle(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if x > PI || x <= -PI {
        x - TAU * ((x + PI) / TAU).floor()
    } else {
        x
    }
}

/// Beams as structure of arrays, one entry per beam, in the order they were made.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Beams {
    pub i: Vec<u32>,
    pub j: Vec<u32>,
    /// Length l0 (m) and unit direction from i to j at rest.
    pub rest_length: Vec<f64>,
    pub rest_direction: Vec<Vec2>,
    /// Length of the shared side (m).
    pub side: Vec<f64>,
    pub alpha: Vec<f64>,
    /// δ l0² and (β/2 − δ) l0²: the torques' stiffnesses (N·m/rad).
    pub bend_own: Vec<f64>,
    pub bend_cross: Vec<f64>,
    pub intact: Vec<bool>,
    /// When each beam broke (s); infinite while intact.
    pub broken_time: Vec<f64>,
}

impl Beams {
    pub fn len(&self) -> usize {
        self.i.len()
    }

    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// Adds a beam between polygons `[i, j]` with centres `[ci, cj]` across a shared side of
    /// length `side`, in a solid of `thickness`, of Young's modulus `young`.
    pub fn push(
        &mut self,
        [i, j]: [usize; 2],
        [ci, cj]: [Vec2; 2],
        side: f64,
        thickness: f64,
        young: f64,
    ) {
        let d = cj - ci;
        let l = d.norm();
        let k = BeamConstants::new(young, l, side * thickness, thickness * side.powi(3) / 12.0);
        self.i.push(i as u32);
        self.j.push(j as u32);
        self.rest_length.push(l);
        self.rest_direction.push(d / l);
        self.side.push(side);
        self.alpha.push(k.alpha);
        self.bend_own.push(k.delta * l * l);
        self.bend_cross.push((0.5 * k.beta - k.delta) * l * l);
        self.intact.push(true);
        self.broken_time.push(f64::INFINITY);
    }

    pub fn broken(&self) -> usize {
        self.intact.iter().filter(|&&b| !b).count()
    }

    /// The response of beam `b` to end positions and rotation angles (Eq. 10–12, co-rotational).
    #[inline(always)]
    pub fn response(&self, b: usize, xi: Vec2, ti: f64, xj: Vec2, tj: f64) -> BeamResponse {
        let d = xj - xi;
        let l = d.norm();
        let e = d / l;
        let e0 = self.rest_direction[b];
        // The beam's line has turned by this much since rest.
        let turn = cross(e0, e).atan2(e0.dot(&e));
        let theta_i = wrap_angle(ti - turn);
        let theta_j = wrap_angle(tj - turn);
        let l0 = self.rest_length[b];
        let (own, crossed) = (self.bend_own[b], self.bend_cross[b]);
        let torque_i = -own * theta_i - crossed * theta_j;
        let torque_j = -own * theta_j - crossed * theta_i;
        let stretch = l - l0;
        let force_j = e * (-self.alpha[b] * stretch) - perp(e) * ((torque_i + torque_j) / l);
        BeamResponse {
            force_j,
            torque_i,
            torque_j,
            strain: stretch / l0,
            theta_i,
            theta_j,
        }
    }

    /// Elastic energy (J) of beam `b` in the state `r` (see the module text).
    pub fn energy(&self, b: usize, r: &BeamResponse) -> f64 {
        beam_energy(
            self.alpha[b],
            self.bend_own[b],
            self.bend_cross[b],
            r.strain * self.rest_length[b],
            r.theta_i,
            r.theta_j,
        )
    }
}

/// `α Δl²/2 + (k_own (Θi² + Θj²) + 2 k_cross Θi Θj) / 2`.
pub fn beam_energy(alpha: f64, own: f64, crossed: f64, stretch: f64, ti: f64, tj: f64) -> f64 {
    0.5 * alpha * stretch * stretch + 0.5 * (own * (ti * ti + tj * tj) + 2.0 * crossed * ti * tj)
}

/// How the two terms of the breaking rule combine. `Eq13` is the paper's rule as printed;
/// the others are the alternative readings the beam2d ablation measures
/// (docs/validation.md, "Ablation").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BreakingForm {
    /// `(ε/t_ε)² + max(|Θ^i|, |Θ^j|)/t_Θ ≥ 1`, stretched beams only (Eq. 13 as printed).
    #[default]
    Eq13,
    /// `(ε/t_ε)² + (max(|Θ^i|, |Θ^j|)/t_Θ)² ≥ 1`: both terms squared (an elliptic criterion).
    Squared,
    /// `(ε/t_ε)² + (|Θ^i| + |Θ^j|)/(2 t_Θ) ≥ 1`: the mean of the two ends' angles.
    MeanAngle,
    /// Eq. 13 with |ε|: compressed beams break as well.
    EitherSign,
}

impl BreakingForm {
    pub fn as_str(self) -> &'static str {
        match self {
            BreakingForm::Eq13 => "eq13",
            BreakingForm::Squared => "squared",
            BreakingForm::MeanAngle => "mean_angle",
            BreakingForm::EitherSign => "either_sign",
        }
    }
}

/// The breaking rule (Eq. 13): only stretched beams break (unless `form` says otherwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreakingRule {
    /// Stretching threshold t_ε.
    pub strain: f64,
    /// Bending threshold t_Θ (rad).
    pub bending: f64,
    /// How the terms combine.
    pub form: BreakingForm,
}

impl BreakingRule {
    #[inline(always)]
    pub fn breaks(&self, r: &BeamResponse) -> bool {
        if r.strain <= 0.0 && self.form != BreakingForm::EitherSign {
            return false;
        }
        let s = r.strain / self.strain;
        let (ti, tj) = (r.theta_i.abs(), r.theta_j.abs());
        let bend = match self.form {
            BreakingForm::Eq13 | BreakingForm::EitherSign => ti.max(tj) / self.bending,
            BreakingForm::Squared => (ti.max(tj) / self.bending).powi(2),
            BreakingForm::MeanAngle => 0.5 * (ti + tj) / self.bending,
        };
        s * s + bend >= 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A steel-like beam: E = 5e8 Pa, l = 1 cm, side 0.6 cm, thickness 1 cm.
    fn one_beam() -> (Beams, f64, f64, f64) {
        let (e, l, side, t) = (5e8, 0.01, 0.006, 0.01);
        let mut b = Beams::default();
        b.push([0, 1], [Vec2::zeros(), Vec2::new(l, 0.0)], side, t, e);
        (b, e, side * t, t * side.powi(3) / 12.0)
    }

    #[test]
    fn constants_follow_eq_7_to_12() {
        let (e, l, s, i) = (5e8, 0.01, 6e-5, 1.8e-10);
        let k = BeamConstants::new(e, l, s, i);
        let a = l / (e * s);
        let c = l.powi(3) / (e * i);
        assert!((k.alpha - 1.0 / a).abs() < 1e-6 * k.alpha);
        let beta = 1.0 / (2.0 * a + c / 12.0);
        assert!((k.beta - beta).abs() < 1e-9 * beta);
        assert!((k.delta - beta * (2.0 * a / c + 1.0 / 3.0)).abs() < 1e-9 * k.delta);
    }

    #[test]
    fn cantilever_takes_the_timoshenko_deflection() {
        // End i clamped at the origin; a transverse load P on end j. Timoshenko:
        // v = P l³/(3EI) + P l/(G S) with G = E/2 (b = 2a), tip rotation P l²/(2EI).
        // In that state the beam must push back on j with exactly −P and no torque.
        let (beams, e, s, i) = one_beam();
        let l: f64 = 0.01;
        // Small enough that the second-order stretch of the chord (∝ P²) is negligible.
        let p = 1e-5;
        let g = e / 2.0;
        let v = p * l.powi(3) / (3.0 * e * i) + p * l / (g * s);
        let rot = p * l * l / (2.0 * e * i);
        let r = beams.response(0, Vec2::zeros(), 0.0, Vec2::new(l, v), rot);
        assert!(
            (r.force_j.y + p).abs() < 1e-6 * p,
            "shear {} vs {}",
            r.force_j.y,
            -p
        );
        assert!(r.force_j.x.abs() < 1e-6 * p, "axial {}", r.force_j.x);
        assert!(r.torque_j.abs() < 1e-6 * p * l, "tip torque {}", r.torque_j);
        // The clamp carries P and the moment P l.
        assert!((r.force_j.y + p).abs() < 1e-6 * p);
        assert!((r.torque_i - p * l).abs() < 1e-6 * p * l, "{}", r.torque_i);
        // Eq. 12 as printed (+ l Θ^j) would give the clamp a moment far from P l.
        let half_beta_l2 = beams.bend_cross[0] + beams.bend_own[0];
        let printed = half_beta_l2 * r.theta_j + beams.bend_own[0] * (r.theta_j - r.theta_i);
        assert!((printed - p * l).abs() > 0.1 * p * l, "{printed}");
    }

    #[test]
    fn pure_stretch_and_pure_bending() {
        let (beams, e, s, i) = one_beam();
        let l = 0.01;
        let r = beams.response(0, Vec2::zeros(), 0.0, Vec2::new(l * 1.001, 0.0), 0.0);
        assert!((r.force_j.x + e * s / l * l * 1e-3).abs() < 1e-9 * e * s);
        assert!((r.strain - 1e-3).abs() < 1e-12);
        // Equal and opposite end rotations bend the beam into an arc: M = E I κ, κ = 2Θ/l
        // for the Euler–Bernoulli part (shear does not enter a uniform moment).
        let th = 1e-4;
        let r = beams.response(0, Vec2::zeros(), -th, Vec2::new(l, 0.0), th);
        let m = e * i * 2.0 * th / l;
        assert!(
            (r.torque_j + m).abs() < 1e-9 * m,
            "{} vs {}",
            r.torque_j,
            -m
        );
        assert!((r.torque_i - m).abs() < 1e-9 * m);
        assert!(r.force_j.norm() < 1e-9 * m / l);
    }

    #[test]
    fn rigid_motion_costs_nothing_and_angles_wrap() {
        let (beams, ..) = one_beam();
        let l = 0.01;
        // Turned by 3 rad and moved: both ends turned along with the line.
        let a = 3.0_f64;
        let x0 = Vec2::new(5.0, -2.0);
        let xj = x0 + Vec2::new(a.cos(), a.sin()) * l;
        let r = beams.response(0, x0, a + 8.0 * std::f64::consts::PI, xj, a);
        assert!(r.force_j.norm() < 1e-6, "{:?}", r.force_j);
        assert!(r.torque_i.abs() < 1e-9 && r.torque_j.abs() < 1e-9);
        assert!(
            (wrap_angle(3.5 * std::f64::consts::PI) + 0.5 * std::f64::consts::PI).abs() < 1e-12
        );
    }

    #[test]
    fn energy_is_the_potential_of_the_forces() {
        // Central differences of the energy against the forces and torques.
        let (beams, ..) = one_beam();
        let (xi, ti) = (Vec2::new(0.0001, -0.0002), 0.003);
        let (xj, tj) = (Vec2::new(0.0102, 0.0004), -0.002);
        let u = |xj: Vec2, tj: f64, ti: f64| {
            let r = beams.response(0, xi, ti, xj, tj);
            beams.energy(0, &r)
        };
        let r = beams.response(0, xi, ti, xj, tj);
        let h = 1e-9;
        let fx =
            -(u(xj + Vec2::new(h, 0.0), tj, ti) - u(xj - Vec2::new(h, 0.0), tj, ti)) / (2.0 * h);
        let fy =
            -(u(xj + Vec2::new(0.0, h), tj, ti) - u(xj - Vec2::new(0.0, h), tj, ti)) / (2.0 * h);
        let mj = -(u(xj, tj + h, ti) - u(xj, tj - h, ti)) / (2.0 * h);
        let mi = -(u(xj, tj, ti + h) - u(xj, tj, ti - h)) / (2.0 * h);
        let scale = r.force_j.norm();
        assert!(
            (fx - r.force_j.x).abs() < 1e-5 * scale,
            "{fx} {}",
            r.force_j.x
        );
        assert!(
            (fy - r.force_j.y).abs() < 1e-5 * scale,
            "{fy} {}",
            r.force_j.y
        );
        assert!((mj - r.torque_j).abs() < 1e-5 * r.torque_j.abs());
        assert!((mi - r.torque_i).abs() < 1e-5 * r.torque_i.abs());
    }

    #[test]
    fn only_stretched_beams_break() {
        let rule = BreakingRule {
            strain: 0.03,
            bending: 4f64.to_radians(),
            form: BreakingForm::Eq13,
        };
        let r = |strain: f64, ti: f64| BeamResponse {
            strain,
            theta_i: ti,
            ..Default::default()
        };
        assert!(rule.breaks(&r(0.031, 0.0)));
        assert!(!rule.breaks(&r(0.029, 0.0)));
        // Half the bending threshold and sqrt(1/2) of the stretching one: exactly on the edge.
        assert!(rule.breaks(&r(0.03 * 0.5f64.sqrt() * 1.0001, 2f64.to_radians())));
        assert!(!rule.breaks(&r(0.03 * 0.5f64.sqrt() * 0.999, 2f64.to_radians())));
        // Compressed and bent far past the threshold: holds.
        assert!(!rule.breaks(&r(-0.01, 0.5)));
    }

    #[test]
    fn the_alternative_forms_differ_where_they_should() {
        let rule = |form| BreakingRule {
            strain: 0.03,
            bending: 4f64.to_radians(),
            form,
        };
        let r = |strain: f64, ti: f64, tj: f64| BeamResponse {
            strain,
            theta_i: ti,
            theta_j: tj,
            ..Default::default()
        };
        // Half the strain threshold (1/4) and 0.8 of the bending one at one end only.
        let bent = r(0.015, 3.2f64.to_radians(), 0.0);
        assert!(rule(BreakingForm::Eq13).breaks(&bent)); // 0.25 + 0.8
        assert!(!rule(BreakingForm::Squared).breaks(&bent)); // 0.25 + 0.64
        assert!(!rule(BreakingForm::MeanAngle).breaks(&bent)); // 0.25 + 0.4
        // Which end is bent does not matter: the rule takes the larger angle.
        let other = r(0.015, 0.0, -3.2f64.to_radians());
        assert!(rule(BreakingForm::Eq13).breaks(&other));
        // Compressed past the threshold: only EitherSign breaks it.
        let squeezed = r(-0.031, 0.0, 0.0);
        assert!(!rule(BreakingForm::Eq13).breaks(&squeezed));
        assert!(rule(BreakingForm::EitherSign).breaks(&squeezed));
    }
}
