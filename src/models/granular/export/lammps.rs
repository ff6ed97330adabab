//! LAMMPS: a data file of the spheres and an input script that runs the scene with LAMMPS's
//! own granular models (`pair_style granular`, `fix wall/gran`).

use std::fmt::Write;

use super::*;

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
        m.poisson
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
