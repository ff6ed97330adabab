//! What a beam2d run reports: fragments, their masses and power law, the beams' energy and
//! the histograms.

use super::*;

/// Fragment labels over the intact beams, and their number.
pub(super) fn fragments(polygons: &Polygons, b: &Beams) -> (Vec<u32>, usize) {
    components(
        polygons.len(),
        (0..b.len())
            .filter(|&k| b.intact[k])
            .map(|k| (b.i[k] as usize, b.j[k] as usize)),
    )
}

impl Beam2d {
    /// Elastic energy (J) stored in the intact beams.
    pub fn beam_energy(&self) -> f64 {
        let (b, p) = (&self.state.beams, &self.state.polygons);
        (0..b.len())
            .filter(|&k| b.intact[k])
            .map(|k| {
                let (i, j) = (b.i[k] as usize, b.j[k] as usize);
                let r = b.response(k, p.centre(i), p.q[i][2], p.centre(j), p.q[j][2]);
                b.energy(k, &r)
            })
            .sum()
    }

    /// Fragment labels over the intact beams, and their number.
    pub fn fragments(&self) -> (Vec<u32>, usize) {
        fragments(&self.state.polygons, &self.state.beams)
    }

    /// Fragment masses (kg) and polygon counts, in label order.
    pub(super) fn fragment_masses(&self) -> (Vec<u32>, Vec<f64>, Vec<usize>) {
        let (labels, count) = self.fragments();
        let masses = sum_by_component(&labels, count, &self.state.polygons.mass);
        let mut sizes = vec![0usize; count];
        for &l in &labels {
            sizes[l as usize] += 1;
        }
        (labels, masses, sizes)
    }

    /// The power-law fit of the mass histogram of fragments of two or more polygons (single
    /// polygons are left out, as in the paper's Fig. 11).
    pub fn power_law(&self) -> Option<PowerLawFit> {
        let masses = self.multi_polygon_fragment_masses();
        self.cfg
            .fragments
            .fit(&masses, self.state.mean_polygon_mass, 1)
    }

    /// Masses (kg) of the fragments of two or more polygons: what the histogram is made of.
    pub fn multi_polygon_fragment_masses(&self) -> Vec<f64> {
        self.fragment_masses_from(2)
    }

    /// Masses (kg) of the fragments of at least `polygons` polygons (1: every fragment).
    pub fn fragment_masses_from(&self, polygons: usize) -> Vec<f64> {
        let (_, masses, sizes) = self.fragment_masses();
        masses
            .iter()
            .zip(&sizes)
            .filter(|(_, s)| **s >= polygons)
            .map(|(m, _)| *m)
            .collect()
    }

    /// Fraction of the broken beams (up to `until`, s) that lay within 30° of the x axis at
    /// rest: perpendicular to the load of the compression tests.
    pub fn broken_lateral_fraction(&self, until: f64) -> Option<f64> {
        let b = &self.state.beams;
        let broken: Vec<usize> = (0..b.len())
            .filter(|&k| !b.intact[k] && b.broken_time[k] <= until)
            .collect();
        if broken.is_empty() {
            return None;
        }
        let lateral = broken
            .iter()
            .filter(|&&k| b.rest_direction[k].y.abs() <= 0.5)
            .count();
        Some(lateral as f64 / broken.len() as f64)
    }

    /// The fragments' keys of summary.json: count, largest share, the power law, the momentum
    /// drift and what stopped the run.
    pub(super) fn fragment_summary(&self, m: &mut Map<String, Value>) {
        let (_, masses, _) = self.fragment_masses();
        let total: f64 = masses.iter().sum();
        let largest = masses.iter().copied().fold(0.0, f64::max);
        m.insert("fragments".into(), masses.len().into());
        let fit = self.power_law();
        m.insert("beta".into(), json!(fit.map(|f| f.exponent)));
        m.insert("beta_fit_range".into(), json!(fit.map(|f| f.range)));
        m.insert(
            "beta_fit_range_polygon_masses".into(),
            json!(fit.map(|f| f.range.map(|x| x / self.state.mean_polygon_mass))),
        );
        m.insert("beta_fit_bins".into(), json!(fit.map(|f| f.bins)));
        m.insert("beta_r_squared".into(), json!(fit.map(|f| f.r_squared)));
        m.insert("largest_fragment_fraction".into(), (largest / total).into());
        m.insert(
            "momentum_drift_relative".into(),
            self.state.max_momentum_drift.into(),
        );
        let quiet = self
            .state
            .loading
            .as_loading()
            .quiet_steps()
            .unwrap_or(u64::MAX);
        m.insert(
            "stopped_by".into(),
            if self.state.steps_since_break >= quiet {
                format!("{quiet} steps without a break")
            } else {
                "loading.end_time".to_string()
            }
            .into(),
        );
    }

    /// fragments.csv: one line per fragment (components over intact beams).
    pub fn fragments_csv(&self) -> String {
        let (labels, masses, sizes) = self.fragment_masses();
        let n = masses.len();
        let (mut centre, mut momentum) = (vec![Vec2::zeros(); n], vec![Vec2::zeros(); n]);
        for (i, &l) in labels.iter().enumerate() {
            let m = self.state.polygons.mass[i];
            centre[l as usize] += self.state.polygons.centre(i) * m;
            momentum[l as usize] += self.state.polygons.velocity(i) * m;
        }
        let mut s = String::from("fragment,polygons,mass,x,y,vx,vy\n");
        for k in 0..n {
            let (c, v) = (centre[k] / masses[k], momentum[k] / masses[k]);
            let _ = writeln!(
                s,
                "{k},{},{:e},{:e},{:e},{:e},{:e}",
                sizes[k], masses[k], c.x, c.y, v.x, v.y
            );
        }
        s
    }

    /// fragment_histogram.csv: the log-binned histogram of fragments of two or more polygons.
    pub fn histogram_csv(&self) -> String {
        let f = &self.cfg.fragments;
        let bins = mass_histogram(
            &self.multi_polygon_fragment_masses(),
            self.state.mean_polygon_mass,
            f.bins_per_decade,
            1,
        );
        let mut s = String::from("mass_lo,mass_hi,mass_centre,count,density\n");
        for b in &bins {
            let _ = writeln!(
                s,
                "{:e},{:e},{:e},{},{:e}",
                b.lo,
                b.hi,
                b.centre(),
                b.count,
                b.density
            );
        }
        s
    }
}

/// The power law fitted to the fragment mass histogram averaged over several runs of one
/// scene (different seeds): the fragments of two or more polygons of all runs, binned in units
/// of the runs' mean polygon mass, per run; fitted by the first run's `fragments` rule.
pub fn averaged_power_law(runs: &[&Beam2dRun]) -> Option<PowerLawFit> {
    let first = runs.first()?;
    averaged_power_law_by(runs, &first.model.cfg.fragments, 2)
}

/// [`averaged_power_law`] by another fit rule `spec`, over the fragments of at least
/// `polygons` polygons (the beam2d ablation's fragment definition and fit window).
pub fn averaged_power_law_by(
    runs: &[&Beam2dRun],
    spec: &scene::FragmentSpec,
    polygons: usize,
) -> Option<PowerLawFit> {
    if runs.is_empty() {
        return None;
    }
    spec.fit(
        &pooled_fragment_masses(runs, polygons),
        mean_polygon_mass(runs),
        runs.len(),
    )
}

/// The mean polygon mass (kg) over `runs` (NaN for none): the mass unit of their pooled
/// histogram.
pub fn mean_polygon_mass(runs: &[&Beam2dRun]) -> f64 {
    runs.iter()
        .map(|r| r.model.state.mean_polygon_mass)
        .sum::<f64>()
        / runs.len() as f64
}

/// The masses (kg) of the fragments of at least `polygons` polygons of every run in `runs`,
/// pooled.
pub fn pooled_fragment_masses(runs: &[&Beam2dRun], polygons: usize) -> Vec<f64> {
    runs.iter()
        .flat_map(|r| r.model.fragment_masses_from(polygons))
        .collect()
}

/// β's 95% interval over the seeds of [`averaged_power_law`]: 2000 bootstrap resamples of the
/// runs, each fitted by the same rule (docs/validation.md, "How β is fitted").
pub fn averaged_power_law_interval(runs: &[&Beam2dRun]) -> Option<[f64; 2]> {
    bootstrap_interval(runs, 2000, 20, |draw| {
        averaged_power_law(&draw.iter().map(|r| **r).collect::<Vec<_>>()).map(|f| f.exponent)
    })
}
