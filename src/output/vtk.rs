//! VTK XML files for ParaView: particles as points (.vtu, one vertex cell per body, with
//! radius, velocity, angular velocity and force as point data), box walls as quads, and .pvd
//! collections that index the snapshots by time. ASCII, full precision.

use std::fmt::Write;

use crate::state::{Bodies, BoxFace, Forces, Vec3, Walls};

pub(crate) fn header(out: &mut String, points: usize, cells: usize) {
    out.push_str("<?xml version=\"1.0\"?>\n");
    out.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    );
    out.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        out,
        "    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    );
}

pub(crate) fn footer(out: &mut String) {
    out.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

pub(crate) fn vectors(out: &mut String, name: &str, values: impl Iterator<Item = Vec3>) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for v in values {
        let _ = writeln!(out, "          {:e} {:e} {:e}", v.x, v.y, v.z);
    }
    out.push_str("        </DataArray>\n");
}

pub(crate) fn scalars<T: std::fmt::LowerExp>(
    out: &mut String,
    name: &str,
    kind: &str,
    values: impl Iterator<Item = T>,
) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"{kind}\" Name=\"{name}\" format=\"ascii\">"
    );
    for v in values {
        let _ = writeln!(out, "          {v:e}");
    }
    out.push_str("        </DataArray>\n");
}

pub(crate) fn integers(
    out: &mut String,
    name: &str,
    kind: &str,
    values: impl Iterator<Item = u64>,
) {
    let _ = write!(
        out,
        "        <DataArray type=\"{kind}\" Name=\"{name}\" format=\"ascii\">\n         "
    );
    for v in values {
        let _ = write!(out, " {v}");
    }
    out.push_str("\n        </DataArray>\n");
}

/// The bodies as a point cloud.
pub fn particles_vtu(bodies: &Bodies, forces: &Forces) -> String {
    let n = bodies.len();
    let mut out = String::with_capacity(256 * n + 1024);
    header(&mut out, n, n);
    out.push_str("      <Points>\n");
    vectors(&mut out, "position", bodies.pos.iter().copied());
    out.push_str("      </Points>\n      <Cells>\n");
    integers(&mut out, "connectivity", "Int64", 0..n as u64);
    integers(&mut out, "offsets", "Int64", 1..=n as u64);
    integers(&mut out, "types", "UInt8", std::iter::repeat_n(1, n));
    out.push_str("      </Cells>\n");
    out.push_str("      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
    scalars(&mut out, "radius", "Float64", bodies.radius.iter().copied());
    vectors(&mut out, "velocity", bodies.vel.iter().copied());
    vectors(&mut out, "angular_velocity", bodies.omega.iter().copied());
    vectors(&mut out, "force", forces.force.iter().copied());
    integers(&mut out, "id", "Int64", 0..n as u64);
    out.push_str("      </PointData>\n");
    footer(&mut out);
    out
}

/// The 26 directions of a cube's face centres, edge midpoints and corners (grid points of
/// {-1, 0, 1}³ but the centre), numbered x fastest, and the 48 triangles of the cube sphere
/// they span (each face's 2 × 2 quads split in two, outward).
fn cube_sphere() -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let index = |x: i32, y: i32, z: i32| {
        let k = ((z + 1) * 9 + (y + 1) * 3 + (x + 1)) as usize;
        if k > 13 { k - 1 } else { k }
    };
    let mut dirs = Vec::with_capacity(26);
    for z in -1..=1 {
        for y in -1..=1 {
            for x in -1..=1 {
                if (x, y, z) != (0, 0, 0) {
                    dirs.push(Vec3::new(x as f64, y as f64, z as f64));
                }
            }
        }
    }
    let mut tris = Vec::with_capacity(48);
    for axis in 0..3 {
        for side in [-1, 1] {
            // Face normal along `axis` at `side`; (u, v) the other two axes, right-handed
            // with the outward normal.
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let (u, v) = if side > 0 { (u, v) } else { (v, u) };
            let at = |a: i32, b: i32| {
                let mut c = [0i32; 3];
                c[axis] = side;
                c[u] = a;
                c[v] = b;
                index(c[0], c[1], c[2])
            };
            for a in -1..1 {
                for b in -1..1 {
                    tris.push([at(a, b), at(a + 1, b), at(a + 1, b + 1)]);
                    tris.push([at(a, b), at(a + 1, b + 1), at(a, b + 1)]);
                }
            }
        }
    }
    (dirs, tris)
}

/// Every grain's surface as a closed triangle mesh through 26 of its surface points (along
/// the directions of a cube's faces, edges and corners in its shape frame, so the tips of its
/// six semi-axes are vertices), for grains that are not spheres and for spheres alike; per
/// cell, the grain's id and the grain of the sample it comes from.
pub fn grains_vtu(bodies: &Bodies, origin: &[u32]) -> String {
    use crate::shape::Shape;
    let (dirs, tris) = cube_sphere();
    let n = bodies.len();
    let mut points = Vec::with_capacity(26 * n);
    for i in 0..n {
        let (o, q) = bodies.shape_placement(i);
        for d in &dirs {
            let local = match &bodies.shape[i] {
                Shape::Sphere | Shape::Polyhedron => d.normalize() * bodies.radius[i],
                Shape::PolyEllipsoid { pe, .. } => pe.surface_point(d),
            };
            points.push(o + q * local);
        }
    }
    let cells = tris.len() * n;
    let mut out = String::with_capacity(64 * points.len() + 48 * cells + 1024);
    header(&mut out, points.len(), cells);
    out.push_str(
        "      <Points>
",
    );
    vectors(&mut out, "position", points.into_iter());
    out.push_str(
        "      </Points>
      <Cells>
",
    );
    integers(
        &mut out,
        "connectivity",
        "Int64",
        (0..n).flat_map(|i| tris.iter().flatten().map(move |&k| (26 * i + k) as u64)),
    );
    integers(
        &mut out,
        "offsets",
        "Int64",
        (1..=cells as u64).map(|k| 3 * k),
    );
    integers(&mut out, "types", "UInt8", std::iter::repeat_n(5, cells));
    out.push_str(
        "      </Cells>
      <CellData Scalars=\"id\">
",
    );
    integers(
        &mut out,
        "id",
        "Int64",
        (0..n).flat_map(|i| std::iter::repeat_n(i as u64, tris.len())),
    );
    integers(
        &mut out,
        "grain",
        "Int64",
        (0..n).flat_map(|i| {
            std::iter::repeat_n(
                origin.get(i).copied().unwrap_or(i as u32) as u64,
                tris.len(),
            )
        }),
    );
    out.push_str(
        "      </CellData>
",
    );
    footer(&mut out);
    out
}

/// The six faces of a box as quads, with the compressive normal stress on each (Pa).
pub fn box_walls_vtu(walls: &Walls) -> String {
    let lo = Vec3::new(
        walls.face(BoxFace::XMin).point.x,
        walls.face(BoxFace::YMin).point.y,
        walls.face(BoxFace::ZMin).point.z,
    );
    let hi = lo + walls.box_size();
    let corner = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    // Corner indices of each face, in BoxFace order.
    let faces: [[u64; 4]; 6] = [
        [0, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ];
    let mut out = String::new();
    header(&mut out, 8, 6);
    out.push_str("      <Points>\n");
    vectors(&mut out, "position", (0..8).map(corner));
    out.push_str("      </Points>\n      <Cells>\n");
    integers(
        &mut out,
        "connectivity",
        "Int64",
        faces.iter().flatten().copied(),
    );
    integers(&mut out, "offsets", "Int64", (1..=6).map(|k| 4 * k));
    integers(&mut out, "types", "UInt8", std::iter::repeat_n(9, 6));
    out.push_str("      </Cells>\n      <CellData Scalars=\"normal_stress\">\n");
    scalars(
        &mut out,
        "normal_stress",
        "Float64",
        BoxFace::ALL.iter().map(|f| walls.face_stress(*f)),
    );
    out.push_str("      </CellData>\n");
    footer(&mut out);
    out
}

/// A .pvd collection of `frames` (time, file relative to the .pvd).
pub fn pvd(frames: &[(f64, String)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (t, file) in frames {
        let _ = writeln!(
            out,
            "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    out.push_str("  </Collection>\n</VTKFile>\n");
    out
}

/// dlsm: the elements as polygons (every face of every polyhedron, in the current pose), with
/// the element's id, displacement from `reference` and force as cell data.
pub fn polyhedra_vtu(
    bodies: &Bodies,
    shapes: &[crate::shape::polyhedron::Polyhedron],
    forces: &Forces,
    reference: &[Vec3],
) -> String {
    let points: usize = shapes.iter().map(|s| s.vertices.len()).sum();
    let faces: usize = shapes.iter().map(|s| s.face_count()).sum();
    let mut out = String::with_capacity(120 * points + 200 * faces + 1024);
    header(&mut out, points, faces);
    out.push_str("      <Points>\n");
    vectors(
        &mut out,
        "position",
        shapes.iter().enumerate().flat_map(|(i, s)| {
            let (x, q) = (bodies.pos[i], bodies.orientation[i]);
            s.vertices.iter().map(move |v| x + q * v)
        }),
    );
    out.push_str("      </Points>\n      <Cells>\n");
    let mut connectivity = Vec::new();
    let mut offsets = Vec::with_capacity(faces);
    let mut owner = Vec::with_capacity(faces);
    let mut base = 0u64;
    for (i, s) in shapes.iter().enumerate() {
        for k in 0..s.face_count() {
            connectivity.extend(s.face(k).iter().map(|&v| base + v as u64));
            offsets.push(connectivity.len() as u64);
            owner.push(i);
        }
        base += s.vertices.len() as u64;
    }
    integers(&mut out, "connectivity", "Int64", connectivity.into_iter());
    integers(&mut out, "offsets", "Int64", offsets.into_iter());
    integers(&mut out, "types", "UInt8", std::iter::repeat_n(7, faces));
    out.push_str("      </Cells>\n      <CellData Scalars=\"element\" Vectors=\"displacement\">\n");
    integers(
        &mut out,
        "element",
        "Int64",
        owner.iter().map(|&i| i as u64),
    );
    vectors(
        &mut out,
        "displacement",
        owner.iter().map(|&i| bodies.pos[i] - reference[i]),
    );
    vectors(&mut out, "force", owner.iter().map(|&i| forces.force[i]));
    out.push_str("      </CellData>\n");
    footer(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube sphere is closed and outward: its signed volume through the 26 directions is
    /// that of the cube [-1, 1]³, and every edge is shared by exactly two triangles.
    #[test]
    fn cube_sphere_is_a_closed_outward_surface() {
        let (dirs, tris) = cube_sphere();
        assert_eq!((dirs.len(), tris.len()), (26, 48));
        let volume: f64 = tris
            .iter()
            .map(|t| dirs[t[0]].dot(&dirs[t[1]].cross(&dirs[t[2]])) / 6.0)
            .sum();
        assert!((volume - 8.0).abs() < 1e-12, "{volume}");
        let mut edges = std::collections::HashMap::new();
        for t in &tris {
            for k in 0..3 {
                let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                *edges.entry((a, b)).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&c| c == 2));
    }
}
