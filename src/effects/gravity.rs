//! Gravity: the body force m·g.

use super::{Effect, StepContext};
use crate::state::{Bodies, Forces, Vec3, Walls};

pub struct Gravity {
    /// Gravitational acceleration (m/s²).
    pub g: Vec3,
}

impl Gravity {
    pub fn new(g: Vec3) -> Self {
        Gravity { g }
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
        for (f, &m) in forces.force.iter_mut().zip(&bodies.mass) {
            *f += self.g * m;
        }
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
