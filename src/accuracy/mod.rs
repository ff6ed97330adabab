//! What accuracy costs: each validation case that has a reference (theory, the paper, a
//! measured ensemble or a fine run) swept over its resolution (grains, cells, polygons) and its
//! time step, on one and two threads, with the error and the wall seconds of every setting.
//! `fractum bench accuracy` runs it and writes accuracy_cost.csv, accuracy_cost.svg/.png and
//! accuracy_report.md (docs/accuracy.md).
//!
//! The cases live with their models (`models/*/accuracy.rs`) and the registry lists them
//! (`models::accuracy_cases`); this module knows none of them: it runs settings, times them,
//! compares them with the reference, and writes the table, the report and the figure.

pub mod figure;

use std::path::Path;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::output::write_atomic;
use crate::run::Run;
use crate::scene::Scene;

/// One setting of a case's two knobs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setting {
    /// The resolution knob's value (grains, cells, polygons, a box edge, a polygon spacing);
    /// `None` for a case without one (two spheres, one grain).
    pub resolution: Option<f64>,
    /// The time-step knob's value (a safety factor, a step in seconds, a fraction of the
    /// Rayleigh step).
    pub step: f64,
}

impl Setting {
    pub const fn new(resolution: f64, step: f64) -> Self {
        Setting {
            resolution: Some(resolution),
            step,
        }
    }

    /// A setting of a case that has no resolution knob.
    pub const fn step(step: f64) -> Self {
        Setting {
            resolution: None,
            step,
        }
    }
}

/// One measured quantity of a setting: its value and, for a case whose reference is known
/// beforehand (theory, the input, the paper, a measured ensemble), the reference value.
#[derive(Clone, Debug)]
pub struct Quantity {
    pub name: &'static str,
    pub value: f64,
    pub reference: Option<f64>,
}

impl Quantity {
    /// A quantity compared with a known value.
    pub fn against(name: &'static str, value: f64, reference: f64) -> Self {
        Quantity {
            name,
            value,
            reference: Some(reference),
        }
    }

    /// A quantity compared with the case's reference run.
    pub fn measured(name: &'static str, value: f64) -> Self {
        Quantity {
            name,
            value,
            reference: None,
        }
    }
}

/// What one setting measured.
#[derive(Clone, Debug)]
pub struct Measured {
    /// Elements of one run (spheres, grains, cells, polygons) at the start.
    pub elements: usize,
    /// Runs behind the numbers (the seeds of an ensemble; 1 otherwise).
    pub runs: usize,
    pub quantities: Vec<Quantity>,
}

/// What a case's quantities are compared with.
#[derive(Clone, Copy, Debug)]
pub enum Reference {
    /// Each quantity carries its own reference value (theory, the input, the paper, a
    /// measured ensemble); the text says which.
    Known(&'static str),
    /// A finer run of this setting, on one thread, run first.
    Run(Setting),
}

/// The settings of one mode (full or quick) and what they are compared with.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The settings, cheapest first (quick mode also runs the first on every thread count).
    pub settings: Vec<Setting>,
    pub reference: Reference,
}

/// Runs one setting on a number of threads; `quick` for the reduced size of quick mode.
pub type Measure = Box<dyn Fn(&Setting, usize, bool) -> Result<Measured> + Send + Sync>;

/// A validation case with a reference, and the two knobs it is swept over.
pub struct Case {
    /// The name on the command line and in the CSV.
    pub name: &'static str,
    /// What is compared with what, in a few words (figure legend, report).
    pub title: &'static str,
    /// The resolution knob (a scene key, or a description), `None` if the case has none.
    pub resolution_key: Option<&'static str>,
    /// The time-step knob.
    pub step_key: &'static str,
    /// The accuracy that the report's line asks for ("within X%"): the tolerance of the
    /// project's test of this case, fixed before any sweep ran.
    pub target: f64,
    pub full: Plan,
    pub quick: Plan,
    pub measure: Measure,
}

impl Case {
    pub fn plan(&self, quick: bool) -> &Plan {
        if quick { &self.quick } else { &self.full }
    }
}

/// The sweep's options.
#[derive(Clone, Debug)]
pub struct Options {
    /// The small sweep of reduced sizes.
    pub quick: bool,
    /// Thread counts: in full mode every setting runs on each; in quick mode every setting
    /// runs on the first and the case's first setting on the others too.
    pub threads: Vec<usize>,
}

/// One row of accuracy_cost.csv.
#[derive(Clone, Debug)]
pub struct Row {
    pub case: &'static str,
    /// The reference run of a case compared with a fine run (error 0 by definition).
    pub is_reference: bool,
    pub resolution_key: Option<&'static str>,
    pub step_key: &'static str,
    pub setting: Setting,
    pub threads: usize,
    pub elements: usize,
    pub runs: usize,
    /// Each quantity: name, value, reference.
    pub values: Vec<(&'static str, f64, f64)>,
    /// The largest relative error over the quantities, |value / reference − 1|; `None` if the
    /// setting did not run to the end (`note` says why).
    pub error: Option<f64>,
    pub wall_seconds: f64,
    /// Not dominated within its case: no other row has both a smaller-or-equal error and
    /// fewer-or-equal seconds, one of them strictly.
    pub pareto: bool,
    pub note: String,
}

/// Progress of a sweep, for a bar or a log.
pub enum Event<'a> {
    /// A run is starting: its case, setting and threads, and how many runs there are in all.
    Start {
        case: &'a Case,
        setting: &'a Setting,
        threads: usize,
        total: usize,
    },
    /// A run has finished.
    Done(&'a Row),
}

/// The cases named in `names` (all when empty), in the registry's order. An unknown name is
/// refused in one sentence naming the allowed values.
pub fn select<'a>(cases: &'a [Case], names: &[String]) -> Result<Vec<&'a Case>> {
    for n in names {
        if !cases.iter().any(|c| c.name == n) {
            let allowed: Vec<&str> = cases.iter().map(|c| c.name).collect();
            return Err(Error::input(
                "command line",
                format!(
                    "bench accuracy: CASE = \"{n}\" is not a case; allowed values: {}",
                    allowed.join(", ")
                ),
            ));
        }
    }
    Ok(cases
        .iter()
        .filter(|c| names.is_empty() || names.iter().any(|n| n == c.name))
        .collect())
}

/// Checks the thread counts: at least one, none zero.
pub fn check_threads(threads: &[usize]) -> Result<()> {
    if threads.is_empty() || threads.contains(&0) {
        return Err(Error::input(
            "command line",
            "bench accuracy: --threads must list thread counts of at least 1, e.g. 1,2",
        ));
    }
    Ok(())
}

/// The runs that `sweep` makes for `cases`: (case, setting, threads, is the reference run).
fn runs<'a>(cases: &[&'a Case], options: &Options) -> Vec<(&'a Case, Setting, usize, bool)> {
    let mut out = Vec::new();
    for &case in cases {
        let plan = case.plan(options.quick);
        if let Reference::Run(s) = plan.reference {
            out.push((case, s, 1, true));
        }
        for (k, s) in plan.settings.iter().enumerate() {
            for (t, &threads) in options.threads.iter().enumerate() {
                if !options.quick || t == 0 || k == 0 {
                    out.push((case, *s, threads, false));
                }
            }
        }
    }
    out
}

/// Runs every setting of `cases`, one at a time (so that each wall time is its own), and
/// returns the rows in order. `case_done` is called with all rows so far after each case
/// (to write the table as the sweep goes). A setting that fails becomes a row without an
/// error, its note saying why; a case whose reference run fails has no errors at all.
pub fn sweep(
    cases: &[&Case],
    options: &Options,
    progress: &mut dyn FnMut(Event),
    case_done: &mut dyn FnMut(&[Row]) -> Result<()>,
) -> Result<Vec<Row>> {
    let plan = runs(cases, options);
    let total = plan.len();
    let mut rows: Vec<Row> = Vec::new();
    let mut reference: Option<Vec<f64>> = None;
    for (k, (case, setting, threads, is_reference)) in plan.iter().enumerate() {
        progress(Event::Start {
            case,
            setting,
            threads: *threads,
            total,
        });
        let (measured, wall_seconds) = timed(|| (case.measure)(setting, *threads, options.quick));
        let mut row = Row {
            case: case.name,
            is_reference: *is_reference,
            resolution_key: case.resolution_key,
            step_key: case.step_key,
            setting: *setting,
            threads: *threads,
            elements: 0,
            runs: 0,
            values: Vec::new(),
            error: None,
            wall_seconds,
            pareto: false,
            note: String::new(),
        };
        match measured {
            Ok(m) => {
                row.elements = m.elements;
                row.runs = m.runs;
                if *is_reference {
                    reference = Some(m.quantities.iter().map(|q| q.value).collect());
                }
                let refs: Option<Vec<f64>> = match case.plan(options.quick).reference {
                    Reference::Known(_) => m.quantities.iter().map(|q| q.reference).collect(),
                    Reference::Run(_) => reference.clone(),
                };
                match refs {
                    Some(refs) if refs.len() == m.quantities.len() => {
                        row.values = m
                            .quantities
                            .iter()
                            .zip(&refs)
                            .map(|(q, r)| (q.name, q.value, *r))
                            .collect();
                        row.error = relative_error(&row.values);
                        if row.error.is_none() {
                            row.note = "a value or its reference is not finite".into();
                        }
                    }
                    _ => {
                        row.values = m
                            .quantities
                            .iter()
                            .map(|q| (q.name, q.value, f64::NAN))
                            .collect();
                        row.note = "no reference: the reference run failed".into();
                    }
                }
            }
            Err(e) => {
                if *is_reference {
                    reference = None;
                }
                row.note = e.to_string();
            }
        }
        progress(Event::Done(&row));
        rows.push(row);
        let case_ends = plan.get(k + 1).is_none_or(|next| next.0.name != case.name);
        if case_ends {
            reference = None;
            mark_pareto(&mut rows);
            case_done(&rows)?;
        }
    }
    Ok(rows)
}

/// The shortest time that one timing may take: a setting that runs faster (the Hertz impacts
/// take microseconds) is repeated until this much has passed, and its mean is its cost.
const SHORTEST_TIMING: f64 = 0.05;

/// `measure`'s result and its wall seconds, over as many repetitions (at most 1000) as it
/// takes to fill [`SHORTEST_TIMING`]; a failure ends the repetitions.
fn timed(measure: impl Fn() -> Result<Measured>) -> (Result<Measured>, f64) {
    let start = Instant::now();
    let mut times = 0;
    loop {
        let m = measure();
        times += 1;
        let elapsed = start.elapsed().as_secs_f64();
        if m.is_err() || elapsed >= SHORTEST_TIMING || times >= 1000 {
            return (m, elapsed / times as f64);
        }
    }
}

/// Seconds with three significant figures.
pub fn seconds(s: f64) -> String {
    if s >= 100.0 {
        format!("{s:.0}")
    } else if s >= 0.01 {
        format!("{}", (s * 1000.0).round() / 1000.0)
    } else {
        format!("{s:.2e}")
    }
}

/// The largest |value / reference − 1| over the quantities; `None` if any is not finite.
pub fn relative_error(values: &[(&'static str, f64, f64)]) -> Option<f64> {
    let mut worst: f64 = 0.0;
    for (_, v, r) in values {
        let e = (v / r - 1.0).abs();
        if !e.is_finite() {
            return None;
        }
        worst = worst.max(e);
    }
    Some(worst)
}

/// Marks the rows of each case that no other row of that case dominates in both error and
/// wall seconds. Reference runs (error 0 by definition) and failed settings take no part.
pub fn mark_pareto(rows: &mut [Row]) {
    let points: Vec<Option<(&str, f64, f64)>> = rows
        .iter()
        .map(|r| {
            r.error
                .filter(|_| !r.is_reference)
                .map(|e| (r.case, e, r.wall_seconds))
        })
        .collect();
    for (k, row) in rows.iter_mut().enumerate() {
        row.pareto = points[k].is_some_and(|(case, e, w)| {
            !points.iter().enumerate().any(|(j, p)| {
                j != k
                    && p.is_some_and(|(c, ej, wj)| {
                        c == case && ej <= e && wj <= w && (ej < e || wj < w)
                    })
            })
        });
    }
}

fn number(v: Option<f64>) -> String {
    v.map(|x| format!("{x}")).unwrap_or_default()
}

/// accuracy_cost.csv: one row per run. `measured` and `reference` list the quantities as
/// `name=value` separated by spaces; `error` is empty (and `note` says why) for a setting
/// that did not run to the end.
pub fn csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "case,role,resolution_key,resolution,step_key,step,elements,runs,threads,error,wall_seconds,pareto,measured,reference,note\n",
    );
    for r in rows {
        let list = |pick: fn(&(&'static str, f64, f64)) -> f64| {
            r.values
                .iter()
                .map(|q| format!("{}={}", q.0, pick(q)))
                .collect::<Vec<_>>()
                .join(" ")
        };
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n",
            r.case,
            if r.is_reference { "reference" } else { "sweep" },
            r.resolution_key.unwrap_or(""),
            number(r.setting.resolution),
            r.step_key,
            r.setting.step,
            r.elements,
            r.runs,
            r.threads,
            number(r.error),
            r.wall_seconds,
            r.pareto,
            list(|q| q.1),
            list(|q| q.2),
            r.note.replace('"', "'"),
        ));
    }
    s
}

/// The knob values of a row, as `key = value` pairs.
fn knobs(r: &Row) -> String {
    match (r.resolution_key, r.setting.resolution) {
        (Some(k), Some(v)) => format!("{k} = {v}, {} = {}", r.step_key, r.setting.step),
        _ => format!("{} = {}", r.step_key, r.setting.step),
    }
}

fn percent(e: f64) -> String {
    let p = 100.0 * e;
    if p >= 10.0 {
        format!("{p:.0}%")
    } else if p >= 1.0 {
        format!("{p:.1}%")
    } else {
        format!("{p:.2}%")
    }
}

/// The report's line for one case: the cheapest one-thread setting within the case's target,
/// or, if none reached it, the most accurate one.
pub fn case_line(case: &Case, rows: &[Row], quick: bool) -> String {
    let ours: Vec<&Row> = rows
        .iter()
        .filter(|r| r.case == case.name && !r.is_reference && r.threads == 1)
        .collect();
    let fmt = |r: &Row| {
        format!(
            "{} element{}{} and {} s on one core here ({}; error {})",
            r.elements,
            if r.elements == 1 { "" } else { "s" },
            if r.runs > 1 {
                format!(" × {} runs", r.runs)
            } else {
                String::new()
            },
            seconds(r.wall_seconds),
            knobs(r),
            percent(r.error.unwrap_or(f64::NAN)),
        )
    };
    let within = ours
        .iter()
        .filter(|r| r.error.is_some_and(|e| e <= case.target))
        .min_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds));
    let best = ours
        .iter()
        .filter(|r| r.error.is_some())
        .min_by(|a, b| a.error.unwrap().total_cmp(&b.error.unwrap()));
    let reference = match case.plan(quick).reference {
        Reference::Known(text) => text.to_string(),
        Reference::Run(s) => {
            let r = rows.iter().find(|r| r.case == case.name && r.is_reference);
            let cost = r
                .map(|r| {
                    let plural = if r.elements == 1 { "" } else { "s" };
                    format!(
                        ", {} element{plural}, {} s",
                        r.elements,
                        seconds(r.wall_seconds)
                    )
                })
                .unwrap_or_default();
            match s.resolution {
                Some(v) => format!(
                    "a run at {} = {v}, {} = {}{cost}",
                    case.resolution_key.unwrap_or(""),
                    case.step_key,
                    s.step
                ),
                None => format!("a run at {} = {}{cost}", case.step_key, s.step),
            }
        }
    };
    let head = format!("**{}** ({}; reference: {reference})", case.name, case.title);
    match (within, best) {
        (Some(r), _) => format!("{head}: within {} takes {}.", percent(case.target), fmt(r)),
        (None, Some(r)) => format!(
            "{head}: within {} is not reached in this sweep; the closest takes {}.",
            percent(case.target),
            fmt(r)
        ),
        (None, None) => format!("{head}: no setting ran to the end."),
    }
}

/// accuracy_report.md: one line per case, then the settings that did not run to the end.
pub fn report(cases: &[&Case], rows: &[Row], quick: bool) -> String {
    let mut s = String::new();
    for case in cases {
        s.push_str(&format!("- {}\n", case_line(case, rows, quick)));
    }
    let failed: Vec<&Row> = rows.iter().filter(|r| r.error.is_none()).collect();
    if !failed.is_empty() {
        s.push_str("\nSettings without an error:\n\n");
        for r in failed {
            s.push_str(&format!(
                "- {} ({}, {} thread(s)): {}\n",
                r.case,
                knobs(r),
                r.threads,
                r.note
            ));
        }
    }
    s
}

/// Writes accuracy_cost.csv, accuracy_report.md, accuracy_cost.svg and accuracy_cost.png into
/// `dir` (created if missing), each file atomically.
pub fn write_outputs(dir: &Path, cases: &[&Case], rows: &[Row], quick: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "create the output folder", e))?;
    write_atomic(&dir.join("accuracy_cost.csv"), csv(rows).as_bytes())?;
    write_atomic(
        &dir.join("accuracy_report.md"),
        report(cases, rows, quick).as_bytes(),
    )?;
    let title = if quick {
        "What accuracy costs (quick sweep)"
    } else {
        "What accuracy costs"
    };
    write_figure(dir, title, &figure::curves(cases, rows))
}

/// accuracy_cost.svg and accuracy_cost.png of `curves` into `dir`, each file atomically.
fn write_figure(dir: &Path, title: &str, curves: &[figure::Curve]) -> Result<()> {
    write_atomic(
        &dir.join("accuracy_cost.svg"),
        figure::svg(title, curves)?.as_bytes(),
    )?;
    write_atomic(&dir.join("accuracy_cost.png"), &figure::png(title, curves)?)
}

/// Draws accuracy_cost.svg and accuracy_cost.png into `dir` from an accuracy_cost.csv (after
/// rows were rerun and merged into it, say), each file atomically; runs nothing.
pub fn replot(csv_path: &Path, dir: &Path) -> Result<()> {
    let text = std::fs::read_to_string(csv_path)
        .map_err(|e| Error::io(csv_path, "read the accuracy table", e))?;
    let curves = figure::curves_from_csv(&text)
        .map_err(|m| Error::input(csv_path.display().to_string(), m))?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, "create the output folder", e))?;
    write_figure(dir, "What accuracy costs", &curves)
}

/// Advances `run` to its end and returns its summary.
pub fn finish(run: &mut dyn Run) -> Result<serde_json::Value> {
    while !run.finished() {
        run.advance(100_000)?;
    }
    Ok(run.summary())
}

/// A shipped scene (its text compiled in, so the sweep runs from any folder) with overrides.
pub fn scene(text: &str, file: &str, overrides: &[String]) -> Result<Scene> {
    Scene::from_toml(text, file, Path::new("scenes"), overrides)
}

/// A number from a summary, or a run error naming the key.
pub fn get(summary: &serde_json::Value, key: &str) -> Result<f64> {
    let mut v = summary;
    for part in key.split('.') {
        v = &v[part];
    }
    v.as_f64()
        .ok_or_else(|| Error::run(format!("the summary has no number `{key}`")))
}

#[cfg(test)]
mod tests;
