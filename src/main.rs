//! The `fractum` command: run, resume, explain and bench.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use fractum::driver::{RunOptions, run_to_end};
use fractum::output::{OutputDir, Start};
use fractum::{Error, Run, Scene};
use indicatif::{ProgressBar, ProgressStyle};

#[derive(Parser)]
#[command(
    name = "fractum",
    version,
    about = "Discrete element solver for brittle fracture"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene to the end of its loading.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output folder (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Override a scene key by its dotted path, e.g. --set material.young=70e9.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        #[command(flatten)]
        options: RunArgs,
    },
    /// Continue a run from a checkpoint.
    Resume {
        /// A checkpoint file written with --checkpoint-every.
        checkpoint: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        options: RunArgs,
    },
    /// Write the scene for a peer code: the sample at full precision and a script that runs
    /// the same contact law, walls, loading, time step and steps, printing series.csv's
    /// columns. LAMMPS: DIR/packing.data (atom_style sphere, units si) and DIR/in.fractum
    /// (writes series_lammps.csv); YADE: DIR/packing.txt (ymport.text) and
    /// DIR/fractum_yade.py (writes series_yade.csv).
    Export {
        /// lammps or yade.
        format: ExportFormat,
        /// The scene file (TOML).
        scene: PathBuf,
        /// Folder to write into.
        dir: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// LAMMPS: a script for the Fractum LAMMPS plugin (make lammps-plugin), with the
        /// grains' shapes in the data file and Fractum's first forces in forces0.csv.
        #[arg(long)]
        plugin: bool,
        #[arg(long)]
        quiet: bool,
    },
    /// Print what a scene builds: sample, force pipeline, loading, time step, outputs.
    Explain {
        scene: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Time particle-steps per second on dense packings (prints figures, asserts nothing);
    /// `fractum bench accuracy`: what accuracy costs, for every validation case.
    #[command(args_conflicts_with_subcommands = true)]
    Bench {
        #[command(subcommand)]
        what: Option<BenchWhat>,
        /// Packing sizes.
        #[arg(long, value_delimiter = ',', default_values_t = [1000usize, 8000])]
        bodies: Vec<usize>,
        /// Thread counts.
        #[arg(long, value_delimiter = ',', default_values_t = [1usize, 2])]
        threads: Vec<usize>,
        /// Timed steps per case.
        #[arg(long, default_value_t = 2000)]
        steps: u64,
    },
}

#[derive(Subcommand)]
enum BenchWhat {
    /// What accuracy costs: each validation case with a reference swept over its resolution
    /// (grains, cells, polygons) and time step, on 1 and 2 threads. Writes
    /// accuracy_cost.csv (case, knobs, error, wall seconds, threads), accuracy_report.md and
    /// accuracy_cost.svg/.png (error against wall seconds, log-log) into --out. The full
    /// sweep takes hours on two cores; --quick runs a small one in a couple of minutes.
    Accuracy {
        /// Cases to run (default: all), e.g. hertz_impact dlsm_tensile.
        cases: Vec<String>,
        /// A small sweep of reduced sizes.
        #[arg(long)]
        quick: bool,
        /// Output folder.
        #[arg(long, default_value = "out/accuracy")]
        out: PathBuf,
        /// Thread counts.
        #[arg(long, value_delimiter = ',', default_values_t = [1usize, 2])]
        threads: Vec<usize>,
        /// No progress bar and no messages.
        #[arg(long)]
        quiet: bool,
        /// Runs nothing: draws accuracy_cost.svg/.png into --out from this accuracy_cost.csv
        /// (after rows were rerun and merged into it).
        #[arg(long, value_name = "CSV")]
        replot: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ExportFormat {
    Lammps,
    Yade,
}

/// Options shared by `run` and `resume`.
#[derive(clap::Args)]
struct RunArgs {
    /// No progress bar and no messages.
    #[arg(long)]
    quiet: bool,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write a checkpoint every N steps into OUT/checkpoints/.
    #[arg(long, value_name = "N")]
    checkpoint_every: Option<u64>,
}

impl RunArgs {
    fn run_options(&self) -> RunOptions {
        RunOptions {
            checkpoint_every: self.checkpoint_every,
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

fn dispatch(command: Command) -> Result<(), Error> {
    match command {
        Command::Run {
            scene,
            out,
            set,
            options,
        } => {
            options.run_options().check()?;
            let scene = Scene::load(&scene, &set)?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(&scene.name));
            let say = messenger(options.quiet);
            say(&format!("{}: building the sample", scene.name));
            let mut note = |m: &str| say(m);
            let sim = fractum::models::build(scene, options.threads, &mut note)?;
            run(sim, out, Vec::new(), None, &options)
        }
        Command::Resume {
            checkpoint: path,
            out,
            options,
        } => {
            options.run_options().check()?;
            let (sim, frames) = fractum::models::resume(&path, options.threads)?;
            messenger(options.quiet)(&format!(
                "{}: resuming at step {} of {}",
                sim.scene().name,
                sim.step(),
                sim.end_step()
            ));
            run(sim, out, frames, Some(&path), &options)
        }
        Command::Export {
            format,
            scene,
            dir,
            set,
            plugin,
            quiet,
        } => {
            let scene = Scene::load(&scene, &set)?;
            let say = messenger(quiet);
            let mut note = |m: &str| say(m);
            let written = fractum::models::granular::export::export(
                scene,
                format == ExportFormat::Lammps,
                plugin,
                &dir,
                &mut note,
            )?;
            say(&written);
            Ok(())
        }
        Command::Explain { scene, set } => {
            let scene = Scene::load(&scene, &set)?;
            print!("{}", fractum::models::explain(&scene)?);
            Ok(())
        }
        Command::Bench {
            what:
                Some(BenchWhat::Accuracy {
                    replot: Some(table),
                    out,
                    ..
                }),
            ..
        } => fractum::accuracy::replot(&table, &out),
        Command::Bench {
            what:
                Some(BenchWhat::Accuracy {
                    cases,
                    quick,
                    out,
                    threads,
                    quiet,
                    replot: None,
                }),
            ..
        } => accuracy(&cases, quick, &out, threads, quiet),
        Command::Bench {
            what: None,
            bodies,
            threads,
            steps,
        } => {
            let cache = fractum::models::granular::bench::default_cache();
            let mut note = |m: &str| eprintln!("{m}");
            let cases =
                fractum::models::granular::bench::run(&bodies, &threads, steps, &cache, &mut note)?;
            println!("{}", fractum::bench::table("particle", &cases));
            Ok(())
        }
    }
}

/// `fractum bench accuracy`: the sweep with a progress bar (or a line per run when stderr is
/// not a terminal), its table, report and figure written into `out` after each case.
fn accuracy(
    names: &[String],
    quick: bool,
    out: &std::path::Path,
    threads: Vec<usize>,
    quiet: bool,
) -> Result<(), Error> {
    use fractum::accuracy::{self, Event, Options};
    let all = fractum::models::accuracy_cases();
    let cases = accuracy::select(&all, names)?;
    accuracy::check_threads(&threads)?;
    let options = Options { quick, threads };
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} runs  {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar
    });
    let say = messenger(quiet || bar.is_some());
    let describe = |case: &str, s: &accuracy::Setting, threads: usize| match s.resolution {
        Some(r) => format!("{case} {r} / {} on {threads} thread(s)", s.step),
        None => format!("{case} {} on {threads} thread(s)", s.step),
    };
    let mut progress = |e: Event| match e {
        Event::Start {
            case,
            setting,
            threads,
            total,
        } => {
            if let Some(bar) = &bar {
                bar.set_length(total as u64);
                bar.set_message(describe(case.name, setting, threads));
            }
        }
        Event::Done(row) => {
            let error = row
                .error
                .map(|e| format!("error {e:.3e}"))
                .unwrap_or_else(|| row.note.clone());
            let line = format!(
                "{}: {error}, {} s",
                describe(row.case, &row.setting, row.threads),
                accuracy::seconds(row.wall_seconds)
            );
            match &bar {
                Some(bar) => {
                    bar.inc(1);
                    bar.println(line);
                }
                None => say(&line),
            }
        }
    };
    let mut written = |rows: &[accuracy::Row]| accuracy::write_outputs(out, &cases, rows, quick);
    let rows = accuracy::sweep(&cases, &options, &mut progress, &mut written)?;
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    accuracy::write_outputs(out, &cases, &rows, quick)?;
    print!("{}", accuracy::report(&cases, &rows, quick));
    say(&format!(
        "outputs in {} (accuracy_cost.csv, accuracy_report.md, accuracy_cost.svg, accuracy_cost.png)",
        out.display()
    ));
    Ok(())
}

/// Progress of a run whose stderr is not a terminal: a line at most every
/// [`ProgressLines::EVERY`] seconds with the step, what the model says of itself (time,
/// strain), the steps per second since the last line and the time left at that rate (a
/// fracturing run slows as its pieces multiply: the rate since the start would promise too
/// little).
struct ProgressLines {
    last: std::time::Instant,
    last_step: u64,
}

impl ProgressLines {
    const EVERY: f64 = 30.0;

    fn new(step: u64) -> Self {
        ProgressLines {
            last: std::time::Instant::now(),
            last_step: step,
        }
    }

    fn due(&mut self, run: &dyn Run) -> Option<String> {
        let seconds = self.last.elapsed().as_secs_f64();
        if seconds < Self::EVERY || run.finished() {
            return None;
        }
        let (step, end) = (run.step(), run.end_step());
        let rate = step.saturating_sub(self.last_step) as f64 / seconds;
        self.last = std::time::Instant::now();
        self.last_step = step;
        Some(format!(
            "{}: step {step} of {end} ({:.1}%), {}, {rate:.0} steps/s, about {} left",
            run.scene().name,
            100.0 * step as f64 / end as f64,
            run.status(),
            duration(end.saturating_sub(step) as f64 / rate),
        ))
    }
}

/// A duration (s) as people read it: `45 s`, `12 min`, `3.2 h`.
fn duration(seconds: f64) -> String {
    if !seconds.is_finite() {
        "an unknown time".to_string()
    } else if seconds < 120.0 {
        format!("{seconds:.0} s")
    } else if seconds < 7200.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// Prints one-line notes to stderr unless quiet.
fn messenger(quiet: bool) -> impl Fn(&str) {
    move |m: &str| {
        if !quiet {
            eprintln!("{m}");
        }
    }
}

fn run(
    mut sim: Box<dyn Run>,
    out: PathBuf,
    frames: Vec<fractum::output::Frame>,
    checkpoint: Option<&std::path::Path>,
    args: &RunArgs,
) -> Result<(), Error> {
    let quiet = args.quiet;
    // The run is set up: only now may the output folder appear, locked and marked in progress
    // before anything else is written into it.
    let start = match checkpoint {
        Some(checkpoint) => Start::Resume {
            checkpoint,
            step: sim.step(),
        },
        None => Start::Fresh,
    };
    let mut dir = OutputDir::claim(&out, sim.as_ref(), start, frames)?;
    let say = messenger(quiet);
    say(&format!(
        "{}: {} bodies, {} steps of {:.3e} s on {} thread(s)",
        sim.scene().name,
        sim.bodies(),
        sim.end_step() - sim.step(),
        sim.dt(),
        sim.threads()
    ));
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(sim.end_step());
        bar.set_style(
            ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {pos}/{len} steps  {per_sec}  {msg}  eta {eta}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_position(sim.step());
        bar
    });
    let options = args.run_options();
    let mut warned = sim.warnings().len();
    // Without a terminal (a log file, a batch job) a line every so often instead of the bar.
    let mut lines = (!quiet && bar.is_none()).then(|| ProgressLines::new(sim.step()));
    let result = run_to_end(sim.as_mut(), &mut dir, options, &mut |s| {
        for w in &s.warnings()[warned..] {
            match &bar {
                Some(bar) => bar.println(format!("warning: {w}")),
                None if !quiet => eprintln!("warning: {w}"),
                None => {}
            }
        }
        warned = s.warnings().len();
        if let Some(bar) = &bar {
            // A shortened step moves the end (granular fracture adapts its step).
            bar.set_length(s.end_step());
            bar.set_position(s.step());
            bar.set_message(s.status());
        }
        if let Some(lines) = &mut lines {
            if let Some(line) = lines.due(s) {
                eprintln!("{line}");
            }
        }
    });
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    result?;
    let pvd: String = dir.indexes.iter().map(|i| format!(", {i}")).collect();
    say(&format!(
        "{}: done; outputs in {} (series.csv, summary.json{pvd}){}",
        sim.scene().name,
        out.display(),
        peak_memory()
            .map(|bytes| format!(
                "; the process's peak memory {:.1} MB, {:.2} kB per body of the {} at the end",
                bytes as f64 / 1e6,
                bytes as f64 / 1e3 / sim.bodies().max(1) as f64,
                sim.bodies()
            ))
            .unwrap_or_default(),
    ));
    Ok(())
}

/// The process's peak resident memory (bytes), where the system says it (Linux's
/// /proc/self/status VmHWM); not in summary.json, which must repeat byte for byte.
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
