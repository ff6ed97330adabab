//! Packings read from files: plain text (`x y z r` per line) and LAMMPS data files
//! (atom_style sphere). Lengths are in metres (LAMMPS `units si`).

use std::path::Path;

use nalgebra::{Quaternion, UnitQuaternion};

use crate::scene::read_regular;
use crate::shape::{self, PolyEllipsoid, Shape};
use crate::state::{Body, Vec3};

/// Spheres read from a file, with the container bounds when the file gives them.
#[derive(Debug, Default)]
pub struct Packing {
    pub spheres: Vec<(Vec3, f64)>,
    pub bounds: Option<(Vec3, Vec3)>,
    /// Initial velocities by sphere index, when the file gives them.
    pub velocities: Vec<(usize, Vec3)>,
    /// The bodies as the Fractum LAMMPS plugin held them, when the file carries its sections
    /// (see [`read_lammps_data`]): shapes, orientations, masses, inertia, velocities.
    pub bodies: Option<Vec<Body>>,
}

fn read(path: &Path) -> Result<String, String> {
    let bytes = read_regular(path, "packing file", 16 << 30)?;
    let mut text = String::from_utf8(bytes)
        .map_err(|_| "is not text: a packing file holds numbers".to_string())?;
    // A byte-order mark (editors on Windows write one) is not part of the first line.
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}

fn number(tok: &str, line: usize, what: &str) -> Result<f64, String> {
    tok.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("line {line}: {what} `{tok}` is not a finite number"))
}

/// Reads `x y z r` per line (blank lines and `#` comments skipped). A comment
/// `# box xlo ylo zlo xhi yhi zhi` sets the container; YADE's `x_y_z_r` export reads as is.
pub fn read_text_packing(path: &Path) -> Result<Packing, String> {
    let text = read(path)?;
    let mut p = Packing::default();
    for (k, line) in text.lines().enumerate() {
        let ln = k + 1;
        let line = line.trim();
        if let Some(comment) = line.strip_prefix('#') {
            let toks: Vec<&str> = comment.split_whitespace().collect();
            if toks.first() == Some(&"box") && toks.len() == 7 {
                let v: Vec<f64> = toks[1..]
                    .iter()
                    .map(|t| number(t, ln, "box bound"))
                    .collect::<Result<_, _>>()?;
                p.bounds = Some((Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5])));
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.len() < 4 {
            return Err(format!(
                "line {ln}: expected `x y z r`, found {} values",
                toks.len()
            ));
        }
        let x = number(toks[0], ln, "x")?;
        let y = number(toks[1], ln, "y")?;
        let z = number(toks[2], ln, "z")?;
        let r = number(toks[3], ln, "r")?;
        if r <= 0.0 {
            return Err(format!(
                "line {ln}: radius {r} is outside the allowed range (0, ∞) m"
            ));
        }
        p.spheres.push((Vec3::new(x, y, z), r));
    }
    if p.spheres.is_empty() {
        return Err("holds no spheres".to_string());
    }
    Ok(p)
}

/// The sections of a data file that the Fractum LAMMPS plugin's `fix property/atom` arrays
/// read and write, by the names `fractum export lammps --plugin` gives them and the names
/// LAMMPS's `write_data` gives them (the fixes' IDs in that export's script); seven values a
/// row each: the shape (sphere flag, semi-axes a+ a- b+ b- c+ c-, m), the orientation (body to
/// world quaternion w x y z, the octant origin in the body frame, m) and the inertia (principal
/// moments, kg m², the shape-to-body quaternion w x y z).
const PLUGIN_SECTIONS: [[&str; 2]; 3] = [
    ["FractumShape", "frshape"],
    ["FractumOrient", "frorient"],
    ["FractumInertia", "frinertia"],
];

/// Reads a LAMMPS data file with `atom_style sphere` atoms:
/// `atom-ID atom-type diameter density x y z [ix iy iz]`, and the `Velocities` section
/// (`atom-ID vx vy vz wx wy wz`) when present. Atoms are ordered by ID; the box comes from the
/// `xlo xhi` / `ylo yhi` / `zlo zhi` header lines. A file that also holds the Fractum plugin's
/// shape, orientation and inertia sections (written by `fractum export lammps --plugin` or by
/// LAMMPS's `write_data` in a plugin run, halves of split grains among them) gives its bodies
/// as the plugin held them (`Packing::bodies`).
pub fn read_lammps_data(path: &Path) -> Result<Packing, String> {
    let text = read(path)?;
    let lines: Vec<&str> = text.lines().collect();
    let mut natoms = None;
    let mut lo = [None; 3];
    let mut hi = [None; 3];
    // ID, centre, radius, density.
    let mut atoms: Vec<(u64, Vec3, f64, f64)> = Vec::new();
    // ID, velocity, angular velocity when given.
    let mut vels: Vec<(u64, Vec3, Option<Vec3>)> = Vec::new();
    // The plugin's sections: ID and seven values a row.
    let mut plugin: [Vec<(u64, [f64; 7])>; 3] = Default::default();
    let strip = |l: &str| l.split('#').next().unwrap_or("").trim().to_string();
    let mut k = 1; // the first line is a title
    while k < lines.len() {
        let line = strip(lines[k]);
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.len() == 2 && toks[1] == "atoms" {
            natoms = Some(toks[0].parse::<usize>().map_err(|_| {
                format!("line {}: atom count `{}` is not an integer", k + 1, toks[0])
            })?);
        }
        for (a, (l, h)) in [("xlo", "xhi"), ("ylo", "yhi"), ("zlo", "zhi")]
            .iter()
            .enumerate()
        {
            if toks.len() == 4 && toks[2] == *l && toks[3] == *h {
                lo[a] = Some(number(toks[0], k + 1, l)?);
                hi[a] = Some(number(toks[1], k + 1, h)?);
            }
        }
        let section = if toks.len() == 1 { toks[0] } else { "" };
        let extra = PLUGIN_SECTIONS
            .iter()
            .position(|names| names.contains(&section));
        if section == "Atoms" || section == "Velocities" || extra.is_some() {
            let n = natoms
                .ok_or_else(|| format!("line {}: `{section}` before the `atoms` count", k + 1))?;
            let mut read_rows = 0;
            k += 1;
            while k < lines.len() && read_rows < n {
                let row = strip(lines[k]);
                k += 1;
                if row.is_empty() {
                    continue;
                }
                let t: Vec<&str> = row.split_whitespace().collect();
                let ln = k;
                let id = t[0]
                    .parse::<u64>()
                    .map_err(|_| format!("line {ln}: atom ID `{}` is not an integer", t[0]))?;
                if let Some(s) = extra {
                    if t.len() != 8 {
                        return Err(format!(
                            "line {ln}: expected the atom ID and 7 values in the {section} section, found {} values",
                            t.len()
                        ));
                    }
                    let mut v = [0.0; 7];
                    for (c, tok) in t[1..].iter().enumerate() {
                        v[c] = number(tok, ln, section)?;
                    }
                    plugin[s].push((id, v));
                } else if section == "Atoms" {
                    if t.len() < 7 {
                        return Err(format!(
                            "line {ln}: expected `atom-ID atom-type diameter density x y z` (atom_style sphere), found {} values",
                            t.len()
                        ));
                    }
                    let d = number(t[2], ln, "diameter")?;
                    if d <= 0.0 {
                        return Err(format!(
                            "line {ln}: diameter {d} is outside the allowed range (0, ∞) m"
                        ));
                    }
                    let x = Vec3::new(
                        number(t[4], ln, "x")?,
                        number(t[5], ln, "y")?,
                        number(t[6], ln, "z")?,
                    );
                    atoms.push((id, x, 0.5 * d, number(t[3], ln, "density")?));
                } else {
                    if t.len() < 4 {
                        return Err(format!("line {ln}: expected `atom-ID vx vy vz wx wy wz`"));
                    }
                    let v = Vec3::new(
                        number(t[1], ln, "vx")?,
                        number(t[2], ln, "vy")?,
                        number(t[3], ln, "vz")?,
                    );
                    let w = if t.len() >= 7 {
                        Some(Vec3::new(
                            number(t[4], ln, "wx")?,
                            number(t[5], ln, "wy")?,
                            number(t[6], ln, "wz")?,
                        ))
                    } else {
                        None
                    };
                    vels.push((id, v, w));
                }
                read_rows += 1;
            }
            if read_rows < n {
                return Err(format!(
                    "the {section} section has {read_rows} rows, the header says {n} atoms"
                ));
            }
            continue;
        }
        k += 1;
    }
    if atoms.is_empty() {
        return Err("has no Atoms section".to_string());
    }
    atoms.sort_by_key(|a| a.0);
    let ids: Vec<u64> = atoms.iter().map(|a| a.0).collect();
    let mut p = Packing {
        spheres: atoms.iter().map(|a| (a.1, a.2)).collect(),
        ..Default::default()
    };
    if let (Some(xl), Some(yl), Some(zl), Some(xh), Some(yh), Some(zh)) =
        (lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])
    {
        p.bounds = Some((Vec3::new(xl, yl, zl), Vec3::new(xh, yh, zh)));
    }
    let mut omegas = Vec::new();
    for (id, v, w) in vels {
        if let Ok(i) = ids.binary_search(&id) {
            p.velocities.push((i, v));
            omegas.extend(w.map(|w| (i, w)));
        }
    }
    let present = plugin.iter().filter(|rows| !rows.is_empty()).count();
    if present == 0 {
        return Ok(p);
    }
    if present < 3 {
        let missing: Vec<&str> = PLUGIN_SECTIONS
            .iter()
            .zip(&plugin)
            .filter(|(_, rows)| rows.is_empty())
            .map(|(names, _)| names[0])
            .collect();
        return Err(format!(
            "has some of the Fractum plugin's sections but not {} (all three give the grains' shapes)",
            missing.join(" and ")
        ));
    }
    let mut rows = [
        vec![None; ids.len()],
        vec![None; ids.len()],
        vec![None; ids.len()],
    ];
    for (s, section) in plugin.iter().enumerate() {
        for (id, v) in section {
            let i = ids.binary_search(id).map_err(|_| {
                format!(
                    "the {} section names atom {id}, which Atoms does not have",
                    PLUGIN_SECTIONS[s][0]
                )
            })?;
            rows[s][i] = Some(*v);
        }
    }
    let mut bodies = Vec::with_capacity(ids.len());
    for (i, &(id, pos, radius, density)) in atoms.iter().enumerate() {
        let [Some(shape), Some(orient), Some(inertia)] = [rows[0][i], rows[1][i], rows[2][i]]
        else {
            return Err(format!(
                "atom {id} lacks a row in one of the Fractum plugin's sections"
            ));
        };
        bodies.push(
            plugin_body(pos, radius, density, &shape, &orient, &inertia)
                .map_err(|m| format!("atom {id}: {m}"))?,
        );
    }
    for &(i, v) in &p.velocities {
        bodies[i].vel = v;
    }
    for (i, w) in omegas {
        bodies[i].omega = w;
    }
    p.bodies = Some(bodies);
    Ok(p)
}

/// One atom of the Fractum plugin as a body: its mass as LAMMPS reads it (the density column
/// times the bounding sphere's volume), its shape, orientation and inertia from the plugin's
/// rows.
fn plugin_body(
    pos: Vec3,
    radius: f64,
    density: f64,
    shape: &[f64; 7],
    orient: &[f64; 7],
    inertia: &[f64; 7],
) -> Result<Body, String> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !positive(density) {
        return Err(format!(
            "density {density} is outside the allowed range (0, ∞) kg/m³"
        ));
    }
    let quat = |q: &[f64]| {
        let q = Quaternion::new(q[0], q[1], q[2], q[3]);
        if (q.norm() - 1.0).abs() > 1e-9 {
            return Err(format!(
                "a quaternion of norm {} (a unit quaternion is needed)",
                q.norm()
            ));
        }
        Ok(UnitQuaternion::new_unchecked(q))
    };
    let moments = Vec3::new(inertia[0], inertia[1], inertia[2]);
    if !moments.iter().all(|&m| positive(m)) {
        return Err(format!(
            "inertia {moments:?} is outside the allowed range (0, ∞) kg m²"
        ));
    }
    let shape = if shape[0] != 0.0 {
        Shape::Sphere
    } else {
        let mut semi = [0.0; 6];
        semi.copy_from_slice(&shape[1..]);
        Shape::PolyEllipsoid {
            pe: PolyEllipsoid::new(semi)?,
            origin: Vec3::new(orient[4], orient[5], orient[6]),
            to_body: quat(&inertia[3..])?,
        }
    };
    Ok(Body::rigid(
        pos,
        quat(&orient[..4])?,
        radius,
        shape::sphere_mass(radius, density),
        moments,
        shape,
    ))
}

/// One grain of an ellipsoid assembly: semi-axes a, b, c (m), centre (m), and the world
/// directions of its a, b and c axes (the columns of `axes`, shape to world).
#[derive(Debug, Clone, Copy)]
pub struct EllipsoidGrain {
    pub semi: [f64; 3],
    pub centre: Vec3,
    pub axes: nalgebra::Rotation3<f64>,
    /// The file's line that gives the grain (for messages).
    pub line: usize,
}

/// The most elongated grain a file may hold: the largest semi-axis over the smallest. The
/// shipped Mason sand grains reach 4.2; a needle or flake of ratio 500 packs hundreds of
/// thousands of grains into a small box and its contacts need a far smaller time step.
pub const GRAIN_ASPECT_MAX: f64 = 10.0;

/// The columns of an ellipsoid assembly file, in order.
pub const ELLIPSOID_COLUMNS: [&str; 16] = [
    "id",
    "radius_a_m",
    "radius_b_m",
    "radius_c_m",
    "x_m",
    "y_m",
    "z_m",
    "angle_a_x",
    "angle_a_y",
    "angle_a_z",
    "angle_b_x",
    "angle_b_y",
    "angle_b_z",
    "angle_c_x",
    "angle_c_y",
    "angle_c_z",
];

/// Reads an ellipsoid assembly: a CSV file with the header [`ELLIPSOID_COLUMNS`], one grain a
/// row (ellip3d's particle file as data/mason_sand_shpb/ carries it): semi-axes (m), centre
/// (m) and the angles (rad) between each principal axis and the global x, y and z axes. The
/// cosines of a row's angles are its axes' direction cosines; rounded in the file, they are
/// orthonormal to a few parts in 10⁶ only, so each grain's rotation is the nearest rotation to
/// them (`Rotation3::from_matrix`, converged to 1e-15). A row whose cosines are further than
/// 1e-3 from a right-handed orthonormal frame is refused.
pub fn read_ellipsoid_assembly(path: &Path) -> Result<Vec<EllipsoidGrain>, String> {
    let text = read(path)?;
    let mut lines = text.lines().enumerate();
    let header = loop {
        match lines.next() {
            Some((_, l)) if l.trim().is_empty() || l.trim_start().starts_with('#') => continue,
            Some((_, l)) => break l,
            None => return Err("holds no grains".to_string()),
        }
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names != ELLIPSOID_COLUMNS {
        return Err(format!(
            "line 1: expected the header `{}`",
            ELLIPSOID_COLUMNS.join(",")
        ));
    }
    let mut grains = Vec::new();
    for (k, line) in lines {
        let ln = k + 1;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let toks: Vec<&str> = line.split(',').map(str::trim).collect();
        if toks.len() != ELLIPSOID_COLUMNS.len() {
            return Err(format!(
                "line {ln}: expected {} values, found {}",
                ELLIPSOID_COLUMNS.len(),
                toks.len()
            ));
        }
        let v: Vec<f64> = toks
            .iter()
            .zip(ELLIPSOID_COLUMNS)
            .skip(1)
            .map(|(t, name)| number(t, ln, name))
            .collect::<Result<_, _>>()?;
        let semi = [v[0], v[1], v[2]];
        if let Some(bad) = semi.iter().find(|&&s| s <= 0.0) {
            return Err(format!(
                "line {ln}: semi-axis {bad} is outside the allowed range (0, ∞) m"
            ));
        }
        let aspect = semi.iter().copied().fold(0.0, f64::max)
            / semi.iter().copied().fold(f64::INFINITY, f64::min);
        if aspect > GRAIN_ASPECT_MAX {
            return Err(format!(
                "line {ln}: the semi-axes {} m are {aspect:.4e} times as long as each other \
                 (largest over smallest), outside the allowed range [1, {GRAIN_ASPECT_MAX}]",
                semi.map(|s| format!("{s:e}")).join(", ")
            ));
        }
        let centre = Vec3::new(v[3], v[4], v[5]);
        // Column j of the shape-to-world matrix is the world direction of axis j (a, b, c).
        let m = nalgebra::Matrix3::from_fn(|row, col| v[6 + 3 * col + row].cos());
        let ortho = (m.transpose() * m - nalgebra::Matrix3::identity())
            .abs()
            .max();
        if ortho > 1e-3 || m.determinant() <= 0.0 {
            return Err(format!(
                "line {ln}: the axes' direction cosines are not a right-handed orthonormal frame (off by {ortho:.1e}, determinant {:.4})",
                m.determinant()
            ));
        }
        let axes =
            nalgebra::Rotation3::from_matrix_eps(&m, 1e-15, 100, nalgebra::Rotation3::identity());
        grains.push(EllipsoidGrain {
            semi,
            centre,
            axes,
            line: ln,
        });
    }
    if grains.is_empty() {
        return Err("holds no grains".to_string());
    }
    Ok(grains)
}

/// An assembly's grains placed as they are may not overlap deeply: two grains whose inscribed
/// spheres (of their smallest semi-axes) overlap are refused, naming both lines. (Grains that
/// merely touch or overlap a little, as assemblies settled by another code do, pass: the
/// shipped Mason sand assembly's closest pair is 1.004 times that distance apart.) Two grains
/// at one centre would stop the run at its first step, and a file of repeated rows would build
/// a pair list of every grain with every other.
pub fn check_assembly_overlaps(grains: &[EllipsoidGrain]) -> Result<(), String> {
    let inscribed = |g: &EllipsoidGrain| g.semi.iter().copied().fold(f64::INFINITY, f64::min);
    let cell = 2.0 * grains.iter().map(inscribed).fold(0.0, f64::max);
    if cell <= 0.0 || !cell.is_finite() {
        return Ok(());
    }
    // Cells of the largest inscribed diameter: an overlapping pair lies in neighbouring cells.
    let key = |p: &Vec3| [0, 1, 2].map(|k| (p[k] / cell).floor() as i64);
    let mut cells: std::collections::HashMap<[i64; 3], Vec<usize>> =
        std::collections::HashMap::new();
    for (i, g) in grains.iter().enumerate() {
        let [x, y, z] = key(&g.centre);
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                for dz in -1..=1i64 {
                    let near = [
                        x.saturating_add(dx),
                        y.saturating_add(dy),
                        z.saturating_add(dz),
                    ];
                    for &j in cells.get(&near).map(Vec::as_slice).unwrap_or(&[]) {
                        let h = &grains[j];
                        let d = (g.centre - h.centre).norm();
                        let reach = inscribed(g) + inscribed(h);
                        if d < reach {
                            return Err(format!(
                                "lines {} and {}: the grains overlap (centres {d:.4e} m apart, \
                                 less than the {reach:.4e} m of their smallest semi-axes together); \
                                 an assembly's grains may touch but not overlap that deeply",
                                h.line, g.line
                            ));
                        }
                    }
                }
            }
        }
        cells.entry([x, y, z]).or_default().push(i);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_lammps_sphere_data() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("d.data");
        std::fs::write(
            &f,
            "LAMMPS data\n\n2 atoms\n1 atom types\n\n0 1e-3 xlo xhi\n0 2e-3 ylo yhi\n0 3e-3 zlo zhi\n\nAtoms # sphere\n\n2 1 6e-4 2650 5e-4 5e-4 5e-4 0 0 0\n1 1 4e-4 2650 2e-4 2e-4 2e-4\n\nVelocities\n\n1 1.0 0 0 0 0 0\n2 0 2.0 0 0 0 0\n",
        )
        .unwrap();
        let p = read_lammps_data(&f).unwrap();
        assert_eq!(p.spheres.len(), 2);
        assert_eq!(p.spheres[0].1, 2e-4);
        assert_eq!(p.spheres[1].1, 3e-4);
        assert_eq!(p.bounds.unwrap().1, Vec3::new(1e-3, 2e-3, 3e-3));
        assert_eq!(
            p.velocities,
            vec![(0, Vec3::new(1.0, 0.0, 0.0)), (1, Vec3::new(0.0, 2.0, 0.0))]
        );
    }

    #[test]
    fn ellipsoid_assembly_rows_and_refusals() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("g.csv");
        let header = ELLIPSOID_COLUMNS.join(",");
        let h = std::f64::consts::FRAC_PI_2;
        // a along y, b along -x, c along z: a quarter turn about z.
        let row = format!(
            "1,3e-4,2e-4,1e-4,1e-3,2e-3,3e-3,{h},0,{h},{},{h},{h},{h},{h},0",
            2.0 * h
        );
        std::fs::write(&f, format!("{header}\n{row}\n")).unwrap();
        let g = read_ellipsoid_assembly(&f).unwrap();
        assert_eq!(g.len(), 1);
        assert_eq!(g[0].semi, [3e-4, 2e-4, 1e-4]);
        assert_eq!(g[0].centre, Vec3::new(1e-3, 2e-3, 3e-3));
        let a = g[0].axes * Vec3::x();
        assert!((a - Vec3::y()).norm() < 1e-15, "{a}");
        let b = g[0].axes * Vec3::y();
        assert!((b + Vec3::x()).norm() < 1e-15, "{b}");
        // A non-positive semi-axis is refused, as is a left-handed frame.
        std::fs::write(
            &f,
            format!("{header}\n{}\n", row.replace("3e-4,2e-4", "-3e-4,2e-4")),
        )
        .unwrap();
        let e = read_ellipsoid_assembly(&f).unwrap_err();
        assert!(e.starts_with("line 2: semi-axis -0.0003"), "{e}");
        let left = format!("1,3e-4,2e-4,1e-4,0,0,0,{h},0,{h},0,{h},{h},{h},{h},0");
        std::fs::write(&f, format!("{header}\n{left}\n")).unwrap();
        let e = read_ellipsoid_assembly(&f).unwrap_err();
        assert!(e.contains("right-handed"), "{e}");
    }

    #[test]
    fn text_packing_rejects_bad_radius_with_line() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("p.txt");
        std::fs::write(&f, "# box 0 0 0 1 1 1\n0.5 0.5 0.5 0.1\n0.2 0.2 0.2 -1\n").unwrap();
        let e = read_text_packing(&f).unwrap_err();
        assert!(e.starts_with("line 3: radius -1"), "{e}");
    }
}
