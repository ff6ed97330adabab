//! Gear's fifth-order predictor–corrector for second-order equations (Gear 1971; Allen and
//! Tildesley, Computer Simulation of Liquids, App. E), the integrator of the `beam2d` paper.
//!
//! Each degree of freedom carries its scaled derivatives `r_k = dt^k/k! · d^k x/dt^k`,
//! k = 0..5. A step predicts them with the Taylor (Pascal triangle) matrix, evaluates the
//! acceleration a at the predicted state, and corrects every derivative by
//! `c_k · (a dt²/2 − r_2)` with
//!
//! ```text
//! c = (3/16, 251/360, 1, 11/18, 1/6, 1/60)
//! ```
//!
//! When forces depend on velocities (damping, friction) c_0 is 3/20 instead of 3/16.
//! The state here is flat: positions `x` and velocities `v` (unscaled) live with the caller;
//! this struct keeps r_2..r_5. A degree of freedom with zero inverse mass gets no acceleration
//! and keeps r_2..r_5 at zero, so prescribed motion can be written straight into x and v.

use serde::{Deserialize, Serialize};

/// Corrector coefficients c_1..c_5 (c_2 = 1).
const C1: f64 = 251.0 / 360.0;
const C3: f64 = 11.0 / 18.0;
const C4: f64 = 1.0 / 6.0;
const C5: f64 = 1.0 / 60.0;

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Gear5 {
    /// c_0: 3/16, or 3/20 for velocity-dependent forces.
    pub c0: f64,
    /// Scaled second to fifth derivatives, one entry per degree of freedom.
    pub r2: Vec<f64>,
    pub r3: Vec<f64>,
    pub r4: Vec<f64>,
    pub r5: Vec<f64>,
}

impl Gear5 {
    /// An integrator for `n` degrees of freedom at rest (higher derivatives zero).
    pub fn new(n: usize, velocity_dependent_forces: bool) -> Self {
        Gear5 {
            c0: if velocity_dependent_forces {
                3.0 / 20.0
            } else {
                3.0 / 16.0
            },
            r2: vec![0.0; n],
            r3: vec![0.0; n],
            r4: vec![0.0; n],
            r5: vec![0.0; n],
        }
    }

    /// Starts from the accelerations `f · inv_m` of the current state (higher derivatives zero).
    pub fn start(&mut self, f: &[f64], inv_m: &[f64], dt: f64) {
        let h = 0.5 * dt * dt;
        for k in 0..self.r2.len() {
            self.r2[k] = f[k] * inv_m[k] * h;
            self.r3[k] = 0.0;
            self.r4[k] = 0.0;
            self.r5[k] = 0.0;
        }
    }

    /// Predicts x, v and the higher derivatives at t + dt.
    pub fn predict(&mut self, x: &mut [f64], v: &mut [f64], dt: f64) {
        let inv_dt = 1.0 / dt;
        for k in 0..x.len() {
            let (r2, r3, r4, r5) = (self.r2[k], self.r3[k], self.r4[k], self.r5[k]);
            let r1 = v[k] * dt;
            x[k] += r1 + r2 + r3 + r4 + r5;
            v[k] = (r1 + 2.0 * r2 + 3.0 * r3 + 4.0 * r4 + 5.0 * r5) * inv_dt;
            self.r2[k] = r2 + 3.0 * r3 + 6.0 * r4 + 10.0 * r5;
            self.r3[k] = r3 + 4.0 * r4 + 10.0 * r5;
            self.r4[k] = r4 + 5.0 * r5;
        }
    }

    /// Corrects the predicted state with the forces `f` evaluated there.
    pub fn correct(&mut self, x: &mut [f64], v: &mut [f64], f: &[f64], inv_m: &[f64], dt: f64) {
        let h = 0.5 * dt * dt;
        let c1 = C1 / dt;
        for k in 0..x.len() {
            let delta = f[k] * inv_m[k] * h - self.r2[k];
            x[k] += self.c0 * delta;
            v[k] += c1 * delta;
            self.r2[k] += delta;
            self.r3[k] += C3 * delta;
            self.r4[k] += C4 * delta;
            self.r5[k] += C5 * delta;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x'' = −ω² x from x = 1, v = 0 for one period, on `steps` steps.
    fn oscillator_error(steps: usize) -> f64 {
        let w = 2.0 * std::f64::consts::PI;
        let dt = 1.0 / steps as f64;
        let (mut x, mut v) = ([1.0], [0.0]);
        let inv_m = [1.0];
        let mut g = Gear5::new(1, false);
        g.start(&[-w * w * x[0]], &inv_m, dt);
        for _ in 0..steps {
            g.predict(&mut x, &mut v, dt);
            let f = [-w * w * x[0]];
            g.correct(&mut x, &mut v, &f, &inv_m, dt);
        }
        (x[0] - 1.0).abs().max(v[0].abs() / w)
    }

    #[test]
    fn harmonic_oscillator_converges() {
        let coarse = oscillator_error(100);
        let fine = oscillator_error(200);
        assert!(fine < 1e-4, "{fine}");
        // Started with zero higher derivatives the scheme settles to at least second order
        // over one period (its local order shows only once r3..r5 are built up).
        assert!(coarse / fine > 3.5, "{coarse} {fine}");
    }

    #[test]
    fn constant_force_is_exact_and_zero_mass_dofs_stay_put() {
        // x'' = −9.81 from rest: every scheme of order >= 2 integrates it exactly.
        let dt = 1e-3;
        let (mut x, mut v) = ([0.0, 2.0], [0.0, 0.5]);
        let inv_m = [1.0, 0.0];
        let f = [-9.81, 123.0];
        let mut g = Gear5::new(2, true);
        g.start(&f, &inv_m, dt);
        for _ in 0..1000 {
            g.predict(&mut x, &mut v, dt);
            g.correct(&mut x, &mut v, &f, &inv_m, dt);
        }
        assert!((x[0] + 0.5 * 9.81).abs() < 1e-9, "{}", x[0]);
        assert!((v[0] + 9.81).abs() < 1e-9);
        // No acceleration for the prescribed dof: it coasts at its own speed.
        assert!((x[1] - 2.5).abs() < 1e-12 && v[1] == 0.5);
    }
}
