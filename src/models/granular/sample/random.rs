//! Random samples: radii drawn to the amount asked, placed loose and compacted in the box.

use super::*;

/// A random sample packed by compaction (`packing = "compaction"`): grains drawn (spheres
/// from the radius distribution, or ellipsoids from `grain_file`'s semi-axes, uniformly with
/// replacement) until they fill `solid_fraction` of `box`; their bounding spheres packed
/// without overlap at solid fraction 0.4 in a box of the same shape, enlarged; turned at
/// random (or aligned); then compressed without friction to `box` by
/// [`compact_to_fraction`]. One sentence if they jam first.
pub(super) fn compacted_sample(
    scene: &Scene,
    cfg: &GranularScene,
    s: &RandomSample,
    orient: &mut ChaCha8Rng,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Bodies, Walls, u64)> {
    let size = Vec3::from(s.box_size);
    // The container: the box, or the sleeve inscribed in it.
    let container = container(cfg, size);
    let box_volume = container.volume_of(size);
    // Each grain as semi-axes (a, b, c); spheres have a = b = c.
    let mut grains: Vec<[f64; 3]> = match &s.shape {
        RandomShape::Ellipsoids { grain_file, .. } => {
            let mut rng = stream(scene.seed, STREAM_RADII);
            let pool = read_grains(scene, "sample.grain_file", grain_file)?;
            let mean = pool.iter().map(|g| volume(&g.semi)).sum::<f64>() / pool.len() as f64;
            if let Amount::SolidFraction(phi) = s.amount {
                check_bodies(
                    scene,
                    "sample.box",
                    phi * box_volume / mean,
                    "grains at that solid fraction",
                )?;
            }
            let mut out = Vec::new();
            let mut v = 0.0;
            loop {
                let enough = match s.amount {
                    Amount::Count(n) | Amount::Both { count: n, .. } => out.len() >= n,
                    Amount::SolidFraction(phi) => v >= phi * box_volume,
                };
                if enough {
                    break out;
                }
                let g = pool[rng.random_range(0..pool.len())].semi;
                v += volume(&g);
                out.push(g);
            }
        }
        RandomShape::Spheres { radii, .. } | RandomShape::PolyEllipsoids { radii, .. } => {
            let radii = draw_radii(scene, radii, s.amount, box_volume);
            radii.into_iter().map(|r| [r; 3]).collect()
        }
    };
    let mut solid: f64 = grains.iter().map(volume).sum();
    if let Amount::SolidFraction(phi) = s.amount {
        // Grains are drawn until they fill the fraction, so the last one overshoots it by up to
        // its own volume (in a 1.2 mm box of Mason sand up to 0.04): it is kept only if that
        // lands closer to the fraction than leaving it out, and whole grains that cannot come
        // within the preparations' tolerance of it are refused (the box is too small for them).
        if grains.len() > 1 {
            let without = solid - volume(grains.last().expect("more than one grain"));
            if (without - phi * box_volume).abs() < (solid - phi * box_volume).abs() {
                grains.pop();
                // Summed again, not `without`: the same bits as a sum of the grains kept.
                solid = grains.iter().map(volume).sum();
            }
        }
        let drawn = solid / box_volume;
        let tolerance = crate::sample::FRACTION_TOLERANCE;
        if (drawn - phi).abs() > tolerance {
            return Err(scene.key_error(
                "sample.solid_fraction",
                format!(
                    "= {phi}: the whole grains drawn for it fill {drawn:.4} of sample.box, not \
                     within {tolerance} of it (one grain is too large a share of so small a box); \
                     enlarge sample.box"
                ),
            ));
        }
    }
    // With both a count and a fraction the box keeps its shape, scaled to the fraction.
    let target = match s.amount {
        Amount::Both { solid_fraction, .. } => size * (solid / solid_fraction / box_volume).cbrt(),
        _ => size,
    };
    let target_volume = container.volume_of(target);
    let bounding: Vec<f64> = grains.iter().map(|g| g[0].max(g[1]).max(g[2])).collect();
    let rmax = bounding.iter().copied().fold(0.0, f64::max);
    too_few_for_the_box(scene, s.amount, target, rmax)?;
    if (0..3).any(|a| target[a] <= 2.0 * rmax) {
        return Err(scene.key_error(
            "sample.box",
            format!(
                "is too small for the largest grain (semi-axis {rmax:e} m): each edge must exceed its length"
            ),
        ));
    }
    sleeve_fits(scene, &container, rmax)?;
    let spheres: f64 = bounding.iter().map(|&r| sphere_volume(r)).sum();
    let start = match container.sleeve {
        // In a sleeve the loose grains stand taller, not wider.
        Some(_) => container.resized(target, (spheres / START_FRACTION / target_volume).max(1.0)),
        None => {
            target
                * (spheres / START_FRACTION / (target.x * target.y * target.z))
                    .cbrt()
                    .max(1.0)
        }
    };
    progress(&format!(
        "placing {} grains (their bounding spheres at solid fraction {START_FRACTION}) before compaction",
        grains.len()
    ));
    let mut prng = stream(scene.seed, STREAM_POSITIONS);
    let pack = if container.sleeve.is_some() {
        pack_geometric_in_sleeve
    } else {
        pack_geometric
    };
    let (pos, _) = pack(&bounding, Vec3::zeros(), start, &mut prng).map_err(|j| {
        scene.key_error(
            "sample.box",
            format!(
                "could not place the grains before compaction: their bounding spheres jammed at {:.3}",
                j.reached
            ),
        )
    })?;
    let random = s.orientations == Orientations::Random;
    let rho = cfg.material.density;
    let mut b = Bodies::default();
    for (p, g) in pos.into_iter().zip(&grains) {
        let q = if random {
            random_orientation(orient)
        } else {
            UnitQuaternion::identity()
        };
        if g[0] == g[1] && g[1] == g[2] {
            b.push_sphere(p, g[0], rho, q);
        } else {
            let pe = ellipsoid(*g).map_err(|m| scene.key_error("sample.grain_file", m))?;
            b.push_poly_ellipsoid(pe, rho * pe.volume(), p, q);
        }
    }
    let order = b.spatial_order(2.0 * rmax);
    b.reorder(&order);
    let mut walls = Walls::new_box(Vec3::zeros(), start);
    if container.sleeve.is_some() {
        walls.add_sleeve();
    }
    let m = &cfg.material;
    if s.packing() == Packing::Jammed {
        let spec = JammedSpec {
            young: m.young,
            poisson: m.poisson,
            density: m.density,
            friction: m.friction,
            skin: cfg.neighbor.skin,
            fraction: solid / target_volume,
        };
        let report = compact_jammed(&mut b, &mut walls, &spec, progress)?.map_err(|short| {
            let why = match short {
                JammedShort::TooLoose { loosest } => format!(
                    "with their friction {} the grains jam at {loosest:.3} already",
                    spec.friction
                ),
                JammedShort::TooDense { densest } => {
                    format!("without friction the grains jam at {densest:.3}")
                }
                JammedShort::Missed { above, below } => format!(
                    "their tries jammed at {above:.3} and {below:.3} but none within {} of it (near no friction the fraction jammed at changes steeply); ask for one of those, or use more grains",
                    crate::sample::FRACTION_TOLERANCE
                ),
            };
            let asked = asked_fraction(s.amount, spec.fraction);
            scene.key_error(
                "sample.solid_fraction",
                format!("{asked} is beyond what jammed compaction of these grains reaches: {why}"),
            )
        })?;
        progress(&format!(
            "jammed at solid fraction {:.4} (friction {:.4} while compacted, {} tries)",
            report.fraction, report.friction, report.tries
        ));
        return Ok((b, walls, report.steps));
    }
    let spec = FractionSpec {
        young: m.young,
        poisson: m.poisson,
        density: m.density,
        skin: cfg.neighbor.skin,
        size: target,
        friction: 0.0,
        pressures_per_modulus: FractionSpec::DEFAULT_PRESSURES,
        search: false,
    };
    let report = compact_to_fraction(&mut b, &mut walls, &spec, progress)?.map_err(|j| {
        let at = if j.reached < j.target - 5e-4 {
            format!("they jammed at about {:.3}", j.reached)
        } else {
            format!(
                "there they are jammed (at rest, they still carry {:.2e} Pa)",
                j.stress
            )
        };
        scene.key_error(
            "sample.solid_fraction",
            format!(
                "{} is beyond what frictionless compaction of these grains reaches: {at}; ask for less, or use more grains (the loose layer along the walls lowers what small boxes reach)",
                asked_fraction(s.amount, j.target)
            ),
        )
    })?;
    progress(&format!(
        "compacted in {} steps: solid fraction {:.4}, face stresses {:.3e} {:.3e} {:.3e} Pa",
        report.steps,
        b.solid_volume() / target_volume,
        report.stresses[0],
        report.stresses[1],
        report.stresses[2]
    ));
    Ok((b, walls, report.steps))
}

/// With both a count and a fraction the box is scaled to hold `count` grains at the fraction:
/// when its shortest edge is not longer than the largest grain (of bounding radius `rmax`),
/// the count is at fault, not the box the user gave (`sample.count = 1` was refused as
/// "sample.box is too small"). `size` is the scaled box.
pub(super) fn too_few_for_the_box(
    scene: &Scene,
    amount: Amount,
    size: Vec3,
    rmax: f64,
) -> Result<()> {
    let Amount::Both {
        count,
        solid_fraction,
    } = amount
    else {
        return Ok(());
    };
    let edge = (0..3).map(|a| size[a]).fold(f64::INFINITY, f64::min);
    if edge > 2.0 * rmax {
        return Ok(());
    }
    let needed = (count as f64 * (2.0 * rmax / edge).powi(3)).ceil() + 1.0;
    Err(scene.key_error(
        "sample.count",
        format!(
            "= {count} grains at sample.solid_fraction = {solid_fraction} fill a box (sample.box's \
             shape, scaled to them) whose shortest edge, {edge:.3e} m, is not longer than the \
             largest grain ({:.3e} m across); allowed: sample.count >= about {needed} at \
             this fraction (the box grows as the cube root of the count)",
            2.0 * rmax
        ),
    ))
}

/// The solid fraction a refused preparation was asked for, as its sentence names it: the
/// scene's `sample.solid_fraction` beside what the grains drawn for it fill (`drawn`), or the
/// latter alone when the scene gives a count.
pub(super) fn asked_fraction(amount: Amount, drawn: f64) -> String {
    match amount {
        Amount::SolidFraction(phi)
        | Amount::Both {
            solid_fraction: phi,
            ..
        } => {
            format!("= {phi} ({drawn:.3} with the grains drawn)")
        }
        Amount::Count(_) => format!("= {drawn:.3}"),
    }
}

/// Solid fraction of the grains' bounding spheres when they are placed for compaction.
pub(super) const START_FRACTION: f64 = 0.4;

/// The radii of a random sample of spheres, from the scene's seed: `count` of them, or as many
/// as fill `solid_fraction` of a box of `box_volume` (m³).
pub(super) fn draw_radii(scene: &Scene, dist: &Radii, amount: Amount, box_volume: f64) -> Vec<f64> {
    let Radii { mean, sd, min, max } = *dist;
    let mut rng = stream(scene.seed, STREAM_RADII);
    match amount {
        Amount::Count(n) | Amount::Both { count: n, .. } => {
            truncated_normal_radii(&mut rng, mean, sd, min, max, |k, _| k < n)
        }
        Amount::SolidFraction(phi) => {
            truncated_normal_radii(&mut rng, mean, sd, min, max, |_, v| v < phi * box_volume)
        }
    }
}

/// A random sample packed by growth without overlap (`packing = "geometric"`), of spheres
/// drawn from `dist`.
pub(super) fn random_sample(
    scene: &Scene,
    cfg: &GranularScene,
    s: &RandomSample,
    dist: &Radii,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Bodies, Walls)> {
    let mut size = Vec3::from(s.box_size);
    let container = container(cfg, size);
    let box_volume = container.volume_of(size);
    let radii = draw_radii(scene, dist, s.amount, box_volume);
    let solid: f64 = radii.iter().map(|&r| sphere_volume(r)).sum();
    if let Amount::Both { solid_fraction, .. } = s.amount {
        // Both a count and a fraction: keep the box's shape, scale it to the fraction.
        size *= (solid / solid_fraction / box_volume).cbrt();
    }
    let phi = solid / container.volume_of(size);
    if phi > 0.65 {
        return Err(scene.key_error(
            "sample.count",
            format!(
                "gives a solid fraction of {phi:.3} in the box, above the 0.65 a random packing can reach; lower sample.count or enlarge sample.box"
            ),
        ));
    }
    let rmax = radii.iter().copied().fold(0.0, f64::max);
    too_few_for_the_box(scene, s.amount, size, rmax)?;
    if (0..3).any(|a| size[a] <= 2.0 * rmax) {
        return Err(scene.key_error(
            "sample.box",
            format!(
                "is too small for the largest sphere (radius {rmax:e} m): each edge must exceed its diameter"
            ),
        ));
    }
    let mut walls = Walls::new_box(Vec3::zeros(), size);
    if container.sleeve.is_some() {
        walls.add_sleeve();
    }
    sleeve_fits(scene, &walls, rmax)?;
    progress(&format!(
        "packing {} spheres at solid fraction {phi:.3}",
        radii.len()
    ));
    let mut prng = stream(scene.seed, STREAM_POSITIONS);
    let pack = if walls.sleeve.is_some() {
        pack_geometric_in_sleeve
    } else {
        pack_geometric
    };
    let (pos, report) = pack(&radii, Vec3::zeros(), size, &mut prng)
        .map_err(|j| {
            scene.key_error(
                "sample.solid_fraction",
                format!(
                    "= {:.3} could not be reached: the spheres jammed at about {:.3} (the loose layer along the walls lowers what small samples reach); lower it, use more spheres, or compact to a pressure instead",
                    j.target, j.reached
                ),
            )
        })?;
    progress(&format!(
        "packed in {} relaxation sweeps, largest overlap {:.2e} of a radius",
        report.sweeps, report.max_overlap
    ));
    let mut b = Bodies::default();
    for (p, r) in pos.into_iter().zip(radii) {
        b.push_sphere(p, r, cfg.material.density, UnitQuaternion::identity());
    }
    // Random indices would scatter neighbours over memory: number the spheres by position.
    let order = b.spatial_order(2.0 * rmax);
    b.reorder(&order);
    Ok((b, walls))
}

/// The walls a random sample of box edges `size` (m) is made in, to measure it by (their
/// volume, how they resize): the box, with the scene's sleeve if it asks for one.
fn container(cfg: &GranularScene, size: Vec3) -> Walls {
    let mut walls = Walls::new_box(Vec3::zeros(), size);
    if cfg.walls.sleeve {
        walls.add_sleeve();
    }
    walls
}
