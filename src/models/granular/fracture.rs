//! Breaking grains inside the granular model: the split step, the energy account, the
//! size distributions and how far comminution has gone.

use super::*;

/// How far comminution has gone at one strain: bodies, pieces (held by intact springs), the
/// bodies of each generation (index: splits since the sample's grain) and the bodies below
/// the comminution limit.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Comminution {
    pub strain: f64,
    pub bodies: usize,
    pub pieces: usize,
    pub generations: Vec<usize>,
    pub at_limit: usize,
}

impl Comminution {
    /// The state of `fracture` over `bodies` at axial strain `strain`.
    pub fn of(strain: f64, bodies: &Bodies, fracture: &GrainFracture) -> Comminution {
        let n = bodies.len();
        let mut generations = Vec::new();
        for &g in &fracture.generation[..n] {
            let g = usize::from(g);
            if generations.len() <= g {
                generations.resize(g + 1, 0);
            }
            generations[g] += 1;
        }
        let at_limit = (0..n)
            .filter(|&i| fracture.params.below_comminution_limit(bodies.volume(i)))
            .count();
        Comminution {
            strain,
            bodies: n,
            pieces: fracture.pieces(n).1,
            generations,
            at_limit,
        }
    }

    pub(super) fn json(&self) -> Value {
        serde_json::json!({
            "bodies": self.bodies,
            "pieces": self.pieces,
            "generations": self.generations,
            "at_comminution_limit": self.at_limit,
        })
    }
}

impl Granular {
    /// Fracture after a step: account the step's energy, break the grains that fail at the
    /// new state, and take the size distribution at the report strains.
    pub(super) fn after_fracture_step(&mut self, clock: &Clock, dt: f64) -> Option<f64> {
        let dissipated = self.pipeline.records().map_or(0.0, |r| r.dissipated);
        if let Some(e) = &mut self.state.energy {
            e.add_step(&self.state.walls, dissipated, dt);
        }
        let st = &mut self.state;
        // A run with fracture records its contacts (its pipeline is built for shapes).
        let (Some(fracture), Some(records)) = (st.fracture.as_mut(), self.pipeline.records())
        else {
            return None;
        };
        let breaking = fracture.check(&st.bodies, &st.forces, records);
        let (_, new_dt) = self.break_grains(clock, &breaking);
        self.take_size_distributions();
        new_dt
    }

    /// Splits the given grains now (each with what broke it; see
    /// [`GrainFracture::check`]), re-evaluates the forces on the new shapes and bonds the
    /// halves. Returns the number of splits made (grains whose shape forbids breaking make
    /// none) and the step to take from now on when the pieces need a shorter one (see
    /// `Granular::adapted_step`). Needs the `fracture` effect.
    pub fn break_grains(
        &mut self,
        clock: &Clock,
        breaking: &[crate::fracture::Breaking],
    ) -> (usize, Option<f64>) {
        if breaking.is_empty() {
            return (0, None);
        }
        let before = self.mechanical_energy();
        let st = &mut self.state;
        let Some(fracture) = st.fracture.as_mut() else {
            return (0, None);
        };
        let pending = fracture.split(&mut st.bodies, &st.forces, breaking, clock.step, clock.time);
        let mut new_dt = None;
        if !pending.is_empty() {
            let reshaped: Vec<usize> = pending.iter().map(|p| p.a).collect();
            self.pipeline.reshaped(&reshaped);
            self.state.forces = Forces::new(self.state.bodies.len());
            self.evaluate_forces(clock.dt, false);
            new_dt = self.adapted_step(clock);
            let after = self.mechanical_energy();
            let st = &mut self.state;
            if let Some(fracture) = st.fracture.as_mut() {
                fracture.split_energy += after.total() - before.total();
                fracture.bond(&st.bodies, &mut st.forces, &pending);
            }
        }
        (pending.len(), new_dt)
    }

    /// Kinetic, contact elastic and gravitational energy now (J); elastic from the contact
    /// records of the last evaluation.
    pub(super) fn mechanical_energy(&self) -> Mechanical {
        let b = &self.state.bodies;
        let elastic = self
            .pipeline
            .records()
            .map_or(0.0, |r| r.list.iter().map(|c| c.energy).sum());
        let gravity = match self.gravity {
            Some(g) => -(0..b.len())
                .map(|i| b.mass[i] * g.dot(&b.pos[i]))
                .sum::<f64>(),
            None => 0.0,
        };
        Mechanical {
            kinetic: b.kinetic_energy(),
            elastic,
            gravity,
        }
    }

    /// The masses and equivalent diameters (of their own volume) of the pieces (grains and
    /// fragments held by intact springs), at the start and once each report strain is passed.
    pub(super) fn take_size_distributions(&mut self) {
        let st = &self.state;
        let Some(f) = &st.fracture else {
            return;
        };
        let strain = self.axial_strain();
        let due = if st.psd.is_empty() {
            Some(0.0)
        } else {
            self.report_strains_iter()
                .find(|&e| strain >= e - 1e-12 && st.psd.iter().all(|(s, _)| *s != e))
        };
        let Some(at) = due else {
            return;
        };
        let n = st.bodies.len();
        let (labels, count) = f.pieces(n);
        let sum = |x: &[f64]| crate::probe::fragments::sum_by_component(&labels, count, x);
        let volumes: Vec<f64> = (0..n).map(|i| st.bodies.volume(i)).collect();
        let pieces = size_distribution::pieces(&sum(&st.bodies.mass), &sum(&volumes));
        let comminution = Comminution::of(at, &st.bodies, f);
        self.state.psd.push((at, pieces));
        self.state.comminution.push(comminution);
    }

    /// Grains of the sample broken so far (0 without the `fracture` effect).
    pub fn broken_particles(&self) -> usize {
        self.state
            .fracture
            .as_ref()
            .map_or(0, |f| f.broken_particles())
    }
}
