//! The box's top and bottom faces, driven from outside (the FMU's and the C ABI's bars).

use super::*;

impl Faces for Granular {
    fn drive(&mut self, top: f64, bottom: f64) -> Result<()> {
        if !self.state.walls.is_box {
            return Err(Error::run(
                "face speeds need a sample in a box (random, lattice or file packing)",
            ));
        }
        if !(top.is_finite() && bottom.is_finite()) {
            return Err(Error::run(format!(
                "face speeds must be finite, got top {top} and bottom {bottom} m/s"
            )));
        }
        self.state.driven = Some(DrivenFaces { top, bottom });
        Ok(())
    }

    fn face_forces(&self) -> (f64, f64) {
        let w = &self.state.walls;
        if !w.is_box {
            return (0.0, 0.0);
        }
        (
            w.face(BoxFace::ZMax).normal_force(),
            w.face(BoxFace::ZMin).normal_force(),
        )
    }

    fn face_stresses(&self) -> (f64, f64) {
        let w = &self.state.walls;
        if !w.is_box {
            return (0.0, 0.0);
        }
        (w.face_stress(BoxFace::ZMax), w.face_stress(BoxFace::ZMin))
    }

    fn face_area(&self) -> f64 {
        let size = self.state.walls.box_size();
        size.x * size.y
    }

    fn axial_strain(&self) -> f64 {
        Granular::axial_strain(self)
    }
}
