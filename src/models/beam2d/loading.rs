//! The loadings of the `beam2d` model (Kun et al., Section 3): the boundary layers of a
//! rectangle driven apart or together (elastic moduli, Section 3.1; confined compression,
//! Section 3.2), an explosion at the centre (Section 3.3.1) and a projectile (Section 3.3.2).
//!
//! Driven boundaries start from rest and accelerate uniformly to their final speed over
//! `ramp_time`, then keep it: "with this slow loading the vibrations of the solid can be
//! reduced drastically". A driven degree of freedom has zero inverse mass, so the integrators
//! leave it alone, and [`Beam2dLoading::prescribe`] writes its exact position and velocity.

use serde::{Deserialize, Serialize};

use super::scene::{Beam2dScene, DrivenSpec, Explosive, LoadingSpec, Projectile, QuietEnd};
use crate::error::Result;
use crate::probe::Series;
use crate::sample::lattice2d::LatticeShape;
use crate::sample::lattice2d::{PolygonSample, SIDE_BOTTOM, SIDE_LEFT, SIDE_RIGHT, SIDE_TOP};
use crate::scene::Scene;
use crate::shape::polygon::Vec2;
use crate::state::polygons::Polygons;

/// Columns of series.csv for driven boundaries: time (s), axial strain ΔL/L (elongation
/// positive), axial stress F/(S t) (Pa, tension positive), lateral strain ΔS/S, kinetic
/// energy (J), overlapping pairs, broken beams.
pub const DRIVEN_COLUMNS: [&str; 7] = [
    "time",
    "strain",
    "stress",
    "lateral_strain",
    "kinetic_energy",
    "contacts",
    "broken_beams",
];

/// Columns for free fragmentation: time, kinetic energy, overlapping pairs, broken beams,
/// fragments (components over intact beams) and the total momentum (kg·m/s).
pub const FREE_COLUMNS: [&str; 7] = [
    "time",
    "kinetic_energy",
    "contacts",
    "broken_beams",
    "fragments",
    "momentum_x",
    "momentum_y",
];

/// Fraction of each phase's end strain from which the moduli are fitted.
pub const MODULUS_FIT_FROM: f64 = 0.25;

/// Fractions of the failure strain between which the confined compression's modulus is fitted.
pub const COMPRESSION_FIT: [f64; 2] = [0.2, 0.6];

/// The top and bottom boundary layers of a rectangle, driven along y, and the free sides.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Driven {
    /// Final speed of each driven layer (m/s) and the time to reach it (s).
    pub speed: f64,
    pub ramp_time: f64,
    /// |strain| at which a phase ends.
    pub end_strain: f64,
    /// Horizontal coordinates and rotations of the layers fixed too (Section 3.2).
    pub confined: bool,
    pub bottom: Vec<u32>,
    pub top: Vec<u32>,
    pub left: Vec<u32>,
    pub right: Vec<u32>,
    /// Initial centres of the driven polygons, bottom then top.
    pub start: Vec<[f64; 2]>,
    /// Distance between the layers' mean heights, and between the sides' mean abscissae (m).
    pub length0: f64,
    pub width0: f64,
    /// Width of the rectangle (m) times its thickness: the loaded section.
    pub section: f64,
    /// +1 stretches, −1 compresses.
    pub sign: f64,
    /// When the current phase began (s); phases of the moduli test: 0 elongation, 1 compression.
    pub phase: u8,
    pub phase_start: f64,
}

impl Driven {
    /// Displacement (m) and speed (m/s) of the top layer `tau` seconds into a phase.
    pub fn motion(&self, tau: f64) -> (f64, f64) {
        let (v, t) = (self.speed, self.ramp_time);
        if tau < t {
            (0.5 * v / t * tau * tau, v / t * tau)
        } else {
            (0.5 * v * t + v * (tau - t), v)
        }
    }

    /// Seconds for a phase to reach the end strain.
    pub fn phase_duration(&self) -> f64 {
        let d = 0.5 * self.end_strain * self.length0;
        let (v, t) = (self.speed, self.ramp_time);
        if t > 0.0 && 0.5 * v * t >= d {
            (2.0 * d * t / v).sqrt()
        } else {
            d / v + 0.5 * t
        }
    }

    fn layers(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.bottom
            .iter()
            .map(|&k| (k as usize, -1.0))
            .chain(self.top.iter().map(|&k| (k as usize, 1.0)))
    }

    /// Strain, stress and lateral strain at the current state with forces `f`.
    pub fn measure(&self, p: &Polygons, f: &[[f64; 3]]) -> (f64, f64, f64) {
        let mean = |ks: &[u32], axis: usize| {
            ks.iter().map(|&k| p.q[k as usize][axis]).sum::<f64>() / ks.len() as f64
        };
        let length = mean(&self.top, 1) - mean(&self.bottom, 1);
        let width = mean(&self.right, 0) - mean(&self.left, 0);
        let force = |ks: &[u32]| ks.iter().map(|&k| f[k as usize][1]).sum::<f64>();
        // The sample pulls the top layer down and the bottom one up when stretched.
        let stress = 0.5 * (force(&self.bottom) - force(&self.top)) / self.section;
        (
            (length - self.length0) / self.length0,
            stress,
            (width - self.width0) / self.width0,
        )
    }
}

/// How the boundaries and initial velocities of a beam2d run are set.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Beam2dLoading {
    /// Elongation to `end_strain`, then compression from the initial state (Section 3.1).
    ElasticModuli(Driven),
    /// Compression between confined boundary layers (Section 3.2).
    ConfinedCompression(Driven),
    /// The centre polygon is the explosive: its neighbours fly off normal to the sides they
    /// share with it at speeds ∝ S/m, with zero total momentum and kinetic energy E0; the
    /// explosive itself is spent (removed).
    Explosion {
        energy: f64,
        quiet_steps: u64,
        end_time: f64,
        /// Mass (kg) and centre of the spent explosive, and how many polygons it kicked.
        explosive_mass: f64,
        explosive_centre: [f64; 2],
        kicked: usize,
        /// Removed (the default) or kept at rest, bonded to its neighbours.
        #[serde(default = "spent_default")]
        spent: bool,
    },
    /// One polygon at the lower middle gets `speed` into the block.
    Projectile {
        speed: f64,
        quiet_steps: u64,
        end_time: f64,
        polygon: usize,
        /// Its beams cut before the start (`loading.projectile = "free"`).
        #[serde(default)]
        free: bool,
    },
}

impl Beam2dLoading {
    /// Sets the sample up for the scene's loading: removes the explosive, gives initial
    /// velocities, fixes the driven degrees of freedom (zero inverse mass).
    pub fn prepare(
        scene: &Scene,
        cfg: &Beam2dScene,
        sample: &mut PolygonSample,
    ) -> Result<Beam2dLoading> {
        let thickness = cfg.sample.thickness;
        Ok(match cfg.loading {
            LoadingSpec::ElasticModuli(l) | LoadingSpec::ConfinedCompression(l) => {
                let confined = matches!(cfg.loading, LoadingSpec::ConfinedCompression(_));
                let driven = driven(scene, &l, sample, confined, thickness)?;
                let p = &mut sample.polygons;
                for (k, _) in driven.layers() {
                    p.inv_m[k][1] = 0.0;
                    if confined {
                        p.inv_m[k][0] = 0.0;
                        p.inv_m[k][2] = 0.0;
                    }
                }
                if confined {
                    Beam2dLoading::ConfinedCompression(driven)
                } else {
                    Beam2dLoading::ElasticModuli(driven)
                }
            }
            LoadingSpec::Explosion {
                energy,
                explosive,
                end,
            } => explode(scene, cfg, sample, energy, explosive, end)?,
            LoadingSpec::Projectile {
                speed,
                projectile,
                end,
            } => {
                let p = &sample.polygons;
                let middle = 0.5 * sample.info.size[0];
                let polygon = (0..p.len())
                    .filter(|&k| sample.outline[k] & SIDE_BOTTOM != 0)
                    .min_by(|&a, &b| {
                        (p.q[a][0] - middle)
                            .abs()
                            .total_cmp(&(p.q[b][0] - middle).abs())
                    })
                    .ok_or_else(|| scene.key_error("sample", "has no polygon on its lower side"))?;
                sample.polygons.v[polygon] = [0.0, speed, 0.0];
                Beam2dLoading::Projectile {
                    speed,
                    quiet_steps: end.quiet_steps,
                    end_time: end.end_time,
                    polygon,
                    free: projectile == Projectile::Free,
                }
            }
        })
    }

    pub fn driven(&self) -> Option<&Driven> {
        match self {
            Beam2dLoading::ElasticModuli(d) | Beam2dLoading::ConfinedCompression(d) => Some(d),
            _ => None,
        }
    }

    /// Steps without a broken beam after which the run stops (free fragmentation only).
    pub fn quiet_steps(&self) -> Option<u64> {
        match self {
            Beam2dLoading::Explosion { quiet_steps, .. }
            | Beam2dLoading::Projectile { quiet_steps, .. } => Some(*quiet_steps),
            _ => None,
        }
    }

    /// The time (s) at which the run ends at the latest.
    pub fn end_time(&self) -> f64 {
        match self {
            Beam2dLoading::ElasticModuli(d) => 2.0 * d.phase_duration(),
            Beam2dLoading::ConfinedCompression(d) => d.phase_duration(),
            Beam2dLoading::Explosion { end_time, .. }
            | Beam2dLoading::Projectile { end_time, .. } => *end_time,
        }
    }

    /// The step at which the run ends at the latest.
    pub fn end_step(&self, dt: f64) -> u64 {
        let steps = |t: f64| crate::run::end_step(t, dt);
        match self {
            Beam2dLoading::ElasticModuli(d) => 2 * steps(d.phase_duration()),
            Beam2dLoading::ConfinedCompression(d) => steps(d.phase_duration()),
            Beam2dLoading::Explosion { end_time, .. }
            | Beam2dLoading::Projectile { end_time, .. } => steps(*end_time),
        }
    }

    /// The series columns of this loading.
    pub fn columns(&self) -> &'static [&'static str] {
        match self.driven() {
            Some(_) => &DRIVEN_COLUMNS,
            None => &FREE_COLUMNS,
        }
    }

    /// Writes the driven degrees of freedom's positions and velocities at time `t`.
    pub fn prescribe(&self, t: f64, p: &mut Polygons) {
        let Some(d) = self.driven() else { return };
        let (u, v) = d.motion(t - d.phase_start);
        for (n, (k, side)) in d.layers().enumerate() {
            let [x0, y0] = d.start[n];
            p.q[k][1] = y0 + side * d.sign * u;
            p.v[k][1] = side * d.sign * v;
            if d.confined {
                p.q[k][0] = x0;
                p.v[k][0] = 0.0;
                p.q[k][2] = 0.0;
                p.v[k][2] = 0.0;
            }
        }
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table (the
    /// lattice, which sets the layers and the polygons kicked, is not built to explain it).
    pub fn describe(l: &LoadingSpec) -> String {
        match *l {
            LoadingSpec::ElasticModuli(d) => format!(
                "elastic moduli: top and bottom layers pulled apart at strain rate {} 1/s (ramp {} s) to strain {}, then compressed from the start to -{}",
                d.strain_rate, d.ramp_time, d.end_strain, d.end_strain
            ),
            LoadingSpec::ConfinedCompression(d) => format!(
                "confined compression at strain rate {} 1/s (ramp {} s) to strain -{}; layers' x and rotation fixed",
                d.strain_rate, d.ramp_time, d.end_strain
            ),
            LoadingSpec::Explosion {
                energy,
                explosive,
                end,
            } => format!(
                "explosion of the centre polygon, energy {energy:e} J{}; stops after {} steps without a break or at {:e} s",
                match explosive {
                    Explosive::Spent => "",
                    Explosive::Kept => " (the polygon stays, at rest and bonded)",
                },
                end.quiet_steps,
                end.end_time
            ),
            LoadingSpec::Projectile {
                speed,
                projectile,
                end,
            } => format!(
                "projectile: the polygon at the lower middle{} starts at {speed} m/s upwards; stops after {} steps without a break or at {:e} s",
                match projectile {
                    Projectile::Bonded => "",
                    Projectile::Free => ", its beams cut,",
                },
                end.quiet_steps,
                end.end_time
            ),
        }
    }

    /// The driven loadings' results from the series: moduli, Poisson's ratios, peak stress.
    pub fn summarize(&self, series: &Series, out: &mut serde_json::Map<String, serde_json::Value>) {
        let Some(d) = self.driven() else { return };
        let (Some(strain), Some(stress), Some(lateral)) = (
            series.column("strain"),
            series.column("stress"),
            series.column("lateral_strain"),
        ) else {
            return;
        };
        let fit = |y: &[f64], lo: f64, hi: f64| {
            let pts: Vec<(f64, f64)> = strain
                .iter()
                .zip(y)
                .filter(|(e, _)| **e >= lo && **e <= hi)
                .map(|(e, s)| (*e, *s))
                .collect();
            (pts.len() >= 3).then(|| crate::probe::fit::least_squares_slope(&pts))
        };
        match self {
            Beam2dLoading::ElasticModuli(_) => {
                let (lo, hi) = (MODULUS_FIT_FROM * d.end_strain, d.end_strain);
                for (name, lo, hi) in [("elongation", lo, hi), ("compression", -hi, -lo)] {
                    if let (Some(k), Some(nu)) = (fit(&stress, lo, hi), fit(&lateral, lo, hi)) {
                        out.insert(format!("young_{name}"), k.into());
                        out.insert(format!("poisson_{name}"), (-nu).into());
                    }
                }
                out.insert("modulus_strain_range".into(), serde_json::json!([lo, hi]));
            }
            Beam2dLoading::ConfinedCompression(_) => {
                let peak = (0..stress.len()).max_by(|&a, &b| (-stress[a]).total_cmp(&-stress[b]));
                let Some(k) = peak else { return };
                let failure = -strain[k];
                out.insert("peak_stress".into(), (-stress[k]).into());
                out.insert("failure_strain".into(), failure.into());
                out.insert("peak_time".into(), series.rows[k][0].into());
                if let Some(last) = stress.last() {
                    out.insert("stress_final".into(), (-last).into());
                }
                // The linear part before failure: 20% to 60% of the failure strain.
                let (lo, hi) = (COMPRESSION_FIT[0] * failure, COMPRESSION_FIT[1] * failure);
                if let Some(k) = fit(&stress, -hi, -lo) {
                    out.insert("young_compression".into(), k.into());
                    out.insert("modulus_strain_range".into(), serde_json::json!([lo, hi]));
                }
            }
            _ => {}
        }
    }
}

/// The driven layers of a rectangle: polygons touching its bottom and top sides, and the
/// free sides' polygons for the lateral strain.
fn driven(
    scene: &Scene,
    l: &DrivenSpec,
    sample: &PolygonSample,
    confined: bool,
    thickness: f64,
) -> Result<Driven> {
    let with = |bit: u8| -> Vec<u32> {
        (0..sample.polygons.len())
            .filter(|&k| sample.outline[k] & bit != 0)
            .map(|k| k as u32)
            .collect()
    };
    let (bottom, top, left, right) = (
        with(SIDE_BOTTOM),
        with(SIDE_TOP),
        with(SIDE_LEFT),
        with(SIDE_RIGHT),
    );
    if bottom.iter().any(|k| top.contains(k)) {
        return Err(scene.key_error(
            "sample.cells",
            "gives polygons touching both the top and the bottom; use more rows",
        ));
    }
    let p = &sample.polygons;
    let mean = |ks: &[u32], axis: usize| {
        ks.iter().map(|&k| p.q[k as usize][axis]).sum::<f64>() / ks.len() as f64
    };
    let length0 = mean(&top, 1) - mean(&bottom, 1);
    let width0 = mean(&right, 0) - mean(&left, 0);
    let start = bottom
        .iter()
        .chain(&top)
        .map(|&k| [p.q[k as usize][0], p.q[k as usize][1]])
        .collect();
    Ok(Driven {
        speed: 0.5 * l.strain_rate * length0,
        ramp_time: l.ramp_time,
        end_strain: l.end_strain,
        confined,
        bottom,
        top,
        left,
        right,
        start,
        length0,
        width0,
        section: sample.info.size[0] * thickness,
        sign: if confined { -1.0 } else { 1.0 },
        phase: 0,
        phase_start: 0.0,
    })
}

fn spent_default() -> bool {
    true
}

/// The explosion's initial velocities; removes the explosive polygon (unless kept).
fn explode(
    scene: &Scene,
    cfg: &Beam2dScene,
    sample: &mut PolygonSample,
    energy: f64,
    explosive: Explosive,
    end: QuietEnd,
) -> Result<Beam2dLoading> {
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
    // Σ S n vanishes around a closed polygon; what round-off and hairline sides (too short for
    // a beam) leave is removed, and the energy set to E0 again.
    let kicked_mass: f64 = velocity.iter().map(|&(k, _)| p.mass[k]).sum();
    let residual: Vec2 = velocity.iter().map(|&(k, v)| v * p.mass[k]).sum::<Vec2>() / kicked_mass;
    let mut e = 0.0;
    for (k, v) in &mut velocity {
        *v -= residual;
        e += 0.5 * p.mass[*k] * v.norm_squared();
    }
    let scale = (energy / e).sqrt();
    // The energy is bounded as the projectile's speed is: the polygons move by Newton's laws,
    // and 1e300 J sent pieces off at 1e151 m/s. The speeds grow as √energy, so the bound is
    // where the fastest kicked polygon would reach the speed of light.
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
    if top_speed.is_nan() || top_speed >= super::scene::SPEED_OF_LIGHT {
        let limit = (super::scene::SPEED_OF_LIGHT / per_root_joule).powi(2);
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
    Ok(Beam2dLoading::Explosion {
        energy,
        quiet_steps: end.quiet_steps,
        end_time: end.end_time,
        explosive_mass,
        explosive_centre,
        kicked: velocity.len(),
        spent,
    })
}
