//! `loading.kind = "brazilian"`: the Brazilian test of a disc (Section 8.2.4).

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::{
    ArcPressure, DEFAULT_RAMP, Loading, RowInputs, Setting, load_fell, mean_of, ramp_factor,
    ramp_travel, vertices,
};
use crate::contact::polyhedron::{GroundContact, Surface};
use crate::error::Result;
use crate::models::dlsm::scene::{BrazilianSpec, LoadBy};
use crate::probe::Series;
use crate::sample::voronoi::{Boundary, Domain};
use crate::shape::polyhedron::Polyhedron;
use crate::state::{Bodies, Forces, Vec3};

/// Radius of the curved jaws over the disc's radius: the ISRM suggested method's 1.5.
pub const JAW_RADIUS: f64 = 1.5;
/// Default servo stiffness of the arcs' pressure, over E t: about 30 times the diametral
/// stiffness of the 20° disc (0.34 E t), so that the closure follows the command.
const SERVO_STIFFNESS: f64 = 10.0;

/// The Brazilian test (Section 8.2.4): the disc squeezed across its y diameter, by driven
/// elements of the loading arcs (the paper's), by two rigid platens or curved jaws, or by a
/// uniform pressure over the loading arcs.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Brazilian {
    pub speed: f64,
    pub end_strain: f64,
    pub ramp_time: f64,
    /// Half loading angle α (rad); 0 for flat loading, platens and jaws.
    pub half_angle: f64,
    pub diameter: f64,
    pub thickness: f64,
    /// The driven elements of the top and bottom loading arcs (empty unless they are driven).
    pub top: Vec<u32>,
    pub bottom: Vec<u32>,
    /// Initial distance between the mean heights of the bottom and top sets (m).
    pub gap: f64,
    /// Compressive force (N) on the top and bottom sets.
    pub reaction: [f64; 2],
    pub stop_fraction: f64,
    pub tensile_strength: Option<f64>,
    /// Rigid surfaces, top (normal −y) and bottom (normal +y), when they load the disc: flat
    /// platens or curved jaws; empty otherwise.
    pub platens: Vec<GroundContact>,
    /// The platens' (jaws') heights (y, m) at the start, top and bottom: their points
    /// nearest to the disc's centre.
    pub platen_start: [f64; 2],
    /// A uniform pressure over the loading arcs, when it loads the disc.
    pub pressure: Option<ArcPressure>,
}

impl Brazilian {
    /// Whether the elements of the loading arcs are driven (rather than platens, jaws or a
    /// pressure loading the disc).
    pub fn drives_elements(&self) -> bool {
        self.platens.is_empty() && self.pressure.is_none()
    }

    /// Whether the platens are curved jaws.
    pub fn jaws(&self) -> bool {
        self.platens
            .first()
            .is_some_and(|p| matches!(p.surface, Surface::Cylinder { .. }))
    }

    /// The `loading.load_by` this loading was built from.
    pub fn load_by(&self) -> LoadBy {
        if self.pressure.is_some() {
            LoadBy::ArcPressure
        } else if self.jaws() {
            LoadBy::CurvedJaws
        } else if !self.platens.is_empty() {
            LoadBy::FlatPlatens
        } else {
            LoadBy::Elements
        }
    }

    /// How far (m) each platen, jaw or side of the servo's command has moved towards the
    /// other by time `t`: `speed × ramp_travel`.
    pub fn travel(&self, t: f64) -> f64 {
        self.speed * ramp_travel(t, self.ramp_time)
    }

    /// The platens' heights (y, m) at time `t`.
    pub fn platen_heights(&self, t: f64) -> [f64; 2] {
        let travel = self.travel(t);
        [self.platen_start[0] - travel, self.platen_start[1] + travel]
    }

    /// The jaws' contact arc 2α (degrees) in the last evaluation: the angle at the disc's
    /// centre spanned by the touching vertices, the mean of the two jaws.
    pub fn contact_arc_degrees(&self) -> f64 {
        let reach = mean_of(&[0, 1], |k| self.platens[k].reach);
        2.0 * (reach / (0.5 * self.diameter)).min(1.0).asin().to_degrees()
    }

    /// The Brazilian test of a `voronoi_disc` sample, loaded as `loading.load_by` says: the
    /// elements of the loading arcs (none empty where they carry the load), the platens or
    /// jaws placed touching the disc, or the arcs' pressure.
    pub fn build(s: &Setting, l: &BrazilianSpec) -> Result<Self> {
        let sample = s.sample;
        let Domain::Disc {
            diameter,
            thickness,
        } = sample.domain
        else {
            return Err(s.scene.key_error(
                "loading.kind",
                "= \"brazilian\" needs sample.kind = \"voronoi_disc\"",
            ));
        };
        let radius = 0.5 * diameter;
        let half_angle = 0.5 * l.arc_degrees.to_radians();
        // Flat loading still needs elements to push: those within half an element of
        // the top (bottom) of the disc.
        let reach = half_angle.max(0.5 * sample.info.element_size / radius);
        let mut top = Vec::new();
        let mut bottom = Vec::new();
        for f in &sample.boundary {
            if f.boundary != Boundary::Curved {
                continue;
            }
            let from_vertical = f.centroid.x.atan2(f.centroid.y.abs()).abs();
            if from_vertical <= reach {
                if f.centroid.y > 0.0 {
                    top.push(f.element);
                } else {
                    bottom.push(f.element);
                }
            }
        }
        top.sort_unstable();
        top.dedup();
        bottom.sort_unstable();
        bottom.dedup();
        let by = l.load_by;
        // Prescribed elements and the arc pressure act on elements of the arcs; platens
        // find what they touch themselves.
        if !by.presses() {
            s.nonempty(&top, "the top loading arc")?;
            s.nonempty(&bottom, "the bottom loading arc")?;
        }
        let (speed, end) = (l.speed, l.end_strain);
        let gap = s.mean(&top, 1) - s.mean(&bottom, 1);
        // Flat platens, or jaws of radius JAW_RADIUS R about z, touching the disc's
        // highest and lowest vertices, their contacts as stiff as a cohesive contact of a
        // mean element (E S / L0 with S = L0² = the element size squared) unless
        // material.contact_stiffness says otherwise, with the material's friction.
        let platens = if by.presses() {
            let m = &s.cfg.material;
            let k = m
                .contact_stiffness
                .unwrap_or(m.young * sample.info.element_size);
            let n = sample.bodies.len();
            [-1.0, 1.0]
                .map(|up| {
                    let g = GroundContact::new(
                        Vec3::zeros(),
                        Vec3::new(0.0, up, 0.0),
                        k,
                        m.friction,
                        n,
                    );
                    let mut g = if by == LoadBy::CurvedJaws {
                        g.cylinder(JAW_RADIUS * radius, Vec3::z())
                    } else {
                        g
                    };
                    g.place_touching(vertices(sample));
                    g
                })
                .to_vec()
        } else {
            Vec::new()
        };
        let platen_start = match platens.as_slice() {
            [top, bottom] => [top.point.y, bottom.point.y],
            _ => [0.0; 2],
        };
        let pressure = (by == LoadBy::ArcPressure).then(|| {
            // Who may hold a point of the arcs: the elements with a face on the curved
            // wall within the arc or three elements beyond it.
            let reach = half_angle + 3.0 * sample.info.element_size / radius;
            let mut near: Vec<u32> = sample
                .boundary
                .iter()
                .filter(|f| {
                    f.boundary == Boundary::Curved
                        && f.centroid.x.atan2(f.centroid.y.abs()).abs() <= reach
                })
                .map(|f| f.element)
                .collect();
            near.sort_unstable();
            near.dedup();
            let stiffness = l
                .servo_stiffness
                .unwrap_or(SERVO_STIFFNESS * s.cfg.material.young * thickness);
            // Sampled every 1/40 of an element: its share of the arc to about 2.5%.
            let spacing = sample.info.element_size / 40.0;
            ArcPressure::new(
                &sample.bodies,
                &near,
                [radius, thickness, half_angle, spacing],
                stiffness,
            )
        });
        let gap = match (&pressure, platens.is_empty()) {
            (Some(_), _) => diameter,
            (None, true) => gap,
            (None, false) => platen_start[0] - platen_start[1],
        };
        let (top, bottom) = if by == LoadBy::Elements {
            (top, bottom)
        } else {
            (Vec::new(), Vec::new())
        };
        Ok(Brazilian {
            speed,
            end_strain: end,
            ramp_time: l
                .ramp_time
                .unwrap_or(DEFAULT_RAMP * end * diameter / (2.0 * speed)),
            half_angle,
            diameter,
            thickness,
            top,
            bottom,
            gap,
            reaction: [0.0; 2],
            stop_fraction: s.stop(l.stop_fraction),
            tensile_strength: s.strength(),
            platens,
            platen_start,
            pressure,
        })
    }

    /// The loading as `fractum explain` states it, from the scene's `[loading]` table.
    pub fn describe(l: &BrazilianSpec) -> String {
        let (speed, end, arc) = (l.speed, l.end_strain, l.arc_degrees);
        match l.load_by {
            LoadBy::FlatPlatens => format!(
                "Brazilian test between two rigid flat platens (frictional contacts), {speed} m/s per side to diametral strain {end}, force read on the platens (Eq. 46)"
            ),
            LoadBy::CurvedJaws => format!(
                "Brazilian test between two rigid curved jaws of radius {JAW_RADIUS} R (frictional contacts), {speed} m/s per side to diametral strain {end}, force read on the jaws (Eq. 46, and Eq. 48 at the contact arc they make)"
            ),
            LoadBy::ArcPressure => format!(
                "Brazilian test, a uniform radial pressure over loading arcs of {arc} degrees (k = {:.4}, Eq. 47) set by a servo on their closure, commanded at {speed} m/s per side to diametral strain {end}; the disc's rigid motions held",
                arc_factor(0.5 * arc.to_radians())
            ),
            LoadBy::Elements => format!(
                "Brazilian test, the elements of a loading arc of {arc} degrees driven (k = {:.4}, Eq. 47), {speed} m/s per side to diametral strain {end}",
                arc_factor(0.5 * arc.to_radians())
            ),
        }
    }
}

impl Loading for Brazilian {
    fn end_time(&self) -> f64 {
        0.5 * self.ramp_time + self.end_strain * self.diameter / (2.0 * self.speed)
    }

    fn prescribe(&self, bodies: &mut Bodies, t: f64) {
        if !self.drives_elements() {
            return;
        }
        let v = self.speed * ramp_factor(t, self.ramp_time);
        for (set, speed) in [(&self.top, -v), (&self.bottom, v)] {
            for &i in set {
                bodies.vel[i as usize].y = speed;
                bodies.omega[i as usize] = Vec3::zeros();
            }
        }
    }

    /// The platens or jaws push the elements they touch (positions at time `t`), their
    /// reactions the compressive forces they carry; or the arcs' pressure is applied.
    fn press(
        &mut self,
        bodies: &Bodies,
        shapes: &[Polyhedron],
        forces: &mut Forces,
        t: f64,
        dt: f64,
    ) {
        let l = self;
        let command = 2.0 * l.travel(t);
        if let Some(arc) = &mut l.pressure {
            arc.apply(bodies, forces, command);
            l.reaction = [arc.load; 2];
            return;
        }
        let heights = l.platen_heights(t);
        let speed = l.speed * ramp_factor(t, l.ramp_time);
        for (k, platen) in l.platens.iter_mut().enumerate() {
            platen.point.y = heights[k];
            // The top platen moves and pushes the elements down (−y), the bottom one up.
            platen.velocity = platen.normal * speed;
            platen.accumulate(bodies, shapes, forces, dt);
            l.reaction[k] = platen.normal.dot(&platen.total);
        }
    }

    fn constrain(&mut self, forces: &mut Forces) {
        if !self.drives_elements() {
            return;
        }
        let mut r = [0.0; 2];
        for (k, set, sign) in [(0usize, &self.top, 1.0), (1, &self.bottom, -1.0)] {
            for &i in set {
                r[k] += sign * forces.force[i as usize].y;
                forces.force[i as usize].y = 0.0;
                forces.torque[i as usize] = Vec3::zeros();
            }
        }
        self.reaction = r;
    }

    fn columns(&self) -> Vec<&'static str> {
        let mut c = vec![
            "time",
            "diametral_strain",
            "force",
            "force_top",
            "force_bottom",
            "broken_contacts",
            "kinetic_energy",
        ];
        if self.jaws() {
            c.push("contact_arc_degrees");
        }
        if self.pressure.is_some() {
            c.push("held_moment");
        }
        c
    }

    fn row(&mut self, r: &RowInputs) -> Vec<f64> {
        let (l, b) = (&*self, r.bodies);
        let ke = b.kinetic_energy();
        let closure = if let Some(arc) = &l.pressure {
            arc.closure[0] + arc.closure[1]
        } else if l.platens.is_empty() {
            // The driven arcs' mean heights.
            l.gap - (mean_of(&l.top, |i| b.pos[i].y) - mean_of(&l.bottom, |i| b.pos[i].y))
        } else {
            let [top, bottom] = l.platen_heights(r.time);
            l.gap - (top - bottom)
        };
        let force = 0.5 * (l.reaction[0] + l.reaction[1]);
        let mut row = vec![
            r.time,
            closure / l.diameter,
            force,
            l.reaction[0],
            l.reaction[1],
            r.broken as f64,
            ke,
        ];
        if l.jaws() {
            row.push(l.contact_arc_degrees());
        }
        if let Some(arc) = &l.pressure {
            row.push(arc.held_moment);
        }
        row
    }

    fn failed(&self, series: &Series) -> bool {
        load_fell(
            series,
            "force",
            self.stop_fraction,
            self.tensile_strength.is_some(),
        )
    }

    fn summarize(&self, series: &Series, _dt_row: f64, out: &mut Map<String, Value>) {
        let l = self;
        // Eq. 46, divided by k of Eq. 47 for a loading arc (Eq. 48).
        let sf = l.tensile_strength.unwrap_or(0.0);
        let eq46 = std::f64::consts::FRAC_PI_2 * sf * l.diameter * l.thickness;
        let theory = eq46 / arc_factor(l.half_angle);
        if let Some(force) = series.column("force") {
            let (k, peak) = force
                .iter()
                .copied()
                .enumerate()
                .fold((0, 0.0), |a, (k, f)| if f > a.1 { (k, f) } else { a });
            let peak_row = (peak > 0.0).then_some(k);
            out.insert("peak_force".into(), peak.into());
            if sf > 0.0 {
                out.insert("theory_force".into(), theory.into());
                out.insert("force_ratio".into(), (peak / theory).into());
            }
            // Jaws: Eq. 48 with the contact arc they made at the peak.
            if let (Some(arcs), Some(k)) = (series.column("contact_arc_degrees"), peak_row) {
                let arc = arcs[k];
                out.insert("contact_arc_degrees".into(), arc.into());
                if sf > 0.0 {
                    let at_arc = eq46 / arc_factor(0.5 * arc.to_radians());
                    out.insert("theory_force_arc".into(), at_arc.into());
                    out.insert("force_ratio_arc".into(), (peak / at_arc).into());
                }
            }
            // The arcs' pressure: the moment the support of the free motions took at the peak,
            // over the load's own moment scale P R.
            if let (Some(held), Some(k)) = (series.column("held_moment"), peak_row) {
                out.insert(
                    "held_moment_ratio".into(),
                    (held[k] / (peak * 0.5 * l.diameter)).into(),
                );
            }
        }
        out.insert(
            "arc_degrees".into(),
            (2.0 * l.half_angle.to_degrees()).into(),
        );
        out.insert(
            "loaded_elements".into(),
            (l.top.len() + l.bottom.len() + l.pressure.as_ref().map_or(0, |p| p.elements.len()))
                .into(),
        );
        out.insert("load_by".into(), l.load_by().as_str().into());
        if let Some(arc) = &l.pressure {
            out.insert("servo_stiffness".into(), arc.stiffness.into());
        }
    }
}

/// Eq. 47: the factor k of a loading arc of half angle α (1 for α = 0).
pub fn arc_factor(alpha: f64) -> f64 {
    if alpha <= 0.0 {
        return 1.0;
    }
    let (c, s) = (alpha.cos(), alpha.sin());
    let num = (2.0 * c * c * c + c + s / alpha).powi(2);
    num / (8.0 * (c + s / alpha)) * alpha / s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_factor_of_the_paper() {
        // Section 8.2.4: 2α = 20° turns 64.2 kN into 66.8 kN, k = 0.9610.
        let k = arc_factor(10f64.to_radians());
        assert!((k - 0.96029).abs() < 1e-4, "{k}");
        assert!((64.2 / k - 66.8).abs() < 0.1);
    }
}
