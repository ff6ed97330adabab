//! Runs a model's run to its end, writing outputs on the way: what `fractum run` and
//! `fractum resume` do, as a library function.

use crate::error::{Error, Result};
use crate::output::OutputDir;
use crate::run::Run;

/// What to write besides series.csv and summary.json.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// Steps between checkpoints; `None` writes none.
    pub checkpoint_every: Option<u64>,
}

impl RunOptions {
    /// The options' ranges (the CLI checks them before it builds or writes anything).
    pub fn check(&self) -> Result<()> {
        if self.checkpoint_every == Some(0) {
            return Err(Error::input(
                "--checkpoint-every",
                "0 is outside the allowed range: N is a number of steps, at least 1",
            ));
        }
        Ok(())
    }
}

fn next_multiple(step: u64, every: u64) -> u64 {
    (step / every + 1) * every
}

/// Advances `run` to its end. `progress` is called every so often.
pub fn run_to_end(
    run: &mut dyn Run,
    out: &mut OutputDir,
    options: RunOptions,
    progress: &mut dyn FnMut(&dyn Run),
) -> Result<()> {
    options.check()?;
    let started = std::time::Instant::now();
    let vtk = run.scene().output.vtk;
    let report_every = (run.end_step() / 400).clamp(1, 2000);
    if vtk > 0 && run.step() % vtk == 0 && !out.frames.iter().any(|f| f.1 == run.step()) {
        out.write_snapshot(run)?;
    }
    while !run.finished() {
        let step = run.step();
        let mut next = run.end_step().min(next_multiple(step, report_every));
        if vtk > 0 {
            next = next.min(next_multiple(step, vtk));
        }
        if let Some(every) = options.checkpoint_every {
            next = next.min(next_multiple(step, every));
        }
        if let Err(e) = run.advance(next - step) {
            // A run that fails while stepping says so in its folder: the series up to the
            // failure and a summary marked incomplete, so that nobody takes the folder for a
            // finished run or for one still in progress. Writing them must not hide the error.
            let _ = out.write_series(run);
            let _ = out.write_failure(run, &e, started.elapsed().as_secs_f64());
            return Err(e);
        }
        let mut wrote = false;
        if vtk > 0 && (run.step() % vtk == 0 || run.finished()) {
            out.write_snapshot(run)?;
            wrote = true;
        }
        if let Some(every) = options.checkpoint_every {
            if run.step() % every == 0 {
                out.write_checkpoint(run)?;
                wrote = true;
            }
        }
        if wrote {
            out.write_series(run)?;
        }
        progress(&*run);
    }
    out.write_series(run)?;
    out.write_results(run, started.elapsed().as_secs_f64())?;
    Ok(())
}
