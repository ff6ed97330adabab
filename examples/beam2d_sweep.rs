//! The paper's Fig. 11 sweep (beam2d paper, Section 3.3.1): β of the
//! fragment mass histogram against both breaking thresholds, for the explosion and the impact.
//!
//! ```sh
//! cargo run --release --example beam2d_sweep     # about 15 minutes on 2 cores
//! ```
//!
//! A grid of t_ε = 1–6% by t_Θ = 1°, 2°, 4°, 7°, plus t_Θ = 3°, 5°, 6° at t_ε = 3% (the paper's
//! Fig. 11b line complete), seeds 1–5 each, every other key as shipped. β by the rule fixed
//! before this sweep was run (docs/validation.md, "How β is fitted"), with its bootstrap
//! interval over the seeds. Prints a Markdown table and the wall time; writes
//! docs/beam2d_sweep.csv and docs/img/beam2d_beta_sweep.svg (β against each threshold) and
//! docs/img/beam2d_sweep_histograms.svg (the explosion's histograms, as the paper's Fig. 11).

use std::fmt::Write as _;
use std::time::Instant;

use fractum::Run;
use fractum::models::beam2d::{
    Beam2dRun, averaged_power_law, averaged_power_law_interval, mean_polygon_mass,
};
use fractum::probe::fragments::mass_histogram;
use plotters::prelude::*;

mod common;
use common::{on_two_workers, root, run};

type Plot = Result<(), Box<dyn std::error::Error>>;

const SEEDS: u64 = 5;
const STRAIN: [f64; 6] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]; // t_ε (%)
const BENDING: [f64; 4] = [1.0, 2.0, 4.0, 7.0]; // t_Θ (degrees)
const BENDING_LINE: [f64; 3] = [3.0, 5.0, 6.0]; // extra t_Θ at t_ε = 3%
/// One colour per curve.
const COLOURS: [RGBColor; 7] = [
    BLUE,
    RED,
    GREEN,
    MAGENTA,
    CYAN,
    BLACK,
    RGBColor(200, 120, 0),
];

/// One setting of one scene: its thresholds, runs and β.
struct Point {
    stem: &'static str,
    strain: f64,
    bending: f64,
    beta: Option<f64>,
    interval: Option<[f64; 2]>,
    bins: usize,
    range: [f64; 2],
    fragments: f64,
    largest: f64,
    quiet: usize,
    masses: Vec<f64>,
    unit: f64,
}

fn main() {
    fractum::output::figure::register_font();
    let start = Instant::now();
    let mut settings: Vec<(f64, f64)> = Vec::new();
    for &e in &STRAIN {
        for &t in &BENDING {
            settings.push((e, t));
        }
    }
    settings.extend(BENDING_LINE.iter().map(|&t| (3.0, t)));
    let scenes = [
        ("explosion_disc.toml", "explosion"),
        ("impact_block.toml", "impact"),
    ];
    let jobs: Vec<(usize, usize, u64)> = (0..scenes.len())
        .flat_map(|s| {
            (0..settings.len()).flat_map(move |k| (1..=SEEDS).map(move |seed| (s, k, seed)))
        })
        .collect();
    // Two workers (two cores), each run on one thread; results by job index.
    let runs: Vec<Beam2dRun> = on_two_workers(&jobs, |&(sc, k, seed)| {
        let (e, t) = settings[k];
        run(scenes[sc].0, seed, e, t, &[])
    });
    let wall = start.elapsed().as_secs_f64();

    let mut points = Vec::new();
    for (s, &(_, stem)) in scenes.iter().enumerate() {
        for (k, &(strain, bending)) in settings.iter().enumerate() {
            let group: Vec<&Beam2dRun> = jobs
                .iter()
                .enumerate()
                .filter(|(_, j)| j.0 == s && j.1 == k)
                .map(|(j, _)| &runs[j])
                .collect();
            let fit = averaged_power_law(&group);
            let n = group.len() as f64;
            let unit = mean_polygon_mass(&group);
            let summaries: Vec<_> = group.iter().map(|r| r.summary()).collect();
            points.push(Point {
                stem,
                strain,
                bending,
                beta: fit.map(|f| f.exponent),
                interval: averaged_power_law_interval(&group),
                bins: fit.map_or(0, |f| f.bins),
                range: fit.map_or([f64::NAN; 2], |f| f.range.map(|x| x / unit)),
                fragments: group.iter().map(|r| r.model.fragments().1).sum::<usize>() as f64 / n,
                largest: summaries
                    .iter()
                    .map(|s| s["largest_fragment_fraction"].as_f64().unwrap())
                    .sum::<f64>()
                    / n,
                quiet: summaries
                    .iter()
                    .filter(|s| s["stopped_by"].as_str().unwrap().contains("without"))
                    .count(),
                masses: group
                    .iter()
                    .flat_map(|r| r.model.multi_polygon_fragment_masses())
                    .collect(),
                unit,
            });
        }
    }
    report(&points, wall);
    plot_beta(&points).unwrap();
    plot_histograms(&points).unwrap();
}

fn report(points: &[Point], wall: f64) {
    let mut csv = String::from(
        "scene,strain_threshold_percent,bending_threshold_degrees,beta,beta_lo95,beta_hi95,fit_bins,fit_from,fit_to,fragments_per_run,largest_fragment_fraction,runs_stopped_quiet\n",
    );
    println!(
        "| scene | t_ε | t_Θ | β | 95% (bootstrap) | bins | fit range (m̄) | fragments per run | largest fragment | stopped by 300 quiet steps |"
    );
    println!("|---|---:|---:|---:|---|---:|---|---:|---:|---:|");
    let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.3}"));
    for p in points {
        let iv = p
            .interval
            .map_or("-".into(), |[a, b]| format!("{a:.3}–{b:.3}"));
        println!(
            "| {} | {}% | {}° | {} | {iv} | {} | {:.1}–{:.1} | {:.0} | {:.3} | {}/{SEEDS} |",
            p.stem,
            p.strain,
            p.bending,
            f(p.beta),
            p.bins,
            p.range[0],
            p.range[1],
            p.fragments,
            p.largest,
            p.quiet
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            p.stem,
            p.strain,
            p.bending,
            p.beta.map_or(String::new(), |v| v.to_string()),
            p.interval.map_or(String::new(), |i| i[0].to_string()),
            p.interval.map_or(String::new(), |i| i[1].to_string()),
            p.bins,
            p.range[0],
            p.range[1],
            p.fragments,
            p.largest,
            p.quiet
        );
    }
    for stem in ["explosion", "impact"] {
        let betas: Vec<f64> = points
            .iter()
            .filter(|p| p.stem == stem)
            .filter_map(|p| p.beta)
            .collect();
        let (lo, hi) = betas
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        println!(
            "\n{stem}: beta from {lo:.3} to {hi:.3} over {} of {} settings with a fit",
            betas.len(),
            points.iter().filter(|p| p.stem == stem).count()
        );
    }
    println!(
        "\nWall time of the sweep: {wall:.0} s ({} runs of one thread, two at a time)",
        points.len() as u64 * SEEDS
    );
    std::fs::write(root().join("docs/beam2d_sweep.csv"), csv).unwrap();
}

/// β against t_ε (one curve per t_Θ) and against t_Θ at t_ε = 3%, both scenes, with the
/// bootstrap intervals and the paper's band 2.0 ± 0.05.
fn plot_beta(points: &[Point]) -> Plot {
    let file = root().join("docs/img/beam2d_beta_sweep.svg");
    let area = SVGBackend::new(&file, (1100, 800)).into_drawing_area();
    area.fill(&WHITE)?;
    let panels = area.split_evenly((2, 2));
    for (row, stem) in ["explosion", "impact"].into_iter().enumerate() {
        for col in 0..2 {
            let panel = &panels[row * 2 + col];
            let by_strain = col == 0;
            let (xdesc, xr) = if by_strain {
                ("stretching threshold t_eps (%)", 0.5..6.5)
            } else {
                ("bending threshold t_Theta (degrees)", 0.5..7.5)
            };
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!(
                        "{stem}: beta against {}",
                        if by_strain {
                            "t_eps (curves: t_Theta)"
                        } else {
                            "t_Theta (curves: t_eps)"
                        }
                    ),
                    ("sans-serif", 16),
                )
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(45)
                .build_cartesian_2d(xr.clone(), 1.0..4.0)?;
            chart.configure_mesh().x_desc(xdesc).y_desc("beta").draw()?;
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(xr.start, 1.95), (xr.end, 2.05)],
                    RGBColor(180, 180, 180).mix(0.5).filled(),
                )))?
                .label("paper: 2.0 +- 0.05")
                .legend(|(x, y)| {
                    Rectangle::new(
                        [(x, y - 4), (x + 16, y + 4)],
                        RGBColor(180, 180, 180).filled(),
                    )
                });
            let curves: Vec<f64> = if by_strain {
                BENDING.to_vec()
            } else {
                STRAIN.to_vec()
            };
            for (c, &fixed) in curves.iter().enumerate() {
                let mut pts: Vec<&Point> = points
                    .iter()
                    .filter(|p| {
                        p.stem == stem
                            && if by_strain {
                                p.bending == fixed
                            } else {
                                p.strain == fixed
                            }
                    })
                    .collect();
                pts.sort_by(|a, b| {
                    let key = |p: &Point| if by_strain { p.strain } else { p.bending };
                    key(a).total_cmp(&key(b))
                });
                let colour = COLOURS[c % COLOURS.len()];
                let xy: Vec<(f64, f64, [f64; 2])> = pts
                    .iter()
                    .filter_map(|p| {
                        let x = if by_strain { p.strain } else { p.bending };
                        p.beta.map(|b| (x, b, p.interval.unwrap_or([b, b])))
                    })
                    .collect();
                let label = if by_strain {
                    format!("t_Theta = {fixed} deg")
                } else {
                    format!("t_eps = {fixed}%")
                };
                chart
                    .draw_series(LineSeries::new(
                        xy.iter().map(|p| (p.0, p.1)),
                        colour.stroke_width(2),
                    ))?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour));
                chart.draw_series(xy.iter().map(|p| {
                    PathElement::new(vec![(p.0, p.2[0]), (p.0, p.2[1])], colour.stroke_width(1))
                }))?;
                chart.draw_series(
                    xy.iter()
                        .map(|p| Circle::new((p.0, p.1), 3, colour.filled())),
                )?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font(("sans-serif", 11))
                .draw()?;
        }
    }
    area.present()?;
    Ok(())
}

/// The explosion's histograms as the paper's Fig. 11: (a) t_ε = 1–6% at t_Θ = 4°,
/// (b) t_Θ = 1–7° at t_ε = 3%.
fn plot_histograms(points: &[Point]) -> Plot {
    let file = root().join("docs/img/beam2d_sweep_histograms.svg");
    let area = SVGBackend::new(&file, (1100, 440)).into_drawing_area();
    area.fill(&WHITE)?;
    let panels = area.split_evenly((1, 2));
    for (col, panel) in panels.iter().enumerate() {
        let mut chosen: Vec<&Point> = points
            .iter()
            .filter(|p| {
                p.stem == "explosion"
                    && if col == 0 {
                        p.bending == 4.0
                    } else {
                        p.strain == 3.0
                    }
            })
            .collect();
        chosen.sort_by(|a, b| {
            let key = |p: &Point| if col == 0 { p.strain } else { p.bending };
            key(a).total_cmp(&key(b))
        });
        let mut chart = ChartBuilder::on(panel)
            .caption(
                if col == 0 {
                    "(a) explosion, t_eps = 1-6%, t_Theta = 4 deg"
                } else {
                    "(b) explosion, t_Theta = 1-7 deg, t_eps = 3%"
                },
                ("sans-serif", 16),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d((1.0..1000.0).log_scale(), (1e-3..1e4).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("fragment mass / mean polygon mass")
            .y_desc("F(m) m-bar (fragments per run)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        for (c, p) in chosen.iter().enumerate() {
            let bins = mass_histogram(&p.masses, p.unit, 4, SEEDS as usize);
            let colour = COLOURS[c % COLOURS.len()];
            let xy: Vec<(f64, f64)> = bins
                .iter()
                .filter(|b| b.count > 0)
                .map(|b| (b.centre() / p.unit, b.density * p.unit))
                .collect();
            let label = if col == 0 {
                format!("t_eps = {}%: beta {}", p.strain, fmt(p.beta))
            } else {
                format!("t_Theta = {} deg: beta {}", p.bending, fmt(p.beta))
            };
            chart
                .draw_series(LineSeries::new(xy.clone(), colour.stroke_width(1)))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour));
            chart.draw_series(xy.iter().map(|q| Circle::new(*q, 3, colour.filled())))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()?;
    }
    area.present()?;
    Ok(())
}

fn fmt(b: Option<f64>) -> String {
    b.map_or("-".into(), |v| format!("{v:.2}"))
}
