//! `fractum explain` for a granular scene.

use std::fmt::Write;

use super::scene::{
    Amount, EFFECTS, Grains, GranularScene, Orientations, Packing, RandomShape, SampleSpec,
};
use crate::error::Result;
use crate::explain::write_pipeline;
use crate::scene::{EffectKind, Scene};

/// A human-readable account of the scene: sample, force pipeline (and what is left out),
/// loading, time step and outputs.
pub fn explain(scene: &Scene, cfg: &GranularScene) -> Result<String> {
    let pipeline = super::pipeline(scene, cfg);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "scene {} (\"{}\"), seed {}",
        scene.source.label, scene.name, scene.seed
    );
    let _ = writeln!(
        s,
        "model: granular, rigid grains (spheres, poly-ellipsoids) with Hertz–Mindlin contacts"
    );
    let mut sample = describe_sample(cfg);
    if cfg.walls.sleeve {
        // In a sleeve the faces close in along its axis only.
        sample = sample.replace(
            "(the box scaled alike in all directions)",
            "(along the sleeve's axis: the z faces move, the sleeve holds)",
        );
    }
    let _ = writeln!(s, "sample: {sample}");
    if cfg.walls.sleeve {
        let friction = cfg
            .walls
            .sleeve_friction
            .or(cfg.walls.friction)
            .unwrap_or(cfg.material.friction);
        let _ = writeln!(
            s,
            "walls: a rigid, fixed sleeve (a circular cylinder along z, its diameter sample.box's x edge, friction {friction}) in place of the box's four side faces, closed by the two z faces; solid fractions are of its volume"
        );
    }
    write_pipeline(
        &mut s,
        scene,
        &pipeline.describe(),
        &EFFECTS,
        "bodies move freely",
    );
    if scene.has_effect(EffectKind::Fracture) {
        let _ = writeln!(s, "after each step: {}", describe_fracture(scene, cfg));
    }
    let mut loading = super::Loading::describe(&cfg.loading);
    if cfg.walls.sleeve {
        loading = loading.replace(
            "the other five walls fixed",
            "the bottom face (z-) and the sleeve fixed",
        );
    }
    let _ = writeln!(s, "loading: {loading}");
    let dt = if scene.has_effect(EffectKind::Fracture) {
        scene.time.describe_step(&format!(
            "the Rayleigh critical step of half the smallest sphere (the pieces), shortened as pieces appear to keep the bound on the highest contact frequency at omega dt <= {:.3} (3 x {})",
            super::ADAPT_PER_SAFETY * scene.time.safety,
            scene.time.safety,
        ))
    } else {
        scene
            .time
            .describe_step("the Rayleigh critical step of the smallest sphere")
    };
    crate::explain::write_integrator(&mut s, "velocity Verlet", &dt);
    crate::explain::write_outputs(&mut s, scene, None, "summary.json");
    Ok(s)
}

/// The fracture effect and the effects that refine it (weibull, cohesion), with their constants.
fn describe_fracture(scene: &Scene, cfg: &GranularScene) -> String {
    let p = super::fracture_params(scene, cfg);
    let mut s = format!(
        "fracture: a free grain splits into two sub-poly-ellipsoids when its average stress fails Hoek-Brown (m_i = {}, sigma_c = {:e} Pa) or when at least {} of its contacts exceed the contact tensile strength sigma_fM = {:e} Pa; break plane {}",
        p.mi,
        p.sigma_c,
        p.critical_contacts,
        p.sigma_f,
        if p.ideal_plane {
            "the ideal one for a sphere (Section 3.3), by the grain's stress or contacts otherwise"
        } else {
            "by the grain's stress or contacts"
        }
    );
    if p.plane_jitter {
        s.push_str(", turned by the random slight rotation");
    }
    match p.weibull {
        Some((w, xm)) => {
            let beta = p.size_exponent;
            let _ = write!(
                s,
                "; + weibull: {} scaled per grain by a Weibull factor ln(1/P)^(1/w) (x/x_M)^(-beta) (modulus {w}, size exponent {beta}, reference radius {xm:e} m)",
                if p.particle_strength {
                    "the particle strength (weibull_on = \"particle\": sigma_c times the factor, the contact tensile strength times its cube root)"
                } else if p.weibull_sigma_c {
                    "both strengths (weibull_on = \"both\")"
                } else {
                    "the contact tensile strength (weibull_on = \"contact\"; sigma_c the same for every grain)"
                }
            );
        }
        None => s.push_str("; strengths the same for every grain (no weibull)"),
    }
    if p.comminution_limit > 0.0 {
        let _ = write!(
            s,
            "; comminution limit: pieces of equivalent radius below {:e} m no longer split",
            p.comminution_limit
        );
    }
    match p.cohesion {
        Some((gc, ns)) => {
            let _ = write!(
                s,
                "; + cohesion: the halves held by {ns} springs per break plane that soften to zero after taking G_c = {gc:.4} J/m2 (K_Ic = {:e} Pa m^0.5)",
                cfg.fracture.toughness
            );
        }
        None => s.push_str("; the halves free at once (no cohesion)"),
    }
    s
}

fn describe_sample(cfg: &GranularScene) -> String {
    let p: &SampleSpec = &cfg.sample;
    let kind = p.kind().as_str();
    match &p.grains {
        Grains::Random(r) => {
            let method = match r.packing() {
                Packing::Geometric => {
                    "packed without overlap by growth and collective rearrangement (He et al. 1999)".to_string()
                }
                Packing::Compaction => {
                    "placed at a low solid fraction (bounding spheres at 0.4), then compressed by the box's faces without friction to the fraction (friction restored for loading)".to_string()
                }
                Packing::Jammed => format!(
                    "placed at a low solid fraction (bounding spheres at 0.4), compressed without friction to 0.45, then compressed until they jam (at rest, carrying {:e} of their modulus) with a friction searched between none and the grains' own until the jammed grains fill the fraction within {} (the box scaled alike in all directions); loading starts from there with the grains' own friction",
                    crate::sample::JAM_PER_MODULUS,
                    crate::sample::FRACTION_TOLERANCE
                ),
            };
            let (grains, radii) = match &r.shape {
                RandomShape::Ellipsoids { grain_file, .. } => {
                    let count = match r.amount {
                        Amount::Count(n) | Amount::Both { count: n, .. } => {
                            format!("{n} ellipsoid grains")
                        }
                        Amount::SolidFraction(phi) => {
                            format!("ellipsoid grains filling solid fraction {phi}")
                        }
                    };
                    return format!(
                        "random packing of {count}, semi-axes drawn (uniformly, with replacement) from the grains of {grain_file}, orientations {}, box {:?} m, {method}",
                        if r.orientations == Orientations::Aligned {
                            "aligned"
                        } else {
                            "random"
                        },
                        r.box_size
                    );
                }
                RandomShape::Spheres { radii, .. } | RandomShape::PolyEllipsoids { radii, .. } => {
                    ("spheres", radii)
                }
            };
            let count = match r.amount {
                Amount::Count(n) | Amount::Both { count: n, .. } => format!("{n} {grains}"),
                Amount::SolidFraction(phi) => format!("{grains} filling solid fraction {phi}"),
            };
            let mut s = format!(
                "random packing of {count}, radii truncated normal (mean {:e} m, sd {:e} m, in [{:e}, {:e}] m), box {:?} m, {method}",
                radii.mean, radii.sd, radii.min, radii.max, r.box_size
            );
            if let Some(c) = p.compaction {
                let _ = write!(
                    s,
                    ", then servo-compacted to {:e} Pa (friction {})",
                    c.pressure, c.friction
                );
            }
            s
        }
        Grains::EllipsoidAssembly { file } => format!(
            "ellipsoid assembly {file} imported as it is (semi-axes, centres, orientations), in the box its grains span"
        ),
        Grains::Lattice(l) => format!(
            "{kind} lattice of {:?} spheres of radius {:e} m",
            l.layers, l.radius
        ),
        Grains::File(f) => format!("{kind} file {}", f.file),
        Grains::Single(g) => format!(
            "one poly-ellipsoid grain, semi-axes [a+, a-, b+, b-, c+, c-] = {:?} m, on the bottom of a box of base {:?} m",
            g.semi_axes,
            [g.box_size[0], g.box_size[1]]
        ),
    }
}
