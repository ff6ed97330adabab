//! The Fractum LAMMPS plugin: a data file that carries the grains' shapes, Fractum's first
//! force evaluation (forces0.csv) and an input script of the plugin's pair and fixes.

use std::fmt::Write;

use super::*;

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
/// (`fix fractum/nve/polyell`), its walls as moving box faces (`fix fractum/platens`, with the
/// scene's sleeve in place of the side faces where it has one) and,
/// with the `fracture` effect, grain fracture (`fix fractum/fracture`; with `cohesion`, its
/// springs: `fix fractum/cohesion`), at Fractum's time
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
         fix             frstate all property/atom d2_fr_springs {} d2_fr_walls {} d2_fr_last 7\n\
         read_data       {data_file} fix frshape NULL FractumShape fix frorient NULL FractumOrient &\n\
         \x20               fix frinertia NULL FractumInertia fix frgrain NULL FractumGrain\n",
        21 * plan.cfg.fracture.springs.max(1),
        // Each face's contact history, and the sleeve's after them.
        7 * (6 + usize::from(st.walls.sleeve.is_some()))
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
    let mut coeff = format!("young {:e} poisson {:e}", m.young, m.poisson);
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
    // Each face's position and, where it is driven, its speed: the loading's at the start
    // (constant for the oedometer and the platens). With a sleeve the side faces touch nothing
    // (Walls::touches): the plugin leaves them out.
    let (mut faces, mut drive) = (String::new(), String::new());
    let mut present = Vec::new();
    for (_, w) in st
        .walls
        .walls
        .iter()
        .enumerate()
        .filter(|(k, _)| st.walls.touches(*k))
    {
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
        let speed = match plan.loading.as_loading().top_speed() {
            Some(down) if face == 5 => -down,
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
        if let Some(sleeve) = &st.walls.sleeve {
            let _ = write!(
                line,
                " sleeve {:.17e} {:.17e} {:.17e}",
                sleeve.centre.x, sleeve.centre.y, sleeve.radius
            );
            if plan.has(EffectKind::Friction) {
                let _ = write!(line, " sleeve_friction {:e}", plan.sleeve_friction());
            }
        }
        let _ = writeln!(s, "{line}");
    }
    let fracture = plan.has(EffectKind::Fracture);
    // Fractum shortens a fracture run's step as pieces stiffen (time.dt = "auto"), checked
    // every STABILITY_EVERY steps; the plugin does the same (fix fractum/dt), so the run ends at
    // Fractum's end time, not after a step count.
    let adapt = sim.model.state.step_control.target.filter(|_| fracture);
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
            if p.particle_strength {
                line.push_str(" weibull_on particle");
            } else if p.weibull_sigma_c {
                line.push_str(" weibull_on both");
            }
            if plan.cfg.fracture.size_exponent.is_some() {
                let _ = write!(line, " size_exponent {:e}", p.size_exponent);
            }
        }
        if p.comminution_limit > 0.0 {
            let _ = write!(line, " comminution_limit {:e}", p.comminution_limit);
        }
        let _ = writeln!(s, "{line}");
        // The cohesive springs between the halves (after the fracture fix, whose splits they
        // bond, and after the faces, as Fractum adds the springs' forces after theirs).
        if let Some((_, ns)) = p.cohesion {
            let _ = writeln!(
                s,
                "fix             cohesion all fractum/cohesion {:e} {ns}",
                plan.cfg.fracture.toughness
            );
        }
        // The step against the contacts (after the fracture fix: it reads the step's splits):
        // adapted as Fractum's, or, with a step in seconds, checked at every step.
        if let Some(omega_dt) = adapt {
            let _ = writeln!(
                s,
                "fix             dt all fractum/dt {} omega_dt {omega_dt:e}",
                crate::models::granular::STABILITY_EVERY,
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
    if st.walls.sleeve.is_some() {
        // The sleeve's radial force (N; over its inner area 2 pi R h, Fractum's
        // stress_lateral) and the force along z its friction holds (sleeve_axial_force).
        for (c, k) in [("sleeve_radial_force", 19), ("sleeve_axial_force", 20)] {
            columns.push(c.into());
            values.push(format!("f_walls[{k}]"));
        }
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
    if adapt.is_some() {
        // Fractum's last step is the first to reach the end time (less a billionth of a
        // step); the step count bounds a run whose step shortens up to 100-fold.
        let end_time = plan.loading.as_loading().end_time();
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
