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
    hcp_positions, pack_geometric, pack_geometric_in_sleeve, random_orientation,
    read_ellipsoid_assembly, read_lammps_data, read_text_packing, simple_cubic_positions, stream,
    truncated_normal_radii,
};
use crate::scene::Scene;
use crate::scene::validate::check_bodies;
use crate::shape::{PolyEllipsoid, sphere_volume};
use crate::state::{Bodies, Vec3, Walls};

mod files;
mod random;

use files::{ellipsoid, ellipsoid_assembly, lattice, packing_file, read_grains, volume};
use random::{compacted_sample, random_sample};

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
    // A sample made in a sleeve is another sample (the key of one without stays as it was).
    if scene
        .tables
        .get("walls")
        .and_then(|t| t.get("sleeve"))
        .and_then(|v| v.as_bool())
        == Some(true)
    {
        eat(b"sleeve");
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
            let (b, mut w, held) = packing_file(scene, f, rho)?;
            if cfg.walls.sleeve {
                into_sleeve(scene, &b, &mut w)?;
            }
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
        solid_fraction: bodies.solid_volume() / walls.volume(),
        compaction_steps,
    };
    Ok(Sample {
        bodies,
        walls,
        info,
    })
}

/// Whether the sleeve of `walls` (if any) can hold grains of bounding radius up to `rmax`
/// (m): it must be wider than the largest grain is long. (A grain touches the sleeve at one
/// point, its farthest from the axis; one nearly as long as the sleeve is wide may also press
/// on the far side, which that contact does not see.)
fn sleeve_fits(scene: &Scene, walls: &Walls, rmax: f64) -> Result<()> {
    let Some(s) = &walls.sleeve else {
        return Ok(());
    };
    if s.radius > rmax {
        return Ok(());
    }
    Err(scene.key_error(
        "walls.sleeve",
        format!(
            "= true: the sleeve, {:.3e} m across (sample.box's x edge), must be wider than the largest grain is long ({:.3e} m); enlarge sample.box's x and y edges",
            2.0 * s.radius,
            2.0 * rmax
        ),
    ))
}

/// Puts the sleeve inscribed in the box of a packing file's `bodies` around them: the box's
/// x and y edges must be equal, the sleeve wider than two of the largest body, and every
/// centre inside it.
fn into_sleeve(scene: &Scene, bodies: &Bodies, walls: &mut Walls) -> Result<()> {
    let size = walls.box_size();
    if (size.x - size.y).abs() > 1e-12 * size.x.abs().max(size.y.abs()) {
        return Err(scene.key_error(
            "walls.sleeve",
            format!(
                "= true: the sleeve is the cylinder inscribed in the box's x-y section, whose x and y edges must then be equal; the packing's box is {:e} × {:e} × {:e} m",
                size.x, size.y, size.z
            ),
        ));
    }
    walls.add_sleeve();
    let rmax = bodies.radius.iter().copied().fold(0.0, f64::max);
    sleeve_fits(scene, walls, rmax)?;
    let sleeve = walls.sleeve.as_ref().expect("just added");
    if let Some(i) = (0..bodies.len()).find(|&i| sleeve.distance(&bodies.pos[i]) < 0.0) {
        let p = bodies.pos[i];
        return Err(scene.key_error(
            "walls.sleeve",
            format!(
                "= true: body {} (centre ({:e}, {:e}, {:e}) m) lies outside the sleeve, {:e} m in radius about ({:e}, {:e}); every centre must lie inside it",
                i + 1,
                p.x,
                p.y,
                p.z,
                sleeve.radius,
                sleeve.centre.x,
                sleeve.centre.y
            ),
        ));
    }
    Ok(())
}

/// The sample of a granular scene (its section read from the scene).
pub fn from_scene(scene: &Scene, progress: &mut (dyn FnMut(&str) + Send)) -> Result<Sample> {
    let cfg = super::Granular::read(scene)?;
    build(scene, &cfg, progress)
}
