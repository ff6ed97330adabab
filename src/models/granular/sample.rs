//! The granular sample a scene describes: random packings (spheres or poly-ellipsoids),
//! lattices, packing files and the single grain, optionally compacted to a pressure.

use nalgebra::UnitQuaternion;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::scene::{
    Amount, FileSample, Grains, GranularScene, LatticeSample, Orientations, Packing, Radii,
    RandomSample, RandomShape, SampleKind, SingleGrain,
};
use crate::error::Result;
use crate::run::Model as _;
use crate::sample::{
    CompactionSpec, EllipsoidGrain, FractionSpec, JammedShort, JammedSpec, STREAM_ORIENTATIONS,
    STREAM_POSITIONS, STREAM_RADII, STREAM_SHAPES, Sample, SampleInfo, bounding_box,
    check_assembly_overlaps, compact_jammed, compact_to_fraction, compact_to_pressure,
    hcp_positions, pack_geometric, random_orientation, read_ellipsoid_assembly, read_lammps_data,
    read_text_packing, simple_cubic_positions, stream, truncated_normal_radii,
};
use crate::scene::Scene;
use crate::scene::validate::check_bodies;
use crate::shape::{PolyEllipsoid, sphere_volume};
use crate::state::{Bodies, Vec3, Walls};

/// `kind = "single"`: one grain of `semi_axes`, its shape frame aligned with the box (or
/// turned at random with `orientations = "random"`), resting on the bottom face, the top face
/// touching it, centred in the box's base.
fn single_grain(
    scene: &Scene,
    cfg: &GranularScene,
    spec: &SingleGrain,
    orient: &mut ChaCha8Rng,
) -> Result<(Bodies, Walls)> {
    let semi = spec.semi_axes;
    let pe = PolyEllipsoid::new(semi).map_err(|m| scene.key_error("sample.semi_axes", m))?;
    let q = match spec.orientations {
        Orientations::Random => random_orientation(orient),
        Orientations::Aligned => UnitQuaternion::identity(),
    };
    let bx = spec.box_size;
    // Extent of the grain along z about its octant origin.
    let up = pe.support_value(&(q.inverse() * Vec3::z()));
    let down = pe.support_value(&(q.inverse() * -Vec3::z()));
    let origin = Vec3::new(0.5 * bx[0], 0.5 * bx[1], down);
    let mut b = Bodies::default();
    let rho = cfg.material.density;
    if semi.iter().all(|&s| s == semi[0]) {
        b.push_sphere(origin, semi[0], rho, q);
    } else {
        b.push_poly_ellipsoid(pe, rho * pe.volume(), origin + q * pe.centroid(), q);
    }
    let hi = Vec3::new(bx[0], bx[1], up + down);
    Ok((b, Walls::new_box(Vec3::zeros(), hi)))
}

/// `shape = "poly_ellipsoid"`: each packed sphere of radius r becomes a poly-ellipsoid inside
/// it, its six semi-axes drawn uniformly in [r / aspect_ratio_max, r] (so that each axis ratio
/// lies between 1 and the maximum), its octant origin at the sphere's centre and its shape
/// frame the sphere's orientation.
fn poly_ellipsoids_in_spheres(
    scene: &Scene,
    cfg: &GranularScene,
    aspect: f64,
    spheres: &Bodies,
) -> Bodies {
    let mut rng = stream(scene.seed, STREAM_SHAPES);
    let rho = cfg.material.density;
    let mut b = Bodies::default();
    for i in 0..spheres.len() {
        let r = spheres.radius[i];
        let semi = [(); 6].map(|_| r * (1.0 / aspect + (1.0 - 1.0 / aspect) * rng.random::<f64>()));
        let pe = PolyEllipsoid::new(semi).expect("positive semi-axes");
        let q = spheres.orientation[i];
        b.push_poly_ellipsoid(pe, rho * pe.volume(), spheres.pos[i] + q * pe.centroid(), q);
    }
    b
}

/// Builds the sample a scene describes. `progress` receives one-line notes on long stages.
pub fn build(
    scene: &Scene,
    cfg: &GranularScene,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Sample> {
    let Some(dir) = std::env::var_os(SAMPLE_CACHE) else {
        return make(scene, cfg, progress);
    };
    // A sweep over the physics of loading prepares the same sample again and again: with
    // FRACTUM_SAMPLE_CACHE set, a sample is kept there under a digest of everything it is
    // made from and read back instead of made.
    let path = std::path::Path::new(&dir).join(cache_name(scene));
    if let Ok(bytes) = std::fs::read(&path) {
        if let Ok((bodies, walls, info)) =
            postcard::from_bytes::<(Bodies, Walls, SampleInfo)>(&bytes)
        {
            progress(&format!("sample read from the cache {}", path.display()));
            return Ok(Sample {
                bodies,
                walls,
                info,
            });
        }
    }
    let sample = make(scene, cfg, progress)?;
    let bytes = postcard::to_stdvec(&(&sample.bodies, &sample.walls, &sample.info))
        .expect("a sample serialises");
    std::fs::create_dir_all(&dir)
        .and_then(|_| crate::output::write_atomic(&path, &bytes).map_err(std::io::Error::other))
        .map_err(|e| {
            crate::error::Error::input(
                &scene.source.label,
                format!(
                    "{SAMPLE_CACHE} = {}: the sample cache cannot be written ({e})",
                    path.display()
                ),
            )
        })?;
    Ok(sample)
}

/// The environment variable naming the sample cache's folder.
pub const SAMPLE_CACHE: &str = "FRACTUM_SAMPLE_CACHE";

/// The file name a scene's prepared sample is kept under in the sample cache
/// (`FRACTUM_SAMPLE_CACHE`): the digest of what it is made from, `{:016x}.sample`.
pub fn cache_name(scene: &Scene) -> String {
    format!("{:016x}.sample", cache_key(scene))
}

/// A digest (FNV-1a, 64 bits) of what a sample is made from: the build and the preparations'
/// revision, the seed, the
/// `[sample]` (less the grain file's path), `[material]` and `[neighbor]` tables and the grain
/// file's bytes.
fn cache_key(scene: &Scene) -> u64 {
    // Each part followed by a 0xff byte, so that no two lists of parts run together alike.
    let mut bytes = Vec::new();
    let mut eat = |part: &[u8]| {
        bytes.extend_from_slice(part);
        bytes.push(0xff);
    };
    eat(env!("CARGO_PKG_VERSION").as_bytes());
    eat(&crate::sample::PREPARATION_REVISION.to_le_bytes());
    eat(&scene.seed.to_le_bytes());
    for table in ["sample", "material", "neighbor"] {
        let mut t = scene.tables.get(table).cloned();
        // The grain file enters by its bytes, not its path: the FMU carries the Mason scene
        // with the file beside it, the path rewritten.
        if let Some(toml::Value::Table(t)) = &mut t {
            t.remove("grain_file");
        }
        eat(t.map(|t| t.to_string()).unwrap_or_default().as_bytes());
    }
    if let Some(file) = scene
        .tables
        .get("sample")
        .and_then(|t| t.get("grain_file"))
        .and_then(|f| f.as_str())
    {
        eat(&std::fs::read(scene.source.dir.join(file)).unwrap_or_default());
    }
    crate::output::sealed::checksum(&bytes)
}

/// The sample of the scene, made.
fn make(
    scene: &Scene,
    cfg: &GranularScene,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Sample> {
    let spec = &cfg.sample;
    let rho = cfg.material.density;
    let mut orient = stream(scene.seed, STREAM_ORIENTATIONS);
    let mut compaction_steps = 0;
    // Whether the grains came with their orientations (else they are aligned, and turned
    // below with `orientations = "random"`).
    let mut own_orientations = true;
    let mut orientations = Orientations::Aligned;
    let (mut bodies, mut walls) = match &spec.grains {
        Grains::Random(r) => match &r.shape {
            RandomShape::Spheres {
                radii,
                packing: Packing::Geometric,
            }
            | RandomShape::PolyEllipsoids {
                radii,
                packing: Packing::Geometric,
                ..
            } => {
                (own_orientations, orientations) = (false, r.orientations);
                random_sample(scene, cfg, r, radii, progress)?
            }
            _ => {
                let (b, w, steps) = compacted_sample(scene, cfg, r, &mut orient, progress)?;
                compaction_steps = steps;
                (b, w)
            }
        },
        Grains::EllipsoidAssembly { file } => ellipsoid_assembly(scene, cfg, file)?,
        Grains::Lattice(l) => {
            (own_orientations, orientations) = (false, l.orientations);
            lattice(l, rho)
        }
        Grains::File(f) => {
            let (b, w, held) = packing_file(scene, f, rho)?;
            (own_orientations, orientations) = (held, f.orientations);
            (b, w)
        }
        Grains::Single(g) => single_grain(scene, cfg, g, &mut orient)?,
    };
    if !own_orientations && orientations == Orientations::Random {
        for q in &mut bodies.orientation {
            *q = random_orientation(&mut orient);
        }
    }
    if let Grains::Random(RandomSample {
        shape: RandomShape::PolyEllipsoids {
            aspect_ratio_max, ..
        },
        ..
    }) = spec.grains
    {
        bodies = poly_ellipsoids_in_spheres(scene, cfg, aspect_ratio_max, &bodies);
    }
    if let Some(c) = spec.compaction {
        let m = &cfg.material;
        let spec = CompactionSpec {
            young: m.young,
            poisson: m.poisson,
            density: m.density,
            skin: cfg.neighbor.skin,
            pressure: c.pressure,
            friction: c.friction,
        };
        let report = compact_to_pressure(&mut bodies, &mut walls, &spec, progress)?;
        compaction_steps += report.steps;
    }
    let size = walls.box_size();
    let info = SampleInfo {
        kind: spec.kind().as_str().to_string(),
        count: bodies.len(),
        box_size: size.into(),
        solid_fraction: bodies.solid_volume() / (size.x * size.y * size.z),
        compaction_steps,
    };
    Ok(Sample {
        bodies,
        walls,
        info,
    })
}

/// `kind = "simple_cubic"` or `"hcp"`: touching spheres, aligned.
fn lattice(l: &LatticeSample, rho: f64) -> (Bodies, Walls) {
    let (pos, size) = if l.hcp {
        hcp_positions(l.radius, l.layers)
    } else {
        simple_cubic_positions(l.radius, l.layers)
    };
    let mut b = Bodies::default();
    for p in pos {
        b.push_sphere(p, l.radius, rho, UnitQuaternion::identity());
    }
    (b, Walls::new_box(Vec3::zeros(), size))
}

/// `kind = "text"`, `"lammps_data"` or `"yade_text"`: the file's spheres (and velocities),
/// aligned, in the file's box, else `box`, else the box they span.
/// The bodies of a packing file and the box; true when they come with their own orientations
/// (a data file of the Fractum LAMMPS plugin: the bodies as the plugin held them).
fn packing_file(scene: &Scene, f: &FileSample, rho: f64) -> Result<(Bodies, Walls, bool)> {
    let file = f.file.as_str();
    let path = scene.resolve(file);
    let packing = if f.format == SampleKind::LammpsData {
        read_lammps_data(&path)
    } else {
        read_text_packing(&path)
    }
    .map_err(|m| scene.key_error("sample.file", format!("= \"{file}\": {m}")))?;
    let mut b = Bodies::default();
    let held = packing.bodies.is_some();
    if let Some(bodies) = packing.bodies {
        for body in bodies {
            b.push(body);
        }
    } else {
        for (p, r) in packing.spheres {
            b.push_sphere(p, r, rho, UnitQuaternion::identity());
        }
        for (i, v) in packing.velocities {
            if i < b.len() {
                b.vel[i] = v;
            }
        }
    }
    // The file's own box first (docs/scenes.md): it is exact data, `box` a fallback.
    let (lo, hi) = match (packing.bounds, f.box_size) {
        (Some(bounds), _) => bounds,
        (None, Some(size)) => (Vec3::zeros(), Vec3::from(size)),
        (None, None) => bounding_box(&b),
    };
    // A centre outside the box (by more than its radius: not touching it from inside) ran on
    // with the body out of reach of the walls, or pushed through one at the first step.
    let (key, whose) = match (packing.bounds, f.box_size) {
        (Some(_), _) => ("sample.file", format!("= \"{file}\": the file's box")),
        (None, Some(size)) => ("sample.box", format!("= {size:?}: the box of \"{file}\"")),
        (None, None) => ("sample.file", String::new()),
    };
    for (i, (p, r)) in b.pos.iter().zip(&b.radius).enumerate() {
        if (0..3).any(|k| p[k] < lo[k] - r || p[k] > hi[k] + r) {
            return Err(scene.key_error(
                key,
                format!(
                    "{whose} [{:e}, {:e}] × [{:e}, {:e}] × [{:e}, {:e}] m does not hold body {} \
                     (centre ({:e}, {:e}, {:e}) m, radius {r:e} m); every centre must lie in \
                     the box",
                    lo.x,
                    hi.x,
                    lo.y,
                    hi.y,
                    lo.z,
                    hi.z,
                    i + 1,
                    p.x,
                    p.y,
                    p.z
                ),
            ));
        }
    }
    Ok((b, Walls::new_box(lo, hi), held))
}

/// The volume (m³) of an ellipsoid of semi-axes a, b, c.
fn volume(g: &[f64; 3]) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * g[0] * g[1] * g[2]
}

/// An ellipsoid of semi-axes a, b, c as a poly-ellipsoid with equal halves.
fn ellipsoid(semi: [f64; 3]) -> std::result::Result<PolyEllipsoid, String> {
    PolyEllipsoid::new([semi[0], semi[0], semi[1], semi[1], semi[2], semi[2]])
}

fn read_grains(scene: &Scene, key: &str, file: &str) -> Result<Vec<EllipsoidGrain>> {
    read_ellipsoid_assembly(&scene.resolve(file))
        .map_err(|m| scene.key_error(key, format!("= \"{file}\": {m}")))
}

/// The least solid fraction an ellipsoid assembly may hold in the box its grains span (the
/// shipped one holds 0.583).
const ASSEMBLY_FRACTION_MIN: f64 = 0.01;

/// `kind = "ellipsoid_assembly"`: the file's grains as they are (semi-axes, centres, axes), in
/// the box their extents span.
fn ellipsoid_assembly(scene: &Scene, cfg: &GranularScene, file: &str) -> Result<(Bodies, Walls)> {
    let grains = read_grains(scene, "sample.file", file)?;
    check_bodies(scene, "sample.file", grains.len() as f64, "grains")?;
    let rho = cfg.material.density;
    let mut b = Bodies::default();
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for g in &grains {
        let pe = ellipsoid(g.semi).map_err(|m| scene.key_error("sample.file", m))?;
        let q = UnitQuaternion::from_rotation_matrix(&g.axes);
        b.push_poly_ellipsoid(pe, rho * pe.volume(), g.centre, q);
        // Half-extent along world axis k: |(a R_k0, b R_k1, c R_k2)|.
        let m = g.axes.matrix();
        let ext = Vec3::from_fn(|k, _| {
            ((g.semi[0] * m[(k, 0)]).powi(2)
                + (g.semi[1] * m[(k, 1)]).powi(2)
                + (g.semi[2] * m[(k, 2)]).powi(2))
            .sqrt()
        });
        lo = lo.inf(&(g.centre - ext));
        hi = hi.sup(&(g.centre + ext));
    }
    check_assembly_overlaps(&grains)
        .map_err(|m| scene.key_error("sample.file", format!("= \"{file}\": {m}")))?;
    // The box is the one the grains span: one grain far from the others (a centre at 1 m, or
    // 1e300 m, among sub-millimetre grains) would make it that large, and the run would go
    // through a box of air without a word.
    let size = hi - lo;
    let fraction = grains.iter().map(|g| volume(&g.semi)).sum::<f64>() / (size.x * size.y * size.z);
    if fraction.is_nan() || fraction < ASSEMBLY_FRACTION_MIN {
        let mut median = Vec3::zeros();
        for k in 0..3 {
            let mut c: Vec<f64> = grains.iter().map(|g| g.centre[k]).collect();
            c.sort_by(f64::total_cmp);
            median[k] = c[c.len() / 2];
        }
        let far = grains
            .iter()
            .max_by(|a, b| {
                (a.centre - median)
                    .norm()
                    .total_cmp(&(b.centre - median).norm())
            })
            .expect("an assembly holds grains");
        return Err(scene.key_error(
            "sample.file",
            format!(
                "= \"{file}\": line {}: the grain at ({:e}, {:e}, {:e}) m lies {:.3e} m from the \
                 others' median centre, so the box the grains span ({:.3e} × {:.3e} × {:.3e} m) \
                 holds them at solid fraction {fraction:.3e}; an assembly's grains must fill at \
                 least {ASSEMBLY_FRACTION_MIN} of the box they span",
                far.line,
                far.centre.x,
                far.centre.y,
                far.centre.z,
                (far.centre - median).norm(),
                size.x,
                size.y,
                size.z
            ),
        ));
    }
    Ok((b, Walls::new_box(lo, hi)))
}

/// A random sample packed by compaction (`packing = "compaction"`): grains drawn (spheres
/// from the radius distribution, or ellipsoids from `grain_file`'s semi-axes, uniformly with
/// replacement) until they fill `solid_fraction` of `box`; their bounding spheres packed
/// without overlap at solid fraction 0.4 in a box of the same shape, enlarged; turned at
/// random (or aligned); then compressed without friction to `box` by
/// [`compact_to_fraction`]. One sentence if they jam first.
fn compacted_sample(
    scene: &Scene,
    cfg: &GranularScene,
    s: &RandomSample,
    orient: &mut ChaCha8Rng,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Bodies, Walls, u64)> {
    let size = Vec3::from(s.box_size);
    let box_volume = size.x * size.y * size.z;
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
                    "= {phi}: the whole grains drawn for it fill {drawn:.4} of sample.box, not                      within {tolerance} of it (one grain is too large a share of so small a box);                      enlarge sample.box"
                ),
            ));
        }
    }
    // With both a count and a fraction the box keeps its shape, scaled to the fraction.
    let target = match s.amount {
        Amount::Both { solid_fraction, .. } => size * (solid / solid_fraction / box_volume).cbrt(),
        _ => size,
    };
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
    let spheres: f64 = bounding.iter().map(|&r| sphere_volume(r)).sum();
    let start = target
        * (spheres / START_FRACTION / (target.x * target.y * target.z))
            .cbrt()
            .max(1.0);
    progress(&format!(
        "placing {} grains (their bounding spheres at solid fraction {START_FRACTION}) before compaction",
        grains.len()
    ));
    let mut prng = stream(scene.seed, STREAM_POSITIONS);
    let (pos, _) = pack_geometric(&bounding, Vec3::zeros(), start, &mut prng).map_err(|j| {
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
    let m = &cfg.material;
    if s.packing() == Packing::Jammed {
        let spec = JammedSpec {
            young: m.young,
            poisson: m.poisson,
            density: m.density,
            friction: m.friction,
            skin: cfg.neighbor.skin,
            fraction: solid / (target.x * target.y * target.z),
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
        b.solid_volume() / (target.x * target.y * target.z),
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
fn too_few_for_the_box(scene: &Scene, amount: Amount, size: Vec3, rmax: f64) -> Result<()> {
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
fn asked_fraction(amount: Amount, drawn: f64) -> String {
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
const START_FRACTION: f64 = 0.4;

/// The radii of a random sample of spheres, from the scene's seed: `count` of them, or as many
/// as fill `solid_fraction` of a box of `box_volume` (m³).
fn draw_radii(scene: &Scene, dist: &Radii, amount: Amount, box_volume: f64) -> Vec<f64> {
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
fn random_sample(
    scene: &Scene,
    cfg: &GranularScene,
    s: &RandomSample,
    dist: &Radii,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Bodies, Walls)> {
    let mut size = Vec3::from(s.box_size);
    let box_volume = size.x * size.y * size.z;
    let radii = draw_radii(scene, dist, s.amount, box_volume);
    let solid: f64 = radii.iter().map(|&r| sphere_volume(r)).sum();
    if let Amount::Both { solid_fraction, .. } = s.amount {
        // Both a count and a fraction: keep the box's shape, scale it to the fraction.
        size *= (solid / solid_fraction / box_volume).cbrt();
    }
    let phi = solid / (size.x * size.y * size.z);
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
    progress(&format!(
        "packing {} spheres at solid fraction {phi:.3}",
        radii.len()
    ));
    let mut prng = stream(scene.seed, STREAM_POSITIONS);
    let (pos, report) = pack_geometric(&radii, Vec3::zeros(), size, &mut prng)
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
    Ok((b, Walls::new_box(Vec3::zeros(), size)))
}

/// The sample of a granular scene (its section read from the scene).
pub fn from_scene(scene: &Scene, progress: &mut (dyn FnMut(&str) + Send)) -> Result<Sample> {
    let cfg = super::Granular::read(scene)?;
    build(scene, &cfg, progress)
}
