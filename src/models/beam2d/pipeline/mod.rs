//! The force pipeline of the `beam2d` model: polygon contacts (`contact`, with `damping` and
//! `friction` compiled in only when the scene names them) and beams (`beams`, with
//! `beam_breaking` compiled in only when named). An effect the scene does not list is not
//! built.
//!
//! Each effect first computes every pair's or beam's force into its own buffer (in parallel
//! where that pays: the items are independent, and with several threads the contacts and the
//! beams are computed side by side), then one pass sums them per polygon in a fixed order:
//! its pairs as the first body, then as the partner, then its beams. That order does not
//! depend on the number of threads, so one and two threads give bit-identical results, and it
//! does not depend on when the neighbour list was last rebuilt (pairs that do not touch add
//! exact zeros), so a resumed run continues bit for bit. Three parallel regions per step
//! (placing the polygons, the forces, the sums): each costs a wake-up of the workers.
//!
//! One effect a file: `contact.rs` (the overlap-area contact over a Verlet list of pairs),
//! `beams.rs` (the Timoshenko beams and their breaking); this file holds the pipeline that
//! runs the ones a scene names.

mod beams;
mod contact;

use rayon::prelude::*;

use super::scene::Beam2dScene;
use crate::bond::beam2d::Beams;
use crate::parallel::threads_here;
use crate::scene::Scene;
use crate::state::polygons::Polygons;

/// Below this many polygons (or beams, or pairs) a loop stays on one thread.
const PARALLEL_MIN_ITEMS: usize = 512;
/// Smallest piece of work handed to a thread.
const PARALLEL_GRAIN: usize = 128;

fn parallel(items: usize) -> bool {
    items >= PARALLEL_MIN_ITEMS && threads_here() > 1
}

/// What one evaluation found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepCounts {
    /// Polygon pairs that overlap.
    pub contacts: usize,
    /// Beams that broke in this evaluation.
    pub broken: usize,
}

/// The effects of a beam2d scene, in a fixed order: contact, then beams.
pub struct PolygonPipeline {
    contact: Option<Box<dyn contact::ContactEffect>>,
    beams: Option<Box<dyn beams::BeamEffect>>,
}

impl PolygonPipeline {
    /// Builds exactly the effects the scene lists. `skin` is the neighbour list's skin (m).
    pub fn build(
        scene: &Scene,
        cfg: &Beam2dScene,
        polys: &Polygons,
        beams: &Beams,
        skin: f64,
    ) -> Self {
        PolygonPipeline {
            contact: contact::build(scene, cfg, skin),
            beams: beams::build(cfg, polys, beams),
        }
    }

    /// Sets `f` to the forces and torques at the current state; breaks beams (at `time`).
    pub fn evaluate(
        &mut self,
        polys: &Polygons,
        beams: &mut Beams,
        time: f64,
        f: &mut [[f64; 3]],
    ) -> StepCounts {
        if let Some(c) = &mut self.contact {
            c.place(polys);
        }
        let (contact, beam) = (&mut self.contact, &mut self.beams);
        let mut contacts = move || contact.as_mut().map_or(0, |c| c.compute(polys));
        let mut broken = move || beam.as_mut().map_or(0, |b| b.compute(polys, beams, time));
        let (contacts, broken) = if threads_here() > 1 {
            rayon::join(contacts, broken)
        } else {
            (contacts(), broken())
        };
        let counts = StepCounts { contacts, broken };
        let (contact, beam) = (self.contact.as_deref(), self.beams.as_deref());
        let gather = |(k, fk): (usize, &mut [f64; 3])| {
            *fk = [0.0; 3];
            if let Some(c) = contact {
                c.gather(k, fk);
            }
            if let Some(b) = beam {
                b.gather(k, fk);
            }
        };
        if parallel(f.len()) {
            f.par_iter_mut()
                .enumerate()
                .with_min_len(PARALLEL_GRAIN)
                .for_each(gather);
        } else {
            f.iter_mut().enumerate().for_each(gather);
        }
        counts
    }

    /// One line per effect, in evaluation order.
    pub fn describe(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(c) = &self.contact {
            lines.push(c.describe());
        }
        if let Some(b) = &self.beams {
            lines.push(b.describe());
        }
        lines
    }
}
