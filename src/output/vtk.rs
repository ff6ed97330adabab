//! VTK XML files for ParaView: particles as points (.vtu, one vertex cell per body, with
//! radius, velocity, angular velocity and force as point data), box walls as quads, and .pvd
//! collections that index the snapshots by time. ASCII, full precision.

use std::fmt::Write;

use crate::state::{Bodies, BoxFace, Forces, Vec3, Walls};

fn header(out: &mut String, points: usize, cells: usize) {
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

fn footer(out: &mut String) {
    out.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

fn vectors(out: &mut String, name: &str, values: impl Iterator<Item = Vec3>) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for v in values {
        let _ = writeln!(out, "          {:e} {:e} {:e}", v.x, v.y, v.z);
    }
    out.push_str("        </DataArray>\n");
}

fn scalars<T: std::fmt::LowerExp>(
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

fn integers(out: &mut String, name: &str, kind: &str, values: impl Iterator<Item = u64>) {
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
    let all = [
        BoxFace::XMin,
        BoxFace::XMax,
        BoxFace::YMin,
        BoxFace::YMax,
        BoxFace::ZMin,
        BoxFace::ZMax,
    ];
    scalars(
        &mut out,
        "normal_stress",
        "Float64",
        all.iter().map(|f| walls.face_stress(*f)),
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
