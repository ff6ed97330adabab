//! Files a run writes into its output folder. Every file is written to a temporary name in
//! the same folder and renamed into place, so a reader never sees half a file.

pub mod checkpoint;
pub mod vtk;

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::simulation::Simulation;

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

/// The output folder of a run.
pub struct OutputDir {
    pub path: PathBuf,
    /// VTK frames written so far: (time, file relative to `path`).
    pub frames: Vec<(f64, String)>,
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
        })
    }

    pub fn file(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// series.csv with every row so far.
    pub fn write_series(&self, sim: &Simulation) -> Result<()> {
        write_atomic(&self.file("series.csv"), sim.series.to_csv().as_bytes())
    }

    /// summary.json.
    pub fn write_summary(&self, sim: &Simulation) -> Result<()> {
        let mut text = serde_json::to_string_pretty(&sim.summary()).expect("summary serialises");
        text.push('\n');
        write_atomic(&self.file("summary.json"), text.as_bytes())
    }

    /// A VTK snapshot of the particles (and of the box walls), and the .pvd index that lists
    /// every snapshot so far for ParaView.
    pub fn write_snapshot(&mut self, sim: &Simulation) -> Result<()> {
        let dir = self.file("vtk");
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, "create the folder", e))?;
        let name = format!("vtk/particles_{:09}.vtu", sim.step);
        write_atomic(
            &self.file(&name),
            vtk::particles_vtu(&sim.bodies, &sim.forces).as_bytes(),
        )?;
        if sim.walls.is_box {
            let wname = format!("vtk/walls_{:09}.vtu", sim.step);
            write_atomic(
                &self.file(&wname),
                vtk::box_walls_vtu(&sim.walls).as_bytes(),
            )?;
        }
        self.frames.retain(|(t, _)| *t < sim.time);
        self.frames.push((sim.time, name));
        write_atomic(
            &self.file("particles.pvd"),
            vtk::pvd(&self.frames, "").as_bytes(),
        )?;
        if sim.walls.is_box {
            write_atomic(
                &self.file("walls.pvd"),
                vtk::pvd(&self.frames, "walls").as_bytes(),
            )?;
        }
        Ok(())
    }

    /// A checkpoint of the whole run at its current step; returns its path.
    pub fn write_checkpoint(&self, sim: &Simulation) -> Result<PathBuf> {
        let dir = self.file("checkpoints");
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, "create the folder", e))?;
        let path = dir.join(format!("step_{:09}.fcp", sim.step));
        let bytes = checkpoint::encode(sim, &self.frames);
        write_atomic(&path, &bytes)?;
        Ok(path)
    }
}
