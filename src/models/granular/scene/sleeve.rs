//! `walls.sleeve` and `walls.sleeve_friction` against the sample they hold.

use super::{Grains, SampleSpec, WallSpec};
use crate::error::Result;
use crate::scene::Scene;
use crate::scene::validate::{Range, check};

/// `walls.sleeve` and `walls.sleeve_friction`: the sleeve holds grains that are placed in it
/// (a random sample, not compacted to a pressure by the box's faces) or read into it (a
/// packing file), in a box whose x and y edges are equal; the grains' sizes are checked
/// against it when the sample is made.
pub(super) fn validate_sleeve(s: &Scene, w: &WallSpec, sample: &SampleSpec) -> Result<()> {
    if let Some(mu) = w.sleeve_friction {
        if !w.sleeve {
            return Err(s.key_error(
                "walls.sleeve_friction",
                "applies with walls.sleeve = true only (the friction between the grains and the sleeve)",
            ));
        }
        check(s, "walls.sleeve_friction", mu, Range::NON_NEGATIVE, "")?;
    }
    if !w.sleeve {
        return Ok(());
    }
    let box_size = match &sample.grains {
        Grains::Random(r) => Some(r.box_size),
        Grains::File(f) => f.box_size,
        _ => {
            return Err(s.key_error(
                "walls.sleeve",
                format!(
                    "= true needs grains placed in the sleeve or read into it (sample.kind = \"random\", \"text\", \"lammps_data\" or \"yade_text\"), not sample.kind = \"{}\"",
                    sample.kind().as_str()
                ),
            ));
        }
    };
    if sample.compaction.is_some() {
        return Err(s.key_error(
            "sample.pressure",
            "cannot be used with walls.sleeve = true: the pressure is reached by servo-controlled box faces on all three axes, and the sleeve stands in place of the side faces (prepare the sample to a solid fraction: sample.packing = \"jammed\" or \"compaction\")",
        ));
    }
    if let Some(b) = box_size {
        if (b[0] - b[1]).abs() > 1e-12 * b[0].abs().max(b[1].abs()) {
            return Err(s.key_error(
                "sample.box",
                format!(
                    "= {b:?}: with walls.sleeve = true its x and y edges must be equal (the sleeve is the cylinder inscribed in the box's x-y section: its diameter)"
                ),
            ));
        }
    }
    Ok(())
}
