//! `cargo bench --bench shpb_ensemble`: what the time step of the main job buys, as an
//! ensemble statement. Granular compaction with breaking grains is chaotic: runs that differ in
//! their step (or seed) follow different, equally valid histories, so the accuracy of a step is
//! the distance of its ensemble mean from a fine-step ensemble's, against the seed-to-seed
//! spread.
//!
//! For each safety factor (`time.safety`: the initial step as a fraction of the Rayleigh step,
//! and the fracture run's step adaptation target ω dt = 3 × safety) and each seed, the main job
//! (scenes/shpb_sand.toml, breaking grains, to 0.4 strain) runs on one thread, as a separate
//! `fractum run` process, `FRACTUM_ENSEMBLE_JOBS` at a time (default 2). Prints per safety the
//! mean and sample standard deviation over the seeds of the axial stress at 0.05, 0.1, 0.2, 0.3
//! and 0.4 strain, the broken fraction and median piece diameter at 0.4, the wall time and
//! steps, and the largest energy-balance error; then each mean's distance from the finest
//! safety's, relative, with the spread. Writes docs/img/shpb_ensemble.svg (largest relative
//! error of the mean over the five strains against the wall seconds per run, taken as the mean
//! steps times the median seconds per step of all runs, the spread as a band).
//!
//! Environment: `FRACTUM_ENSEMBLE_SAFETY` (default `0.05,0.1,0.2,0.4`; runs go in this order),
//! `FRACTUM_ENSEMBLE_SEEDS` (default `1,2,3,4,5`), `FRACTUM_ENSEMBLE_JOBS`, `FRACTUM_BIN` (the
//! fractum binary to run; default the one cargo built: a copy keeps an ensemble on one build
//! while the tree changes), `FRACTUM_ENSEMBLE_REPORT_ONLY` (set: report the finished runs, start
//! none). Each finished run's summary.json is kept
//! under target/shpb_ensemble/ with the binary's size and modification time in the folder name,
//! so an interrupted ensemble picks up where it stopped and a rebuilt binary starts afresh.
//! Asserts nothing. Full ensembles take hours on two cores: run on an idle machine.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

use plotters::prelude::*;
use serde_json::Value;

const STRAINS: [&str; 5] = ["0.05", "0.1", "0.2", "0.3", "0.4"];

fn list(var: &str, default: &str) -> Vec<String> {
    std::env::var(var)
        .unwrap_or_else(|_| default.to_string())
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

/// One finished run: its summary.
struct Run {
    safety: f64,
    summary: Value,
}

fn binary_tag(bin: &Path) -> String {
    let meta = std::fs::metadata(bin).expect("the fractum binary");
    let modified = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_secs());
    format!("{}-{}", meta.len(), modified)
}

fn run_one(bin: &Path, dir: &Path, safety: &str, seed: &str) -> Option<Value> {
    let summary = dir.join("summary.json");
    let report_only = std::env::var_os("FRACTUM_ENSEMBLE_REPORT_ONLY").is_some();
    if !summary.exists() && !report_only {
        let status = Command::new(bin)
            .args([
                "run",
                "scenes/shpb_sand.toml",
                "--quiet",
                "--threads",
                "1",
                "--out",
            ])
            .arg(dir)
            .args(["--set", &format!("seed={seed}")])
            .args(["--set", &format!("time.safety={safety}")])
            .args(["--set", "output.vtk=0"])
            .status()
            .expect("fractum runs");
        if !status.success() {
            eprintln!("safety {safety} seed {seed}: fractum stopped ({status})");
            return None;
        }
    }
    serde_json::from_str(&std::fs::read_to_string(summary).ok()?).ok()
}

fn mean_sd(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = if xs.len() > 1 {
        xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

fn at(s: &Value, key: &str, strain: &str) -> f64 {
    s[key][strain].as_f64().unwrap_or(f64::NAN)
}

fn main() {
    fractum::output::figure::register_font();
    let bin = std::env::var_os("FRACTUM_BIN").map_or_else(
        || PathBuf::from(env!("CARGO_BIN_EXE_fractum")),
        PathBuf::from,
    );
    let safeties = list("FRACTUM_ENSEMBLE_SAFETY", "0.05,0.1,0.2,0.4");
    let seeds = list("FRACTUM_ENSEMBLE_SEEDS", "1,2,3,4,5");
    let jobs: usize = std::env::var("FRACTUM_ENSEMBLE_JOBS")
        .ok()
        .and_then(|j| j.parse().ok())
        .unwrap_or(2)
        .max(1);
    let root = PathBuf::from("target/shpb_ensemble").join(binary_tag(&bin));
    std::fs::create_dir_all(&root).unwrap();
    let mut work: Vec<(String, String)> = Vec::new();
    for s in &safeties {
        for seed in &seeds {
            work.push((s.clone(), seed.clone()));
        }
    }
    eprintln!(
        "{} runs of the main job ({} safeties x {} seeds), {jobs} at a time, in {}",
        work.len(),
        safeties.len(),
        seeds.len(),
        root.display()
    );
    let queue = Mutex::new(work.into_iter());
    let done = Mutex::new(Vec::<Run>::new());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let Some((safety, seed)) = queue.lock().unwrap().next() else {
                        break;
                    };
                    let dir = root.join(format!("safety{safety}_seed{seed}"));
                    if let Some(summary) = run_one(&bin, &dir, &safety, &seed) {
                        eprintln!(
                            "  safety {safety} seed {seed}: {} steps, {:.0} s",
                            summary["steps"],
                            summary["wall_seconds"].as_f64().unwrap_or(f64::NAN)
                        );
                        done.lock().unwrap().push(Run {
                            safety: safety.parse().unwrap(),
                            summary,
                        });
                    }
                }
            });
        }
    });
    let runs = done.into_inner().unwrap();
    let mut by: BTreeMap<u64, Vec<&Run>> = BTreeMap::new();
    for r in &runs {
        by.entry(r.safety.to_bits()).or_default().push(r);
    }
    // Per safety: mean and spread of each measure.
    struct Row {
        safety: f64,
        n: usize,
        stress: Vec<(f64, f64)>,
        broken: (f64, f64),
        d50: (f64, f64),
        wall: (f64, f64),
        steps: f64,
        balance: f64,
    }
    let rows: Vec<Row> = by
        .values()
        .map(|rs| {
            let col = |f: &dyn Fn(&Value) -> f64| -> (f64, f64) {
                mean_sd(&rs.iter().map(|r| f(&r.summary)).collect::<Vec<_>>())
            };
            Row {
                safety: rs[0].safety,
                n: rs.len(),
                stress: STRAINS
                    .iter()
                    .map(|e| col(&|s| at(s, "stress_at_strain", e)))
                    .collect(),
                broken: col(&|s| {
                    s["broken_particles"].as_f64().unwrap_or(f64::NAN)
                        / s["sample"]["count"].as_f64().unwrap_or(f64::NAN)
                }),
                d50: col(&|s| at(s, "median_diameter_at_strain", "0.4") * 1e6),
                wall: col(&|s| s["wall_seconds"].as_f64().unwrap_or(f64::NAN)),
                steps: col(&|s| s["steps"].as_f64().unwrap_or(f64::NAN)).0,
                balance: rs
                    .iter()
                    .map(|r| {
                        r.summary["energy"]["balance_error_relative"]
                            .as_f64()
                            .unwrap_or(f64::NAN)
                            .abs()
                    })
                    .fold(0.0, f64::max),
            }
        })
        .collect();
    println!(
        "| safety | seeds | stress at 0.05 / 0.1 / 0.2 / 0.3 / 0.4 strain, MPa (mean ± sd) | broken fraction | d50 at 0.4, µm | steps | wall s | energy balance (worst) |"
    );
    println!("|---:|---:|---|---:|---:|---:|---:|---:|");
    for r in &rows {
        let stress: Vec<String> = r
            .stress
            .iter()
            .map(|(m, s)| format!("{:.1} ± {:.1}", m / 1e6, s / 1e6))
            .collect();
        println!(
            "| {} | {} | {} | {:.3} ± {:.3} | {:.0} ± {:.0} | {:.0} | {:.0} ± {:.0} | {:.2}% |",
            r.safety,
            r.n,
            stress.join(" / "),
            r.broken.0,
            r.broken.1,
            r.d50.0,
            r.d50.1,
            r.steps,
            r.wall.0,
            r.wall.1,
            100.0 * r.balance
        );
    }
    let Some(reference) = rows.first() else {
        return;
    };
    println!(
        "\nDistance of each ensemble mean from the safety-{} ensemble's (relative), and whether it lies within that reference ensemble's spread (one sd):",
        reference.safety
    );
    println!("| safety | 0.05 | 0.1 | 0.2 | 0.3 | 0.4 | all within the spread |");
    println!("|---:|---:|---:|---:|---:|---:|---|");
    let mut points = Vec::new();
    // The cost axis: steps at the median seconds per step of all runs (runs paused for other
    // work on the machine would otherwise put their ensemble far right).
    let mut rates: Vec<f64> = by
        .values()
        .flatten()
        .filter_map(|r| Some(r.summary["wall_seconds"].as_f64()? / r.summary["steps"].as_f64()?))
        .collect();
    rates.sort_by(f64::total_cmp);
    let per_step = rates.get(rates.len() / 2).copied().unwrap_or(f64::NAN);
    for r in &rows {
        let mut worst: f64 = 0.0;
        let mut band: f64 = 0.0;
        let mut inside = true;
        let cells: Vec<String> = r
            .stress
            .iter()
            .zip(&reference.stress)
            .map(|((m, _), (rm, rs))| {
                let d = (m - rm).abs();
                worst = worst.max(d / rm);
                band = band.max(rs / rm);
                inside &= d <= *rs;
                format!("{:.3}", d / rm)
            })
            .collect();
        println!(
            "| {} | {} | {} |",
            r.safety,
            cells.join(" | "),
            if inside { "yes" } else { "no" }
        );
        points.push((r.steps * per_step, worst, band, r.safety));
    }
    if let Err(e) = plot(&points) {
        eprintln!("plot: {e}");
    } else {
        println!("\nwrote docs/img/shpb_ensemble.svg");
    }
}

/// (wall s per run, largest relative error of the mean, largest relative spread, safety).
fn plot(points: &[(f64, f64, f64, f64)]) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("docs/img")?;
    let root = SVGBackend::new("docs/img/shpb_ensemble.svg", (680, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let xmax = points.iter().map(|p| p.0).fold(1.0, f64::max);
    let xmin = points.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let ymax = points.iter().map(|p| p.1.max(p.2)).fold(0.01, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Main job ensembles: error of the mean stress vs wall time (1 thread)",
            ("sans-serif", 17),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((0.7 * xmin..1.4 * xmax).log_scale(), 0.0..1.2 * ymax)?;
    chart
        .configure_mesh()
        .x_desc("wall seconds per run (mean steps x the median seconds per step of all runs)")
        .y_desc("largest relative distance of the mean, 0.05-0.4 strain")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.3}"))
        .draw()?;
    let band: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.2)).collect();
    let mut area = band.clone();
    area.push((band.last().map_or(1.0, |p| p.0), 0.0));
    area.push((band.first().map_or(1.0, |p| p.0), 0.0));
    chart
        .draw_series(std::iter::once(Polygon::new(area, BLUE.mix(0.15).filled())))?
        .label("seed-to-seed spread of the finest ensemble (sd / mean)")
        .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 18, y + 5)], BLUE.mix(0.15).filled()));
    let pts: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
    chart
        .draw_series(LineSeries::new(pts.clone(), &RED))?
        .label("distance of the ensemble mean from the finest")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED));
    chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, RED.filled())))?;
    chart.draw_series(points.iter().map(|p| {
        Text::new(
            format!("safety {}", p.3),
            (p.0 * 1.03, p.1 + 0.02 * ymax),
            ("sans-serif", 12),
        )
    }))?;
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
