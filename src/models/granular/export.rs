//! Packings in the formats of the peer codes, written at full precision so that LAMMPS, YADE
//! and Fractum start from the very same spheres: a LAMMPS data file (`atom_style sphere`,
//! `units si`) and a YADE `ymport.text` file (`x y z r` per line). Numbers are written in the
//! shortest form that reads back to the same double; both files carry the box.

use std::fmt::Write;

use super::Simulation;
use super::loading::Loading;
use super::scene::GranularScene;
use crate::contact::restitution::damping_for_restitution;
use crate::error::{Error, Result};
use crate::probe::{BOX_COLUMNS, FREE_COLUMNS};
use crate::run::Model;
use crate::scene::{EffectKind, Scene};
use crate::state::{Bodies, BoxFace, Vec3, Walls};

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

/// A LAMMPS data file: atom IDs from 1 in Fractum's order, one atom type, diameters and
/// densities per atom (`density(i)`, kg/m³), and the initial velocities.
pub fn lammps_data(
    bodies: &Bodies,
    walls: &Walls,
    density: impl Fn(usize) -> f64,
    title: &str,
) -> String {
    let (lo, hi) = bounds(bodies, walls);
    let mut s = format!(
        "{title} (Fractum, units si, atom_style sphere)\n\n{} atoms\n1 atom types\n\n",
        bodies.len()
    );
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(s, "{:e} {:e} {name}lo {name}hi", lo[a], hi[a]);
    }
    s.push_str("\nAtoms # sphere\n\n");
    for (i, (p, r)) in bodies.pos.iter().zip(&bodies.radius).enumerate() {
        let _ = writeln!(
            s,
            "{} 1 {:e} {:e} {:e} {:e} {:e}",
            i + 1,
            2.0 * r,
            density(i),
            p.x,
            p.y,
            p.z
        );
    }
    s.push_str("\nVelocities\n\n");
    for (i, (v, w)) in bodies.vel.iter().zip(&bodies.omega).enumerate() {
        let _ = writeln!(
            s,
            "{} {:e} {:e} {:e} {:e} {:e} {:e}",
            i + 1,
            v.x,
            v.y,
            v.z,
            w.x,
            w.y,
            w.z
        );
    }
    s
}

/// A YADE `ymport.text` file (`x y z r`), with the box as a `# box` comment that YADE skips
/// and Fractum's text import reads.
pub fn yade_text(bodies: &Bodies, walls: &Walls, title: &str) -> String {
    let (lo, hi) = bounds(bodies, walls);
    let mut s = format!(
        "# {title} (Fractum): x y z r in metres\n# box {:e} {:e} {:e} {:e} {:e} {:e}\n",
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
    );
    for (p, r) in bodies.pos.iter().zip(&bodies.radius) {
        let _ = writeln!(s, "{:e} {:e} {:e} {:e}", p.x, p.y, p.z, r);
    }
    s
}

/// What a peer-code script needs from a granular run: the scene, the starting state, the
/// time step and the number of steps Fractum takes.
pub struct RunPlan<'a> {
    pub scene: &'a Scene,
    pub cfg: &'a GranularScene,
    pub bodies: &'a Bodies,
    pub walls: &'a Walls,
    pub loading: &'a Loading,
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

    /// Speed of the driven top wall (m/s, downwards) and the box height at the start.
    fn top_speed(&self) -> Option<(f64, f64)> {
        match self.loading {
            Loading::Oedometer {
                strain_rate,
                height0,
                ..
            } => Some((strain_rate * height0, *height0)),
            _ => None,
        }
    }
}

/// The restitution to give LAMMPS `damping coeff_restitution` so that its damping force
/// equals Fractum's `c sqrt(m* S_n) v_n`.
///
/// LAMMPS (2023 and later, `gran_sub_mod_damping.cpp`) uses
/// `η = sqrt(3/2) 2 sqrt(5/6) β sqrt(m* F_n/δ)` with `F_n/δ = 4/3 E* a = 2/3 S_n`, i.e.
/// `η = 2 sqrt(5/6) β sqrt(m* S_n)`, and `β = -ln e / sqrt(ln² e + π²)`. So
/// `β = c / (2 sqrt(5/6))` and `e_L = exp(-π β / sqrt(1 - β²))`. e_L differs from the
/// restitution Fractum is asked for (0.5 → 0.4363) because LAMMPS's β comes from a linear
/// spring; the force law, and so the restitution obtained, is then the same in both codes.
pub fn lammps_restitution(c: f64) -> f64 {
    if c <= 0.0 {
        return 1.0;
    }
    let beta = c / (2.0 * (5.0_f64 / 6.0).sqrt());
    assert!(beta < 1.0, "damping coefficient {c} is beyond critical");
    (-std::f64::consts::PI * beta / (1.0 - beta * beta).sqrt()).exp()
}

/// Refuses what the peer codes cannot reproduce (every granular sphere scene can be, but faces
/// driven by a host have no script equivalent).
fn check_exportable(plan: &RunPlan, code: &str) -> Result<()> {
    if let Loading::Faces { .. } = plan.loading {
        return Err(Error::input(
            &plan.scene.source.label,
            format!("faces driven from outside (FFI/FMU) cannot be exported to {code}"),
        ));
    }
    Ok(())
}

/// The contact-model arguments of `pair_coeff` / `fix wall/gran` for friction `mu`.
fn lammps_model(plan: &RunPlan, mu: f64) -> String {
    let m = &plan.cfg.material;
    let c = plan.damping_coefficient();
    let damping = if c > 0.0 {
        "damping coeff_restitution"
    } else {
        "damping none"
    };
    let tangential = if plan.has(EffectKind::Friction) {
        format!("tangential mindlin NULL 1.0 {mu:e}")
    } else {
        "tangential linear_nohistory 0.0 0.0".to_string()
    };
    format!(
        "hertz/material {:e} {:.17e} {:e} {tangential} {damping} limit_damping",
        m.young,
        lammps_restitution(c),
        m.poisson()
    )
}

/// A LAMMPS input script (units si) that runs the scene from `data_file`: the same contact
/// law (Hertz with E*, Mindlin k_t = 8 G* a, damping, Coulomb limit), the same walls (one
/// `fix wall/gran` per face; the oedometer's top face a moving plane region), the same time
/// step and number of steps, and a `fix print` of series.csv's columns to `series_file`.
pub fn lammps_input(plan: &RunPlan, data_file: &str, series_file: &str) -> Result<String> {
    check_exportable(plan, "LAMMPS")?;
    let scene = plan.scene;
    let every = scene.output.every.max(1);
    let model = lammps_model(plan, plan.cfg.material.friction);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# LAMMPS input written by `fractum export lammps` from {} (scene \"{}\").\n\
         # Needs LAMMPS 2023 or later with the GRANULAR package (damping none/coeff_restitution).\n\
         # Run: lmp -in in.fractum   (or mpirun -np N lmp -in in.fractum)\n\
         # Units si: m, kg, s, N, Pa. series columns as Fractum's series.csv (compression positive).",
        scene.source.label, scene.name
    );
    let boundary = if plan.walls.is_box { "f f f" } else { "m m m" };
    let _ = writeln!(
        s,
        "units           si\natom_style      sphere\ndimension       3\nboundary        {boundary}\n\
         newton          off\ncomm_modify     vel yes\nread_data       {data_file}\n"
    );
    let _ = writeln!(
        s,
        "# Fractum restitution {} -> damping coefficient c = {:.10} -> LAMMPS coeff_restitution {:.10}",
        plan.cfg.material.restitution,
        plan.damping_coefficient(),
        lammps_restitution(plan.damping_coefficient())
    );
    let _ = writeln!(s, "pair_style      granular\npair_coeff      * * {model}");
    let skin = plan.skin();
    let _ = writeln!(
        s,
        "neighbor        {skin:e} bin\nneigh_modify    delay 0 every 1 check yes\n\
         timestep        {:.17e}\nfix             integrate all nve/sphere",
        plan.dt
    );
    if plan.has(EffectKind::Gravity) {
        let g = Vec3::from(scene.gravity.acceleration);
        if g.norm() > 0.0 {
            let d = g.normalize();
            let _ = writeln!(
                s,
                "fix             gravity all gravity {:e} vector {:e} {:e} {:e}",
                g.norm(),
                d.x,
                d.y,
                d.z
            );
        }
    }
    let _ = writeln!(
        s,
        "# compute ke sums m v^2/2 (thermo's ke comes from the temperature, without the 3 centre-of-mass dof)\n\
         compute         trans all ke\ncompute         rot all erotate/sphere\ncompute         cpa all contact/atom\n\
         compute         npair all reduce sum c_cpa\nvariable        ke equal c_trans+c_rot\n\
         variable        contacts equal c_npair/2"
    );
    let mut columns: Vec<&str> = FREE_COLUMNS.to_vec();
    let mut values = vec!["time", "v_ke", "v_contacts"];
    if plan.walls.is_box {
        let wall_model = lammps_model(plan, plan.wall_friction());
        let lo = plan.walls.face(BoxFace::ZMin).point.z;
        let l0 = plan.walls.box_size();
        let x0 = plan.walls.face(BoxFace::XMin).point.x;
        let y0 = plan.walls.face(BoxFace::YMin).point.y;
        let top0 = lo + l0.z;
        let speed = plan.top_speed().map_or(0.0, |v| v.0);
        let _ = writeln!(
            s,
            "\n# The box: five fixed faces and the top face, a plane moving down at {speed:e} m/s.\n\
             variable        ztop equal {top0:.17e}-{speed:.17e}*time\n\
             variable        dz equal -{speed:.17e}*time\n\
             region          top plane 0 0 {top0:.17e} 0 0 -1 side in move NULL NULL v_dz units box"
        );
        let faces = [
            ("xlo", format!("xplane {:.17e} NULL", x0)),
            ("xhi", format!("xplane NULL {:.17e}", x0 + l0.x)),
            ("ylo", format!("yplane {:.17e} NULL", y0)),
            ("yhi", format!("yplane NULL {:.17e}", y0 + l0.y)),
            ("zlo", format!("zplane {:.17e} NULL", lo)),
        ];
        for (name, plane) in &faces {
            let _ = writeln!(
                s,
                "fix             {name} all wall/gran granular {wall_model} {plane} contacts"
            );
        }
        let _ = writeln!(
            s,
            "fix             zhi all wall/gran/region granular {wall_model} region top contacts"
        );
        let _ = writeln!(
            s,
            "# per-face sums of the contact flag and of the force on the grains\n\
             variable        lx equal {:.17e}\nvariable        ly equal {:.17e}\n\
             variable        lz equal v_ztop-{lo:.17e}",
            l0.x, l0.y
        );
        for (name, axis) in [
            ("xlo", 5),
            ("xhi", 5),
            ("ylo", 6),
            ("yhi", 6),
            ("zlo", 7),
            ("zhi", 7),
        ] {
            let _ = writeln!(
                s,
                "compute         n{name} all reduce sum f_{name}[1]\n\
                 compute         f{name} all reduce sum f_{name}[{}]",
                axis - 3
            );
        }
        let vol = plan.bodies.solid_volume();
        let _ = writeln!(
            s,
            "variable        strain equal ({:.17e}-v_lz)/{:.17e}\n\
             variable        sdriven equal -c_fzhi/(v_lx*v_ly)\n\
             variable        sopposite equal c_fzlo/(v_lx*v_ly)\n\
             variable        slatx equal 0.5*(c_fxlo-c_fxhi)/(v_ly*v_lz)\n\
             variable        slaty equal 0.5*(c_fylo-c_fyhi)/(v_lx*v_lz)\n\
             variable        wcontacts equal c_nxlo+c_nxhi+c_nylo+c_nyhi+c_nzlo+c_nzhi\n\
             variable        phi equal {vol:.17e}/(v_lx*v_ly*v_lz)",
            l0.z, l0.z
        );
        columns = BOX_COLUMNS.to_vec();
        values = vec![
            "time",
            "v_strain",
            "v_sdriven",
            "v_sopposite",
            "v_slatx",
            "v_slaty",
            "v_ke",
            "v_contacts",
            "v_wcontacts",
            "v_phi",
        ];
    }
    let line: Vec<String> = values.iter().map(|v| format!("$({v}:%.10e)")).collect();
    let line = line.join(",");
    let _ = writeln!(
        s,
        "\nfix             series all print {every} \"{line}\" file {series_file} screen no title \"{}\"\n\
         thermo          {}\nthermo_style    custom step time ke\nrun             {}",
        columns.join(","),
        (plan.steps / 20).max(every),
        plan.steps
    );
    if plan.steps % every != 0 {
        // Fractum records the last step too.
        let _ = writeln!(
            s,
            "print           \"{line}\" append {series_file} screen no"
        );
    }
    Ok(s)
}

/// A YADE script (Python, run with `yade -n -x script.py`) that runs the scene from the
/// `ymport.text` file `packing_file`: FrictMat grains, `Ip2_FrictMat_FrictMat_MindlinPhys` and
/// `Law2_ScGeom_MindlinPhys_Mindlin`, six `utils.wall` faces (the oedometer's top face moving
/// down), the same time step and number of steps, and series.csv's columns every
/// `output.every` steps to `series_file`.
///
/// What YADE does differently: its Mindlin law takes the damping as a ratio `betan` of the
/// critical `2 sqrt(m* k_n)` with `k_n` the tangent stiffness `S_n`, so `betan = c/2` gives
/// Fractum's normal damping (tangential `betas` set equal). It takes `R* = R/2` for a sphere on
/// a wall where Fractum and LAMMPS take `R* = R`: the script gives the walls the Young's
/// modulus `E/(√2 − 1)`, which restores the normal force (not the wall's shear stiffness).
pub fn yade_script(plan: &RunPlan, packing_file: &str, series_file: &str) -> Result<String> {
    check_exportable(plan, "YADE")?;
    let scene = plan.scene;
    let m = &plan.cfg.material;
    let every = scene.output.every.max(1);
    let fric = plan.has(EffectKind::Friction);
    let mu = if fric { m.friction } else { 0.0 };
    let mu_wall = if fric { plan.wall_friction() } else { 0.0 };
    let beta = 0.5 * plan.damping_coefficient();
    let g = if plan.has(EffectKind::Gravity) {
        scene.gravity.acceleration
    } else {
        [0.0; 3]
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"# YADE script written by `fractum export yade` from {label} (scene "{name}").
# Run: yade -n -x {{this file}}   (headless; YADE 2023 or later). SI units.
# Columns of {series_file} as Fractum's series.csv (compression positive).
import math
from yade import ymport, utils

E, NU, RHO = {e:.17e}, {nu:.17e}, {rho:.17e}
MU, MU_WALL = {mu:.17e}, {mu_wall:.17e}
BETA = {beta:.17e}     # Fractum damping coefficient c = {c:.10} (restitution {rest}) -> betan = c/2
DT, STEPS, EVERY = {dt:.17e}, {steps}, {every}

grains = O.materials.append(FrictMat(young=E, poisson=NU, density=RHO, frictionAngle=math.atan(MU), label='grains'))
# YADE's Ip2 takes R* = R/2 for a sphere on a wall (both radii = the sphere's); Fractum and
# LAMMPS take R* = R. A wall of Young's modulus E/(sqrt(2)-1) gives E* sqrt(R*) and so the same
# normal force at the same overlap (its shear modulus then differs: wall friction is not the same).
wallmat = O.materials.append(FrictMat(young=E / (math.sqrt(2.0) - 1.0), poisson=NU, density=RHO, frictionAngle=math.atan(MU_WALL), label='walls'))
spheres = O.bodies.append(ymport.text('{packing_file}', material=grains))
vol = sum(4.0 / 3.0 * math.pi * O.bodies[i].shape.radius ** 3 for i in spheres)
"#,
        label = scene.source.label,
        name = scene.name,
        e = m.young,
        nu = m.poisson(),
        rho = m.density,
        c = plan.damping_coefficient(),
        rest = m.restitution,
        dt = plan.dt,
        steps = plan.steps,
    );
    // Initial velocities: the packing file holds positions only.
    let moving: Vec<usize> = (0..plan.bodies.len())
        .filter(|&i| plan.bodies.vel[i] != Vec3::zeros() || plan.bodies.omega[i] != Vec3::zeros())
        .collect();
    if !moving.is_empty() {
        s.push_str("vel0 = {\n");
        for i in moving {
            let (v, w) = (plan.bodies.vel[i], plan.bodies.omega[i]);
            let _ = writeln!(
                s,
                "    {i}: (({:e}, {:e}, {:e}), ({:e}, {:e}, {:e})),",
                v.x, v.y, v.z, w.x, w.y, w.z
            );
        }
        s.push_str(
            "}\nfor k, (v, w) in vel0.items():\n    O.bodies[spheres[k]].state.vel = Vector3(*v)\n    O.bodies[spheres[k]].state.angVel = Vector3(*w)\n",
        );
    }
    let mut record = String::from(
        "def contacts():\n    pair = wall = 0\n    for i in O.interactions:\n        if not i.isReal:\n            continue\n        if i.id1 in wall_ids or i.id2 in wall_ids:\n            wall += 1\n        else:\n            pair += 1\n    return pair, wall\n\n",
    );
    if plan.walls.is_box {
        let lo = Vec3::new(
            plan.walls.face(BoxFace::XMin).point.x,
            plan.walls.face(BoxFace::YMin).point.y,
            plan.walls.face(BoxFace::ZMin).point.z,
        );
        let l0 = plan.walls.box_size();
        let speed = plan.top_speed().map_or(0.0, |v| v.0);
        let _ = writeln!(
            s,
            "LO = ({:.17e}, {:.17e}, {:.17e})\nL0 = ({:.17e}, {:.17e}, {:.17e})\nSPEED = {speed:.17e}   # top face, m/s downwards\n\
             faces = {{}}\nfor name, axis, pos, sense in [('xlo', 0, LO[0], 1), ('xhi', 0, LO[0] + L0[0], -1),\n\
             \x20                                ('ylo', 1, LO[1], 1), ('yhi', 1, LO[1] + L0[1], -1),\n\
             \x20                                ('zlo', 2, LO[2], 1), ('zhi', 2, LO[2] + L0[2], -1)]:\n\
             \x20   faces[name] = O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=wallmat))\n\
             O.bodies[faces['zhi']].state.vel = Vector3(0, 0, -SPEED)\nwall_ids = set(faces.values())\n",
            lo.x, lo.y, lo.z, l0.x, l0.y, l0.z
        );
        let _ = write!(
            record,
            "def record():\n    # PyRunner runs after NewtonIntegrator: the forces are those of O.time, the wall has\n    # already moved on by one step.\n    top = O.bodies[faces['zhi']].state\n    lz = top.pos[2] - top.vel[2] * O.dt - LO[2]\n    lx, ly = L0[0], L0[1]\n\
             \x20   f = {{k: O.forces.f(i) for k, i in faces.items()}}\n    pair, wall = contacts()\n\
             \x20   row = [O.time, (L0[2] - lz) / L0[2], f['zhi'][2] / (lx * ly), -f['zlo'][2] / (lx * ly),\n\
             \x20          0.5 * (f['xhi'][0] - f['xlo'][0]) / (ly * lz), 0.5 * (f['yhi'][1] - f['ylo'][1]) / (lx * lz),\n\
             \x20          utils.kineticEnergy(), pair, wall, vol / (lx * ly * lz)]\n\
             \x20   out.write(','.join('%.10e' % v for v in row) + '\\n')\n\n"
        );
        let _ = writeln!(s, "COLUMNS = {:?}", BOX_COLUMNS.join(","));
    } else {
        s.push_str("wall_ids = set()\n");
        record.push_str(
            "def record():\n    pair, wall = contacts()\n    row = [O.time, utils.kineticEnergy(), pair]\n    out.write(','.join('%.10e' % v for v in row) + '\\n')\n\n",
        );
        let _ = writeln!(s, "COLUMNS = {:?}", FREE_COLUMNS.join(","));
    }
    let skin = plan.skin();
    let _ = write!(
        s,
        r#"
out = open('{series_file}', 'w')
out.write(COLUMNS + '\n')
{record}O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()], verletDist={skin:e}),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_MindlinPhys(betan=BETA, betas=BETA)],
        [Law2_ScGeom_MindlinPhys_Mindlin()],
    ),
    NewtonIntegrator(damping=0.0, gravity=Vector3({gx:e}, {gy:e}, {gz:e})),
    PyRunner(iterPeriod=EVERY, command='record()', initRun=True),
]
O.dt = DT
O.run(STEPS, True)   # rows at every EVERY-th step from 0; none after the last of them
out.close()
"#,
        gx = g[0],
        gy = g[1],
        gz = g[2],
    );
    Ok(s)
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
    let cfg: GranularScene = scene.section()?;
    let sample = super::sample::build(&scene, &cfg, progress)?;
    let count = sample.bodies.len();
    let sim = Simulation::from_sample(scene, sample, 1)?;
    let plan = RunPlan::of(&sim);
    let name = &sim.scene.name;
    let (bodies, walls) = (&sim.model.state.bodies, &sim.model.state.walls);
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
                lammps_input(&plan, "packing.data", "series_lammps.csv")?,
            ),
        ]
    } else {
        vec![
            ("packing.txt", yade_text(bodies, walls, name)),
            (
                "fractum_yade.py",
                yade_script(&plan, "packing.txt", "series_yade.csv")?,
            ),
        ]
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "create the folder", e))?;
    for (file, text) in &files {
        crate::output::write_atomic(&dir.join(file), text.as_bytes())?;
    }
    let names: Vec<&str> = files.iter().map(|f| f.0).collect();
    Ok(format!(
        "{name}: wrote {} in {} ({count} grains, {} steps of {:.4e} s)",
        names.join(", "),
        dir.display(),
        sim.clock.end_step,
        sim.clock.dt
    ))
}

/// The box faces of the plugin (`fix fractum/platens`), in its order.
const PLUGIN_FACES: [&str; 6] = ["xlo", "xhi", "ylo", "yhi", "zlo", "zhi"];

/// The face of `fix fractum/platens` a wall is, from its normal (into the bodies' side), and
/// the position of its plane along that axis; `None` for a wall not normal to an axis.
fn plugin_face(normal: &Vec3, point: &Vec3) -> Option<(usize, f64)> {
    for axis in 0..3 {
        let mut e = Vec3::zeros();
        e[axis] = 1.0;
        if *normal == e {
            return Some((2 * axis, point[axis]));
        }
        if *normal == -e {
            return Some((2 * axis + 1, point[axis]));
        }
    }
    None
}

/// The plugin's data file: `atom_style sphere` atoms (IDs from 1 in Fractum's order, the
/// bounding diameter, the density that gives each body its mass) and the sections the
/// plugin's `fix property/atom` arrays read (docs/lammps.md): the shape (sphere flag,
/// semi-axes), the orientation with the octant origin, the principal inertia with the
/// shape-to-body turn, and the grain state (Weibull factor, sample grain, splits, springs). Every number is written at
/// full precision (shortest round trip).
pub fn plugin_data(sim: &Simulation, title: &str) -> String {
    let st = &sim.model.state;
    let (bodies, walls) = (&st.bodies, &st.walls);
    // The mass through LAMMPS's density column: mass / the bounding sphere's volume.
    let mut s = lammps_data(
        bodies,
        walls,
        |i| bodies.mass[i] / crate::shape::sphere_volume(bodies.radius[i]),
        title,
    );
    let fracture = st.fracture.as_ref();
    // One section per array: read_data reads a section's lines into 256-character buffers,
    // which seven numbers at full precision fit.
    let mut sections: [(&str, String); 4] = [
        ("FractumShape", String::new()),
        ("FractumOrient", String::new()),
        ("FractumInertia", String::new()),
        ("FractumGrain", String::new()),
    ];
    for i in 0..bodies.len() {
        let q = bodies.orientation[i];
        let (sphere, semi, origin, to_body) = match &bodies.shape[i] {
            crate::shape::Shape::PolyEllipsoid {
                pe,
                origin,
                to_body,
            } => (0.0, pe.semi, *origin, *to_body),
            _ => (
                1.0,
                [bodies.radius[i]; 6],
                Vec3::zeros(),
                nalgebra::UnitQuaternion::identity(),
            ),
        };
        let inertia = bodies.inertia[i];
        let (strength, grain, generation, bonds) = match fracture {
            Some(f) => (
                f.strength[i],
                f.origin[i] as f64 + 1.0,
                f.generation[i] as f64,
                f.bonds[i] as f64,
            ),
            None => (1.0, i as f64 + 1.0, 0.0, 0.0),
        };
        let rows: [Vec<f64>; 4] = [
            std::iter::once(sphere).chain(semi).collect(),
            vec![q.w, q.i, q.j, q.k, origin.x, origin.y, origin.z],
            vec![
                inertia.x, inertia.y, inertia.z, to_body.w, to_body.i, to_body.j, to_body.k,
            ],
            // The parent's tag: 0 for a grain of the sample (the plugin fills it at splits).
            vec![strength, grain, generation, bonds, 0.0],
        ];
        for ((_, text), row) in sections.iter_mut().zip(rows) {
            let _ = write!(text, "{}", i + 1);
            for v in row {
                let _ = write!(text, " {v:e}");
            }
            text.push('\n');
        }
    }
    for (name, text) in &sections {
        let _ = write!(s, "\n{name}\n\n{text}");
    }
    s
}

/// Fractum's first force evaluation (the one before the first step), per body: the CSV
/// `id,fx,fy,fz,tx,ty,tz` (N, N m) that a LAMMPS `run 0` with the plugin must reproduce.
pub fn first_forces(sim: &Simulation) -> String {
    let f = &sim.model.state.forces;
    let mut s = String::from("id,fx,fy,fz,tx,ty,tz\n");
    for i in 0..f.force.len() {
        let (a, t) = (f.force[i], f.torque[i]);
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e},{:e},{:e}",
            i + 1,
            a.x,
            a.y,
            a.z,
            t.x,
            t.y,
            t.z
        );
    }
    s
}

/// A LAMMPS input that runs the scene with the Fractum plugin from `data_file`: Fractum's
/// contact law for spheres and poly-ellipsoids (`pair fractum/granular`), its integrator
/// (`fix fractum/nve/polyell`), its walls as moving box faces (`fix fractum/platens`) and,
/// with the `fracture` effect, grain fracture (`fix fractum/fracture`), at Fractum's time
/// step for Fractum's number of steps. `series_file` gets, every `output.every` steps, the
/// time, each face's force (N, the grains on the face along its axis) and position (m), the
/// number of atoms and, with fracture, the splits and grains broken.
pub fn plugin_input(sim: &Simulation, data_file: &str, series_file: &str) -> Result<String> {
    let plan = RunPlan::of(sim);
    check_exportable(&plan, "LAMMPS")?;
    let scene = plan.scene;
    let st = &sim.model.state;
    let m = &plan.cfg.material;
    if plan.has(EffectKind::Gravity) {
        return Err(Error::input(
            &scene.source.label,
            "gravity is not exported to the Fractum LAMMPS plugin (use LAMMPS's fix gravity by hand)",
        ));
    }
    let every = scene.output.every.max(1);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# LAMMPS input written by `fractum export lammps --plugin` from {} (scene \"{}\").\n\
         # Needs the Fractum plugin: make lammps-plugin (dist/fractumplugin.so); run with\n\
         #   lmp -in in.fractum -var plugin /path/to/dist/fractumplugin.so\n\
         # Units si: m, kg, s, N, Pa.",
        scene.source.label, scene.name
    );
    let boundary = if st.walls.is_empty() {
        "m m m"
    } else {
        "f f f"
    };
    let plugin = std::env::current_exe()
        .ok()
        .and_then(|exe| exe.parent()?.parent()?.parent().map(|p| p.join("dist")))
        .map(|d| d.join("fractumplugin.so").display().to_string())
        .unwrap_or_else(|| "dist/fractumplugin.so".into());
    let _ = writeln!(
        s,
        "variable        plugin index {plugin}\nplugin          load ${{plugin}}\n\
         units           si\natom_style      sphere\natom_modify     map array\ndimension       3\n\
         boundary        {boundary}\nnewton          off\ncomm_modify     vel yes\n\
         # Fractum's per-atom data (docs/lammps.md): shape, orientation, inertia and grain state\n\
         # from the data file; cohesive springs (21 numbers each) and the faces' contact histories\n\
         fix             frshape all property/atom d2_fr_shape 7 ghost yes\n\
         fix             frorient all property/atom d2_fr_orient 7 ghost yes\n\
         fix             frinertia all property/atom d2_fr_inertia 7 ghost yes\n\
         fix             frgrain all property/atom d2_fr_grain 5 ghost yes\n\
         # how far each body may have moved (m, summed by fix fractum/nve/polyell): the pair's\n\
         # separated pairs' skip reads it (leave it out and every candidate is searched)\n\
         fix             frtravel all property/atom d2_fr_travel 1 ghost yes\n\
         fix             frstate all property/atom d2_fr_springs {} d2_fr_walls 42 d2_fr_last 7\n\
         read_data       {data_file} fix frshape NULL FractumShape fix frorient NULL FractumOrient &\n\
         \x20               fix frinertia NULL FractumInertia fix frgrain NULL FractumGrain\n",
        21 * plan.cfg.fracture.springs.max(1)
    );
    if !st.walls.is_empty() {
        // LAMMPS drops an atom whose centre leaves a fixed boundary: a grain pressed into a
        // wall, or a half made at a split there, can have its centre beyond the wall plane (the
        // main job on 2 ranks stopped at 0.39 strain: "a half lies outside the simulation
        // box"), and pieces between two platens fly off sideways. The domain grows; the walls
        // stay where fix fractum/platens puts them.
        let b = &st.bodies;
        let margin = if st.walls.is_box {
            b.max_radius()
        } else {
            let (lo, hi) = bounds(b, &st.walls);
            (hi - lo).max() + b.max_radius()
        };
        let _ = writeln!(
            s,
            "change_box      all x delta {lo:e} {margin:e} y delta {lo:e} {margin:e} z delta {lo:e} {margin:e} units box",
            lo = -margin
        );
    }
    let mut coeff = format!("young {:e} poisson {:e}", m.young, m.poisson());
    if plan.has(EffectKind::Damping) {
        let _ = write!(coeff, " restitution {:e}", m.restitution);
    }
    if plan.has(EffectKind::Friction) {
        let _ = write!(coeff, " friction {:e}", m.friction);
    }
    let skin = plan.skin();
    let _ = writeln!(
        s,
        "pair_style      fractum/granular\npair_coeff      * * {coeff}\n\
         neighbor        {skin:e} bin\nneigh_modify    delay 0 every 1 check yes\n\
         timestep        {:.17e}\nfix             integrate all fractum/nve/polyell",
        plan.dt
    );
    let mut faces = String::new();
    let mut present = Vec::new();
    for w in &st.walls.walls {
        let Some((face, pos)) = plugin_face(&w.normal, &w.point) else {
            return Err(Error::input(
                &scene.source.label,
                format!(
                    "wall {} is not normal to an axis: the plugin's platens are box faces",
                    w.label
                ),
            ));
        };
        let _ = write!(faces, " {} {pos:.17e}", PLUGIN_FACES[face]);
        present.push(face);
    }
    // The driven faces: the loading's speeds at the start (constant for the oedometer and the
    // platens).
    let mut drive = String::new();
    for w in &st.walls.walls {
        let (face, _) = plugin_face(&w.normal, &w.point).expect("checked above");
        let speed = match plan.loading {
            Loading::Oedometer {
                strain_rate,
                height0,
                ..
            } if face == 5 => -strain_rate * height0,
            Loading::Platens { speed, .. } if face == 5 => -speed,
            _ => w.velocity[face / 2],
        };
        if speed != 0.0 {
            let _ = write!(drive, " vel {} {speed:.17e}", PLUGIN_FACES[face]);
        }
    }
    if !present.is_empty() {
        let mut line = format!("fix             walls all fractum/platens{faces}{drive}");
        if plan.has(EffectKind::Friction) {
            let _ = write!(line, " friction {:e}", plan.wall_friction());
        }
        let _ = writeln!(s, "{line}");
    }
    let fracture = plan.has(EffectKind::Fracture);
    // Fractum shortens a fracture run's step as pieces stiffen (time.dt = "auto"), checked
    // every STABILITY_EVERY steps; the plugin does the same (fix fractum/dt), so the run ends at
    // Fractum's end time, not after a step count.
    let adapt = fracture && sim.model.auto_dt;
    if let Some(f) = st.fracture.as_ref().filter(|_| fracture) {
        let p = &f.params;
        let mut line = format!(
            "fix             fracture all fractum/fracture mi {:e} sigma_c {:e} sigma_f {:e} critical_contacts {} ideal_plane {} plane_jitter {} seed {}",
            p.mi,
            p.sigma_c,
            p.sigma_f,
            p.critical_contacts,
            if p.ideal_plane { "yes" } else { "no" },
            if p.plane_jitter { "yes" } else { "no" },
            scene.seed
        );
        if let Some((w, xm)) = p.weibull {
            let _ = write!(line, " weibull {w:e} {xm:e}");
            if p.weibull_sigma_c {
                line.push_str(" weibull_on both");
            }
        }
        if let Some((_, ns)) = p.cohesion {
            let _ = write!(line, " cohesion {:e} {ns}", plan.cfg.fracture.toughness);
        }
        let _ = writeln!(s, "{line}");
        // The step against the contacts (after the fracture fix: it reads the step's splits):
        // adapted as Fractum's, or, with a step in seconds, checked at every step.
        if adapt {
            let _ = writeln!(
                s,
                "fix             dt all fractum/dt {} omega_dt {:e}",
                super::STABILITY_EVERY,
                sim.model.adapt_omega_dt
            );
        } else {
            let _ = writeln!(s, "fix             dt all fractum/dt 0");
        }
    }
    let mut columns = vec!["time".to_string()];
    let mut values = vec!["time".to_string()];
    for &face in &present {
        columns.push(format!("force_{}", PLUGIN_FACES[face]));
        values.push(format!("f_walls[{}]", face + 1));
    }
    for &face in &present {
        columns.push(format!("position_{}", PLUGIN_FACES[face]));
        values.push(format!("f_walls[{}]", face + 7));
    }
    columns.push("atoms".into());
    values.push("atoms".into());
    if fracture {
        for (c, k) in [("splits", 1), ("broken_particles", 2), ("springs", 5)] {
            columns.push(c.into());
            values.push(format!("f_fracture[{k}]"));
        }
    }
    let _ = writeln!(
        s,
        "thermo_style    custom {}",
        values.join(" ").replace("time", "step time")
    );
    let line: Vec<String> = values.iter().map(|v| format!("$({v}:%.10e)")).collect();
    let line = line.join(",");
    let _ = writeln!(
        s,
        "fix             series all print {every} \"{line}\" file {series_file} screen no title \"{}\"\n\
         thermo          {}",
        columns.join(","),
        (plan.steps / 20).max(every),
    );
    if adapt {
        // Fractum's last step is the first to reach the end time (less a billionth of a
        // step); the step count bounds a run whose step shortens up to 100-fold.
        let end_time = plan.loading.end_time();
        let _ = writeln!(
            s,
            "variable        fr_time equal time\n\
             fix             end all halt 1 v_fr_time >= {:.17e} error continue message no\n\
             run             {}",
            end_time - 1e-9 * plan.dt,
            plan.steps.saturating_mul(100)
        );
    } else {
        let _ = writeln!(s, "run             {}", plan.steps);
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lammps_restitution_gives_back_fractums_damping_coefficient() {
        for e in [0.2, 0.5, 0.8, 1.0] {
            let c = damping_for_restitution(e);
            let e_l = lammps_restitution(c);
            // LAMMPS coeff_restitution: c = 2 sqrt(5/6) beta, beta = -ln e / sqrt(ln^2 e + pi^2).
            let l = e_l.ln();
            let beta = -l / (l * l + std::f64::consts::PI.powi(2)).sqrt();
            assert!(
                (2.0 * (5.0_f64 / 6.0).sqrt() * beta - c).abs() < 1e-12,
                "e = {e}"
            );
            // The linear-spring closed form asks LAMMPS for less than the restitution obtained.
            assert!(e_l <= e);
        }
        assert!((lammps_restitution(damping_for_restitution(0.5)) - 0.43629).abs() < 1e-5);
    }
}
