//! Full-size validation runs of the beam2d model for docs/validation.md:
//!
//! ```sh
//! cargo run --release --example beam2d_validation     # about 10 minutes on 2 cores
//! ```
//!
//! * elastic moduli of scenes/beam2d_moduli.toml (20 x 30 polygons) for beam moduli E from
//!   1e8 to 4e9 Pa (Fig. 4-6 of the paper);
//! * the confined compression of scenes/beam2d_compression.toml (25 x 40 polygons): stress
//!   against strain and the broken beams at three moments (Fig. 8-9);
//! * scenes/explosion_disc.toml and scenes/impact_block.toml with seeds 1 to 5: the fragment
//!   mass histogram averaged over the seeds and its power law (Fig. 11-12), the fragments of
//!   seed 1 drawn where they started (Fig. 1 and II), and how beta depends on the contact
//!   damping and on the fit range.
//!
//! Prints Markdown tables and writes the plots to docs/img/beam2d_*.svg.

use std::path::{Path, PathBuf};

use fractum::Run;
use fractum::Scene;
use fractum::models::beam2d::{
    Beam2dRun, averaged_power_law, mean_polygon_mass, pooled_fragment_masses,
};
use fractum::probe::fragments::{fit_power_law, mass_histogram};
use fractum::shape::polygon::{MAX_VERTICES, Vec2};
use plotters::prelude::*;

type Plot = Result<(), Box<dyn std::error::Error>>;

fn scene_path(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(file)
}

fn img(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("docs/img")
        .join(file)
}

fn run(file: &str, sets: &[String]) -> Beam2dRun {
    let scene = Scene::load(&scene_path(file), sets).expect("scene");
    let mut r = Beam2dRun::new(scene, 1, &mut |_| {}).expect("run");
    while !r.finished() {
        r.advance(5000).expect("step");
    }
    r
}

/// Runs the jobs two at a time (the machine has two cores), results in order.
fn two_at_a_time<T: Send>(jobs: Vec<Box<dyn FnOnce() -> T + Send>>) -> Vec<T> {
    let mut out = Vec::new();
    let mut jobs = jobs.into_iter();
    loop {
        let batch: Vec<_> = jobs.by_ref().take(2).collect();
        if batch.is_empty() {
            return out;
        }
        std::thread::scope(|s| {
            let handles: Vec<_> = batch.into_iter().map(|j| s.spawn(j)).collect();
            out.extend(handles.into_iter().map(|h| h.join().unwrap()));
        });
    }
}

fn main() {
    fractum::output::figure::register_font();
    std::fs::create_dir_all(img("")).unwrap();
    moduli().unwrap();
    compression().unwrap();
    let mut scan = String::from(
        "| scene | gamma_N = gamma_T (1/s) | beta (averaged histogram) | mean of per-seed beta | fragments per run | largest fragment |\n|---|---:|---:|---:|---:|---:|\n",
    );
    for (file, stem) in [
        ("explosion_disc.toml", "explosion"),
        ("impact_block.toml", "impact"),
    ] {
        fragmentation(file, stem, &mut scan).unwrap();
    }
    println!("\n### beta against the contact damping (5 seeds each)\n\n{scan}");
}

fn moduli() -> Plot {
    let es = [1e8, 2.5e8, 5e8, 1e9, 2e9, 4e9];
    let jobs: Vec<Box<dyn FnOnce() -> Beam2dRun + Send>> = es
        .iter()
        .map(|&e| {
            Box::new(move || run("beam2d_moduli.toml", &[format!("material.beam_young={e}")]))
                as Box<dyn FnOnce() -> Beam2dRun + Send>
        })
        .collect();
    let runs = two_at_a_time(jobs);
    println!("### Elastic moduli (scenes/beam2d_moduli.toml, 20 x 30 polygons)\n");
    println!(
        "| E (Pa) | K elongation (Pa) | K compression (Pa) | K_el / E | nu elongation | nu compression |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    for (e, r) in es.iter().zip(&runs) {
        let s = r.summary();
        let g = |k: &str| s[k].as_f64().unwrap();
        let row = (
            *e,
            g("young_elongation"),
            g("young_compression"),
            g("poisson_elongation"),
            g("poisson_compression"),
        );
        println!(
            "| {:.2e} | {:.4e} | {:.4e} | {:.3} | {:.3} | {:.3} |",
            row.0,
            row.1,
            row.2,
            row.1 / row.0,
            row.3,
            row.4
        );
        rows.push(row);
    }
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.0, r.1)).collect();
    let slope = fractum::probe::fit::least_squares_slope(&pts);
    println!(
        "\nK elongation against E: slope {slope:.4}, R² = {:.6}\n",
        fractum::probe::fit::r_squared(&pts, slope)
    );
    let file = img("beam2d_moduli.svg");
    let root = SVGBackend::new(&file, (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Young modulus K of the solid against the beam modulus E",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..4.2e9, 0.0..4.2e9)?;
    chart
        .configure_mesh()
        .x_desc("beam Young modulus E (GPa)")
        .y_desc("K (GPa)")
        .x_label_formatter(&|v| format!("{:.1}", v / 1e9))
        .y_label_formatter(&|v| format!("{:.1}", v / 1e9))
        .draw()?;
    both_phases(&mut chart, &rows, |r| [r.2, r.1])?;
    chart
        .draw_series(LineSeries::new(
            vec![(0.0, 1e9), (4.2e9, 1e9)],
            BLACK.mix(0.4),
        ))?
        .label("grain modulus Y")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.mix(0.4)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;

    let file = img("beam2d_poisson.svg");
    let root = SVGBackend::new(&file, (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Poisson's ratio of the solid against the beam modulus E",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d((0.8e8..5e9).log_scale(), 0.0..1.2)?;
    chart
        .configure_mesh()
        .x_desc("beam Young modulus E (GPa)")
        .y_desc("nu")
        .x_label_formatter(&|v| format!("{}", v / 1e9))
        .draw()?;
    both_phases(&mut chart, &rows, |r| [r.4, r.3])?;
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;

    // Fig. 4: stress against strain for E = 5e8 Pa (the scene as shipped).
    let r = &runs[2];
    let strain = r.series.column("strain").unwrap();
    let stress = r.series.column("stress").unwrap();
    let file = img("beam2d_stress_strain.svg");
    let root = SVGBackend::new(&file, (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Uniaxial elongation and compression, E = 5e8 Pa",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.0022..0.0022, -2e6..1e6)?;
    chart
        .configure_mesh()
        .x_desc("strain dL/L (elongation positive)")
        .y_desc("stress F/S (MPa)")
        .y_label_formatter(&|v| format!("{:.1}", v / 1e6))
        .draw()?;
    for (sign, color) in [(1.0, BLUE), (-1.0, RED)] {
        let p: Vec<(f64, f64)> = strain
            .iter()
            .zip(&stress)
            .filter(|(e, _)| sign * **e >= 0.0)
            .map(|(e, s)| (*e, *s))
            .collect();
        chart.draw_series(p.iter().map(|q| Circle::new(*q, 2, color.filled())))?;
    }
    root.present()?;
    Ok(())
}

/// A moduli row: E, K elongation, K compression, ν elongation, ν compression.
type Row = (f64, f64, f64, f64, f64);

/// Draws `pick(row)` = [compression, elongation] against E as two labelled series.
fn both_phases<DB, X>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    rows: &[Row],
    pick: impl Fn(&Row) -> [f64; 2],
) -> Plot
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64>,
{
    for (k, color, label) in [(0, RED, "compression"), (1, BLUE, "elongation")] {
        let p: Vec<(f64, f64)> = rows.iter().map(|r| (r.0, pick(r)[k])).collect();
        chart
            .draw_series(LineSeries::new(p.clone(), color))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color));
        chart.draw_series(p.iter().map(|q| Circle::new(*q, 3, color.filled())))?;
    }
    Ok(())
}

fn compression() -> Plot {
    let r = run("beam2d_compression.toml", &["output.vtk=0".to_string()]);
    let s = r.summary();
    println!("### Confined compression (scenes/beam2d_compression.toml, 25 x 40 polygons)\n");
    for k in [
        "peak_stress",
        "failure_strain",
        "young_compression",
        "stress_final",
        "broken_beams",
        "beams_lateral_fraction",
        "broken_beams_lateral_fraction_at_peak",
        "broken_beams_lateral_fraction",
    ] {
        println!("- {k}: {}", s[k]);
    }
    let strain = r.series.column("strain").unwrap();
    let stress = r.series.column("stress").unwrap();
    let file = img("beam2d_compression.svg");
    let root = SVGBackend::new(&file, (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Confined compression: stress against strain",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..0.041, 0.0..3e7)?;
    chart
        .configure_mesh()
        .x_desc("compressive strain")
        .y_desc("compressive stress (MPa)")
        .y_label_formatter(&|v| format!("{:.0}", v / 1e6))
        .draw()?;
    let p: Vec<(f64, f64)> = strain.iter().zip(&stress).map(|(e, s)| (-e, -s)).collect();
    chart.draw_series(LineSeries::new(p, &BLUE))?;
    root.present()?;

    // Fig. 8: the broken beams at half the failure time, at failure and at the end, drawn
    // between the polygons' centres at rest.
    let peak_time = s["peak_time"].as_f64().unwrap();
    let start = Beam2dRun::new(r.scene.clone(), 1, &mut |_| {}).unwrap();
    let moments = [0.9 * peak_time, peak_time, r.clock.time];
    let file = img("beam2d_compression_cracks.svg");
    let root = SVGBackend::new(&file, (780, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 3));
    for (panel, t) in panels.iter().zip(moments) {
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("t = {:.1} ms", t * 1e3), ("sans-serif", 16))
            .margin(8)
            .build_cartesian_2d(-0.01..0.26, -0.01..0.41)?;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(0.0, 0.0), (0.25, 0.4)],
            BLACK.mix(0.3),
        )))?;
        let b = &r.model.state.beams;
        chart.draw_series(
            (0..b.len())
                .filter(|&k| !b.intact[k] && b.broken_time[k] <= t)
                .map(|k| {
                    let (ci, cj) = (
                        start.model.state.polygons.centre(b.i[k] as usize),
                        start.model.state.polygons.centre(b.j[k] as usize),
                    );
                    PathElement::new(vec![(ci.x, ci.y), (cj.x, cj.y)], RED.stroke_width(2))
                }),
        )?;
    }
    root.present()?;
    println!();
    Ok(())
}

fn fragmentation(file: &'static str, stem: &str, scan: &mut String) -> Plot {
    let seeds = || 1..=5u64;
    let mut by_damping = Vec::new();
    for gamma in [30.0, 100.0, 300.0, 1000.0] {
        let jobs: Vec<Box<dyn FnOnce() -> Beam2dRun + Send>> = seeds()
            .map(|seed| {
                Box::new(move || {
                    run(
                        file,
                        &[
                            format!("seed={seed}"),
                            format!("material.normal_damping={gamma}"),
                            format!("material.tangential_damping={gamma}"),
                        ],
                    )
                }) as Box<dyn FnOnce() -> Beam2dRun + Send>
            })
            .collect();
        let runs = two_at_a_time(jobs);
        let refs: Vec<&Beam2dRun> = runs.iter().collect();
        let fit = averaged_power_law(&refs);
        let per_seed: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.model.power_law().map(|f| f.exponent))
            .collect();
        let mean = if per_seed.is_empty() {
            "-".to_string()
        } else {
            format!(
                "{:.3} ({} of {})",
                per_seed.iter().sum::<f64>() / per_seed.len() as f64,
                per_seed.len(),
                runs.len()
            )
        };
        let frags =
            runs.iter().map(|r| r.model.fragments().1).sum::<usize>() as f64 / runs.len() as f64;
        let largest = runs
            .iter()
            .map(|r| r.summary()["largest_fragment_fraction"].as_f64().unwrap())
            .sum::<f64>()
            / runs.len() as f64;
        scan.push_str(&format!(
            "| {stem} | {gamma} | {} | {mean} | {frags:.0} | {largest:.3} |\n",
            fit.map_or("-".into(), |f| format!("{:.3}", f.exponent))
        ));
        by_damping.push(runs);
    }
    let runs = &by_damping[0];
    println!("### {stem} ({file}, seeds 1-5, as shipped)\n");
    println!(
        "| seed | polygons | steps | broken beams | fragments | beta | largest fragment | momentum drift |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in runs {
        let s = r.summary();
        println!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.1e} |",
            r.scene.seed,
            r.model.state.polygons.len(),
            r.clock.step,
            s["broken_beams"],
            s["fragments"],
            s["beta"].as_f64().unwrap_or(f64::NAN),
            s["largest_fragment_fraction"].as_f64().unwrap(),
            s["momentum_drift_relative"].as_f64().unwrap()
        );
    }
    let refs: Vec<&Beam2dRun> = runs.iter().collect();
    let fit = averaged_power_law(&refs).unwrap();
    println!(
        "\nAveraged histogram: beta = {:.3} over {} bins, R² = {:.4}, fit range {:?} kg\n",
        fit.exponent, fit.bins, fit.r_squared, fit.range
    );
    // The fit range's influence, on the same averaged histogram.
    let unit = mean_polygon_mass(&refs);
    let masses = pooled_fragment_masses(&refs, 2);
    let bins = mass_histogram(&masses, unit, 4, runs.len());
    print!("Fit range (mean polygon masses) -> beta:");
    for (lo, hi) in [
        (2.0, 20.0),
        (1.5, 30.0),
        (2.0, 50.0),
        (3.0, 30.0),
        (2.0, 100.0),
    ] {
        let f = fit_power_law(&bins, lo * unit, hi * unit);
        print!(
            " [{lo}, {hi}] {}",
            f.map_or("-".into(), |f| format!("{:.3}", f.exponent))
        );
    }
    println!("\n");

    let file = img(&format!("beam2d_{stem}_histogram.svg"));
    let root = SVGBackend::new(&file, (640, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let used: Vec<_> = bins.iter().filter(|b| b.count > 0).collect();
    let (ymin, ymax) = used.iter().fold((f64::INFINITY, 0.0f64), |(a, b), x| {
        (a.min(x.density), b.max(x.density))
    });
    let xmax = used.iter().map(|b| b.hi / unit).fold(1.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{stem}: fragment mass histogram, 5 seeds"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (1.0..2.0 * xmax).log_scale(),
            (0.5 * ymin..2.0 * ymax).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("fragment mass / mean polygon mass")
        .y_desc("F(m) (fragments per kg per run)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    let pts: Vec<(f64, f64)> = used
        .iter()
        .map(|b| (b.centre() / unit, b.density))
        .collect();
    chart
        .draw_series(pts.iter().map(|p| Circle::new(*p, 4, BLUE.filled())))?
        .label("fragments of 2 or more polygons")
        .legend(|(x, y)| Circle::new((x + 9, y), 4, BLUE.filled()));
    // The fitted line through the fitted bins' mean point.
    let inside: Vec<&(f64, f64)> = pts
        .iter()
        .filter(|p| p.0 >= fit.range[0] / unit && p.0 <= fit.range[1] / unit)
        .collect();
    let mx = inside.iter().map(|p| p.0.ln()).sum::<f64>() / inside.len() as f64;
    let my = inside.iter().map(|p| p.1.ln()).sum::<f64>() / inside.len() as f64;
    let line = |x: f64| (my - fit.exponent * (x.ln() - mx)).exp();
    let (x0, x1) = (fit.range[0] / unit, fit.range[1] / unit);
    chart
        .draw_series(LineSeries::new(
            vec![(x0, line(x0)), (x1, line(x1))],
            RED.stroke_width(2),
        ))?
        .label(format!(
            "m^-{:.2}, fitted over [{x0:.0}, {x1:.0}]",
            fit.exponent
        ))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED));
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;

    // The fragments of seed 1, coloured, where their polygons started (Fig. 1 and II).
    let r = &runs[0];
    let start = Beam2dRun::new(r.scene.clone(), 1, &mut |_| {}).unwrap();
    let (labels, _) = r.model.fragments();
    let mut sizes = vec![0usize; labels.len()];
    for &l in &labels {
        sizes[l as usize] += 1;
    }
    fragment_map(
        &start,
        &labels,
        &sizes,
        &img(&format!("beam2d_{stem}_fragments.svg")),
        stem,
    )?;
    Ok(())
}

fn fragment_map(
    start: &Beam2dRun,
    labels: &[u32],
    sizes: &[usize],
    path: &Path,
    stem: &str,
) -> Plot {
    let p = &start.model.state.polygons;
    let (mut lo, mut hi) = (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY));
    for i in 0..p.len() {
        lo = lo.inf(&p.centre(i));
        hi = hi.sup(&p.centre(i));
    }
    let pad = 0.02;
    let (w, h) = (hi.x - lo.x + 2.0 * pad, hi.y - lo.y + 2.0 * pad);
    let width = 640u32;
    let height = (width as f64 * h / w) as u32 + 40;
    let root = SVGBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{stem}, seed 1: fragments where they started (singles grey)"),
            ("sans-serif", 16),
        )
        .margin(6)
        .build_cartesian_2d(lo.x - pad..hi.x + pad, lo.y - pad..hi.y + pad)?;
    let mut w = [Vec2::zeros(); MAX_VERTICES];
    chart.draw_series((0..p.len()).map(|i| {
        let n = p.world_vertices(i, &mut w);
        let l = labels[i] as usize;
        let color = if sizes[l] < 2 {
            RGBColor(215, 215, 215)
        } else {
            // A fixed scramble of the label into a hue.
            let hue = ((l as u64).wrapping_mul(2654435761) % 360) as f64 / 360.0;
            let c = HSLColor(hue, 0.65, 0.55).to_rgba();
            RGBColor(c.0, c.1, c.2)
        };
        Polygon::new(
            w[..n].iter().map(|v| (v.x, v.y)).collect::<Vec<_>>(),
            color.filled(),
        )
    }))?;
    root.present()?;
    Ok(())
}
