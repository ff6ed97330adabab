//! What the two driven loadings share: the top and bottom boundary layers of a rectangle
//! driven along y, their motion, what a row measures and the fit of a modulus from the series.

use serde::{Deserialize, Serialize};

use super::super::Beam2d;
use super::super::scene::DrivenSpec;
use crate::error::Result;
use crate::probe::Series;
use crate::sample::lattice2d::{PolygonSample, SIDE_BOTTOM, SIDE_LEFT, SIDE_RIGHT, SIDE_TOP};
use crate::scene::Scene;
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
    /// The driven layers of a rectangle: polygons touching its bottom and top sides, and the
    /// free sides' polygons for the lateral strain. Fixes the driven degrees of freedom (zero
    /// inverse mass): y, and with `confined` also x and the rotation.
    pub fn build(
        scene: &Scene,
        l: &DrivenSpec,
        sample: &mut PolygonSample,
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
        let driven = Driven {
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
        };
        let p = &mut sample.polygons;
        for (k, _) in driven.layers() {
            p.inv_m[k][1] = 0.0;
            if confined {
                p.inv_m[k][0] = 0.0;
                p.inv_m[k][2] = 0.0;
            }
        }
        Ok(driven)
    }

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

    /// Writes the driven degrees of freedom's positions and velocities at time `t`.
    pub fn prescribe(&self, t: f64, p: &mut Polygons) {
        let (u, v) = self.motion(t - self.phase_start);
        for (n, (k, side)) in self.layers().enumerate() {
            let [x0, y0] = self.start[n];
            p.q[k][1] = y0 + side * self.sign * u;
            p.v[k][1] = side * self.sign * v;
            if self.confined {
                p.q[k][0] = x0;
                p.v[k][0] = 0.0;
                p.q[k][2] = 0.0;
                p.v[k][2] = 0.0;
            }
        }
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

    /// One row of [`DRIVEN_COLUMNS`] at `time` (s).
    pub fn row(&self, model: &Beam2d, time: f64) -> Vec<f64> {
        let st = &model.state;
        let p = &st.polygons;
        let ke = p.kinetic_energy();
        let broken = st.beams.broken() as f64;
        let (strain, stress, lateral) = self.measure(p, &st.forces);
        vec![
            time,
            strain,
            stress,
            lateral,
            ke,
            st.contacts as f64,
            broken,
        ]
    }
}

/// The strain, stress and lateral strain columns of a driven run's series.
pub struct DrivenSeries {
    pub strain: Vec<f64>,
    pub stress: Vec<f64>,
    pub lateral: Vec<f64>,
}

impl DrivenSeries {
    /// The three columns, if the series has them all.
    pub fn read(series: &Series) -> Option<DrivenSeries> {
        Some(DrivenSeries {
            strain: series.column("strain")?,
            stress: series.column("stress")?,
            lateral: series.column("lateral_strain")?,
        })
    }

    /// The least-squares slope of `y` against the strain over the rows with a strain in
    /// [`lo`, `hi`]; none below three such rows.
    pub fn fit(&self, y: &[f64], lo: f64, hi: f64) -> Option<f64> {
        let pts: Vec<(f64, f64)> = self
            .strain
            .iter()
            .zip(y)
            .filter(|(e, _)| **e >= lo && **e <= hi)
            .map(|(e, s)| (*e, *s))
            .collect();
        (pts.len() >= 3).then(|| crate::probe::fit::least_squares_slope(&pts))
    }
}
