//! `loading.kind = "free_vibration"`: a bar released from a static field (Section 8.2.2).

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::{Loading, RowInputs, Setting, mean_of};
use crate::error::Result;
use crate::models::dlsm::scene::{SampleShape, VibrationMode, VibrationSpec};
use crate::probe::Series;
use crate::probe::spectrum::dominant_frequency;
use crate::sample::voronoi::Boundary;
use crate::state::{Bodies, Forces, Vec3};

/// A cylinder released from a static field, x− face clamped (Section 8.2.2). In tension the
/// clamp holds the axial motion of its elements and lets the section contract, as the rod
/// theory of Eq. 44 assumes (holding the lateral motion too stiffens an end zone of about a
/// sixth of the radius: +1.7% on the frequency of the 1 m bar); in torsion it holds them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FreeVibration {
    pub mode: VibrationMode,
    /// A (tension) or α (torsion, rad/m).
    pub amplitude: f64,
    pub end_time: f64,
    pub length: f64,
    pub clamped: Vec<u32>,
    pub free: Vec<u32>,
    /// Eq. 44 / 45 (Hz).
    pub frequency_theory: f64,
}

impl FreeVibration {
    /// The free vibration of a bar: its clamped x− and watched x+ elements, none empty, and
    /// the frequency Eq. 44 (tension) or Eq. 45 (torsion) gives.
    pub fn build(s: &Setting, l: &VibrationSpec) -> Result<Self> {
        let (m, sample) = (&s.cfg.material, s.sample);
        // The bar's length: the sample was made longer by the clamp's grip.
        let SampleShape::Cylinder { length, .. } = s.cfg.sample.shape else {
            return Err(s.scene.key_error(
                "loading.kind",
                "= \"free_vibration\" needs sample.kind = \"voronoi_cylinder\"",
            ));
        };
        let mode = l.mode;
        let clamped = sample.elements_on(Boundary::XMin);
        let free = sample.elements_on(Boundary::XMax);
        s.nonempty(&clamped, "x-")?;
        s.nonempty(&free, "x+")?;
        let shear = m.young / (2.0 * (1.0 + m.poisson));
        let modulus = match mode {
            VibrationMode::Tension => m.young,
            VibrationMode::Torsion => shear,
        };
        Ok(FreeVibration {
            mode,
            amplitude: l.amplitude,
            end_time: l.end_time,
            length,
            clamped,
            free,
            // Eq. 44 / 45.
            frequency_theory: (modulus / m.density).sqrt() / (4.0 * length),
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(l: &VibrationSpec) -> String {
        let mode = match l.mode {
            VibrationMode::Tension => "tension",
            VibrationMode::Torsion => "torsion",
        };
        format!(
            "free vibration from a static {mode} field (loading.mode = \"{mode}\"), x- clamped, for {:e} s",
            l.end_time
        )
    }

    /// The static field the vibration starts from (Section 8.2.2): the displacement (m) of
    /// the point at `x` (m).
    pub fn initial_displacement(&self, x: &Vec3) -> Vec3 {
        match self.mode {
            VibrationMode::Tension => Vec3::new(self.amplitude * x.x, 0.0, 0.0),
            VibrationMode::Torsion => {
                let (s, c) = (self.amplitude * x.x).sin_cos();
                Vec3::new(0.0, x.y * c - x.z * s - x.y, x.y * s + x.z * c - x.z)
            }
        }
    }
}

impl Loading for FreeVibration {
    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn prescribe(&self, bodies: &mut Bodies, _t: f64) {
        for &i in &self.clamped {
            match self.mode {
                VibrationMode::Tension => bodies.vel[i as usize].x = 0.0,
                VibrationMode::Torsion => bodies.vel[i as usize] = Vec3::zeros(),
            }
            bodies.omega[i as usize] = Vec3::zeros();
        }
    }

    fn constrain(&mut self, forces: &mut Forces) {
        for &i in &self.clamped {
            match self.mode {
                VibrationMode::Tension => forces.force[i as usize].x = 0.0,
                VibrationMode::Torsion => forces.force[i as usize] = Vec3::zeros(),
            }
            forces.torque[i as usize] = Vec3::zeros();
        }
    }

    fn columns(&self) -> Vec<&'static str> {
        match self.mode {
            VibrationMode::Tension => vec![
                "time",
                "free_face_displacement",
                "kinetic_energy",
                "strain_energy",
                "total_energy",
            ],
            VibrationMode::Torsion => vec![
                "time",
                "free_face_rotation",
                "kinetic_energy",
                "strain_energy",
                "total_energy",
            ],
        }
    }

    fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        let b = r.bodies;
        let ke = b.kinetic_energy();
        let signal = match self.mode {
            VibrationMode::Tension => mean_of(&self.free, |i| b.pos[i].x - r.reference[i].x),
            VibrationMode::Torsion => mean_of(&self.free, |i| {
                let (p, q) = (b.pos[i], r.reference[i]);
                (q.y * p.z - q.z * p.y).atan2(q.y * p.y + q.z * p.z)
            }),
        };
        vec![r.time, signal, ke, r.strain_energy, ke + r.strain_energy]
    }

    fn summarize(&self, series: &Series, dt_row: f64, out: &mut Map<String, Value>) {
        let name = match self.mode {
            VibrationMode::Tension => "free_face_displacement",
            VibrationMode::Torsion => "free_face_rotation",
        };
        if let Some(signal) = series.column(name) {
            if let Some(f) = dominant_frequency(&signal, dt_row) {
                out.insert("frequency_measured".into(), f.into());
                out.insert(
                    "frequency_error".into(),
                    (f / self.frequency_theory - 1.0).into(),
                );
            }
        }
        out.insert("frequency_theory".into(), self.frequency_theory.into());
    }
}
