//! Where β differs from the paper (Kun et al. 1999, docs/references.md, Section 3.3): each
//! modelling or analysis choice switched alone, at t_ε = 3% with t_Θ = 4° (the paper's setting)
//! and 2°, both scenes, seeds 1–5; and the shipped scenes at (3%, 4°) over seeds 1–20.
//!
//! ```sh
//! cargo run --release --example beam2d_ablation     # 23 minutes on 2 shared cores
//! cargo run --release --example beam2d_ablation -- seeds 40   # only the shipped scenes
//! ```
//!
//! The switches (docs/validation.md, "Ablation", gives the paper's sentence for each):
//! - (a) the breaking rule: `material.beam_breaking_rule` = "squared", "mean_angle",
//!   "either_sign" against Eq. 13 as printed ("eq13");
//! - (b) the lattice: `sample.disorder` half the spacing against the whole square;
//! - (c) the loading: the explosive `loading.explosive = "kept"`, the projectile
//!   `loading.projectile = "free"`;
//! - (d) the integrator: `time.integrator = "velocity_verlet"` against Gear5;
//! - (e) the fragment definition: single polygons counted (fitted from the bin of one polygon
//!   mass), from the same runs as the baseline;
//! - (f) the fit window: a fixed decade [2, 20], the counted rule to 2 fragments per bin
//!   instead of 5, and from 3 polygon masses instead of 2, from the same runs.
//!
//! β by the rule fixed before the threshold sweep (docs/validation.md, "How β is fitted")
//! unless the switch is that rule; 95% interval from 2000 bootstrap resamples of the seeds.
//! Prints a Markdown table and writes docs/beam2d_ablation.csv.

use std::fmt::Write as _;
use std::time::Instant;

use fractum::models::beam2d::scene::FragmentSpec;
use fractum::models::beam2d::{Beam2dRun, averaged_power_law_by, mean_polygon_mass};
use fractum::probe::fragments::bootstrap_interval;

mod common;
use common::{on_two_workers, root, run};

const SEEDS: u64 = 5;
/// Seeds of the shipped scenes at the paper's setting.
const MANY_SEEDS: u64 = 20;
/// t_ε (%) and t_Θ (degrees).
const SETTINGS: [(f64, f64); 2] = [(3.0, 4.0), (3.0, 2.0)];
const SCENES: [(&str, &str); 2] = [
    ("explosion_disc.toml", "explosion"),
    ("impact_block.toml", "impact"),
];

/// A switch that changes the runs: its name and the keys it sets, per scene.
struct RunSwitch {
    name: &'static str,
    explosion: &'static [&'static str],
    impact: &'static [&'static str],
}

const RUN_SWITCHES: [RunSwitch; 7] = [
    RunSwitch {
        name: "shipped (Eq. 13, disorder = spacing, spent explosive / bonded projectile, Gear5)",
        explosion: &[],
        impact: &[],
    },
    RunSwitch {
        name: "(a) both terms squared",
        explosion: &["material.beam_breaking_rule=\"squared\""],
        impact: &["material.beam_breaking_rule=\"squared\""],
    },
    RunSwitch {
        name: "(a) mean of the two ends' angles",
        explosion: &["material.beam_breaking_rule=\"mean_angle\""],
        impact: &["material.beam_breaking_rule=\"mean_angle\""],
    },
    RunSwitch {
        name: "(a) compressed beams break too",
        explosion: &["material.beam_breaking_rule=\"either_sign\""],
        impact: &["material.beam_breaking_rule=\"either_sign\""],
    },
    RunSwitch {
        name: "(b) disorder half the spacing",
        explosion: &["sample.disorder=0.0054"],
        impact: &["sample.disorder=0.005"],
    },
    RunSwitch {
        name: "(c) explosive kept / projectile free",
        explosion: &["loading.explosive=\"kept\""],
        impact: &["loading.projectile=\"free\""],
    },
    RunSwitch {
        name: "(d) velocity Verlet",
        explosion: &["time.integrator=\"velocity_verlet\""],
        impact: &["time.integrator=\"velocity_verlet\""],
    },
];

/// A switch of the analysis only, applied to the shipped runs: fragments of at least
/// `polygons` polygons, fitted by `spec`.
struct FitSwitch {
    name: &'static str,
    polygons: usize,
    spec: FragmentSpec,
}

fn fit_switches() -> Vec<FitSwitch> {
    let rule = FragmentSpec::default();
    vec![
        FitSwitch {
            name: "(e) single polygons counted (fit from 1 m̄)",
            polygons: 1,
            spec: FragmentSpec {
                fit_from: 1.0,
                ..rule.clone()
            },
        },
        FitSwitch {
            name: "(f) fixed window [2, 20] m̄",
            polygons: 2,
            spec: FragmentSpec {
                fit_range: Some([2.0, 20.0]),
                ..rule.clone()
            },
        },
        FitSwitch {
            name: "(f) to 2 fragments per bin per run",
            polygons: 2,
            spec: FragmentSpec {
                min_per_bin: 2.0,
                ..rule.clone()
            },
        },
        FitSwitch {
            name: "(f) from 3 m̄",
            polygons: 2,
            spec: FragmentSpec {
                fit_from: 3.0,
                ..rule
            },
        },
    ]
}

/// One job: switch, scene, setting, seed.
#[derive(Clone, Copy)]
struct Job {
    switch: usize,
    scene: usize,
    setting: usize,
    seed: u64,
}

/// One row of the result.
struct Row {
    switch: String,
    scene: &'static str,
    setting: (f64, f64),
    seeds: usize,
    beta: Option<f64>,
    interval: Option<[f64; 2]>,
    bins: usize,
    range: [f64; 2],
    fragments: f64,
}

fn fit_row(
    name: &str,
    scene: &'static str,
    setting: (f64, f64),
    group: &[&Beam2dRun],
    spec: &FragmentSpec,
    polygons: usize,
) -> Row {
    let n = group.len();
    let unit = mean_polygon_mass(group);
    let fit = averaged_power_law_by(group, spec, polygons);
    let interval = bootstrap_interval(group, 2000, 20, |draw| {
        let d: Vec<&Beam2dRun> = draw.iter().map(|r| **r).collect();
        averaged_power_law_by(&d, spec, polygons).map(|f| f.exponent)
    });
    Row {
        switch: name.to_string(),
        scene,
        setting,
        seeds: n,
        beta: fit.map(|f| f.exponent),
        interval,
        bins: fit.map_or(0, |f| f.bins),
        range: fit.map_or([f64::NAN; 2], |f| f.range.map(|x| x / unit)),
        fragments: group
            .iter()
            .map(|r| r.model.fragment_masses_from(polygons).len())
            .sum::<usize>() as f64
            / n as f64,
    }
}

fn main() {
    let start = Instant::now();
    // `-- seeds N`: only the shipped scenes at the paper's setting, over seeds 1..=N.
    let args: Vec<String> = std::env::args().collect();
    let only_many: Option<u64> = args
        .iter()
        .position(|a| a == "seeds")
        .and_then(|k| args.get(k + 1))
        .map(|n| n.parse().expect("seeds N: N a whole number"));
    let many = only_many.unwrap_or(MANY_SEEDS);
    let switches = if only_many.is_some() {
        1
    } else {
        RUN_SWITCHES.len()
    };
    let mut jobs = Vec::new();
    for switch in 0..switches {
        for scene in 0..SCENES.len() {
            for setting in 0..SETTINGS.len() {
                let seeds = if switch == 0 && setting == 0 {
                    many
                } else if only_many.is_some() {
                    0
                } else {
                    SEEDS
                };
                for seed in 1..=seeds {
                    jobs.push(Job {
                        switch,
                        scene,
                        setting,
                        seed,
                    });
                }
            }
        }
    }
    // Two workers (two cores), each run on one thread; results by job index.
    let runs: Vec<Beam2dRun> = on_two_workers(&jobs, |job| {
        let (strain, bending) = SETTINGS[job.setting];
        let sw = &RUN_SWITCHES[job.switch];
        let extra = if job.scene == 0 {
            sw.explosion
        } else {
            sw.impact
        };
        run(SCENES[job.scene].0, job.seed, strain, bending, extra)
    });
    let wall = start.elapsed().as_secs_f64();

    let rule = FragmentSpec::default();
    let group = |switch: usize, scene: usize, setting: usize, seeds: u64| -> Vec<&Beam2dRun> {
        jobs.iter()
            .enumerate()
            .filter(|(_, j)| {
                j.switch == switch && j.scene == scene && j.setting == setting && j.seed <= seeds
            })
            .map(|(k, _)| &runs[k])
            .collect()
    };
    let mut rows = Vec::new();
    for (setting, &thresholds) in SETTINGS.iter().enumerate() {
        if only_many.is_some() {
            break;
        }
        for (scene, &(_, stem)) in SCENES.iter().enumerate() {
            for (switch, sw) in RUN_SWITCHES.iter().enumerate() {
                let g = group(switch, scene, setting, SEEDS);
                rows.push(fit_row(sw.name, stem, thresholds, &g, &rule, 2));
            }
            let base = group(0, scene, setting, SEEDS);
            for fs in fit_switches() {
                rows.push(fit_row(
                    fs.name,
                    stem,
                    thresholds,
                    &base,
                    &fs.spec,
                    fs.polygons,
                ));
            }
        }
    }
    for (scene, &(_, stem)) in SCENES.iter().enumerate() {
        let g = group(0, scene, 0, many);
        rows.push(fit_row(
            &format!("shipped, seeds 1-{many}"),
            stem,
            SETTINGS[0],
            &g,
            &rule,
            2,
        ));
        // The seeds as sets of five: how far apart five-seed estimates fall.
        for set in 0..many / 5 {
            let five: Vec<&Beam2dRun> = g[(5 * set) as usize..(5 * set + 5) as usize].to_vec();
            let fit = averaged_power_law_by(&five, &rule, 2);
            eprintln!(
                "{stem} seeds {}-{}: beta {}",
                5 * set + 1,
                5 * set + 5,
                fit.map_or("-".into(), |f| format!("{:.3}", f.exponent))
            );
        }
    }
    report(&rows, wall);
}

fn report(rows: &[Row], wall: f64) {
    let mut csv = String::from(
        "switch,scene,strain_threshold_percent,bending_threshold_degrees,seeds,beta,beta_lo95,beta_hi95,fit_bins,fit_from,fit_to,fragments_per_run\n",
    );
    println!(
        "| switch | scene | t_ε | t_Θ | seeds | β | 95% (bootstrap) | bins | fit range (m̄) | fragments per run |"
    );
    println!("|---|---|---:|---:|---:|---:|---|---:|---|---:|");
    for r in rows {
        let beta = r.beta.map_or("-".to_string(), |v| format!("{v:.3}"));
        let iv = r
            .interval
            .map_or("-".into(), |[a, b]| format!("{a:.3}–{b:.3}"));
        println!(
            "| {} | {} | {}% | {}° | {} | {beta} | {iv} | {} | {:.1}–{:.1} | {:.0} |",
            r.switch,
            r.scene,
            r.setting.0,
            r.setting.1,
            r.seeds,
            r.bins,
            r.range[0],
            r.range[1],
            r.fragments
        );
        let _ = writeln!(
            csv,
            "\"{}\",{},{},{},{},{},{},{},{},{},{},{}",
            r.switch,
            r.scene,
            r.setting.0,
            r.setting.1,
            r.seeds,
            r.beta.map_or(String::new(), |v| v.to_string()),
            r.interval.map_or(String::new(), |i| i[0].to_string()),
            r.interval.map_or(String::new(), |i| i[1].to_string()),
            r.bins,
            r.range[0],
            r.range[1],
            r.fragments
        );
    }
    println!("\n{wall:.0} s wall");
    if rows.len() > 2 {
        std::fs::write(root().join("docs/beam2d_ablation.csv"), csv).expect("write csv");
    }
}
