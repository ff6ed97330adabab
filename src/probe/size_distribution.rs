//! Particle size distributions as sieve curves: the mass fraction finer than each size.
//!
//! A piece's size is its equivalent diameter, that of the sphere of the piece's own mass and
//! density, `(6 m / (π ρ_piece))^(1/3) = (6 V / π)^(1/3)`, and the curves weigh pieces by
//! mass, the measure that fracture conserves. The two differ from a conversion at the nominal
//! density: the halves of a split hold their parent's mass in 90% of its volume (their
//! density rises by 1/0.9 per split), so a piece of generation g is (0.9^g)^(1/3) the size the
//! nominal density would give its mass (0.965 after one split, 0.90 after three).

/// The equivalent diameter (m) of a piece of volume `volume` (m³): that of the sphere of its
/// own mass and density.
pub fn equivalent_diameter(volume: f64) -> f64 {
    (6.0 * volume / std::f64::consts::PI).cbrt()
}

/// Pieces of the given masses (kg) and volumes (m³) as (mass, equivalent diameter) pairs.
pub fn pieces(masses: &[f64], volumes: &[f64]) -> Vec<(f64, f64)> {
    masses
        .iter()
        .zip(volumes)
        .map(|(&m, &v)| (m, equivalent_diameter(v)))
        .collect()
}

/// `bins` sieve sizes spaced evenly in log between the smallest and largest of `diameters`.
pub fn sieve_sizes(diameters: impl Iterator<Item = f64>, bins: usize) -> Vec<f64> {
    let (lo, hi) = diameters.fold((f64::INFINITY, 0.0f64), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    if !(lo.is_finite() && hi > 0.0) {
        return Vec::new();
    }
    let (lo, hi) = (0.999 * lo, 1.001 * hi);
    (0..bins)
        .map(|k| lo * (hi / lo).powf(k as f64 / (bins - 1).max(1) as f64))
        .collect()
}

/// The mass fraction of pieces (masses, with their diameters) finer than or equal to each
/// sieve size.
pub fn passing(pieces: &[(f64, f64)], sieves: &[f64]) -> Vec<f64> {
    let total: f64 = pieces.iter().map(|p| p.0).sum();
    sieves
        .iter()
        .map(|&s| pieces.iter().filter(|p| p.1 <= s).map(|p| p.0).sum::<f64>() / total)
        .collect()
}

/// The mass-weighted median diameter (m): the size half the mass is finer than.
pub fn median_diameter(pieces: &[(f64, f64)]) -> f64 {
    let mut sorted: Vec<(f64, f64)> = pieces.to_vec();
    sorted.sort_by(|a, b| a.1.total_cmp(&b.1));
    let total: f64 = sorted.iter().map(|p| p.0).sum();
    let mut acc = 0.0;
    for (m, d) in &sorted {
        acc += m;
        if acc >= 0.5 * total {
            return *d;
        }
    }
    sorted.last().map_or(0.0, |p| p.1)
}

/// The modes of a size distribution: the diameters (m, geometric bin centres) where the mass
/// per log-diameter bin peaks. Bins are `ratio` wide (a diameter d falls in bin
/// `floor(ln d / ln ratio)`, so every curve of every run shares them); a bin is a mode when it
/// holds at least `floor` of the mass, more than the bin below and at least as much as the bin
/// above. Two modes is the bimodal distribution of crushed sand (granular paper
/// Fig. 30/31): grains that kept their size, and fragments.
pub fn modes(pieces: &[(f64, f64)], ratio: f64, floor: f64) -> Vec<f64> {
    let total: f64 = pieces.iter().map(|p| p.0).sum();
    if !(total > 0.0 && ratio > 1.0) {
        return Vec::new();
    }
    let width = ratio.ln();
    let mut mass = std::collections::BTreeMap::<i64, f64>::new();
    for &(m, d) in pieces {
        if d > 0.0 && d.is_finite() {
            *mass.entry((d.ln() / width).floor() as i64).or_default() += m / total;
        }
    }
    let at = |k: i64| mass.get(&k).copied().unwrap_or(0.0);
    mass.iter()
        .filter(|&(&k, &f)| f >= floor && f > at(k - 1) && f >= at(k + 1))
        .map(|(&k, _)| ((k as f64 + 0.5) * width).exp())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sieve_curve_of_two_sizes() {
        let rho = 2650.0;
        let d1: f64 = 0.6e-3;
        let v1 = std::f64::consts::PI / 6.0 * d1.powi(3);
        let m1 = v1 * rho;
        assert!((equivalent_diameter(v1) / d1 - 1.0).abs() < 1e-12);
        // A half of a split: half the mass in 0.45 of the volume, 0.45^(1/3) of the diameter.
        let half = pieces(&[m1 / 2.0], &[0.45 * v1]);
        assert!((half[0].1 / (0.45f64.cbrt() * d1) - 1.0).abs() < 1e-12);
        // One big grain and eight pieces of an eighth of its mass each: half the mass is fine.
        let mut pieces = vec![(m1, d1)];
        for _ in 0..8 {
            pieces.push((m1 / 8.0, d1 / 2.0));
        }
        let sieves = sieve_sizes(pieces.iter().map(|p| p.1), 5);
        assert_eq!(sieves.len(), 5);
        assert!(sieves[0] < d1 / 2.0 && sieves[4] > d1);
        let pass = passing(&pieces, &sieves);
        assert_eq!(pass[0], 0.0);
        assert!((pass[4] - 1.0).abs() < 1e-12);
        let pass = passing(&pieces, &[d1 / 2.0, 0.99 * d1, d1]);
        assert!((pass[0] - 0.5).abs() < 1e-12 && pass[1] == pass[0] && pass[2] == 1.0);
        assert!((median_diameter(&pieces) - d1 / 2.0).abs() < 1e-15);
    }

    #[test]
    fn modes_of_one_and_of_two_populations() {
        // Grains of 0.6 mm and fragments of 0.3 mm, a third of the mass: two modes, one in
        // each population's quarter-octave bin; the grains alone: one.
        let q = 2f64.powf(0.25);
        let mut pieces: Vec<(f64, f64)> =
            (0..20).map(|k| (2.0, 0.58e-3 + 1e-6 * k as f64)).collect();
        let grains = modes(&pieces, q, 0.03);
        assert_eq!(grains.len(), 1, "{grains:?}");
        pieces.extend((0..40).map(|k| (0.5, 0.29e-3 + 1e-6 * k as f64)));
        let both = modes(&pieces, q, 0.03);
        assert_eq!(both.len(), 2, "{both:?}");
        assert!((both[0] / 0.3e-3).ln().abs() < q.ln() && (both[1] / 0.6e-3).ln().abs() < q.ln());
        // Below the floor a bump is no mode: the fragments hold a third, the grains two.
        assert_eq!(modes(&pieces, q, 0.5).len(), 1);
        assert!(modes(&[], q, 0.03).is_empty());
    }
}
