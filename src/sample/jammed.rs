//! A jammed sample at a given solid fraction, carrying load before loading
//! (`sample.packing = "jammed"`): the friction-adjusted compaction.
//!
//! A sample compressed without friction is loose (at rest, carrying nothing) below the
//! frictionless jamming fraction; one compressed with the grains' friction jams where that
//! friction lets it, looser the more friction. Between the two, the friction the grains
//! have while they are compressed sets the fraction they jam at: DEM studies prepare samples
//! of a given density this way, by adjusting the interparticle friction during the isotropic
//! compression and restoring it for loading (Salot, Gotteland and Villard 2009, Granular
//! Matter 11, 221). Here:
//!
//! 1. the grains, placed loose, are compressed without friction to solid fraction
//!    [`LOOSE_FRACTION`] (below where any of them jam);
//! 2. from there, the box's faces compress them with a friction μ_p, waiting whenever the
//!    grains push back, until they jam: settled, at rest, still carrying
//!    [`JAM_PER_MODULUS`] of their modulus ([`compact_to_fraction`] with friction); μ_p is
//!    searched in [0, μ] (μ the grains' friction: halving until a try jams denser than
//!    asked, then interpolating in the bracket; after three halvings, no friction) until the jammed sample fills the fraction
//!    asked within [`FRACTION_TOLERANCE`] (8 tries at most; the closest is kept); each try
//!    starts from the same loose sample;
//! 3. loading starts from the chosen sample with the grains' own friction, its faces fixed
//!    where they jammed.
//!
//! No parameter depends on the fraction asked: the search finds μ_p. The fractions a
//! material reaches this way span its loosest jammed state (μ_p = μ) to its frictionless
//! jamming fraction (μ_p = 0); outside, the sample is refused naming the one it reached, and
//! so it is when the tries jam either side of the fraction asked but none within the
//! tolerance (jammed fractions scatter from try to try, and near no friction they change
//! steeply with it). The
//! searches compress with a hundredth of the grains' stiffness ([`SEARCH_STIFFNESS`]; a step
//! ten times as long): the jamming pressure is a fraction of the modulus, so the overlaps are
//! those of the true stiffness, and with it the jammed sample carries the same forces times
//! a hundred, in the same balance (Hertz forces at fixed overlaps scale with the modulus).

use super::compaction::{FractionSpec, compact_to_fraction};
use crate::error::Result;
use crate::state::{Bodies, Walls};

/// The stress at which a compressed sample counts as jammed, as a fraction of E/(1 − ν²):
/// the faces wait whenever the grains carry ten times this, and the grains are jammed when,
/// settled at rest, they still carry this. Hertz overlaps are then at most about 10⁻⁴ of a
/// grain's radius, so the fraction found is the jamming fraction to about 3·10⁻⁴. The sample
/// starts loading carrying what it settled with: for quartz between about 10 kPa and 0.1
/// MPa, a light seating of the specimen far below what loading brings (several MPa at 3%
/// strain for sand).
pub const JAM_PER_MODULUS: f64 = 1e-7;
/// The solid fraction of the loose sample every search starts from, whatever is asked: below
/// the loosest jammed packings of frictional grains (spheres of infinite friction jam near
/// 0.55), so the fraction a friction jams at does not depend on where it started.
pub const LOOSE_FRACTION: f64 = 0.45;
/// The sample lands within this of the solid fraction asked (0.01 of quartz: 26.5 kg/m³).
/// Where grains jam scatters from try to try by about as much: measured on the 3 mm Mason
/// cube, friction 0.264 jammed at 0.583 and 0.286 at 0.567 where the trend between 0.2 and
/// 0.4 says 0.006 apart, and near no friction in the 2 mm box 0.0084 at 0.659 and 0.0054 at
/// 0.656. At 0.003 the search had not found 0.574 there after seven tries (five minutes each).
pub const FRACTION_TOLERANCE: f64 = 0.01;
/// The grains' stiffness while μ_p is searched, as a fraction of theirs.
pub const SEARCH_STIFFNESS: f64 = 0.01;
/// Tries of μ_p at most.
const TRIES: usize = 8;

/// What to prepare, and the grains' material.
#[derive(Debug, Clone, Copy)]
pub struct JammedSpec {
    /// Young's modulus (Pa), Poisson's ratio, density (kg/m³) and friction of the grains.
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    pub friction: f64,
    /// Verlet skin (m) of the neighbour list; `None`: the default.
    pub skin: Option<f64>,
    /// The solid fraction asked for.
    pub fraction: f64,
}

/// The prepared sample.
#[derive(Debug, Clone, Copy)]
pub struct JammedReport {
    /// Steps of the frictionless compaction to the loose sample (the tries' are not counted).
    pub steps: u64,
    /// The friction the grains were compressed with, and how many were tried.
    pub friction: f64,
    pub tries: usize,
    /// The sample's solid fraction.
    pub fraction: f64,
}

/// Why the fraction asked cannot be prepared: the loosest fraction the grains jam at (with
/// their friction), or the densest the search reached (its friction near none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JammedShort {
    TooLoose {
        loosest: f64,
    },
    TooDense {
        densest: f64,
    },
    /// Every try jammed further than the tolerance from the fraction asked (tries that jam
    /// either side of it, none close enough): the closest, above and below.
    Missed {
        above: f64,
        below: f64,
    },
}

fn fraction_of(bodies: &Bodies, walls: &Walls) -> f64 {
    bodies.solid_volume() / walls.volume()
}

/// Prepares the bodies (placed loose in the box `walls`) as a jammed sample at
/// `spec.fraction`; see the module's description.
pub fn compact_jammed(
    bodies: &mut Bodies,
    walls: &mut Walls,
    spec: &JammedSpec,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<std::result::Result<JammedReport, JammedShort>> {
    let size = walls.box_size();
    let loose = LOOSE_FRACTION.min(spec.fraction);
    // The loose sample's box: the faces close in alike in all directions, or in a sleeve
    // along its axis only.
    let ratio = (fraction_of(bodies, walls) / loose).min(1.0);
    let loose_size = walls.resized(size, ratio);
    let soft = spec.young * SEARCH_STIFFNESS;
    let fill = FractionSpec {
        young: soft,
        poisson: spec.poisson,
        density: spec.density,
        skin: spec.skin,
        size: loose_size,
        friction: 0.0,
        pressures_per_modulus: FractionSpec::DEFAULT_PRESSURES,
        search: false,
    };
    let steps = match compact_to_fraction(bodies, walls, &fill, progress)? {
        Ok(r) => r.steps,
        // Jammed without friction below the loose fraction: denser than any friction allows.
        Err(j) => {
            return Ok(Err(JammedShort::TooDense { densest: j.reached }));
        }
    };
    let start = (bodies.clone(), walls.clone());
    // Each try compresses the loose sample with friction mu towards a box the grains could
    // never fill (solid fraction 0.9) and stops where they jam: at rest, carrying the jamming
    // pressure.
    let to_dense = fraction_of(bodies, walls) / 0.9;
    let dense = match walls.sleeve {
        Some(_) => walls.resized(loose_size, to_dense),
        // As the loose box was made (the same bits as before the sleeve existed).
        None => size * to_dense.cbrt() * ratio.cbrt(),
    };
    let attempt = |mu: f64| -> Result<(Bodies, Walls, f64, u64)> {
        let (mut b, mut w) = start.clone();
        let c = FractionSpec {
            size: dense,
            friction: mu,
            pressures_per_modulus: (10.0 * JAM_PER_MODULUS, JAM_PER_MODULUS),
            search: true,
            ..fill
        };
        let (phi, steps) = match compact_to_fraction(&mut b, &mut w, &c, &mut |_| {})? {
            Err(j) => (j.reached, j.steps),
            Ok(r) => (0.9, r.steps),
        };
        Ok((b, w, phi, steps))
    };
    // The bracket [lo, hi] of μ_p, with the fractions jammed at its ends where known: more
    // friction, looser.
    let (mut lo, mut hi) = ((0.0, None::<f64>), (spec.friction, 0.0));
    let loosest = attempt(hi.0)?;
    hi.1 = loosest.2;
    progress(&format!(
        "jammed with the grains' friction {} at solid fraction {:.4} ({} steps)",
        hi.0, loosest.2, loosest.3
    ));
    if loosest.2 > spec.fraction + FRACTION_TOLERANCE {
        return Ok(Err(JammedShort::TooLoose { loosest: loosest.2 }));
    }
    let mut best = (hi.0, loosest);
    let mut tries = 1;
    while (best.1.2 - spec.fraction).abs() > FRACTION_TOLERANCE && tries < TRIES {
        // Halve the bracket until its dense end is known, then interpolate in it (kept a
        // quarter away from either end, as jammed fractions scatter from try to try).
        let mu = match lo.1 {
            // After three halvings without a denser try, no friction at all: if the grains
            // jam looser than asked even then, nothing between helps.
            None if hi.0 <= spec.friction / 8.0 => 0.0,
            None => 0.5 * (lo.0 + hi.0),
            Some(phi_lo) => {
                let t = ((phi_lo - spec.fraction) / (phi_lo - hi.1)).clamp(0.25, 0.75);
                lo.0 + t * (hi.0 - lo.0)
            }
        };
        let here = attempt(mu)?;
        tries += 1;
        progress(&format!(
            "jammed with friction {mu:.4} at solid fraction {:.4} (asked {:.4}; {} steps)",
            here.2, spec.fraction, here.3
        ));
        if here.2 > spec.fraction {
            lo = (mu, Some(here.2));
        } else {
            hi = (mu, here.2);
        }
        let loose_without_friction = mu == 0.0 && here.2 < spec.fraction;
        if (here.2 - spec.fraction).abs() < (best.1.2 - spec.fraction).abs() {
            best = (mu, here);
        }
        if loose_without_friction {
            break;
        }
    }
    if (best.1.2 - spec.fraction).abs() > FRACTION_TOLERANCE {
        return Ok(Err(match lo.1 {
            // Tries jammed either side of the fraction, none within the tolerance: refused
            // rather than prepared at another density than asked.
            Some(above) => JammedShort::Missed { above, below: hi.1 },
            // Every try, the last without friction, jammed looser than asked.
            None => JammedShort::TooDense { densest: best.1.2 },
        }));
    }
    let (mu, (b, w, phi, _)) = best;
    *bodies = b;
    *walls = w;
    Ok(Ok(JammedReport {
        steps,
        friction: mu,
        tries,
        fraction: phi,
    }))
}
