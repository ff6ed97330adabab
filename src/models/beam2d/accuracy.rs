//! The beam2d model's cases of `fractum bench accuracy` (docs/accuracy.md): the elastic moduli
//! against the finest run, and the explosion's fragment-mass exponent β (five seeds, the
//! averaged histogram) against the paper's 2.0, over the polygon count and the time step.

use super::{Beam2dRun, averaged_power_law};
use crate::accuracy::{Case, Measured, Plan, Quantity, Reference, Setting, finish, get, scene};
use crate::error::{Error, Result};
use crate::run::Run;

const MODULI: &str = include_str!("../../../scenes/beam2d_moduli.toml");
const EXPLOSION: &str = include_str!("../../../scenes/explosion_disc.toml");

/// The paper's β of the explosion (Section 3.3.1).
const PAPER_BETA: f64 = 2.0;

fn run(text: &str, file: &str, overrides: &[String], threads: usize) -> Result<Beam2dRun> {
    let mut run = Beam2dRun::new(scene(text, file, overrides)?, threads, &mut |_| {})?;
    finish(&mut run)?;
    Ok(run)
}

/// The beam2d model's accuracy cases.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "beam2d_moduli",
            title: "Young modulus and Poisson ratio in elongation and compression vs the finest run",
            resolution_key: Some("sample.cells (width; length 1.5 x)"),
            step_key: "time.dt",
            target: 0.05,
            full: Plan {
                settings: vec![
                    Setting::new(8.0, 1e-6),
                    Setting::new(12.0, 1e-6),
                    Setting::new(20.0, 2e-6),
                    Setting::new(20.0, 1e-6),
                    Setting::new(20.0, 5e-7),
                    Setting::new(30.0, 1e-6),
                ],
                reference: Reference::Run(Setting::new(30.0, 5e-7)),
            },
            quick: Plan {
                settings: vec![Setting::new(8.0, 1e-6), Setting::new(12.0, 2e-6)],
                reference: Reference::Run(Setting::new(12.0, 1e-6)),
            },
            measure: Box::new(|s, threads, _| {
                let n = s.resolution.unwrap_or(20.0);
                let r = run(
                    MODULI,
                    "scenes/beam2d_moduli.toml",
                    &[
                        format!("sample.cells=[{n}, {}]", (1.5 * n).round()),
                        format!("time.dt={:e}", s.step),
                    ],
                    threads,
                )?;
                let summary = r.summary();
                let q = |name, key| Ok::<_, Error>(Quantity::measured(name, get(&summary, key)?));
                Ok(Measured {
                    elements: get(&summary, "polygons")? as usize,
                    runs: 1,
                    quantities: vec![
                        q("young_elongation", "young_elongation")?,
                        q("poisson_elongation", "poisson_elongation")?,
                        q("young_compression", "young_compression")?,
                        q("poisson_compression", "poisson_compression")?,
                    ],
                })
            }),
        },
        Case {
            name: "beam2d_beta",
            title: "explosion fragment-mass exponent β, 5 seeds, vs the paper's 2.0",
            resolution_key: Some("sample.spacing (m)"),
            step_key: "time.dt",
            target: 0.1,
            full: Plan {
                settings: vec![
                    Setting::new(0.0144, 1e-6),
                    Setting::new(0.0108, 1e-6),
                    Setting::new(0.0108, 5e-7),
                    Setting::new(0.0081, 1e-6),
                ],
                reference: Reference::Known("the paper's β = 2.0 (Section 3.3.1)"),
            },
            quick: Plan {
                settings: vec![Setting::new(0.018, 1e-6)],
                reference: Reference::Known("the paper's β = 2.0 (Section 3.3.1)"),
            },
            measure: Box::new(|s, threads, _| {
                let spacing = s.resolution.unwrap_or(0.0108);
                let runs = (1..=5u64)
                    .map(|seed| {
                        run(
                            EXPLOSION,
                            "scenes/explosion_disc.toml",
                            &[
                                format!("seed={seed}"),
                                format!("sample.spacing={spacing}"),
                                format!("sample.disorder={spacing}"),
                                format!("time.dt={:e}", s.step),
                            ],
                            threads,
                        )
                    })
                    .collect::<Result<Vec<_>>>()?;
                let refs: Vec<&Beam2dRun> = runs.iter().collect();
                let fit = averaged_power_law(&refs).ok_or_else(|| {
                    Error::run("no power-law fit: too few fragments of two or more polygons")
                })?;
                let polygons = runs
                    .iter()
                    .map(|r| r.model.state.polygons.len())
                    .sum::<usize>()
                    / runs.len();
                Ok(Measured {
                    elements: polygons,
                    runs: runs.len(),
                    quantities: vec![Quantity::against("beta", fit.exponent, PAPER_BETA)],
                })
            }),
        },
    ]
}
