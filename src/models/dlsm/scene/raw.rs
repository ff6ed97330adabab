//! The raw form of the dlsm tables, as serde reads them (every key that some kind lacks is
//! an `Option`), and the checks that turn it into the typed forms of the parent module:
//! ranges, and which samples, loadings, effects and integrators go together.
//!
//! The raw structs have the names of the typed ones they become (those are `typed::` here):
//! serde's type errors print a struct's name ("expected struct SampleSpec"), and the messages
//! stay as they were.

use serde::Deserialize;

use super::{
    self as typed, BrazilianSpec, DropSpec, Grip, LoadBy, LoadingKind, Material, SampleKind,
    SampleMethod, SampleShape, Seeds, TensionSpec, VibrationMode, VibrationSpec,
};
use crate::error::Result;
use crate::models::dlsm::sample::{DEFAULT_DISPERSION, DEFAULT_NOISE};
use crate::scene::validate::{Range, check, check_bodies, require};
use crate::scene::{EffectKind, IntegratorKind, Scene};

/// `[sample]` as written. Which keys apply depends on `kind`; see docs/scenes.md.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    pub kind: SampleKind,
    /// How Voronoi seeds are placed.
    pub method: Option<SampleMethod>,
    /// Noise range d of the noisy grid, in [0, 1] (Section 7.1).
    pub noise: Option<f64>,
    /// About how many Voronoi elements to make.
    pub elements: Option<usize>,
    /// Edge of a cubic box, or length of a cylinder (m).
    pub length: Option<f64>,
    /// Box edge lengths [x, y, z] (m).
    #[serde(rename = "box")]
    pub box_size: Option<[f64; 3]>,
    /// Radius of a cylinder or ball (m).
    pub radius: Option<f64>,
    /// Diameter (m) and thickness (m) of a disc.
    pub diameter: Option<f64>,
    pub thickness: Option<f64>,
    /// Relative half-width δ of the uniform radius distribution of the packing method.
    pub radius_dispersion: Option<f64>,
}

/// `[loading]` as written. Which keys apply depends on `kind`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadingSpec {
    pub kind: LoadingKind,
    /// Axial strain rate (1/s) of the tension test, > 0.
    pub strain_rate: Option<f64>,
    /// Strain at which the tension or Brazilian test ends, in (0, 1).
    pub end_strain: Option<f64>,
    /// Duration (s) of a free vibration, a drop or `kind = "none"`.
    pub end_time: Option<f64>,
    /// Speed (m/s) of each loaded side of a Brazilian disc, > 0.
    pub speed: Option<f64>,
    /// Time (s) over which the prescribed speeds rise smoothly from zero.
    pub ramp_time: Option<f64>,
    /// How the tension test's driven elements hold the x faces: "sliding" (y, z free, the
    /// default) or "clamped" (y, z held).
    pub grip: Option<Grip>,
    /// Loading arc 2α (degrees) of the Brazilian test; 0 loads the top and bottom elements.
    pub arc_degrees: Option<f64>,
    /// How a Brazilian disc is loaded: "elements" (prescribed speeds on the elements of the
    /// loading arcs, the default), "flat_platens" or "curved_jaws" (two rigid platens, or
    /// jaws of radius 1.5 R, touching the disc's elements through frictional contacts,
    /// driven at `speed`; the force is read on them) or "arc_pressure" (a uniform radial
    /// pressure over the loading arcs, set by a servo on their closure commanded at
    /// `speed`).
    pub load_by: Option<LoadBy>,
    /// Stiffness (N/m) of the servo of `load_by = "arc_pressure"`, > 0.
    pub servo_stiffness: Option<f64>,
    /// With `fracture`: the run ends once the load has fallen below this fraction of its
    /// peak (0: never early).
    pub stop_fraction: Option<f64>,
    /// The static field a free vibration starts from.
    pub mode: Option<VibrationMode>,
    /// Initial strain A of a free vibration in tension.
    pub initial_strain: Option<f64>,
    /// Initial twist α (rad/m) of a free vibration in torsion.
    pub twist: Option<f64>,
    /// Initial velocity (m/s) of a dropped body.
    pub initial_velocity: Option<[f64; 3]>,
    /// Inclination (degrees) of the ground plane, descending towards +x.
    pub ground_angle_degrees: Option<f64>,
    /// Gap (m) between the dropped body and the ground at the start.
    pub drop_height: Option<f64>,
}

/// The dlsm model's tables of a scene as written: the model's `Section`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DlsmScene {
    pub material: Material,
    pub sample: SampleSpec,
    pub loading: LoadingSpec,
}

/// Range checks of a dlsm scene, and what goes with what; the scene in its typed form.
pub fn validate(s: &Scene, d: &DlsmScene) -> Result<typed::DlsmScene> {
    let m = &d.material;
    check(s, "material.young", m.young, Range::POSITIVE, "Pa")?;
    check(s, "material.poisson", m.poisson, Range::open(-1.0, 0.5), "")?;
    check(s, "material.density", m.density, Range::POSITIVE, "kg/m³")?;
    check(s, "material.friction", m.friction, Range::NON_NEGATIVE, "")?;
    if let Some(sf) = m.tensile_strength {
        check(s, "material.tensile_strength", sf, Range::POSITIVE, "Pa")?;
    }
    if let Some(k) = m.contact_stiffness {
        check(s, "material.contact_stiffness", k, Range::POSITIVE, "N/m")?;
    }
    let sample = validate_sample(s, &d.sample)?;
    let loading = validate_loading(s, &d.loading)?;
    let t = &s.time;
    match (t.integrator, t.phi) {
        (IntegratorKind::TchamwaWielgosz, Some(phi)) => {
            check(s, "time.phi", phi, Range::closed(0.5, 10.0), "")?;
        }
        (IntegratorKind::VelocityVerlet, Some(_)) => {
            return Err(s.key_error(
                "time.phi",
                "applies to time.integrator = \"tchamwa_wielgosz\" (velocity Verlet is φ = 0.5)",
            ));
        }
        _ => {}
    }
    let (sample_kind, loading_kind) = (d.sample.kind, d.loading.kind);
    let needs = match loading_kind {
        LoadingKind::Tension => Some(SampleKind::VoronoiBox),
        LoadingKind::FreeVibration => Some(SampleKind::VoronoiCylinder),
        LoadingKind::Brazilian => Some(SampleKind::VoronoiDisc),
        LoadingKind::None | LoadingKind::Drop => None,
    };
    if let Some(k) = needs {
        if sample_kind != k {
            return Err(s.key_error(
                "loading.kind",
                format!(
                    "= \"{}\" needs sample.kind = \"{}\", not \"{}\"",
                    loading_kind.as_str(),
                    k.as_str(),
                    sample_kind.as_str()
                ),
            ));
        }
    }
    if s.has_effect(EffectKind::Fracture) {
        require(
            s,
            "material.tensile_strength",
            m.tensile_strength,
            "for the \"fracture\" effect",
        )?;
    }
    s.requires_contact(EffectKind::Friction)?;
    if s.has_effect(EffectKind::Contact) {
        if loading_kind != LoadingKind::Drop {
            return Err(s.key_error(
                "effects",
                "lists \"contact\", the element–ground contact, which needs the ground of loading.kind = \"drop\"",
            ));
        }
        require(
            s,
            "material.contact_stiffness",
            m.contact_stiffness,
            "for the \"contact\" effect of model.kind = \"dlsm\"",
        )?;
    }
    Ok(typed::DlsmScene {
        material: m.clone(),
        sample,
        loading,
    })
}

/// The keys of a Voronoi sample, and the sample in its typed form.
fn validate_sample(s: &Scene, p: &SampleSpec) -> Result<typed::SampleSpec> {
    let why = format!("for sample.kind = \"{}\"", p.kind.as_str());
    let n = require(s, "sample.elements", p.elements, &why)?;
    if n < 8 {
        return Err(s.key_error(
            "sample.elements",
            format!("= {n} is outside the allowed range [8, ∞)"),
        ));
    }
    check_bodies(s, "sample.elements", n as f64, "elements")?;
    // Each applies to its method only and is ignored by the others, so that one scene can
    // switch methods with --set.
    if let Some(d) = p.noise {
        check(s, "sample.noise", d, Range::closed(0.0, 1.0), "")?;
    }
    if let Some(delta) = p.radius_dispersion {
        check(
            s,
            "sample.radius_dispersion",
            delta,
            Range::closed(0.15, 0.9),
            "",
        )?;
    }
    let positive = |key: &str, v: Option<f64>| -> Result<f64> {
        let v = require(s, key, v, &why)?;
        check(s, key, v, Range::POSITIVE, "m")?;
        Ok(v)
    };
    let shape = match p.kind {
        SampleKind::VoronoiBox => match (p.box_size, p.length) {
            (Some(_), Some(_)) => {
                return Err(s.key_error(
                    "sample.length",
                    "and sample.box both give the box; keep one",
                ));
            }
            (Some(bx), None) => {
                for (axis, v) in ["x", "y", "z"].iter().zip(bx) {
                    if !Range::POSITIVE.contains(v) {
                        return Err(s.key_error(
                            "sample.box",
                            format!("has {axis} edge {v}, outside the allowed range (0, ∞) m"),
                        ));
                    }
                }
                SampleShape::Box { size: bx }
            }
            (None, l) => {
                let l = positive("sample.length", l)?;
                SampleShape::Box { size: [l; 3] }
            }
        },
        SampleKind::VoronoiCylinder => SampleShape::Cylinder {
            length: positive("sample.length", p.length)?,
            radius: positive("sample.radius", p.radius)?,
        },
        SampleKind::VoronoiDisc => SampleShape::Disc {
            diameter: positive("sample.diameter", p.diameter)?,
            thickness: positive("sample.thickness", p.thickness)?,
        },
        SampleKind::VoronoiBall => SampleShape::Ball {
            radius: positive("sample.radius", p.radius)?,
        },
    };
    let seeds = match p.method.unwrap_or(SampleMethod::NoisyGrid) {
        SampleMethod::NoisyGrid => Seeds::NoisyGrid {
            noise: p.noise.unwrap_or(DEFAULT_NOISE),
        },
        SampleMethod::Packing => Seeds::Packing {
            radius_dispersion: p.radius_dispersion.unwrap_or(DEFAULT_DISPERSION),
        },
        SampleMethod::Grid => Seeds::Grid,
    };
    Ok(typed::SampleSpec {
        shape,
        elements: n,
        seeds,
    })
}

/// The keys of the dlsm loadings, and the loading in its typed form.
fn validate_loading(s: &Scene, l: &LoadingSpec) -> Result<typed::LoadingSpec> {
    let why = format!("for loading.kind = \"{}\"", l.kind.as_str());
    if let Some(t) = l.ramp_time {
        check(s, "loading.ramp_time", t, Range::NON_NEGATIVE, "s")?;
    }
    if let Some(f) = l.stop_fraction {
        check(s, "loading.stop_fraction", f, Range::closed(0.0, 0.99), "")?;
    }
    Ok(match l.kind {
        LoadingKind::Tension => {
            let rate = require(s, "loading.strain_rate", l.strain_rate, &why)?;
            check(s, "loading.strain_rate", rate, Range::POSITIVE, "1/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
            typed::LoadingSpec::Tension(TensionSpec {
                strain_rate: rate,
                end_strain: end,
                ramp_time: l.ramp_time,
                stop_fraction: l.stop_fraction,
                grip: l.grip.unwrap_or_default(),
            })
        }
        _ if l.grip.is_some() => {
            return Err(s.key_error(
                "loading.grip",
                format!(
                    "applies to loading.kind = \"tension\", not \"{}\"",
                    l.kind.as_str()
                ),
            ));
        }
        LoadingKind::FreeVibration => {
            let mode = require(s, "loading.mode", l.mode, &why)?;
            let amplitude = match mode {
                VibrationMode::Tension => {
                    if let Some(a) = l.initial_strain {
                        check(
                            s,
                            "loading.initial_strain",
                            a,
                            Range::closed(-0.01, 0.01),
                            "",
                        )?;
                    }
                    l.initial_strain.unwrap_or(1e-5)
                }
                VibrationMode::Torsion => {
                    if let Some(t) = l.twist {
                        check(s, "loading.twist", t, Range::closed(-1.0, 1.0), "rad/m")?;
                    }
                    l.twist.unwrap_or(1e-4)
                }
            };
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            typed::LoadingSpec::FreeVibration(VibrationSpec {
                mode,
                amplitude,
                end_time: end,
            })
        }
        LoadingKind::Brazilian => {
            let v = require(s, "loading.speed", l.speed, &why)?;
            check(s, "loading.speed", v, Range::POSITIVE, "m/s")?;
            let end = require(s, "loading.end_strain", l.end_strain, &why)?;
            check(s, "loading.end_strain", end, Range::open(0.0, 1.0), "")?;
            let arc = l.arc_degrees.unwrap_or(0.0);
            check(
                s,
                "loading.arc_degrees",
                arc,
                Range::closed(0.0, 90.0),
                "degrees",
            )?;
            let by = l.load_by.unwrap_or(LoadBy::Elements);
            match by {
                by if by.presses() && arc > 0.0 => {
                    return Err(s.key_error(
                        "loading.arc_degrees",
                        format!(
                            "= {arc} is outside the allowed range [0, 0] degrees with loading.load_by = \"{}\", whose contact makes its own arc: leave it out or 0",
                            by.as_str()
                        ),
                    ));
                }
                LoadBy::ArcPressure if arc <= 0.0 => {
                    return Err(s.key_error(
                        "loading.arc_degrees",
                        "is 0, and loading.load_by = \"arc_pressure\" spreads its pressure over the loading arc: give it in the allowed range (0, 90] degrees",
                    ));
                }
                _ => {}
            }
            match (l.servo_stiffness, by) {
                (Some(k), LoadBy::ArcPressure) => {
                    check(s, "loading.servo_stiffness", k, Range::POSITIVE, "N/m")?;
                }
                (Some(_), _) => {
                    return Err(s.key_error(
                        "loading.servo_stiffness",
                        format!(
                            "applies to loading.load_by = \"arc_pressure\", not \"{}\"",
                            by.as_str()
                        ),
                    ));
                }
                (None, _) => {}
            }
            typed::LoadingSpec::Brazilian(BrazilianSpec {
                speed: v,
                end_strain: end,
                arc_degrees: arc,
                load_by: by,
                servo_stiffness: l.servo_stiffness,
                ramp_time: l.ramp_time,
                stop_fraction: l.stop_fraction,
            })
        }
        LoadingKind::Drop => {
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            if let Some(a) = l.ground_angle_degrees {
                check(
                    s,
                    "loading.ground_angle_degrees",
                    a,
                    Range::closed(0.0, 60.0),
                    "degrees",
                )?;
            }
            if let Some(h) = l.drop_height {
                check(s, "loading.drop_height", h, Range::NON_NEGATIVE, "m")?;
            }
            if let Some(v) = l.initial_velocity {
                if v.iter().any(|c| !c.is_finite()) {
                    return Err(
                        s.key_error("loading.initial_velocity", "has a non-finite component")
                    );
                }
            }
            typed::LoadingSpec::Drop(DropSpec {
                end_time: end,
                initial_velocity: l.initial_velocity.unwrap_or([0.0; 3]),
                ground_angle_degrees: l.ground_angle_degrees.unwrap_or(0.0),
                drop_height: l.drop_height.unwrap_or(0.0),
            })
        }
        LoadingKind::None => {
            let end = require(s, "loading.end_time", l.end_time, &why)?;
            check(s, "loading.end_time", end, Range::POSITIVE, "s")?;
            typed::LoadingSpec::None { end_time: end }
        }
    })
}
