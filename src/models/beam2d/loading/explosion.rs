//! `loading.kind = "explosion"` (Section 3.3.1): the centre polygon is the explosive; its
//! neighbours fly off normal to the sides they share with it.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::super::Beam2d;
use super::super::scene::{Beam2dScene, Explosive, QuietEnd, SPEED_OF_LIGHT};
use super::Loading;
use super::fragmentation::{self, FREE_COLUMNS};
use crate::error::Result;
use crate::probe::Series;
use crate::sample::lattice2d::{LatticeShape, PolygonSample};
use crate::scene::Scene;
use crate::shape::polygon::Vec2;

/// The centre polygon's neighbours fly off normal to the sides they share with it at speeds
/// ∝ S/m, with zero total momentum and kinetic energy E0; the explosive itself is spent
/// (removed).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Explosion {
    pub energy: f64,
    pub quiet_steps: u64,
    pub end_time: f64,
    /// Mass (kg) and centre of the spent explosive, and how many polygons it kicked.
    pub explosive_mass: f64,
    pub explosive_centre: [f64; 2],
    pub kicked: usize,
    /// Removed (the default) or kept at rest, bonded to its neighbours.
    #[serde(default = "spent_default")]
    pub spent: bool,
}

fn spent_default() -> bool {
    true
}

impl Explosion {
    /// The explosion's initial velocities; removes the explosive polygon (unless kept).
    pub fn build(
        scene: &Scene,
        cfg: &Beam2dScene,
        sample: &mut PolygonSample,
        energy: f64,
        explosive: Explosive,
        end: QuietEnd,
    ) -> Result<Explosion> {
        let p = &sample.polygons;
        let centre = match sample.info.outline.as_str() {
            "disc" => Vec2::zeros(),
            _ => 0.5 * Vec2::new(sample.info.size[0], sample.info.size[1]),
        };
        let k0 = (0..p.len())
            .min_by(|&a, &b| {
                (p.centre(a) - centre)
                    .norm()
                    .total_cmp(&(p.centre(b) - centre).norm())
            })
            .expect("a sample has polygons");
        if sample.outline[k0] != 0 {
            // Discs are held to a size that cannot get here (scene validation); a rectangle of
            // fewer than 12 squares each way can.
            let (key, size) = match cfg.sample.shape {
                LatticeShape::Rectangle(c) => ("sample.cells", format!("{c:?}")),
                LatticeShape::Disc(d) => ("sample.diameter", format!("{d}")),
            };
            return Err(scene.key_error(
                key,
                format!("= {size} is too small for an explosion: the centre polygon lies on the outline; 12 lattice spacings each way always leave it inside"),
            ));
        }
        // Neighbours, the shared side's length and its normal out of the explosive.
        let kicks: Vec<(usize, f64, Vec2)> = sample
            .sides
            .iter()
            .filter_map(|s| {
                if s.i as usize == k0 {
                    Some((s.j as usize, s.length, s.normal))
                } else if s.j as usize == k0 {
                    Some((s.i as usize, s.length, -s.normal))
                } else {
                    None
                }
            })
            .collect();
        // v = C S / m along the normal; E0 = C² Σ S²/m / 2.
        let sum: f64 = kicks.iter().map(|&(k, s, _)| s * s / p.mass[k]).sum();
        let c = (2.0 * energy / sum).sqrt();
        let mut velocity: Vec<(usize, Vec2)> = kicks
            .iter()
            .map(|&(k, s, n)| (k, n * (c * s / p.mass[k])))
            .collect();
        // Σ S n vanishes around a closed polygon; what round-off and hairline sides (too short
        // for a beam) leave is removed, and the energy set to E0 again.
        let kicked_mass: f64 = velocity.iter().map(|&(k, _)| p.mass[k]).sum();
        let residual: Vec2 =
            velocity.iter().map(|&(k, v)| v * p.mass[k]).sum::<Vec2>() / kicked_mass;
        let mut e = 0.0;
        for (k, v) in &mut velocity {
            *v -= residual;
            e += 0.5 * p.mass[*k] * v.norm_squared();
        }
        let scale = (energy / e).sqrt();
        // The energy is bounded as the projectile's speed is: the polygons move by Newton's
        // laws, and 1e300 J sent pieces off at 1e151 m/s. The speeds grow as √energy, so the
        // bound is where the fastest kicked polygon would reach the speed of light.
        // The same kicks at unit strength (C = 1), which the speeds are proportional to.
        let unit: Vec<(usize, Vec2)> = kicks
            .iter()
            .map(|&(k, s, n)| (k, n * (s / p.mass[k])))
            .collect();
        let drift: Vec2 = unit.iter().map(|&(k, v)| v * p.mass[k]).sum::<Vec2>() / kicked_mass;
        let (mut unit_fastest, mut unit_energy) = (0.0f64, 0.0);
        for &(k, v) in &unit {
            let w = v - drift;
            unit_fastest = unit_fastest.max(w.norm());
            unit_energy += 0.5 * p.mass[k] * w.norm_squared();
        }
        let per_root_joule = unit_fastest / unit_energy.sqrt();
        let top_speed = per_root_joule * energy.sqrt();
        if top_speed.is_nan() || top_speed >= SPEED_OF_LIGHT {
            let limit = (SPEED_OF_LIGHT / per_root_joule).powi(2);
            return Err(scene.key_error(
                "loading.energy",
                format!(
                    "= {energy:e} J is outside the allowed range (0, {limit:.4e}) J for this \
                     sample: above it the fastest polygon the explosion kicks would move faster \
                     than light (the model is Newtonian)"
                ),
            ));
        }
        let explosive_mass = p.mass[k0];
        let explosive_centre = [p.q[k0][0], p.q[k0][1]];
        for (k, v) in &velocity {
            sample.polygons.v[*k] = [v.x * scale, v.y * scale, 0.0];
        }
        let spent = explosive == Explosive::Spent;
        if spent {
            sample.remove(k0);
        }
        Ok(Explosion {
            energy,
            quiet_steps: end.quiet_steps,
            end_time: end.end_time,
            explosive_mass,
            explosive_centre,
            kicked: velocity.len(),
            spent,
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table (the
    /// lattice, which sets the polygons kicked, is not built to explain it).
    pub fn describe(energy: f64, explosive: Explosive, end: &QuietEnd) -> String {
        format!(
            "explosion of the centre polygon, energy {energy:e} J{}; stops after {} steps without a break or at {:e} s",
            match explosive {
                Explosive::Spent => "",
                Explosive::Kept => " (the polygon stays, at rest and bonded)",
            },
            end.quiet_steps,
            end.end_time
        )
    }
}

impl Loading for Explosion {
    fn end_time(&self) -> f64 {
        self.end_time
    }

    fn quiet_steps(&self) -> Option<u64> {
        Some(self.quiet_steps)
    }

    fn conserves_momentum(&self) -> bool {
        true
    }

    fn columns(&self) -> &'static [&'static str] {
        &FREE_COLUMNS
    }

    fn row(&self, model: &Beam2d, time: f64) -> Vec<f64> {
        fragmentation::row(model, time)
    }

    /// The fragments, their power law and what stopped the run; the explosive's mass and the
    /// polygons it kicked.
    fn summarize(&self, model: &Beam2d, _series: &Series, out: &mut Map<String, Value>) {
        model.fragment_summary(out);
        out.insert("explosive_mass".into(), self.explosive_mass.into());
        out.insert("kicked_polygons".into(), self.kicked.into());
    }
}
