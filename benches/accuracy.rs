//! `cargo bench --bench accuracy`: what accuracy costs in time.
//!
//! 1. A head-on Hertz impact (r = 0.3 mm, 1 m/s each way) at time steps from 1 to 0.005 times
//!    the Rayleigh step: error of the contact time against Hertz theory (undamped) and of the
//!    restitution against the requested 0.5 (damped).
//! 2. The SHPB main job to 10% strain at safety factors 0.8 to 0.05 (the time-step guard stops
//!    the runs whose step is too long): the axial stress at 10%
//!    against a run at safety 0.025, with the wall time of each run.
//!
//! Prints both tables and writes docs/img/hertz_impact_error.svg and
//! docs/img/shpb_error_vs_cost.svg. Asserts nothing.

use std::path::Path;
use std::time::Instant;

use fractum::Run;
use fractum::Scene;
use fractum::models::granular::Simulation;
use fractum::sample::{Sample, SampleInfo};
use fractum::state::{Bodies, Vec3, Walls};
use nalgebra::UnitQuaternion;
use plotters::prelude::*;

const E: f64 = 60e9;
const NU: f64 = 0.17;
const RHO: f64 = 2650.0;

fn impact_scene(effects: &str, dt: f64, end: f64) -> Scene {
    let text = format!(
        r#"
name = "impact"
effects = [{effects}]
[material]
young = {E:e}
poisson = {NU}
density = {RHO}
restitution = 0.5
[sample]
kind = "text"
file = "none"
[loading]
kind = "none"
end_time = {end:e}
[time]
dt = {dt:e}
[output]
every = 1000000000
"#
    );
    Scene::from_toml(&text, "impact", Path::new("."), &[]).unwrap()
}

/// Contact time (s) and rebound speed ratio of a head-on impact at time step `dt`.
fn impact(effects: &str, dt: f64, r: f64, v: f64, t_c: f64) -> (f64, f64) {
    let mut b = Bodies::default();
    b.push_sphere(Vec3::new(-r, 0.0, 0.0), r, RHO, UnitQuaternion::identity());
    b.push_sphere(Vec3::new(r, 0.0, 0.0), r, RHO, UnitQuaternion::identity());
    b.vel[0].x = v;
    b.vel[1].x = -v;
    let sample = Sample {
        bodies: b,
        walls: Walls::default(),
        info: SampleInfo::default(),
    };
    let mut sim = Simulation::from_sample(impact_scene(effects, dt, 3.0 * t_c), sample, 1).unwrap();
    let gap = |s: &Simulation| (s.bodies.pos[1] - s.bodies.pos[0]).norm() - 2.0 * r;
    let mut prev = (0.0, gap(&sim));
    let mut end = None;
    while !sim.finished() && end.is_none() {
        sim.advance(1).unwrap();
        let now = (sim.clock.time, gap(&sim));
        if prev.1 < 0.0 && now.1 >= 0.0 {
            end = Some(prev.0 + (now.0 - prev.0) * (-prev.1) / (now.1 - prev.1));
        }
        prev = now;
    }
    (end.unwrap_or(f64::NAN), -sim.bodies.vel[0].x / v)
}

fn main() {
    std::fs::create_dir_all("docs/img").unwrap();
    // 1. Hertz impact.
    let (r, v) = (0.3e-3, 1.0);
    let e_eff = E / (2.0 * (1.0 - NU * NU));
    let m_eff = 0.5 * fractum::shape::sphere_mass(r, RHO);
    // Hertz: t_c = 2 B(2/5, 1/2) / (5/2) · δmax / v = 2.943 δmax / v, i.e.
    // 2.8682657 (m*² / (R* E*² v))^(1/5) with the relative speed v.
    let t_c = 2.868_265_7 * (m_eff * m_eff / (0.5 * r * e_eff * e_eff * 2.0 * v)).powf(0.2);
    let rayleigh = fractum::integrate::rayleigh_time_step(r, RHO, E, NU);
    println!(
        "Hertz impact, r = 0.3 mm, 1 m/s each way: contact time {t_c:.4e} s, Rayleigh step {rayleigh:.4e} s"
    );
    println!(
        "| dt / Rayleigh | steps per contact | contact time error | restitution (asked 0.5) |"
    );
    println!("|---:|---:|---:|---:|");
    let mut hertz = Vec::new();
    for s in [1.0, 0.5, 0.3, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005] {
        let dt = s * rayleigh;
        let (tc, _) = impact("\"contact\"", dt, r, v, t_c);
        // The contact starts at t = 0 (the spheres touch at the start).
        let err_t = (tc / t_c - 1.0).abs();
        let (_, e) = impact("\"contact\", \"damping\"", dt, r, v, t_c);
        let err_e = (e / 0.5 - 1.0).abs();
        println!("| {s} | {:.0} | {err_t:.2e} | {e:.5} |", t_c / dt);
        hertz.push((t_c / dt, err_t, err_e));
    }
    // 2. SHPB to 10% strain.
    let path = Path::new("scenes/shpb_sand.toml");
    let run = |safety: f64| -> Option<(f64, f64, u64)> {
        let set = vec![
            "loading.end_strain=0.1".to_string(),
            format!("time.safety={safety}"),
            "output.vtk=0".to_string(),
        ];
        let scene = Scene::load(path, &set).unwrap();
        let mut sim = Simulation::new(scene, 1, &mut |_| {}).unwrap();
        let start = Instant::now();
        sim.advance(u64::MAX).ok()?;
        let wall = start.elapsed().as_secs_f64();
        let stress = sim.summary()["stress_final"].as_f64()?;
        stress.is_finite().then_some((stress, wall, sim.clock.step))
    };
    let (reference, ref_wall, ref_steps) = run(0.025).expect("the reference run is stable");
    println!(
        "\nSHPB to 10% strain, 1 thread: reference safety 0.025 -> {reference:.6e} Pa in {ref_wall:.2} s ({ref_steps} steps)"
    );
    println!("| safety | steps | wall s | stress at 10% (Pa) | error |");
    println!("|---:|---:|---:|---:|---:|");
    let mut shpb = Vec::new();
    for s in [0.8, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1, 0.05] {
        match run(s) {
            Some((stress, wall, steps)) => {
                let err = (stress / reference - 1.0).abs();
                println!("| {s} | {steps} | {wall:.2} | {stress:.6e} | {err:.2e} |");
                shpb.push((wall, err, s));
            }
            None => println!("| {s} | | | stopped: omega dt > 2 | |"),
        }
    }
    plot_hertz(&hertz).unwrap();
    plot_shpb(&shpb).unwrap();
    println!("\nwrote docs/img/hertz_impact_error.svg and docs/img/shpb_error_vs_cost.svg");
}

fn plot_hertz(points: &[(f64, f64, f64)]) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new("docs/img/hertz_impact_error.svg", (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Hertz impact: error vs time steps per contact",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((1.0f64..1e4).log_scale(), (1e-7f64..1.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("time steps per contact")
        .y_desc("relative error")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    let t: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1.max(1e-7))).collect();
    let e: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.2.max(1e-7))).collect();
    chart
        .draw_series(LineSeries::new(t.clone(), &BLUE))?
        .label("contact time vs Hertz (undamped)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLUE));
    chart.draw_series(t.iter().map(|p| Circle::new(*p, 3, BLUE.filled())))?;
    chart
        .draw_series(LineSeries::new(e.clone(), &RED))?
        .label("restitution vs requested 0.5 (damped)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED));
    chart.draw_series(e.iter().map(|p| Circle::new(*p, 3, RED.filled())))?;
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn plot_shpb(points: &[(f64, f64, f64)]) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new("docs/img/shpb_error_vs_cost.svg", (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let (xmax, xmin) = points.iter().fold((0.0f64, f64::INFINITY), |(a, b), p| {
        (a.max(p.0), b.min(p.0))
    });
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "SHPB to 10% strain: stress error vs wall time (1 thread)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (0.5 * xmin..2.0 * xmax).log_scale(),
            (1e-6f64..1.0).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("wall seconds")
        .y_desc("relative error of the axial stress at 10%")
        .x_label_formatter(&|v| format!("{v:.1}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    let pts: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1.max(1e-6))).collect();
    chart.draw_series(LineSeries::new(pts.clone(), &BLUE))?;
    chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, BLUE.filled())))?;
    chart.draw_series(points.iter().map(|p| {
        Text::new(
            format!("{}", p.2),
            (p.0 * 1.05, p.1.max(1e-6) * 1.4),
            ("sans-serif", 12),
        )
    }))?;
    root.present()?;
    Ok(())
}
