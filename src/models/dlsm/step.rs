//! One dlsm step's forces and the record of the bonds that broke in it.

use super::*;

impl Dlsm {
    /// Forces and torques at the current positions, which are those of time `at`: bonds,
    /// the pipeline's effects, platens, reactions. `clock` is where the run is (breaks are logged at its step).
    pub(super) fn evaluate_forces(&mut self, clock: &Clock, at: f64) {
        let strength = self.tensile_strength;
        let st = &mut self.state;
        let broke = self.bonds.evaluate(&st.bodies, &mut st.forces, strength);
        if !broke.is_empty() {
            self.record_breaks(clock, &broke);
        }
        let st = &mut self.state;
        st.pipeline
            .accumulate(&st.bodies, &self.shapes, &mut st.forces, clock.dt);
        let loading = st.loading.as_loading_mut();
        loading.press(&st.bodies, &self.shapes, &mut st.forces, at, clock.dt);
        loading.constrain(&mut st.forces);
    }

    pub(super) fn record_breaks(&mut self, clock: &Clock, broke: &[usize]) {
        let st = &mut self.state;
        let mid = |c: usize| {
            let [i, j] = self.bonds.pair[c];
            0.5 * (st.bodies.pos[i as usize] + st.bodies.pos[j as usize])
        };
        if st.first_break.is_none() {
            st.first_break = Some(FirstBreak {
                step: clock.step,
                contact: broke[0],
                position: mid(broke[0]),
                time: clock.time,
            });
        }
        for &c in broke {
            st.broken_order.push(c as u32);
            st.break_log.push((clock.step, mid(c)));
            if let Some(b) = &mut st.pipeline.broken {
                let k = self.bonds.young * self.bonds.area[c] / self.bonds.length0[c];
                b.add(self.bonds.pair[c], k);
            }
        }
    }
}
