//! What every model's run shares, written once: the clock, advancing by steps or to a time,
//! the output cadence, the finiteness watchdog, series rows, checkpoints and the thread pool.
//!
//! A model ([`Model`]) supplies its physics (build, one step, hooks at output steps), its
//! series row, summary and snapshot; [`Runner`] drives any model and implements [`Run`], the
//! interface of the driver, the CLI, the C ABI and checkpoints. The registry
//! (`crate::models`) picks the model from `model.kind`.
//!
//! ```text
//! advance:   while step < target and the model has not stopped:
//!              model.step(clock, dt)          the physics of one step
//!              clock: step + 1, time + dt
//!              model.after_step(clock)        e.g. granular fracture; may ask for a new dt
//!              finite? -> model.fault -> model.check_step (stability; may ask for a new dt)
//!              a new dt asked for: clock.set_dt (the runner alone writes the clock)
//!              at output steps (every `output.every`, the last, and those the model asks):
//!                series row -> model.after_row
//! ```

mod clock;
mod interface;
mod limits;
mod model;
mod runner;
mod saved;

pub use clock::{Clock, MAX_STEPS, MIN_STEPS, end_step};
pub use interface::{Run, common_summary};
pub use limits::CallLimits;
pub use model::{BodiesView, Built, Faces, Model, Physics, Report, RunInfo};
pub use runner::Runner;
pub use saved::SceneIdentity;
