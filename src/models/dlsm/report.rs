//! What a dlsm run reports: its summary keys and the elements' VTK file.

use super::*;

impl Dlsm {
    /// The model's summary keys (after those every model shares).
    pub(super) fn summary_keys(&self, run: &RunInfo, m: &mut Map<String, Value>) {
        let st = &self.state;
        m.insert("elements".into(), st.bodies.len().into());
        m.insert(
            "sample".into(),
            serde_json::to_value(&self.sample).expect("sample info serialises"),
        );
        m.insert("contacts".into(), self.bonds.contacts().into());
        m.insert("broken_contacts".into(), st.broken_order.len().into());
        m.insert("dt_critical".into(), self.dt_critical.into());
        m.insert("dt_rotational".into(), self.dt_rotational.into());
        m.insert("phi".into(), self.integrator.phi.into());
        m.insert("stopped_after_failure".into(), st.stopped.into());
        m.insert(
            "kinetic_energy_final".into(),
            st.bodies.kinetic_energy().into(),
        );
        let dt_row = run.scene.output.every as f64 * run.clock.dt;
        let mut series = run.series.clone();
        if matches!(st.loading, DlsmLoading::FreeVibration(_)) {
            // The spectrum needs evenly spaced rows: drop a last row off the grid.
            let off = |r: &Vec<f64>| {
                let k = r[0] / dt_row;
                (k - k.round()).abs() > 1e-6
            };
            if series.rows.last().is_some_and(off) {
                series.rows.pop();
            }
        }
        st.loading.as_loading().summarize(&series, dt_row, m);
        if let Some(fb) = &st.first_break {
            m.insert("first_break_step".into(), fb.step.into());
            m.insert("first_break_time".into(), fb.time.into());
            m.insert(
                "first_break_position".into(),
                serde_json::json!([fb.position.x, fb.position.y, fb.position.z]),
            );
            if let Domain::Disc { diameter, .. } = self.domain {
                let offset = |p: &Vec3| p.x.hypot(p.y) / diameter;
                m.insert("crack_start_offset".into(), offset(&fb.position).into());
                // The macroscopic crack: the first contact to break once the load is within
                // 5% of its peak (isolated breaks under the loading arcs come earlier).
                if let Some(force) = run.series.column("force") {
                    let peak = force.iter().copied().fold(0.0, f64::max);
                    let row_step = |k: usize| (run.series.rows[k][0] / run.clock.dt).round() as u64;
                    if let Some(k) = force.iter().position(|&f| f >= 0.95 * peak) {
                        let from = if k > 0 { row_step(k - 1) } else { 0 };
                        if let Some((_, p)) = st.break_log.iter().find(|(s, _)| *s >= from) {
                            m.insert("main_crack_start_offset".into(), offset(p).into());
                        }
                    }
                }
                // The crack's path, once the disc has split: the share of the broken contacts
                // within a tenth of D of the loaded (y) diameter.
                if st.stopped {
                    let near = st
                        .break_log
                        .iter()
                        .filter(|(_, p)| p.x.abs() < 0.1 * diameter)
                        .count();
                    m.insert(
                        "crack_band_fraction".into(),
                        (near as f64 / st.break_log.len() as f64).into(),
                    );
                }
            }
        }
    }

    /// The elements as a polyhedral mesh for ParaView.
    pub fn elements_vtu(&self) -> String {
        vtk::polyhedra_vtu(
            &self.state.bodies,
            &self.shapes,
            &self.state.forces,
            &self.reference,
        )
    }
}
