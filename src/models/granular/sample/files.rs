//! Samples read from files: a lattice, a packing of the Fractum LAMMPS plugin, an ellipsoid
//! assembly.

use super::*;

/// `kind = "simple_cubic"` or `"hcp"`: touching spheres, aligned.
pub(super) fn lattice(l: &LatticeSample, rho: f64) -> (Bodies, Walls) {
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
pub(super) fn packing_file(
    scene: &Scene,
    f: &FileSample,
    rho: f64,
) -> Result<(Bodies, Walls, bool)> {
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
pub(super) fn volume(g: &[f64; 3]) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * g[0] * g[1] * g[2]
}

/// An ellipsoid of semi-axes a, b, c as a poly-ellipsoid with equal halves.
pub(super) fn ellipsoid(semi: [f64; 3]) -> std::result::Result<PolyEllipsoid, String> {
    PolyEllipsoid::new([semi[0], semi[0], semi[1], semi[1], semi[2], semi[2]])
}

pub(super) fn read_grains(scene: &Scene, key: &str, file: &str) -> Result<Vec<EllipsoidGrain>> {
    read_ellipsoid_assembly(&scene.resolve(file))
        .map_err(|m| scene.key_error(key, format!("= \"{file}\": {m}")))
}

/// The least solid fraction an ellipsoid assembly may hold in the box its grains span (the
/// shipped one holds 0.583).
pub(super) const ASSEMBLY_FRACTION_MIN: f64 = 0.01;

/// `kind = "ellipsoid_assembly"`: the file's grains as they are (semi-axes, centres, axes), in
/// the box their extents span.
pub(super) fn ellipsoid_assembly(
    scene: &Scene,
    cfg: &GranularScene,
    file: &str,
) -> Result<(Bodies, Walls)> {
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
