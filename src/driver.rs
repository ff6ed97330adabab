//! Runs a simulation to its end, writing outputs on the way: what `fractum run` and
//! `fractum resume` do, as a library function.

use crate::error::Result;
use crate::output::OutputDir;
use crate::simulation::Simulation;

/// What to write besides series.csv and summary.json.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// Steps between checkpoints; `None` writes none.
    pub checkpoint_every: Option<u64>,
}

fn next_multiple(step: u64, every: u64) -> u64 {
    (step / every + 1) * every
}

/// Advances `sim` to the end of its loading. `progress` is called every so often.
pub fn run_to_end(
    sim: &mut Simulation,
    out: &mut OutputDir,
    options: RunOptions,
    progress: &mut dyn FnMut(&Simulation),
) -> Result<()> {
    let vtk = sim.scene.output.vtk;
    let report_every = (sim.end_step / 400).clamp(1, 2000);
    if vtk > 0 && sim.step % vtk == 0 && !out.frames.iter().any(|f| f.0 == sim.time) {
        out.write_snapshot(sim)?;
    }
    while !sim.finished() {
        let mut next = sim.end_step.min(next_multiple(sim.step, report_every));
        if vtk > 0 {
            next = next.min(next_multiple(sim.step, vtk));
        }
        if let Some(every) = options.checkpoint_every {
            next = next.min(next_multiple(sim.step, every));
        }
        sim.advance(next - sim.step)?;
        let mut wrote = false;
        if vtk > 0 && (sim.step % vtk == 0 || sim.finished()) {
            out.write_snapshot(sim)?;
            wrote = true;
        }
        if let Some(every) = options.checkpoint_every {
            if sim.step % every == 0 {
                out.write_checkpoint(sim)?;
                wrote = true;
            }
        }
        if wrote {
            out.write_series(sim)?;
        }
        progress(sim);
    }
    out.write_series(sim)?;
    out.write_summary(sim)?;
    Ok(())
}
