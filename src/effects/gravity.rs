//! Gravity: the body force m·g.

use super::{Effect, StepContext};
use crate::state::{Bodies, Forces, Vec3, Walls};

/// The weight of every body, with `g` the same everywhere.
#[derive(Debug, Clone, Copy)]
pub struct Gravity {
    /// Gravitational acceleration (m/s²).
    pub g: Vec3,
}

impl Gravity {
    pub fn new(g: Vec3) -> Self {
        Gravity { g }
    }

    /// Adds each body's weight m·g to its force (the dlsm model's elements too).
    pub fn add_weight(&self, bodies: &Bodies, forces: &mut Forces) {
        for (f, &m) in forces.force.iter_mut().zip(&bodies.mass) {
            *f += self.g * m;
        }
    }
}

impl Effect for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn describe(&self) -> String {
        format!(
            "body force m·g, g = ({}, {}, {}) m/s²",
            self.g.x, self.g.y, self.g.z
        )
    }

    fn accumulate(&mut self, _: &StepContext, bodies: &Bodies, _: &mut Walls, forces: &mut Forces) {
        self.add_weight(bodies, forces);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    #[test]
    fn adds_weight() {
        let mut b = Bodies::default();
        b.push_sphere(Vec3::zeros(), 0.01, 1000.0, UnitQuaternion::identity());
        let mut f = Forces::new(1);
        let mut g = Gravity::new(Vec3::new(0.0, 0.0, -9.81));
        let ctx = StepContext {
            dt: 1e-6,
            update_history: true,
        };
        g.accumulate(&ctx, &b, &mut Walls::default(), &mut f);
        assert!((f.force[0].z + b.mass[0] * 9.81).abs() < 1e-15);
    }
}
