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
}

fn snapshot_name(stem: &str, step: u64) -> String {
    format!("vtk/{stem}_{step:09}.vtu")
}

impl OutputDir {
    /// Creates the folder (and its parents). Call this only once the run is set up, so bad
    /// input never leaves a folder behind.
    pub fn create(path: &Path) -> Result<Self> {
        std::fs::create_dir_all(path)
            .map_err(|e| Error::io(path, "create the output folder", e))?;
        Ok(OutputDir {
            path: path.to_path_buf(),
            frames: Vec::new(),
            indexes: Vec::new(),
        })
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
