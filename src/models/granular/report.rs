//! What a granular run reports: strains, stresses, the fracture summary and the size
//! distributions.

use super::*;

/// The value of `ys` at `x` by linear interpolation along the increasing `xs`; `None` outside
/// (and where `ys` is shorter).
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let k = xs.iter().position(|&v| v >= x).filter(|&k| k < ys.len())?;
    if k == 0 {
        return (xs[0] == x).then(|| ys[0]);
    }
    let t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    Some(ys[k - 1] + t * (ys[k] - ys[k - 1]))
}

/// Axial stress of each series row: the mean of the top and bottom faces (Pa).
fn axial_stress_column(series: &Series) -> Vec<f64> {
    match (
        series.column("stress_driven"),
        series.column("stress_opposite"),
    ) {
        (Some(a), Some(b)) => a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect(),
        _ => Vec::new(),
    }
}

impl Granular {
    /// The box's height (z, m) when loading began: what `axial_strain` is relative to (0
    /// without a box). A prepared sample's box is not the scene's nominal one: a jammed sample
    /// stops within its fraction's tolerance, its box scaled to match.
    pub fn initial_height(&self) -> f64 {
        if self.state.walls.is_box {
            self.state.height0
        } else {
            0.0
        }
    }

    /// The axial strain of the box (0 without one).
    pub fn axial_strain(&self) -> f64 {
        let st = &self.state;
        if st.walls.is_box {
            (st.height0 - st.walls.box_size().z) / st.height0
        } else {
            0.0
        }
    }

    /// The strains at which the size distribution and the stress are reported: those of an
    /// oedometer run up to its end strain.
    pub fn report_strains(&self) -> Vec<f64> {
        self.report_strains_iter().collect()
    }

    /// [`Granular::report_strains`] without collecting them (checked at every step).
    pub(super) fn report_strains_iter(&self) -> impl Iterator<Item = f64> + '_ {
        let end = self
            .state
            .loading()
            .and_then(|l| l.end_strain())
            .unwrap_or(f64::NEG_INFINITY);
        self.strains_asked
            .iter()
            .copied()
            .filter(move |&e| e <= end + 1e-12)
    }

    /// The mean stress on the walls (Pa, compression positive: each wall's normal force over
    /// its box face's area, averaged over the walls) and the mean coordination number
    /// (contacts per body, a wall contact counting once) at the last force evaluation.
    pub(super) fn load_bearing(&self) -> [f64; 2] {
        let st = &self.state;
        let walls = &st.walls;
        let stress = if walls.is_box {
            crate::state::BoxFace::ALL
                .iter()
                .map(|&f| walls.face_stress(f))
                .sum::<f64>()
                / 6.0
        } else {
            0.0
        };
        let wall_contacts = walls.contacts();
        let n = st.bodies.len().max(1);
        let coordination = (2 * self.pipeline.contacts() + wall_contacts) as f64 / n as f64;
        [stress, coordination]
    }

    /// The `fracture` effect's results: grains broken, fragments, splits by criterion, springs,
    /// the stress at the report strains, the median size at each, and the energy account.
    pub(super) fn fracture_summary(&self, f: &GrainFracture, m: &mut Map<String, Value>) {
        use serde_json::json;
        let n = self.state.bodies.len();
        m.insert("broken_particles".into(), f.broken_particles().into());
        m.insert("fragments".into(), f.fragments(n).into());
        m.insert("particles_final".into(), n.into());
        m.insert(
            "comminution".into(),
            Comminution::of(self.axial_strain(), &self.state.bodies, f).json(),
        );
        let by =
            |c: crate::fracture::Criterion| f.events.iter().filter(|e| e.criterion == c).count();
        m.insert(
            "splits".into(),
            json!({
                "total": f.events.len(),
                "hoek_brown": by(crate::fracture::Criterion::HoekBrown),
                "contacts": by(crate::fracture::Criterion::Contacts),
            }),
        );
        m.insert(
            "springs".into(),
            json!({"made": f.springs.len(), "intact": f.intact_springs()}),
        );
        if let Some(first) = f.events.first() {
            m.insert("first_split_time".into(), first.time.into());
            m.insert(
                "first_split".into(),
                json!({
                    "step": first.step,
                    "time": first.time,
                    "axis": first.axis,
                    "criterion": first.criterion,
                    "semi_plus": first.semi[0],
                    "semi_minus": first.semi[1],
                }),
            );
        }
        let strains = self.report_strains();
        if !strains.is_empty() {
            // The mass median and the modes (quarter-octave bins, 0.19 in ln d, a mode holding
            // at least 3% of the mass) of each distribution.
            let (mut d50, mut peaks) = (serde_json::Map::new(), serde_json::Map::new());
            for (e, pieces) in &self.state.psd {
                let median = size_distribution::median_diameter(pieces);
                let at = size_distribution::modes(pieces, 2f64.powf(0.25), 0.03);
                d50.insert(format!("{e}"), median.into());
                peaks.insert(format!("{e}"), at.into());
            }
            m.insert("median_diameter_at_strain".into(), Value::Object(d50));
            m.insert("size_modes_at_strain".into(), Value::Object(peaks));
            let mut at = serde_json::Map::new();
            for c in &self.state.comminution {
                at.insert(format!("{}", c.strain), c.json());
            }
            m.insert("comminution_at_strain".into(), Value::Object(at));
        }
        if let Some(e) = &self.state.energy {
            m.insert(
                "energy".into(),
                e.report(self.mechanical_energy(), f.spring_work, f.split_energy),
            );
        }
    }

    /// The stresses (Pa, compression positive) at the report strains of an oedometer run:
    /// `stress_at_strain` the axial stress (mean of the driven and the opposite face),
    /// `stress_driven_at_strain` and `stress_opposite_at_strain` each face's own (an SHPB's
    /// one-wave stress is the opposite face's, on the transmitted bar), and
    /// `stress_lateral_at_strain` the mean of the four side faces (with a sleeve, its mean
    /// radial stress); with a sleeve also `stress_radial_profile_at_strain`, its radial stress
    /// on each axial slice from the opposite face up.
    pub(super) fn stress_summary(&self, series: &Series, m: &mut Map<String, Value>) {
        let strains = self.report_strains();
        if strains.is_empty() {
            return;
        }
        let eps = series.column("axial_strain").unwrap_or_default();
        let (x, y) = (
            series.column("stress_lateral_x").unwrap_or_default(),
            series.column("stress_lateral_y").unwrap_or_default(),
        );
        let lateral: Vec<f64> = x.iter().zip(&y).map(|(a, b)| 0.5 * (a + b)).collect();
        let columns = [
            ("stress_at_strain", axial_stress_column(series)),
            (
                "stress_driven_at_strain",
                series.column("stress_driven").unwrap_or_default(),
            ),
            (
                "stress_opposite_at_strain",
                series.column("stress_opposite").unwrap_or_default(),
            ),
            ("stress_lateral_at_strain", lateral),
        ];
        for (key, column) in columns {
            let mut at = serde_json::Map::new();
            for e in &strains {
                if let Some(v) = interpolate(&eps, &column, *e) {
                    at.insert(format!("{e}"), v.into());
                }
            }
            m.insert(key.into(), Value::Object(at));
        }
        if self.state.walls.sleeve.is_some() {
            let slices: Vec<Vec<f64>> = probe::SLEEVE_COLUMNS[1..]
                .iter()
                .map(|c| series.column(c).unwrap_or_default())
                .collect();
            let mut at = serde_json::Map::new();
            for e in &strains {
                let profile: Option<Vec<f64>> =
                    slices.iter().map(|c| interpolate(&eps, c, *e)).collect();
                if let Some(p) = profile {
                    at.insert(format!("{e}"), p.into());
                }
            }
            m.insert("stress_radial_profile_at_strain".into(), Value::Object(at));
        }
    }

    /// psd.csv: the sieve curves (mass fraction finer than each equivalent diameter) at the
    /// start and at each report strain reached.
    pub fn psd_csv(&self) -> Option<String> {
        if self.state.psd.is_empty() || self.state.fracture.is_none() {
            return None;
        }
        let curves: Vec<&Vec<(f64, f64)>> = self.state.psd.iter().map(|(_, p)| p).collect();
        let sieves =
            size_distribution::sieve_sizes(curves.iter().flat_map(|c| c.iter().map(|p| p.1)), 40);
        let passing: Vec<Vec<f64>> = curves
            .iter()
            .map(|c| size_distribution::passing(c, &sieves))
            .collect();
        let mut s = String::from("diameter");
        for (e, _) in &self.state.psd {
            s.push_str(&format!(",passing_at_strain_{e}"));
        }
        s.push('\n');
        for (k, d) in sieves.iter().enumerate() {
            s.push_str(&format!("{d:e}"));
            for p in &passing {
                s.push_str(&format!(",{:e}", p[k] + 0.0)); // no "-0"
            }
            s.push('\n');
        }
        Some(s)
    }
}
