//! Measurements recorded during a run: the rows of series.csv.

pub mod energy;
pub mod fit;
pub mod fragments;
pub mod modes;
pub mod size_distribution;
pub mod spectrum;

use serde::{Deserialize, Serialize};

use crate::state::{Bodies, BoxFace, SLEEVE_SLICES, Walls};

/// A table of measurements, one row per output step.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Series {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Series {
    pub fn new(columns: &[&str]) -> Self {
        Series {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// The position of a column, if it exists.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The values of one column, if it exists.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.index(name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }

    /// The table as CSV: a header line, then one line per row. Numbers are written in the
    /// shortest form that reads back to the same f64.
    pub fn to_csv(&self) -> String {
        let mut s = self.columns.join(",");
        s.push('\n');
        for row in &self.rows {
            let cells: Vec<String> = row
                .iter()
                .map(|v| {
                    if v.fract() == 0.0 && v.abs() < 1e15 {
                        format!("{}", *v as i64)
                    } else {
                        format!("{v:e}")
                    }
                })
                .collect();
            s.push_str(&cells.join(","));
            s.push('\n');
        }
        s
    }
}

/// Columns of series.csv for a sample in a box (stresses in Pa, compression positive):
/// time (s), axial strain along z, the normal stress on the driven top face (z+) and on the
/// opposite face (z-), the mean normal stress on the two x faces and on the two y faces,
/// kinetic energy (J), body–body contacts, body–wall contacts and the solid fraction.
pub const BOX_COLUMNS: [&str; 10] = [
    "time",
    "axial_strain",
    "stress_driven",
    "stress_opposite",
    "stress_lateral_x",
    "stress_lateral_y",
    "kinetic_energy",
    "contacts",
    "wall_contacts",
    "solid_fraction",
];

/// Columns added with a sleeve (after the box's, whose lateral stresses are then the sleeve's
/// mean radial stress): the axial force the sleeve takes from the grains by friction (N,
/// along +z: the driven top face pushes the grains down against it), and the radial stress
/// (Pa) on each of its [`SLEEVE_SLICES`] axial slices, from the opposite (z-) face up to the
/// driven (z+) one.
pub const SLEEVE_COLUMNS: [&str; 1 + SLEEVE_SLICES] = [
    "sleeve_axial_force",
    "stress_radial_1",
    "stress_radial_2",
    "stress_radial_3",
    "stress_radial_4",
    "stress_radial_5",
    "stress_radial_6",
    "stress_radial_7",
    "stress_radial_8",
    "stress_radial_9",
    "stress_radial_10",
];

/// The sleeve's columns of one row ([`SLEEVE_COLUMNS`]).
pub fn sleeve_row(walls: &Walls, row: &mut Vec<f64>) {
    if let Some(s) = &walls.sleeve {
        row.push(s.force.z);
        row.extend_from_slice(&s.radial_profile(walls.box_size().z));
    }
}

/// Columns when there is no box: time, kinetic energy and contacts.
pub const FREE_COLUMNS: [&str; 3] = ["time", "kinetic_energy", "contacts"];

/// Columns between platens (single-grain crushing): time (s), platen displacement (m), the
/// compressive force on the top and on the bottom platen (N), kinetic energy (J), body–body
/// and body–wall contacts.
pub const PLATEN_COLUMNS: [&str; 7] = [
    "time",
    "displacement",
    "force_top",
    "force_bottom",
    "kinetic_energy",
    "contacts",
    "wall_contacts",
];

/// Columns added by the `fracture` effect: bodies, grains broken, fragments (pieces of broken
/// grains, counting bonded halves as one), intact cohesive springs, elastic energy in the
/// contacts (J), work of the walls on the sample (J), energy dissipated by contact damping and
/// sliding (J) and spent in fracture by the springs (J).
pub const FRACTURE_COLUMNS: [&str; 8] = [
    "bodies",
    "broken_particles",
    "fragments",
    "intact_springs",
    "elastic_energy",
    "boundary_work",
    "dissipated",
    "fracture_energy",
];

/// One row between platens.
pub fn platen_row(
    time: f64,
    height0: f64,
    bodies: &Bodies,
    walls: &Walls,
    contacts: usize,
) -> Vec<f64> {
    vec![
        time,
        height0 - walls.box_size().z,
        walls.face(BoxFace::ZMax).normal_force(),
        walls.face(BoxFace::ZMin).normal_force(),
        bodies.kinetic_energy(),
        contacts as f64,
        walls.contacts() as f64,
    ]
}

/// One row of box measurements.
pub fn box_row(
    time: f64,
    height0: f64,
    bodies: &Bodies,
    walls: &Walls,
    contacts: usize,
) -> Vec<f64> {
    let size = walls.box_size();
    let lateral = |a: BoxFace, b: BoxFace| 0.5 * (walls.face_stress(a) + walls.face_stress(b));
    vec![
        time,
        (height0 - size.z) / height0,
        walls.face_stress(BoxFace::ZMax),
        walls.face_stress(BoxFace::ZMin),
        lateral(BoxFace::XMin, BoxFace::XMax),
        lateral(BoxFace::YMin, BoxFace::YMax),
        bodies.kinetic_energy(),
        contacts as f64,
        walls.contacts() as f64,
        bodies.solid_volume() / walls.volume(),
    ]
}

pub fn free_row(time: f64, bodies: &Bodies, contacts: usize) -> Vec<f64> {
    vec![time, bodies.kinetic_energy(), contacts as f64]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_numbers() {
        let mut s = Series::new(&["a", "b"]);
        s.rows.push(vec![0.1 + 0.2, 3.0]);
        let csv = s.to_csv();
        let line = csv.lines().nth(1).unwrap();
        let v: Vec<f64> = line.split(',').map(|t| t.parse().unwrap()).collect();
        assert_eq!(v, vec![0.1 + 0.2, 3.0]);
    }
}
