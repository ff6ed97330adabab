//! The one generic run over any model: it alone writes the clock, records the series and
//! seals checkpoints.

use serde_json::Value;

use crate::error::{Error, Result};
use crate::parallel::Threads;
use crate::probe::Series;
use crate::scene::Scene;
use crate::state::Vec3;

use super::clock::check_restored_clock;
use super::limits::Budget;
use super::saved::{RunnerState, STATE_MAGIC, STATE_VERSION};
use super::{
    Built, CallLimits, Clock, Faces, MAX_STEPS, Model, Run, RunInfo, SceneIdentity, common_summary,
};

/// One generic run over any [`Model`].
pub struct Runner<M> {
    pub scene: Scene,
    pub clock: Clock,
    pub series: Series,
    pub warnings: Vec<String>,
    pub model: M,
    /// The step of the last series row (rows are recorded once per step at most).
    last_row: Option<u64>,
    /// The run's worker threads (none: everything runs on the caller's thread).
    threads: Threads,
    /// Bounds on each advance call (not saved).
    limits: CallLimits,
}

impl<M: Model> Runner<M> {
    /// Builds the model a scene describes and records the first row. `threads` = 0 uses
    /// every core.
    pub fn new(
        scene: Scene,
        threads: usize,
        progress: &mut (dyn FnMut(&str) + Send),
    ) -> Result<Self> {
        let cfg = M::read(&scene)?;
        let threads = Threads::new(threads)?;
        let built = threads.run(M::build_members(threads.count()), || {
            M::build(&scene, cfg, progress)
        })?;
        Runner::start(scene, built, threads)
    }

    /// Sets a run up on a model built elsewhere.
    pub fn from_built(scene: Scene, built: Built<M>, threads: usize) -> Result<Self> {
        Runner::start(scene, built, Threads::new(threads)?)
    }

    fn start(scene: Scene, built: Built<M>, threads: Threads) -> Result<Self> {
        let mut run = Runner {
            scene,
            clock: built.clock,
            series: Series::new(&built.columns),
            warnings: built.warnings,
            model: built.model,
            last_row: None,
            limits: CallLimits::default(),
            threads,
        };
        run.record_row()?;
        Ok(run)
    }

    /// Restores a run from the bytes [`Run::save_state`] wrote for this scene.
    pub fn restore(scene: Scene, bytes: &[u8], threads: usize) -> Result<Self> {
        let bytes =
            crate::output::sealed::open(bytes, STATE_MAGIC, STATE_VERSION).map_err(|why| {
                Error::run(format!(
                    "the saved {} state is not usable: it {why}",
                    M::KIND
                ))
            })?;
        let s: RunnerState = postcard::from_bytes(bytes).map_err(|e| {
            Error::run(format!(
                "the checkpoint's {} state is damaged ({e})",
                M::KIND
            ))
        })?;
        let ours = SceneIdentity::of(&scene);
        if s.scene != ours {
            let differs = if s.scene.name == ours.name && s.scene.seed == ours.seed {
                " with other keys or overrides"
            } else {
                ""
            };
            return Err(Error::run(format!(
                "the saved state belongs to another scene: it is the state of {}, this run is {ours}{differs}; restore a state into a run of the scene that saved it",
                s.scene
            )));
        }
        let c = &s.clock;
        if !(c.time.is_finite() && c.time >= 0.0 && c.dt.is_finite() && c.dt > 0.0) {
            return Err(Error::run(format!(
                "the saved {} state is inconsistent: its clock reads t = {:e} s with a step of {:e} s (a finite time from 0 and a positive finite step expected)",
                M::KIND,
                c.time,
                c.dt
            )));
        }
        check_restored_clock(c).map_err(|why| {
            Error::run(format!(
                "the saved {} state is inconsistent: its clock {why}",
                M::KIND
            ))
        })?;
        let cfg = M::read(&scene)?;
        let threads = Threads::new(threads)?;
        let model = threads.run(1, || M::restore(&scene, cfg, &s.model))?;
        if let Some(i) = model.first_non_finite() {
            return Err(Error::run(format!(
                "the saved {} state is inconsistent: {} {i} has a non-finite position or velocity",
                M::KIND,
                M::BODY
            )));
        }
        Ok(Runner {
            scene,
            clock: s.clock,
            series: s.series,
            warnings: s.warnings,
            model,
            last_row: s.last_row,
            limits: CallLimits::default(),
            threads,
        })
    }

    pub fn threads(&self) -> usize {
        self.threads.count()
    }

    /// Takes steps with `one` (which returns false when there is none left to take) on the
    /// run's threads, against one call's [`CallLimits`]. The model's choice of the worker team
    /// ([`Physics::team_members`]) is read again after every step and the threads re-entered when it
    /// changes (a granular run of spheres gets its first poly-ellipsoid at a split): it follows
    /// the state, not how the caller cuts its run into `advance` calls. Before, it was read
    /// once per call: one `advance` over a whole run of spheres that break kept the pieces off
    /// the team to the end (the accuracy sweep's "two threads" ran on one), and a run's bits
    /// depended on where its calls began.
    fn stepping(
        &mut self,
        mut one: impl FnMut(&mut Self, &mut Budget) -> Result<bool> + Send,
    ) -> Result<()> {
        let threads = self.threads.clone();
        let limits = self.limits.clone();
        let mut budget = Budget::start(&limits);
        loop {
            let team = self.model.team_members(threads.count());
            let done = threads.run(team, || -> Result<bool> {
                loop {
                    if !one(self, &mut budget)? {
                        return Ok(true);
                    }
                    if self.model.team_members(threads.count()) != team {
                        return Ok(false);
                    }
                }
            })?;
            if done {
                return Ok(());
            }
        }
    }

    pub fn finished(&self) -> bool {
        self.clock.step >= self.clock.end_step || self.model.stopped()
    }

    /// Takes up to `steps` steps (never past the end), recording series rows on the way.
    /// Fails when the state stops being finite.
    pub fn advance(&mut self, steps: u64) -> Result<()> {
        // The end is read at every step, not once per call: a run that shortens its step
        // (granular fracture) moves its end step later while it advances, and a call for
        // `u64::MAX` steps stopped at the old end and returned with the run unfinished.
        let target = self.clock.step.saturating_add(steps);
        if self.clock.end_step == u64::MAX && steps as f64 > MAX_STEPS && !self.limits.bounded() {
            return Err(Error::run(format!(
                "cannot take {steps} steps in one call: this run has no end of its own (its faces are driven from outside) and more than the limit of 1e9 steps would run for days; advance by fewer steps, advance to a time, or bound the call (max_steps, max_seconds)"
            )));
        }
        self.stepping(|run, budget| {
            if run.clock.step >= target.min(run.clock.end_step) || run.model.stopped() {
                return Ok(false);
            }
            budget.before_step(&run.clock)?;
            run.step_by(run.clock.dt);
            run.after_step()?;
            Ok(true)
        })
    }

    /// Advances to exactly `time` (s): whole steps, then one shorter step that lands on it.
    /// The step size, not the distance to `time`, sets the accuracy. Series rows are recorded
    /// as in [`Runner::advance`]. Never past the end, as [`Runner::advance`]: a time beyond it
    /// stops at the end step ([`Runner::finished`]), short of `time`.
    pub fn advance_to(&mut self, time: f64) -> Result<()> {
        if !time.is_finite() || time < self.clock.time {
            return Err(Error::run(format!(
                "cannot advance to t = {time:e} s from t = {:e} s",
                self.clock.time
            )));
        }
        if !self.model.variable_step() {
            // Whole steps only: refuse a time off the grid before taking any step.
            let steps = (time - self.clock.time) / self.clock.dt;
            if (steps - steps.round()).abs() > 1e-9 * steps.max(1.0) {
                return Err(Error::run(format!(
                    "cannot land on t = {time:e} s: this run's integrator takes whole steps of {:e} s only, and t is {steps:.6} steps away",
                    self.clock.dt
                )));
            }
            return self.advance(steps.round() as u64);
        }
        // A remainder below this is rounding, not a step to take.
        let tiny = 1e-9 * self.clock.dt;
        self.stepping(|run, budget| {
            // The scene's end stops it as it stops `advance`: a time past the end used to drive
            // the loading on beyond it (platens past their end displacement).
            if time - run.clock.time <= tiny || run.finished() {
                return Ok(false);
            }
            budget.before_step(&run.clock)?;
            let h = (time - run.clock.time).min(run.clock.dt);
            if time - run.clock.time - h <= tiny {
                run.step_by(time - run.clock.time);
                run.clock.time = time;
            } else {
                run.step_by(h);
            }
            run.after_step()?;
            Ok(true)
        })
    }

    /// One step of `dt` (the run's step, or a shorter one that lands on a requested time).
    fn step_by(&mut self, dt: f64) {
        self.model.step(&self.clock, dt);
        self.clock.step += 1;
        self.clock.time += dt;
        if let Some(dt) = self.model.after_step(&self.clock, dt) {
            self.clock.set_dt(dt);
        }
    }

    /// After every step: check the state is finite (a pass over the bodies, cheap beside the
    /// step; at output steps only, a run driven with a long output interval went on stepping
    /// NaN and reported success), and let the model check its stability and adapt its step
    /// ([`Physics::check_step`]). At output steps: record a series row. What a run computes
    /// does not depend on `output.every`, only what it writes.
    fn after_step(&mut self) -> Result<()> {
        if let Some(i) = self.model.first_non_finite() {
            return Err(Error::run(format!(
                "the run became unstable at step {} (t = {:e} s): {} {i} has a non-finite position or velocity; {}",
                self.clock.step,
                self.clock.time,
                M::BODY,
                self.model.instability_hint(&self.scene, &self.clock)
            )));
        }
        if let Some(why) = self.model.fault(&self.clock) {
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): {why}",
                self.clock.step, self.clock.time
            )));
        }
        if let Some(dt) = self
            .model
            .check_step(&self.scene, &self.clock, &mut self.warnings)?
        {
            self.clock.set_dt(dt);
        }
        let c = &self.clock;
        let due = c.step % self.scene.output.every == 0
            || c.step == c.end_step
            || self.model.stopped()
            || self.model.output_due(c);
        if !due {
            return Ok(());
        }
        self.record_row()?;
        self.model.after_row(&self.clock, &self.series);
        Ok(())
    }

    /// Records the series row of this step. A row with a non-finite value stops the run: the
    /// bodies can be finite while what is measured from them is not (a beam2d projectile at
    /// 1e308 m/s has a finite velocity and an infinite kinetic energy), and series.csv got `inf`
    /// with exit code 0.
    fn record_row(&mut self) -> Result<()> {
        if self.last_row == Some(self.clock.step) {
            return Ok(());
        }
        self.last_row = Some(self.clock.step);
        let row = self.model.row(&self.clock);
        if let Some(c) = row.iter().position(|v| !v.is_finite()) {
            let hint = if self.clock.step == 0 {
                "the scene's initial state overflows: check the loading's speeds and energies"
                    .to_string()
            } else {
                self.model.instability_hint(&self.scene, &self.clock)
            };
            return Err(Error::run(format!(
                "the run stopped at step {} (t = {:e} s): the series column `{}` is {}, not a number series.csv can hold; {hint}",
                self.clock.step, self.clock.time, self.series.columns[c], row[c],
            )));
        }
        // A row of another length than the header shifts every column after the difference:
        // a model's row and its columns disagree, which is a bug, not bad input.
        assert_eq!(
            row.len(),
            self.series.columns.len(),
            "a series row of {} values under {} columns",
            row.len(),
            self.series.columns.len()
        );
        self.series.rows.push(row);
        Ok(())
    }
}

impl<M: Model> Run for Runner<M> {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn model(&self) -> &'static str {
        M::KIND
    }
    fn bodies(&self) -> usize {
        self.model.bodies()
    }
    fn step(&self) -> u64 {
        self.clock.step
    }
    fn end_step(&self) -> u64 {
        self.clock.end_step
    }
    fn time(&self) -> f64 {
        self.clock.time
    }
    fn dt(&self) -> f64 {
        self.clock.dt
    }
    fn threads(&self) -> usize {
        Runner::threads(self)
    }
    fn finished(&self) -> bool {
        Runner::finished(self)
    }
    fn advance(&mut self, steps: u64) -> Result<()> {
        Runner::advance(self, steps)
    }
    fn advance_to(&mut self, time: f64) -> Result<()> {
        Runner::advance_to(self, time)
    }
    fn series(&self) -> &Series {
        &self.series
    }
    fn summary(&self) -> Value {
        let mut m = common_summary(self);
        let info = RunInfo {
            scene: &self.scene,
            clock: &self.clock,
            series: &self.series,
        };
        self.model.summary(&info, &mut m);
        Value::Object(m)
    }
    fn snapshot(&self) -> Vec<(&'static str, String)> {
        self.model.snapshot()
    }
    fn extra_outputs(&self) -> Vec<(String, Vec<u8>)> {
        self.model.extra_outputs()
    }
    fn save_state(&self) -> Vec<u8> {
        let state = RunnerState {
            scene: SceneIdentity::of(&self.scene),
            clock: self.clock,
            series: self.series.clone(),
            warnings: self.warnings.clone(),
            last_row: self.last_row,
            model: self.model.save(),
        };
        crate::output::sealed::seal(
            STATE_MAGIC,
            STATE_VERSION,
            &postcard::to_stdvec(&state).expect("the run's state serialises"),
        )
    }
    fn status(&self) -> String {
        self.model.status(&self.clock)
    }
    fn warnings(&self) -> &[String] {
        &self.warnings
    }
    fn positions(&self) -> Vec<Vec3> {
        self.model.positions()
    }
    fn velocities(&self) -> Vec<Vec3> {
        self.model.velocities()
    }
    fn orientations(&self) -> Vec<[f64; 4]> {
        self.model.orientations()
    }
    fn radii(&self) -> Option<Vec<f64>> {
        self.model.radii()
    }
    fn grain_loads(&self) -> Option<Vec<crate::fracture::GrainLoad>> {
        self.model.grain_loads()
    }
    fn contacts(&self) -> Option<usize> {
        self.model.contacts()
    }
    fn kinetic_energy(&self) -> f64 {
        self.model.kinetic_energy()
    }
    fn faces(&self) -> Option<&dyn Faces> {
        self.model.faces()
    }
    fn set_call_limits(&mut self, limits: CallLimits) {
        self.limits = limits;
    }
    fn set_face_speeds(&mut self, top: f64, bottom: f64) -> Result<()> {
        let faces = self.model.faces_mut().ok_or_else(|| {
            Error::run(format!(
                "a {} run has no driven faces: face speeds need a granular sample in a box",
                M::KIND
            ))
        })?;
        faces.drive(top, bottom)?;
        self.clock.end_step = u64::MAX;
        self.clock.end_time = f64::INFINITY;
        Ok(())
    }
}
