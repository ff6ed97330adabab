//! Bounds on one `advance` call of an embedded run: steps, wall time, cancellation.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

use super::Clock;

/// Bounds on each `advance` / `advance_to` call, for hosts that embed a run (the C ABI):
/// a call stops with [`Error::Interrupted`] before a step once it has taken `max_steps` steps
/// or run `max_seconds` of wall time, or once `cancel` is set (from any thread; the stop
/// clears it). Always at a whole step: the run stays consistent and the next call goes on.
/// Not part of the saved state.
#[derive(Debug, Clone, Default)]
pub struct CallLimits {
    /// Most steps one call takes (0: no bound).
    pub max_steps: u64,
    /// Most wall-clock seconds one call runs (0: no bound).
    pub max_seconds: f64,
    /// Set to stop the call in progress, or the next one, before its next step.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl CallLimits {
    /// Whether a call ends by itself, whatever the run: a bound on its steps or its time.
    pub(super) fn bounded(&self) -> bool {
        self.max_steps > 0 || self.max_seconds > 0.0
    }
}

/// One call's account against its [`CallLimits`].
pub(super) struct Budget<'a> {
    limits: &'a CallLimits,
    start: std::time::Instant,
    steps: u64,
}

impl<'a> Budget<'a> {
    pub(super) fn start(limits: &'a CallLimits) -> Self {
        Budget {
            limits,
            start: std::time::Instant::now(),
            steps: 0,
        }
    }

    /// Before each step: an interruption when a bound has run out, else counts the step.
    pub(super) fn before_step(&mut self, clock: &Clock) -> Result<()> {
        let l = self.limits;
        let why = if l
            .cancel
            .as_ref()
            .is_some_and(|c| c.swap(false, Ordering::AcqRel))
        {
            Some("it was cancelled".to_string())
        } else if l.max_steps > 0 && self.steps >= l.max_steps {
            Some(format!(
                "its bound of {} steps per call ran out",
                l.max_steps
            ))
        } else if l.max_seconds > 0.0 && self.start.elapsed().as_secs_f64() >= l.max_seconds {
            Some(format!(
                "its bound of {} s of wall time per call ran out",
                l.max_seconds
            ))
        } else {
            None
        };
        if let Some(why) = why {
            return Err(Error::Interrupted(format!(
                "the call stopped after {} steps at step {} (t = {:e} s) because {why}; the run is consistent and the next call goes on from here",
                self.steps, clock.step, clock.time
            )));
        }
        self.steps += 1;
        Ok(())
    }
}
