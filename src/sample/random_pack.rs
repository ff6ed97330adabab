//! Geometric random packing by growth and collective rearrangement.
//!
//! Centres start uniformly at random in the box with every radius scaled down to a dilute
//! solid fraction. The radii then grow by small factors (1%, halved whenever the relaxation
//! does not converge, down to 1e-5); after each growth, overlapping pairs
//! (and spheres crossing a wall) are pushed apart along their line of centres, Gauss–Seidel
//! fashion, until no overlap larger than a tolerance is left (the "collective rearrangement"
//! of He, Ekere & Cai 1999 and Jodrey & Tory 1985). At full size the relaxation runs to a
//! strict tolerance, so the packing starts the simulation with no overlap that could blow it
//! up. The procedure is serial and deterministic.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::contact::neighbor::CellGrid;
use crate::state::Vec3;

#[derive(Debug, Clone, Copy)]
pub struct PackReport {
    /// Relaxation sweeps over all pairs.
    pub sweeps: usize,
    /// Largest overlap left, as a fraction of the smaller radius of the pair.
    pub max_overlap: f64,
}

/// Tolerance of the relaxation during growth and at the end (overlap / smaller radius).
const GROWTH_TOLERANCE: f64 = 1e-3;
const FINAL_TOLERANCE: f64 = 1e-10;
/// Radii grow by this factor per stage, less when the packing gets crowded.
const GROWTH_FACTOR: f64 = 1.01;
/// Smallest growth step tried before the packing is declared jammed.
const MIN_GROWTH: f64 = 1e-5;
const SWEEPS_PER_STAGE: usize = 2_000;
const MAX_FINAL_SWEEPS: usize = 20_000;

/// Why [`pack_geometric`] failed: the spheres jammed before they reached their full radii.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jammed {
    /// Solid fraction of the spheres at their full radii in the box.
    pub target: f64,
    /// About where they jammed.
    pub reached: f64,
}

/// Places spheres of `radii` in the box [lo, hi] without overlaps.
pub fn pack_geometric(
    radii: &[f64],
    lo: Vec3,
    hi: Vec3,
    rng: &mut ChaCha8Rng,
) -> Result<(Vec<Vec3>, PackReport), Jammed> {
    pack(
        radii,
        Domain {
            lo,
            hi,
            sleeve: false,
        },
        rng,
    )
}

/// Places spheres of `radii` without overlaps in the sleeve inscribed in the box [lo, hi]
/// (a cylinder along z whose diameter is the box's x edge, equal to its y edge).
pub fn pack_geometric_in_sleeve(
    radii: &[f64],
    lo: Vec3,
    hi: Vec3,
    rng: &mut ChaCha8Rng,
) -> Result<(Vec<Vec3>, PackReport), Jammed> {
    pack(
        radii,
        Domain {
            lo,
            hi,
            sleeve: true,
        },
        rng,
    )
}

/// Where the spheres go: the box [lo, hi], and with `sleeve` only its inscribed cylinder
/// along z.
#[derive(Debug, Clone, Copy)]
struct Domain {
    lo: Vec3,
    hi: Vec3,
    sleeve: bool,
}

impl Domain {
    fn centre(&self) -> Vec3 {
        0.5 * (self.lo + self.hi)
    }

    fn radius(&self) -> f64 {
        0.5 * (self.hi.x - self.lo.x)
    }

    /// How far a sphere of radius `r` at `p` reaches through the sleeve (m; <= 0: inside),
    /// and the unit radial direction at `p`.
    fn sleeve_excess(&self, p: &Vec3, r: f64) -> (f64, Vec3) {
        let d = crate::state::radial(&self.centre(), p);
        let rho = d.norm();
        let e = if rho > 0.0 { d / rho } else { Vec3::x() };
        (rho + r - self.radius(), e)
    }
}

fn pack(
    radii: &[f64],
    domain: Domain,
    rng: &mut ChaCha8Rng,
) -> Result<(Vec<Vec3>, PackReport), Jammed> {
    let Domain { lo, hi, .. } = domain;
    let size = hi - lo;
    let mut pos: Vec<Vec3> = radii
        .iter()
        .map(|&r| {
            loop {
                let u = Vec3::new(rng.random(), rng.random(), rng.random());
                let p = lo + Vec3::repeat(r) + (size - Vec3::repeat(2.0 * r)).component_mul(&u);
                // In a sleeve, drawn again until inside it (at most 1 - π/4 of the draws miss).
                if !domain.sleeve || domain.sleeve_excess(&p, r).0 <= 0.0 {
                    break p;
                }
            }
        })
        .collect();
    let solid: f64 = radii.iter().map(|&r| crate::shape::sphere_volume(r)).sum();
    let volume = size.x * size.y * size.z;
    let phi = solid
        / if domain.sleeve {
            0.25 * std::f64::consts::PI * volume
        } else {
            volume
        };
    let mut scale = (0.2 / phi).cbrt().min(1.0);
    let mut settled = scale;
    let mut growth = GROWTH_FACTOR;
    let mut sweeps = 0;
    loop {
        let last = scale >= 1.0;
        let (tol, budget) = if last {
            (FINAL_TOLERANCE, MAX_FINAL_SWEEPS)
        } else {
            (GROWTH_TOLERANCE, SWEEPS_PER_STAGE)
        };
        let mut converged = false;
        for _ in 0..budget {
            sweeps += 1;
            if relax_sweep(&mut pos, radii, scale, &domain) < tol {
                converged = true;
                break;
            }
        }
        if converged && last {
            let left = overlap_left(&pos, radii, &domain);
            if left < tol {
                return Ok((
                    pos,
                    PackReport {
                        sweeps,
                        max_overlap: left,
                    },
                ));
            }
            converged = false;
        }
        if converged {
            settled = scale;
        } else {
            // Too big a step for the crowding reached: go back and grow more gently.
            growth = 1.0 + 0.5 * (growth - 1.0);
            if growth - 1.0 < MIN_GROWTH {
                return Err(Jammed {
                    target: phi,
                    reached: phi * settled.powi(3),
                });
            }
        }
        scale = (settled * growth).min(1.0);
    }
}

/// One Gauss–Seidel sweep pushing apart overlapping pairs of spheres with radii
/// `scale * radii`; returns the largest overlap met, relative to the smaller radius.
fn relax_sweep(pos: &mut [Vec3], radii: &[f64], scale: f64, domain: &Domain) -> f64 {
    let Domain { lo, hi, .. } = *domain;
    let rmax = radii.iter().copied().fold(0.0, f64::max) * scale;
    let grid = CellGrid::new(pos, 2.0 * rmax);
    let mut worst = 0.0_f64;
    // One neighbour buffer for the whole sweep (it was allocated, and often regrown, per body).
    let mut near = Vec::with_capacity(64);
    for i in 0..pos.len() {
        let ri = radii[i] * scale;
        near.clear();
        grid.for_each_near(&pos[i], |j| {
            if j != i {
                near.push(j)
            }
        });
        for &j in &near {
            let rj = radii[j] * scale;
            let d = pos[i] - pos[j];
            let reach = ri + rj;
            let d2 = d.norm_squared();
            if d2 >= reach * reach {
                continue;
            }
            let dist = d2.sqrt();
            let n = if dist > 0.0 {
                d / dist
            } else {
                // Coincident centres: separate along an index-dependent axis.
                [Vec3::x(), Vec3::y(), Vec3::z()][(i + j) % 3]
            };
            let overlap = reach - dist;
            worst = worst.max(overlap / ri.min(rj));
            // Larger spheres move less (weights by volume).
            let (vi, vj) = (ri * ri * ri, rj * rj * rj);
            let wi = vj / (vi + vj);
            pos[i] += n * (overlap * wi);
            pos[j] -= n * (overlap * (1.0 - wi));
        }
        for a in 0..3 {
            let below = lo[a] + ri - pos[i][a];
            if below > 0.0 {
                worst = worst.max(below / ri);
                pos[i][a] += below;
            }
            let above = pos[i][a] + ri - hi[a];
            if above > 0.0 {
                worst = worst.max(above / ri);
                pos[i][a] -= above;
            }
        }
        if domain.sleeve {
            let (excess, e) = domain.sleeve_excess(&pos[i], ri);
            if excess > 0.0 {
                worst = worst.max(excess / ri);
                pos[i] -= e * excess;
            }
        }
    }
    worst
}

/// [`max_overlap`] in `domain`, the sleeve included.
fn overlap_left(pos: &[Vec3], radii: &[f64], domain: &Domain) -> f64 {
    let worst = max_overlap(pos, radii, domain.lo, domain.hi);
    if !domain.sleeve {
        return worst;
    }
    pos.iter()
        .zip(radii)
        .map(|(p, &r)| domain.sleeve_excess(p, r).0 / r)
        .fold(worst, f64::max)
}

/// Largest overlap (relative to the smaller radius) between spheres or with the box.
pub fn max_overlap(pos: &[Vec3], radii: &[f64], lo: Vec3, hi: Vec3) -> f64 {
    let rmax = radii.iter().copied().fold(0.0, f64::max);
    let grid = CellGrid::new(pos, 2.0 * rmax);
    let mut worst = 0.0_f64;
    for i in 0..pos.len() {
        grid.for_each_near(&pos[i], |j| {
            if j > i {
                let overlap = radii[i] + radii[j] - (pos[i] - pos[j]).norm();
                if overlap > 0.0 {
                    worst = worst.max(overlap / radii[i].min(radii[j]));
                }
            }
        });
        for a in 0..3 {
            worst = worst.max((lo[a] + radii[i] - pos[i][a]) / radii[i]);
            worst = worst.max((pos[i][a] + radii[i] - hi[a]) / radii[i]);
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn packs_polydisperse_spheres_to_055_without_overlap() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let radii: Vec<f64> = (0..300).map(|_| 0.8 + 0.4 * rng.random::<f64>()).collect();
        let solid: f64 = radii.iter().map(|&r| crate::shape::sphere_volume(r)).sum();
        let edge = (solid / 0.55).cbrt();
        let hi = Vec3::repeat(edge);
        let (pos, report) = pack_geometric(&radii, Vec3::zeros(), hi, &mut rng).unwrap();
        assert!(report.max_overlap < FINAL_TOLERANCE);
        assert!(max_overlap(&pos, &radii, Vec3::zeros(), hi) < FINAL_TOLERANCE);
    }
}
