//! Packings in the formats of the peer codes, written at full precision so that LAMMPS, YADE
//! and Fractum start from the very same spheres: a LAMMPS data file (`atom_style sphere`,
//! `units si`) and a YADE `ymport.text` file (`x y z r` per line). Numbers are written in the
//! shortest form that reads back to the same double; both files carry the box.

use std::fmt::Write;

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
/// densities per atom, and the initial velocities.
pub fn lammps_data(bodies: &Bodies, walls: &Walls, density: f64, title: &str) -> String {
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
            density,
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
