//! Throughput benchmark: particle-steps per second on dense, jammed sphere packings. Used by
//! `fractum bench` and `cargo bench`; it prints figures and asserts nothing.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::Simulation;
use super::scene::LoadingSpec;
use crate::bench::Timed;
use crate::error::{Error, Result};
use crate::output::write_atomic;
use crate::run::Model as _;
use crate::sample::Sample;
use crate::scene::Scene;

/// The material and contact model of the benchmark (that of scenes/oedometer_spheres.toml):
/// r = 0.3 mm ± 10%, E = 60 GPa, ν = 0.17, μ = 0.5, e = 0.5, Hertz–Mindlin with damping.
fn scene_text(bodies: usize) -> String {
    format!(
        r#"
name = "bench_{bodies}"
seed = 2024
effects = ["contact", "damping", "friction"]
[material]
young = 60e9
poisson = 0.17
density = 2650.0
friction = 0.5
restitution = 0.5
[sample]
kind = "random"
count = {bodies}
radius_mean = 0.3e-3
radius_sd = 0.03e-3
radius_min = 0.27e-3
radius_max = 0.33e-3
box = [1.0, 1.0, 1.0]
solid_fraction = 0.55
pressure = 1e5
compaction_friction = 0.1
[loading]
kind = "none"
end_time = 1.0
[time]
safety = 0.3
[output]
every = 1000000000
"#
    )
}

/// A jammed packing of `bodies` spheres at 100 kPa, made once and cached as a text packing
/// under `cache` (the compaction of 8000 spheres takes a while).
pub fn dense_packing(
    bodies: usize,
    cache: &Path,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Sample> {
    let file = cache.join(format!("dense_{bodies}.txt"));
    let scene = Scene::from_toml(&scene_text(bodies), "bench", cache, &[])?;
    if file.exists() {
        let mut s = scene.clone();
        if let Some(toml::Value::Table(t)) = s.tables.get_mut("sample") {
            t.insert("kind".into(), "text".into());
            t.insert("file".into(), format!("dense_{bodies}.txt").into());
            // The packing is made: the keys that made it do not apply to a file (and are
            // refused there).
            for key in [
                "box",
                "pressure",
                "compaction_friction",
                "count",
                "solid_fraction",
            ] {
                t.remove(key);
            }
        }
        return super::sample::from_scene(&s, progress);
    }
    let made = super::sample::from_scene(&scene, progress)?;
    std::fs::create_dir_all(cache).map_err(|e| Error::io(cache, "create the folder", e))?;
    let walls = &made.walls;
    let lo = walls.walls[0].point.x;
    let lo = [lo, walls.walls[2].point.y, walls.walls[4].point.z];
    let size = walls.box_size();
    let mut text = format!(
        "# box {:e} {:e} {:e} {:e} {:e} {:e}\n",
        lo[0],
        lo[1],
        lo[2],
        lo[0] + size.x,
        lo[1] + size.y,
        lo[2] + size.z
    );
    for (p, r) in made.bodies.pos.iter().zip(&made.bodies.radius) {
        text.push_str(&format!("{:e} {:e} {:e} {:e}\n", p.x, p.y, p.z, r));
    }
    write_atomic(&file, text.as_bytes())?;
    Ok(made)
}

/// Times `steps` steps (after 200 warm-up steps) of the packing on `threads` threads.
pub fn time_case(sample: &Sample, bodies: usize, threads: usize, steps: u64) -> Result<Timed> {
    let scene = Scene::from_toml(&scene_text(bodies), "bench", Path::new("."), &[])?;
    time_sample(scene, sample, threads, steps)
}

/// Times `steps` steps of (a copy of) `sample` under `scene` after 200 warm-up steps.
fn time_sample(scene: Scene, sample: &Sample, threads: usize, steps: u64) -> Result<Timed> {
    let copy = Sample {
        bodies: sample.bodies.clone(),
        walls: sample.walls.clone(),
        info: sample.info.clone(),
    };
    let scene_name = scene.name.clone();
    let mut sim = Simulation::from_sample(scene, copy, threads)?;
    sim.advance(200)?;
    let start = Instant::now();
    sim.advance(steps)?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(Timed {
        case: scene_name,
        bodies: sim.model.state.bodies.len(),
        contacts: Some(sim.model.pipeline.contacts()),
        threads,
        steps,
        seconds,
    })
}

/// The default cache folder for benchmark packings.
pub fn default_cache() -> PathBuf {
    PathBuf::from("target").join("fractum-bench")
}

/// Runs every (bodies, threads) case and returns the results.
pub fn run(
    sizes: &[usize],
    threads: &[usize],
    steps: u64,
    cache: &Path,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<Vec<Timed>> {
    let mut cases = Vec::new();
    // A packing not yet made is compacted on the largest thread count asked for: the same
    // packing on any (its pair loop in parts of fixed rows, crate::sample::PREPARATION_PART_ROWS).
    let most = threads.iter().copied().max().unwrap_or(1);
    let pool = crate::parallel::Threads::new(most)?;
    for &n in sizes {
        let sample = pool.run(most, || dense_packing(n, cache, &mut *progress))?;
        for &t in threads {
            let case = time_case(&sample, n, t, steps)?;
            progress(&format!(
                "{} bodies, {} thread(s): {:.3e} particle-steps/s",
                case.bodies,
                case.threads,
                case.body_steps_per_second()
            ));
            cases.push(case);
        }
    }
    Ok(cases)
}

// granular fracture: poly-ellipsoid contact throughput and the SHPB scene's cost per strain.

/// A dense packing of `bodies` poly-ellipsoids with axis ratios from 1 to 2 (each semi-axis
/// uniform in [r/2, r] of a packed sphere of radius r), randomly oriented: the sample of the
/// sphere benchmark's scene with `shape = "poly_ellipsoid"`, compacted by its servo walls
/// until every wall carries 100 kPa. Returns the scene with it.
pub fn dense_poly_ellipsoids(
    bodies: usize,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<(Scene, Sample)> {
    let text = scene_text(bodies).replace(
        "compaction_friction = 0.1\n",
        "compaction_friction = 0.1\nshape = \"poly_ellipsoid\"\naspect_ratio_max = 2.0\n",
    );
    let scene = Scene::from_toml(&text, "bench", Path::new("."), &[])?;
    let sample = super::sample::from_scene(&scene, progress)?;
    Ok((scene, sample))
}

/// Times `steps` steps (after 200 warm-up steps) of a poly-ellipsoid packing from
/// [`dense_poly_ellipsoids`] on `threads` threads: the contact model of [`time_case`]
/// (Hertz–Mindlin with damping) on the local curvatures.
pub fn time_poly_ellipsoid_case(
    scene: &Scene,
    sample: &Sample,
    threads: usize,
    steps: u64,
) -> Result<Timed> {
    time_sample(scene.clone(), sample, threads, steps)
}

/// Runs a shipped SHPB scene (with `overrides`) to its end on `threads` threads and returns
/// the wall seconds of the stepping per 1% of axial strain, the grains at the start and the
/// bodies at the end.
pub fn time_shpb(path: &Path, overrides: &[String], threads: usize) -> Result<(f64, usize, usize)> {
    let scene = Scene::load(path, overrides)?;
    let cfg = super::Granular::read(&scene)?;
    let end_strain = match cfg.loading {
        LoadingSpec::Oedometer { end_strain, .. } => end_strain,
        _ => 0.0,
    };
    let mut sim = Simulation::new(scene, threads, &mut |_| {})?;
    let grains = sim.model.state.bodies.len();
    let start = Instant::now();
    while !sim.finished() {
        sim.advance(1000)?;
    }
    let seconds = start.elapsed().as_secs_f64();
    Ok((
        seconds / (100.0 * end_strain),
        grains,
        sim.model.state.bodies.len(),
    ))
}
