//! Fragments: connected components of bodies over the links that still hold them together
//! (intact beams in `beam2d`, intact cohesive springs between sub-particles in `granular`).

/// Disjoint sets with path halving and union by size.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> Self {
        assert!(n <= u32::MAX as usize, "at most 2^32 - 1 elements");
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    pub fn len(&self) -> usize {
        self.parent.len()
    }

    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// The representative of `i`'s set.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] as usize != i {
            let grand = self.parent[self.parent[i] as usize];
            self.parent[i] = grand;
            i = grand as usize;
        }
        i
    }

    /// Joins the sets of `a` and `b`; false when they were one set already.
    pub fn union(&mut self, a: usize, b: usize) -> bool {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        if self.size[ra] < self.size[rb] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb] = ra as u32;
        self.size[ra] += self.size[rb];
        true
    }

    /// A component label per element, numbered 0, 1, ... in the order of each component's
    /// lowest element (deterministic whatever the order of the unions), and the number of
    /// components.
    pub fn labels(&mut self) -> (Vec<u32>, usize) {
        let n = self.len();
        let mut label_of_root = vec![u32::MAX; n];
        let mut labels = vec![0; n];
        let mut count = 0;
        for (i, label) in labels.iter_mut().enumerate() {
            let r = self.find(i);
            if label_of_root[r] == u32::MAX {
                label_of_root[r] = count as u32;
                count += 1;
            }
            *label = label_of_root[r];
        }
        (labels, count)
    }
}

/// The components of `n` bodies joined by `links`: a label per body (see
/// [`UnionFind::labels`]) and the number of components.
pub fn components(n: usize, links: impl IntoIterator<Item = (usize, usize)>) -> (Vec<u32>, usize) {
    let mut uf = UnionFind::new(n);
    for (a, b) in links {
        uf.union(a, b);
    }
    uf.labels()
}

/// The total of `values` (masses, volumes) per component, in label order.
pub fn sum_by_component(labels: &[u32], count: usize, values: &[f64]) -> Vec<f64> {
    let mut sums = vec![0.0; count];
    for (&l, &v) in labels.iter().zip(values) {
        sums[l as usize] += v;
    }
    sums
}

/// One logarithmic bin of fragment masses.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MassBin {
    /// Bin edges (kg).
    pub lo: f64,
    pub hi: f64,
    /// Fragments in the bin (over all runs pooled).
    pub count: usize,
    /// F(m): fragments per unit mass per run (1/kg).
    pub density: f64,
}

impl MassBin {
    /// The bin's geometric centre (kg).
    pub fn centre(&self) -> f64 {
        (self.lo * self.hi).sqrt()
    }
}

/// A histogram of fragment masses in logarithmic bins: edges at `unit × 10^(k / per_decade)`.
pub fn mass_histogram(masses: &[f64], unit: f64, per_decade: u32, runs: usize) -> Vec<MassBin> {
    let per = per_decade as f64;
    let index = |m: f64| (per * (m / unit).log10()).floor() as i64;
    let (Some(first), Some(last)) = (
        masses.iter().map(|&m| index(m)).min(),
        masses.iter().map(|&m| index(m)).max(),
    ) else {
        return Vec::new();
    };
    let edge = |k: i64| unit * 10f64.powf(k as f64 / per);
    let mut bins: Vec<MassBin> = (first..=last)
        .map(|k| MassBin {
            lo: edge(k),
            hi: edge(k + 1),
            count: 0,
            density: 0.0,
        })
        .collect();
    for &m in masses {
        bins[(index(m) - first) as usize].count += 1;
    }
    for b in &mut bins {
        b.density = b.count as f64 / ((b.hi - b.lo) * runs.max(1) as f64);
    }
    bins
}

/// A power law F(m) ~ m^(−β) fitted to a histogram.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PowerLawFit {
    /// The exponent β.
    pub exponent: f64,
    /// The mass range (kg) whose bin centres were fitted.
    pub range: [f64; 2],
    /// Bins with fragments in the range, and the R² of the fit of ln F against ln m.
    pub bins: usize,
    pub r_squared: f64,
}

/// The least-squares fit of ln F(m) against ln m over the non-empty bins whose centres lie in
/// `[lo, hi]` (kg); none with fewer than three such bins.
pub fn fit_power_law(bins: &[MassBin], lo: f64, hi: f64) -> Option<PowerLawFit> {
    let pts: Vec<(f64, f64)> = bins
        .iter()
        .filter(|b| b.count > 0 && b.centre() >= lo && b.centre() <= hi)
        .map(|b| (b.centre().ln(), b.density.ln()))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let slope = crate::probe::fit::least_squares_slope(&pts);
    Some(PowerLawFit {
        exponent: -slope,
        range: [lo, hi],
        bins: pts.len(),
        r_squared: crate::probe::fit::r_squared(&pts, slope),
    })
}

/// The fit of the pre-stated rule (docs/validation.md, "How β is fitted"): from the
/// first bin whose centre is at least `lo` (kg) up to, not including, the first bin after it
/// holding fewer than `min_per_run × runs` fragments; none with fewer than three bins.
pub fn fit_power_law_counted(
    bins: &[MassBin],
    lo: f64,
    min_per_run: f64,
    runs: usize,
) -> Option<PowerLawFit> {
    let least = min_per_run * runs.max(1) as f64;
    let used: Vec<&MassBin> = bins
        .iter()
        .skip_while(|b| b.centre() < lo)
        .take_while(|b| b.count as f64 >= least)
        .collect();
    let (first, last) = (used.first()?, used.last()?);
    let fit = fit_power_law(&bins_of(&used), first.centre(), last.centre())?;
    Some(PowerLawFit {
        range: [first.lo, last.hi],
        ..fit
    })
}

fn bins_of(used: &[&MassBin]) -> Vec<MassBin> {
    used.iter().map(|b| **b).collect()
}

/// A 95% interval of a statistic of several runs by the bootstrap: `resamples` draws of
/// `runs.len()` runs with replacement (a fixed-seed ChaCha stream, so the interval is
/// reproducible), the statistic of each draw, and its 2.5 and 97.5 percentiles over the draws
/// that gave one. None when fewer than half did.
pub fn bootstrap_interval<T>(
    runs: &[T],
    resamples: usize,
    seed: u64,
    statistic: impl Fn(&[&T]) -> Option<f64>,
) -> Option<[f64; 2]> {
    use rand::{RngExt, SeedableRng};
    if runs.is_empty() {
        return None;
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut values: Vec<f64> = (0..resamples)
        .filter_map(|_| {
            let draw: Vec<&T> = (0..runs.len())
                .map(|_| &runs[rng.random_range(0..runs.len())])
                .collect();
            statistic(&draw).filter(|v| v.is_finite())
        })
        .collect();
    if values.len() * 2 < resamples.max(1) {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((q * (values.len() - 1) as f64).round()) as usize];
    Some([at(0.025), at(0.975)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_law_masses_give_their_exponent_back() {
        // Masses m_k = (1 - u_k)^(-1/(β-1)) on a regular grid of u follow F(m) ~ m^-β exactly
        // in the mean; β = 2.
        let n = 200_000;
        let masses: Vec<f64> = (0..n)
            .map(|k| 1.0 / (1.0 - (k as f64 + 0.5) / n as f64))
            .collect();
        let bins = mass_histogram(&masses, 1.0, 5, 1);
        assert_eq!(bins.iter().map(|b| b.count).sum::<usize>(), n);
        let fit = fit_power_law(&bins, 2.0, 500.0).unwrap();
        assert!((fit.exponent - 2.0).abs() < 0.02, "{fit:?}");
        assert!(fit.r_squared > 0.999);
        // Two runs pooled give the same exponent and half the density per run.
        let twice: Vec<f64> = masses.iter().chain(&masses).copied().collect();
        let bins2 = mass_histogram(&twice, 1.0, 5, 2);
        assert!((bins2[3].density - bins[3].density).abs() < 1e-12 * bins[3].density);
        assert!(fit_power_law(&bins, 2.0, 2.5).is_none());
    }

    #[test]
    fn the_counted_fit_stops_where_the_bins_thin_out() {
        // 50 runs of the same exact β = 2 sample (m from 2 to 2000): the per-run count per
        // quarter decade falls by 10^0.25 a bin, so with at least 5 per run the fit ends
        // where the pooled count first drops under 250.
        let n = 2000;
        let one: Vec<f64> = (0..n)
            .map(|k| 2.0 / (1.0 - 0.999 * (k as f64 + 0.5) / n as f64))
            .collect();
        let runs = 50;
        let pooled: Vec<f64> = (0..runs).flat_map(|_| one.iter().copied()).collect();
        let bins = mass_histogram(&pooled, 1.0, 4, runs);
        let fit = fit_power_law_counted(&bins, 2.0, 5.0, runs).unwrap();
        let first = bins.iter().position(|b| b.centre() >= 2.0).unwrap();
        let after = bins[first..]
            .iter()
            .position(|b| (b.count as f64) < 5.0 * runs as f64)
            .unwrap();
        assert_eq!(fit.bins, after);
        assert_eq!(fit.range, [bins[first].lo, bins[first + after - 1].hi]);
        assert!(bins[first + after - 1].count >= 250 && bins[first + after].count < 250);
        // The first bin is cut by the sample's lower end (2 in [1.78, 3.16)); β near 2 anyway.
        assert!((fit.exponent - 2.0).abs() < 0.15, "{fit:?}");
        // Fewer than three bins with enough fragments: no fit.
        assert!(fit_power_law_counted(&bins, 2.0, 500.0, runs).is_none());
    }

    #[test]
    fn bootstrap_interval_brackets_the_mean_and_repeats() {
        let runs: Vec<f64> = (0..20).map(|k| k as f64).collect();
        let mean = |d: &[&f64]| Some(d.iter().copied().sum::<f64>() / d.len() as f64);
        let a = bootstrap_interval(&runs, 2000, 7, mean).unwrap();
        assert_eq!(a, bootstrap_interval(&runs, 2000, 7, mean).unwrap());
        // The mean of 20 values 0..19 (sd 5.92): its standard error 1.32, 95% about ±2.6.
        assert!(a[0] < 9.5 && a[1] > 9.5, "{a:?}");
        assert!(
            (a[1] - a[0] - 2.0 * 1.96 * 5.77 / 20f64.sqrt()).abs() < 0.6,
            "{a:?}"
        );
        assert!(bootstrap_interval(&runs, 100, 1, |_| None).is_none());
    }

    #[test]
    fn chains_and_singletons() {
        // 0-1-2 and 4-5, with 3 and 6 alone.
        let (labels, count) = components(7, [(1, 2), (5, 4), (0, 1)]);
        assert_eq!(count, 4);
        assert_eq!(labels, vec![0, 0, 0, 1, 2, 2, 3]);
        let masses = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        assert_eq!(
            sum_by_component(&labels, count, &masses),
            vec![6.0, 4.0, 11.0, 7.0]
        );
    }

    #[test]
    fn union_reports_whether_it_joined() {
        let mut uf = UnionFind::new(3);
        assert!(uf.union(0, 2));
        assert!(!uf.union(2, 0));
        assert_eq!(uf.find(0), uf.find(2));
        assert_ne!(uf.find(1), uf.find(0));
    }
}
