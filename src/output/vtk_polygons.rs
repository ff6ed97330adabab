//! VTK files of the `beam2d` model for ParaView: polygons as polygon cells (with their
//! fragment, velocity, angular velocity and mass), beams as lines between the centres of mass
//! (intact ones with their strain, broken ones with the time they broke).

use crate::bond::beam2d::Beams;
use crate::output::vtk::{footer, header, integers, scalars, vectors};
use crate::shape::polygon::{MAX_VERTICES, Vec2};
use crate::state::Vec3;
use crate::state::polygons::Polygons;

const VTK_LINE: u64 = 3;
const VTK_POLYGON: u64 = 7;

fn point(v: Vec2) -> Vec3 {
    Vec3::new(v.x, v.y, 0.0)
}

/// The polygons in their current place; `fragment` labels each with its fragment.
pub fn polygons_vtu(p: &Polygons, fragment: &[u32]) -> String {
    let n = p.len();
    let total: usize = p.n_vertices.iter().map(|&k| k as usize).sum();
    let mut out = String::with_capacity(200 * total + 1024);
    header(&mut out, total, n);
    out.push_str("      <Points>\n");
    let mut w = [Vec2::zeros(); MAX_VERTICES];
    let mut points = Vec::with_capacity(total);
    for i in 0..n {
        let k = p.world_vertices(i, &mut w);
        points.extend(w[..k].iter().map(|v| point(*v)));
    }
    vectors(&mut out, "position", points.into_iter());
    out.push_str("      </Points>\n      <Cells>\n");
    integers(&mut out, "connectivity", "Int64", 0..total as u64);
    let mut offset = 0u64;
    integers(
        &mut out,
        "offsets",
        "Int64",
        p.n_vertices.iter().map(|&k| {
            offset += k as u64;
            offset
        }),
    );
    integers(
        &mut out,
        "types",
        "UInt8",
        std::iter::repeat_n(VTK_POLYGON, n),
    );
    out.push_str("      </Cells>\n      <CellData Scalars=\"fragment\" Vectors=\"velocity\">\n");
    integers(&mut out, "id", "Int64", 0..n as u64);
    integers(
        &mut out,
        "fragment",
        "Int64",
        fragment.iter().map(|&f| f as u64),
    );
    vectors(
        &mut out,
        "velocity",
        p.v.iter().map(|v| Vec3::new(v[0], v[1], 0.0)),
    );
    scalars(
        &mut out,
        "angular_velocity",
        "Float64",
        p.v.iter().map(|v| v[2]),
    );
    scalars(&mut out, "mass", "Float64", p.mass.iter().copied());
    out.push_str("      </CellData>\n");
    footer(&mut out);
    out
}

/// The beams that are intact (`broken` false, with their strain) or broken (with the time
/// they broke), as lines between the current centres of mass.
pub fn beams_vtu(p: &Polygons, beams: &Beams, broken: bool) -> String {
    let chosen: Vec<usize> = (0..beams.len())
        .filter(|&b| beams.intact[b] != broken)
        .collect();
    let n = p.len();
    let mut out = String::with_capacity(100 * n + 60 * chosen.len() + 1024);
    header(&mut out, n, chosen.len());
    out.push_str("      <Points>\n");
    vectors(&mut out, "position", (0..n).map(|i| point(p.centre(i))));
    out.push_str("      </Points>\n      <Cells>\n");
    integers(
        &mut out,
        "connectivity",
        "Int64",
        chosen
            .iter()
            .flat_map(|&b| [beams.i[b] as u64, beams.j[b] as u64]),
    );
    integers(
        &mut out,
        "offsets",
        "Int64",
        (1..=chosen.len() as u64).map(|k| 2 * k),
    );
    integers(
        &mut out,
        "types",
        "UInt8",
        std::iter::repeat_n(VTK_LINE, chosen.len()),
    );
    out.push_str("      </Cells>\n      <CellData>\n");
    integers(&mut out, "beam", "Int64", chosen.iter().map(|&b| b as u64));
    scalars(
        &mut out,
        "side",
        "Float64",
        chosen.iter().map(|&b| beams.side[b]),
    );
    if broken {
        scalars(
            &mut out,
            "break_time",
            "Float64",
            chosen.iter().map(|&b| beams.broken_time[b]),
        );
    } else {
        scalars(
            &mut out,
            "strain",
            "Float64",
            chosen.iter().map(|&b| {
                let l = (p.centre(beams.j[b] as usize) - p.centre(beams.i[b] as usize)).norm();
                l / beams.rest_length[b] - 1.0
            }),
        );
    }
    out.push_str("      </CellData>\n");
    footer(&mut out);
    out
}
