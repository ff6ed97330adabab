//! Packings and run scripts in the formats of the peer codes, written at full precision so
//! that LAMMPS, YADE and Fractum start from the very same spheres, one file per format:
//! `lammps.rs` (a LAMMPS data file, `atom_style sphere`, `units si`, and an input script of
//! LAMMPS's own granular models), `yade.rs` (a YADE `ymport.text` file, `x y z r` per line, and
//! a YADE script) and `plugin.rs` (the data file with the grains' shapes, Fractum's first
//! forces and an input script for the Fractum LAMMPS plugin). Numbers are written in the
//! shortest form that reads back to the same double; the packing files carry the box. This
//! file holds what they share: the run's plan, the box, and `fractum export` itself.

use super::Simulation;
use super::loading::Loading;
use super::scene::GranularScene;
use crate::contact::restitution::damping_for_restitution;
use crate::error::{Error, Result};
use crate::probe::{BOX_COLUMNS, FREE_COLUMNS};
use crate::run::Model;
use crate::scene::{EffectKind, Scene};
use crate::state::{Bodies, BoxFace, Vec3, Walls};

mod lammps;
mod plugin;
mod yade;

pub use lammps::{lammps_data, lammps_input, lammps_restitution};
pub use plugin::{first_forces, plugin_data, plugin_input};
pub use yade::{yade_script, yade_text};

/// The lower and upper corners of the box of `walls` (the bodies' bounding box without one).
fn bounds(bodies: &Bodies, walls: &Walls) -> (Vec3, Vec3) {
    if walls.is_box {
        let lo = Vec3::new(
            walls.face(BoxFace::XMin).point.x,
            walls.face(BoxFace::YMin).point.y,
            walls.face(BoxFace::ZMin).point.z,
        );
        return (lo, lo + walls.box_size());
    }
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for (p, &r) in bodies.pos.iter().zip(&bodies.radius) {
        lo = lo.inf(&(p - Vec3::repeat(r)));
        hi = hi.sup(&(p + Vec3::repeat(r)));
    }
    (lo, hi)
}

/// What a peer-code script needs from a granular run: the scene, the starting state, the
/// time step and the number of steps Fractum takes.
pub struct RunPlan<'a> {
    pub scene: &'a Scene,
    pub cfg: &'a GranularScene,
    pub bodies: &'a Bodies,
    pub walls: &'a Walls,
    pub loading: &'a Loading,
    /// Whether a host drives the faces (then the loading is not in force).
    pub driven: bool,
    /// Time step (s).
    pub dt: f64,
    /// Steps of the run.
    pub steps: u64,
}

impl<'a> RunPlan<'a> {
    pub fn of(sim: &'a Simulation) -> Self {
        RunPlan {
            scene: &sim.scene,
            cfg: &sim.model.cfg,
            bodies: &sim.model.state.bodies,
            walls: &sim.model.state.walls,
            loading: &sim.model.state.loading,
            driven: sim.model.state.driven.is_some(),
            dt: sim.clock.dt,
            steps: sim.clock.end_step,
        }
    }

    /// The neighbour skin (m) Fractum's run uses: the scene's `neighbor.skin`, else the
    /// contact effect's default.
    fn skin(&self) -> f64 {
        self.cfg
            .neighbor
            .skin
            .unwrap_or_else(|| crate::effects::contact::default_skin(self.bodies))
    }

    fn has(&self, e: EffectKind) -> bool {
        self.scene.effects.contains(&e)
    }

    /// The dimensionless damping coefficient c of Fractum's contact law (0 without damping).
    fn damping_coefficient(&self) -> f64 {
        if self.has(EffectKind::Damping) {
            damping_for_restitution(self.cfg.material.restitution)
        } else {
            0.0
        }
    }

    fn wall_friction(&self) -> f64 {
        self.cfg
            .walls
            .friction
            .unwrap_or(self.cfg.material.friction)
    }

    /// The sleeve's friction coefficient, as the contact effect defaults it: its own, else
    /// the walls', else the grains'.
    fn sleeve_friction(&self) -> f64 {
        self.cfg
            .walls
            .sleeve_friction
            .unwrap_or_else(|| self.wall_friction())
    }

    /// Speed of the driven top wall (m/s, downwards) and the box height at the start.
    fn top_speed(&self) -> Option<(f64, f64)> {
        match self.loading {
            Loading::Oedometer(o) => Some((o.strain_rate * o.height0, o.height0)),
            _ => None,
        }
    }
}

/// Refuses what the peer codes cannot reproduce (every granular sphere scene can be, but faces
/// driven by a host have no script equivalent).
fn check_exportable(plan: &RunPlan, code: &str) -> Result<()> {
    if plan.driven {
        return Err(Error::input(
            &plan.scene.source.label,
            format!("faces driven from outside (FFI/FMU) cannot be exported to {code}"),
        ));
    }
    Ok(())
}

/// `fractum export lammps|yade`: the scene's sample and a peer-code script that runs it
/// (`lammps`: packing.data and in.fractum; otherwise packing.txt and fractum_yade.py) in
/// `dir`. With `plugin` (LAMMPS only) the script uses the Fractum LAMMPS plugin, the data file
/// carries the grains' shapes, and forces0.csv holds Fractum's first force evaluation. Returns
/// the line that says what was written.
pub fn export(
    scene: Scene,
    lammps: bool,
    plugin: bool,
    dir: &std::path::Path,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<String> {
    // Checked first: another model's scene would otherwise be read as a granular one and
    // refused for keys it rightly has.
    if scene.model.kind != super::Granular::KIND {
        return Err(scene.key_error(
            "model.kind",
            format!(
                "= \"{}\": `fractum export` writes granular scenes only (model.kind = \"granular\")",
                scene.model.kind
            ),
        ));
    }
    if plugin && !lammps {
        return Err(Error::input(
            &scene.source.label,
            "--plugin applies to `fractum export lammps` only",
        ));
    }
    let cfg = super::Granular::read(&scene)?;
    if cfg.walls.sleeve && !plugin {
        let code = if lammps { "lammps" } else { "yade" };
        return Err(scene.key_error(
            "walls.sleeve",
            format!(
                "= true: `fractum export {code}` writes flat walls only, and the sleeve (a cylinder) has no counterpart there (`fractum export lammps --plugin` writes it: the plugin's fix fractum/platens has the sleeve)"
            ),
        ));
    }
    let sample = super::sample::build(&scene, &cfg, progress)?;
    let count = sample.bodies.len();
    let sim = Simulation::from_sample(scene, sample, 1)?;
    let plan = RunPlan::of(&sim);
    let name = &sim.scene.name;
    let (bodies, walls) = (&sim.model.state.bodies, &sim.model.state.walls);
    // The plain exports write spheres and LAMMPS's or YADE's own contact laws: a grain of
    // another shape would become its bounding sphere (the Mason sand ellipsoids then fill 1.4
    // times their box), so those scenes are refused; what they leave out of a sphere scene is
    // said in the line returned and at the top of the script.
    let mut dropped = String::new();
    if !plugin {
        let code = if lammps { "lammps" } else { "yade" };
        let shaped = bodies
            .shape
            .iter()
            .filter(|s| !matches!(s, crate::shape::Shape::Sphere))
            .count();
        if shaped > 0 {
            return Err(Error::input(
                &sim.scene.source.label,
                format!(
                    "{shaped} of the sample's {count} grains are not spheres, and `fractum export \
                     {code}` writes spheres only (each grain would become its bounding sphere); \
                     `fractum export lammps --plugin` exports their shapes"
                ),
            ));
        }
        let effects: Vec<String> = [
            EffectKind::Fracture,
            EffectKind::Cohesion,
            EffectKind::Weibull,
        ]
        .into_iter()
        .filter(|e| plan.has(*e))
        .map(|e| format!("\"{}\"", e.as_str()))
        .collect();
        if !effects.is_empty() {
            dropped = format!(
                "not exported: the effects {} (the peer code's contact law does not break \
                 grains; `fractum export lammps --plugin` runs them)",
                effects.join(", ")
            );
        }
    }
    let noted = |script: String| {
        if dropped.is_empty() {
            script
        } else {
            format!("# {dropped}\n{script}")
        }
    };
    let files: Vec<(&str, String)> = if plugin {
        vec![
            ("packing.data", plugin_data(&sim, name)),
            (
                "in.fractum",
                plugin_input(&sim, "packing.data", "series_lammps.csv")?,
            ),
            ("forces0.csv", first_forces(&sim)),
        ]
    } else if lammps {
        vec![
            (
                "packing.data",
                lammps_data(bodies, walls, |_| sim.model.cfg.material.density, name),
            ),
            (
                "in.fractum",
                noted(lammps_input(&plan, "packing.data", "series_lammps.csv")?),
            ),
        ]
    } else {
        vec![
            ("packing.txt", yade_text(bodies, walls, name)),
            (
                "fractum_yade.py",
                noted(yade_script(&plan, "packing.txt", "series_yade.csv")?),
            ),
        ]
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "create the folder", e))?;
    for (file, text) in &files {
        crate::output::write_atomic(&dir.join(file), text.as_bytes())?;
    }
    let names: Vec<&str> = files.iter().map(|f| f.0).collect();
    let dropped = if dropped.is_empty() {
        dropped
    } else {
        format!("; {dropped}")
    };
    Ok(format!(
        "{name}: wrote {} in {} ({count} grains, {} steps of {:.4e} s){dropped}",
        names.join(", "),
        dir.display(),
        sim.clock.end_step,
        sim.clock.dt
    ))
}
