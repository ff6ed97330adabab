//! Files a run writes into its output folder. Every file is written to a temporary name in
//! the same folder and renamed into place, so a reader never sees half a file.

pub mod checkpoint;
// Figures: SVG and PNG with the compiled-in font.
pub mod figure;
pub mod sealed;
pub mod vtk;
// beam2d: polygons and beams for ParaView.
pub mod vtk_polygons;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::run::Run;

/// Writes `bytes` to `path` atomically: a temporary file beside it, flushed, then renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, "write", e)
    })
}

/// A VTK snapshot already written: its time (s) and step.
pub type Frame = (f64, u64);

/// The output folder of a run.
pub struct OutputDir {
    pub path: PathBuf,
    /// VTK snapshots written so far.
    pub frames: Vec<Frame>,
    /// The .pvd indexes written (one per snapshot stem).
    pub indexes: Vec<String>,
    /// The folder's lock, held while the run writes (None for a folder made by [`Self::create`]).
    lock: Option<Lock>,
}

fn snapshot_name(stem: &str, step: u64) -> String {
    format!("vtk/{stem}_{step:09}.vtu")
}

/// The lock file a run holds in its output folder: the process id of the run writing there.
pub const LOCK_NAME: &str = ".fractum.lock";

/// The result files a run writes at the folder's top (besides the `.pvd` indexes, `vtk/` and
/// `checkpoints/`): summary.json, series.csv and the models' further outputs
/// ([`crate::run::Report::extra_outputs`]). A run taking a folder removes an earlier run's.
const RESULT_FILES: &[&str] = &[
    "summary.json",
    "series.csv",
    "psd.csv",
    "fragments.csv",
    "fragment_histogram.csv",
];

/// How a run takes its output folder.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// A run from its first step: an earlier run's files in the folder go.
    Fresh,
    /// A run resumed from `checkpoint` at `step`. When the checkpoint lies in the folder's own
    /// checkpoints/, the run's history up to `step` stays (the checkpoints up to it and the
    /// snapshots it lists); everything else an earlier run wrote goes.
    Resume { checkpoint: &'a Path, step: u64 },
}

/// A held lock file; dropping it removes the file if it still names this process.
struct Lock {
    path: PathBuf,
}

impl Drop for Lock {
    fn drop(&mut self) {
        if lock_holder(&self.path) == Some(std::process::id()) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

fn lock_holder(path: &Path) -> Option<u32> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// Whether process `pid` is alive (a zombie is not). Where this cannot be told, it is taken
/// as alive: a wrong refusal names the lock file to remove, a wrong takeover mixes two runs.
fn alive(pid: u32) -> bool {
    if Path::new("/proc/self/stat").exists() {
        return match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
            // The state is the first field after the command's closing parenthesis.
            Ok(stat) => stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().next())
                .is_none_or(|state| state != "Z" && state != "X"),
            Err(_) => false,
        };
    }
    std::process::Command::new("kill")
        .args(["-0", &pid.to_string()])
        .stderr(std::process::Stdio::null())
        .status()
        .map_or(true, |s| s.success())
}

/// Takes the lock of `dir`: refused while another live process holds it, taken over from a
/// process that is gone (a run killed without a word). The lock file appears with its
/// content at once (a temporary file hard-linked into place), so a reader never finds it empty.
fn take_lock(dir: &Path) -> Result<Lock> {
    let path = dir.join(LOCK_NAME);
    let me = std::process::id();
    let tmp = dir.join(format!("{LOCK_NAME}.{me}.tmp"));
    std::fs::write(&tmp, format!("{me}\n")).map_err(|e| Error::io(&tmp, "write", e))?;
    let result = (|| {
        for _ in 0..3 {
            let linked = std::fs::hard_link(&tmp, &path).or_else(|e| {
                // A file system without hard links: create the lock file in place.
                if e.kind() == std::io::ErrorKind::AlreadyExists {
                    return Err(e);
                }
                let mut f = std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&path)?;
                f.write_all(format!("{me}\n").as_bytes())
            });
            match linked {
                Ok(()) => return Ok(Lock { path: path.clone() }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    match lock_holder(&path) {
                        Some(pid) if pid != me && alive(pid) => {
                            return Err(Error::input(
                                dir.display().to_string(),
                                format!(
                                    "is being written by another Fractum run (process {pid}, \
                                     named in {LOCK_NAME}); wait for it to end or choose \
                                     another --out"
                                ),
                            ));
                        }
                        // A lock left by a run that is gone: take it over.
                        _ => {
                            let _ = std::fs::remove_file(&path);
                        }
                    }
                }
                Err(e) => return Err(Error::io(&path, "create the lock file", e)),
            }
        }
        Err(Error::run(format!(
            "{}: cannot take the lock file: other runs keep taking it",
            path.display()
        )))
    })();
    let _ = std::fs::remove_file(&tmp);
    result
}

/// The step of a file named `{prefix}_{step:09}.{ext}` (a snapshot or a checkpoint).
fn step_of(name: &str, ext: &str) -> Option<u64> {
    let stem = name.strip_suffix(ext)?.strip_suffix('.')?;
    let (_, digits) = stem.rsplit_once('_')?;
    (digits.len() >= 9 && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse().ok())
        .flatten()
}

/// Removes the files of `dir` (not recursing) that `remove` picks by name.
fn remove_files(dir: &Path, remove: impl Fn(&str) -> bool) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if entry.file_type().is_ok_and(|t| t.is_file()) && remove(&name) {
            std::fs::remove_file(entry.path())
                .map_err(|e| Error::io(&entry.path(), "remove an earlier run's file", e))?;
        }
    }
    Ok(())
}

impl OutputDir {
    /// Creates the folder (and its parents). Call this only once the run is set up, so bad
    /// input never leaves a folder behind. [`Self::claim`] is what a run writing into a
    /// folder that may hold another run's files calls.
    pub fn create(path: &Path) -> Result<Self> {
        std::fs::create_dir_all(path)
            .map_err(|e| Error::io(path, "create the output folder", e))?;
        Ok(OutputDir {
            path: path.to_path_buf(),
            frames: Vec::new(),
            indexes: Vec::new(),
            lock: None,
        })
    }

    /// Creates the folder and takes it for `run` before anything is written: its lock (a
    /// second live run into the folder is refused; a killed run's lock is taken over), an
    /// earlier run's results, snapshots and checkpoints removed (but for the resumed run's own
    /// history, see [`Start`]), and a summary.json with `"complete": false` that says the run
    /// is in progress, so a run killed without a word never leaves a finished run's summary
    /// over its own partial files. `frames` are the snapshots a resumed run's checkpoint lists.
    pub fn claim(path: &Path, run: &dyn Run, start: Start, frames: Vec<Frame>) -> Result<Self> {
        let mut dir = Self::create(path)?;
        dir.lock = Some(take_lock(path)?);
        let keep_upto = match start {
            Start::Resume { checkpoint, step } => {
                let own = checkpoint
                    .parent()
                    .and_then(|p| p.canonicalize().ok())
                    .is_some_and(|p| Some(p) == dir.file("checkpoints").canonicalize().ok());
                own.then_some(step)
            }
            Start::Fresh => None,
        };
        let kept: Vec<u64> = match keep_upto {
            Some(step) => frames.iter().map(|f| f.1).filter(|s| *s <= step).collect(),
            None => Vec::new(),
        };
        remove_files(path, |name| {
            RESULT_FILES.contains(&name)
                || name.ends_with(".pvd")
                || (name.starts_with('.') && name.ends_with(".tmp") && !name.starts_with(LOCK_NAME))
        })?;
        let temporary = |name: &str| name.starts_with('.') && name.ends_with(".tmp");
        remove_files(&dir.file("vtk"), |name| {
            temporary(name) || step_of(name, "vtu").is_some_and(|s| !kept.contains(&s))
        })?;
        remove_files(&dir.file("checkpoints"), |name| {
            temporary(name)
                || (name.starts_with("step_")
                    && step_of(name, "fcp").is_some_and(|s| keep_upto.is_none_or(|k| s > k)))
        })?;
        dir.adopt_frames(frames);
        dir.write_in_progress(run)?;
        Ok(dir)
    }

    /// summary.json while the run is in progress: `"complete": false`, what the run is and
    /// where it started; replaced when the run ends (finished or failed).
    fn write_in_progress(&self, run: &dyn Run) -> Result<()> {
        let scene = run.scene();
        let summary = serde_json::json!({
            "name": scene.name,
            "model": run.model(),
            "seed": scene.seed,
            "complete": false,
            "in_progress": format!(
                "started by process {}; the run replaces this summary when it ends, so one \
                 killed without a word leaves it",
                std::process::id()
            ),
            "steps": run.step(),
            "time": run.time(),
        });
        let mut text = serde_json::to_string_pretty(&summary).expect("summary serialises");
        text.push('\n');
        write_atomic(&self.file("summary.json"), text.as_bytes())
    }

    pub fn file(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// Keeps those of `frames` whose files are in this folder (a resumed run writing
    /// elsewhere lists only its own).
    pub fn adopt_frames(&mut self, frames: Vec<Frame>) {
        let dir = self.file("vtk");
        self.frames = frames
            .into_iter()
            .filter(|(_, step)| {
                std::fs::read_dir(&dir).is_ok_and(|entries| {
                    let tail = format!("_{step:09}.vtu");
                    entries
                        .flatten()
                        .any(|e| e.file_name().to_string_lossy().ends_with(&tail))
                })
            })
            .collect();
    }

    /// series.csv with every row so far.
    pub fn write_series(&self, run: &dyn Run) -> Result<()> {
        write_atomic(&self.file("series.csv"), run.series().to_csv().as_bytes())
    }

    /// summary.json and the model's further result files. `wall_seconds` (the time this
    /// process spent advancing the run) is the summary's last key and the only one that
    /// differs between repeated runs.
    pub fn write_results(&self, run: &dyn Run, wall_seconds: f64) -> Result<()> {
        for (name, bytes) in run.extra_outputs() {
            write_atomic(&self.file(&name), &bytes)?;
        }
        let mut summary = run.summary();
        if let Some(m) = summary.as_object_mut() {
            m.insert("wall_seconds".into(), wall_seconds.into());
        }
        let mut text = serde_json::to_string_pretty(&summary).expect("summary serialises");
        text.push('\n');
        write_atomic(&self.file("summary.json"), text.as_bytes())
    }

    /// summary.json of a run that failed while stepping: what the run is, where it stopped,
    /// `"complete": false` and the failure's sentence, and `wall_seconds` last. The model's own
    /// summary is not asked for: its state may hold the non-finite values that stopped it.
    pub fn write_failure(&self, run: &dyn Run, error: &Error, wall_seconds: f64) -> Result<()> {
        let scene = run.scene();
        let summary = serde_json::json!({
            "name": scene.name,
            "model": run.model(),
            "seed": scene.seed,
            "complete": false,
            "failure": error.to_string(),
            "steps": run.step(),
            "time": run.time(),
            "wall_seconds": wall_seconds,
        });
        let mut text = serde_json::to_string_pretty(&summary).expect("summary serialises");
        text.push('\n');
        write_atomic(&self.file("summary.json"), text.as_bytes())
    }

    /// A VTK snapshot of the run (one .vtu per stem: particles, walls, ...) and, per stem, the
    /// .pvd index of every snapshot so far, for ParaView.
    pub fn write_snapshot(&mut self, run: &dyn Run) -> Result<()> {
        let dir = self.file("vtk");
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, "create the folder", e))?;
        let files = run.snapshot();
        for (stem, text) in &files {
            write_atomic(
                &self.file(&snapshot_name(stem, run.step())),
                text.as_bytes(),
            )?;
        }
        self.frames.retain(|(t, _)| *t < run.time());
        self.frames.push((run.time(), run.step()));
        for (stem, _) in &files {
            let listed: Vec<(f64, String)> = self
                .frames
                .iter()
                .map(|(t, step)| (*t, snapshot_name(stem, *step)))
                .collect();
            let index = format!("{stem}.pvd");
            write_atomic(&self.file(&index), vtk::pvd(&listed).as_bytes())?;
            if !self.indexes.contains(&index) {
                self.indexes.push(index);
            }
        }
        Ok(())
    }

    /// A checkpoint of the whole run at its current step; returns its path.
    pub fn write_checkpoint(&self, run: &dyn Run) -> Result<PathBuf> {
        let dir = self.file("checkpoints");
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, "create the folder", e))?;
        let path = dir.join(format!("step_{:09}.fcp", run.step()));
        let bytes = checkpoint::encode(run, &self.frames);
        write_atomic(&path, &bytes)?;
        Ok(path)
    }
}
