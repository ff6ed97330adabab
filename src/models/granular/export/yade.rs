//! YADE: a `ymport.text` file of the spheres and a script that runs the scene with YADE's
//! Mindlin law.

use std::fmt::Write;

use super::*;

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
        nu = m.poisson,
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
