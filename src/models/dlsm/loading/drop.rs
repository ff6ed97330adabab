//! `loading.kind = "drop"`: a body thrown onto an inclined ground plane (Section 8.1).

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::{Loading, RowInputs, Setting, extent_along};
use crate::error::Result;
use crate::models::dlsm::scene::DropSpec;
use crate::probe::Series;
use crate::scene::EffectKind;
use crate::state::Vec3;

/// A body thrown onto an inclined ground plane (Section 8.1).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Drop {
    pub end_time: f64,
    /// The ground: a point on it and its upward unit normal.
    pub ground_point: Vec3,
    pub ground_normal: Vec3,
    /// Down the slope, and the axis about which rolling down turns.
    pub downslope: Vec3,
    pub roll_axis: Vec3,
    pub gravity: Vec3,
    /// Turns about `roll_axis` so far, and the body's angular velocity at the last row.
    pub turns: f64,
    pub last_spin: f64,
    pub last_time: f64,
    pub centre0: Vec3,
    /// The body's extent across the ground at the start (m): a ball's diameter.
    #[serde(default)]
    pub size: f64,
}

impl Drop {
    /// The ground under the sample, inclined `loading.ground_angle_degrees` about y and
    /// `loading.drop_height` (m) below its lowest vertex, and the gravity the scene's
    /// `gravity` effect applies (zero without it).
    pub fn build(s: &Setting, l: &DropSpec) -> Result<Self> {
        let (sample, scene) = (s.sample, s.scene);
        let angle = l.ground_angle_degrees.to_radians();
        let normal = Vec3::new(angle.sin(), 0.0, angle.cos());
        let downslope = Vec3::new(angle.cos(), 0.0, -angle.sin());
        let (lowest, highest) = extent_along(sample, &normal);
        let ground_point = normal * (lowest - l.drop_height);
        let total: f64 = sample.bodies.mass.iter().sum();
        let centre = sample
            .bodies
            .pos
            .iter()
            .zip(&sample.bodies.mass)
            .map(|(p, m)| p * *m)
            .sum::<Vec3>()
            / total;
        let gravity = if scene.has_effect(EffectKind::Gravity) {
            Vec3::from(scene.gravity.acceleration)
        } else {
            Vec3::zeros()
        };
        Ok(Drop {
            end_time: l.end_time,
            ground_point,
            ground_normal: normal,
            downslope,
            roll_axis: normal.cross(&downslope),
            gravity,
            turns: 0.0,
            last_spin: 0.0,
            last_time: 0.0,
            centre0: centre,
            size: highest - lowest,
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(l: &DropSpec) -> String {
        format!(
            "drop at {:?} m/s onto a ground inclined {} degrees, for {:e} s",
            l.initial_velocity, l.ground_angle_degrees, l.end_time
        )
    }
}

impl Loading for Drop {
    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn columns(&self) -> Vec<&'static str> {
        vec![
            "time",
            "kinetic_energy",
            "potential_energy",
            "strain_energy",
            "contact_energy",
            "total_energy",
            "downslope_distance",
            "height",
            "rotation_turns",
            "ground_contacts",
        ]
    }

    fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        let (d, b) = (self, r.bodies);
        let ke = b.kinetic_energy();
        let mut mass = 0.0;
        let mut centre = Vec3::zeros();
        let mut momentum = Vec3::zeros();
        let mut potential = 0.0;
        for i in 0..b.len() {
            mass += b.mass[i];
            centre += b.pos[i] * b.mass[i];
            momentum += b.vel[i] * b.mass[i];
            potential -= b.mass[i] * d.gravity.dot(&(b.pos[i] - r.reference[i]));
        }
        centre /= mass;
        // The body's rigid rotation: its angular momentum about the centre of mass over its
        // inertia tensor there (the elements' positions, not their spins).
        let vc = momentum / mass;
        let mut l = Vec3::zeros();
        let mut inertia = Matrix3::zeros();
        for i in 0..b.len() {
            let x = b.pos[i] - centre;
            l += x.cross(&(b.vel[i] - vc)) * b.mass[i];
            inertia += (Matrix3::identity() * x.norm_squared() - x * x.transpose()) * b.mass[i];
        }
        let spin = inertia
            .try_inverse()
            .map_or(0.0, |inv| (inv * l).dot(&d.roll_axis));
        // Trapezoidal turning between rows.
        d.turns += 0.5 * (spin + d.last_spin) * (r.time - d.last_time) / std::f64::consts::TAU;
        d.last_spin = spin;
        d.last_time = r.time;
        let total = ke + potential + r.strain_energy + r.contact_energy;
        vec![
            r.time,
            ke,
            potential,
            r.strain_energy,
            r.contact_energy,
            total,
            (centre - d.centre0).dot(&d.downslope),
            (centre - d.ground_point).dot(&d.ground_normal),
            d.turns,
            r.ground_contacts as f64,
        ]
    }

    /// `bounces`: how often the body left the ground after touching it, i.e. output rows with
    /// no ground contact after a row with some; `downslope_sizes`: the distance travelled down
    /// the slope in units of the body's extent across the ground at the start (a ball's
    /// diameter).
    fn summarize(&self, series: &Series, _dt_row: f64, out: &mut Map<String, Value>) {
        if let (Some(total), Some(down)) = (
            series.column("total_energy"),
            series.column("downslope_distance"),
        ) {
            if let Some(&e0) = total.first() {
                let top = total.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                out.insert("max_energy_ratio".into(), (top / e0).into());
                out.insert("initial_energy".into(), e0.into());
            }
            let distance = down.last().copied().unwrap_or(0.0);
            out.insert("downslope_distance".into(), distance.into());
            if self.size > 0.0 {
                out.insert("downslope_sizes".into(), (distance / self.size).into());
            }
        }
        if let Some(contacts) = series.column("ground_contacts") {
            out.insert("bounces".into(), take_offs(&contacts).into());
        }
        out.insert("rotation_turns".into(), self.turns.into());
    }
}

/// Take-offs in a series of contact counts: rows with none that follow a row with some.
fn take_offs(contacts: &[f64]) -> usize {
    contacts
        .windows(2)
        .filter(|w| w[0] > 0.0 && w[1] == 0.0)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn take_offs_count_rows_leaving_the_ground() {
        // In the air, lands, leaves, chatters down to none for one row, rests.
        assert_eq!(
            take_offs(&[0.0, 0.0, 3.0, 5.0, 0.0, 0.0, 2.0, 0.0, 4.0, 4.0]),
            2
        );
        assert_eq!(take_offs(&[]), 0);
        assert_eq!(take_offs(&[0.0, 0.0]), 0);
    }
}
