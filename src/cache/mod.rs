//! Simulation caches: a shot simulated once, one record per frame, and rendered from the records
//! by any machine, in any order (DESIGN, "Shots across machines").
//!
//! - [`SimulationCache`]: a folder of [`FrameRecord`]s (`frame_00012.hlc`, …) and the
//!   checkpoints that chain simulation chunks (`checkpoint_00015.json`), bound to one run by
//!   its fingerprint ([`run_fingerprint`]: every character's model, the settings, the camera
//!   path, frames, frame rate and image size). A record of another run, layout or hairlod
//!   version, a damaged or truncated one, or a missing one is refused, naming the file and
//!   frame. Records are written atomically: a killed writer never leaves half a record.
//! - [`simulate`]: the frame loop without a renderer, writing each frame's record.
//! - [`CachedRun`]: the frame loop's [`Runnable`](crate::run::Runnable) that reads the records
//!   instead of simulating; drawn by the same renderers, its frames are bit-identical to the
//!   frames rendered in the simulating process.
//! - [`Chunk`]: a shot's frames split into even chunks (the farm's tasks).
//!
//! ```no_run
//! use hairlod::cache::{SimulationCache, run_fingerprint, simulate};
//! use hairlod::pipeline::CharacterModel;
//! use hairlod::run::{FrameLoop, RunOptions};
//! use hairlod::SceneFile;
//!
//! let shot = SceneFile::default().resolve()?;
//! let scene = shot.build_scene()?;
//! let model = CharacterModel::new(scene.clone().into(), shot.environment.clone());
//! let cache = SimulationCache::create("cache", run_fingerprint(&shot, &[model]))?;
//! let pipeline = shot.pipeline(&scene, shot.settings, None)?;
//! let frame_loop = FrameLoop::new(&shot, pipeline, 0..shot.frames, None)?;
//! simulate(frame_loop, &cache, |_| Ok(()))?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bodies;
mod chunk;
mod player;
mod record;

use std::path::{Path, PathBuf};

use hair_core::atomic_file::write_file_atomically;
use hair_render::ActiveSkeletons;

pub use chunk::Chunk;
pub use player::CachedRun;
pub use record::{FrameRecord, RECORD_MAGIC, RECORD_VERSION};

use crate::pipeline::{CharacterModel, DrawnSource, Fnv1a, PipelineError, Result};
use crate::run::{FrameLoop, Runnable};
use crate::shot::Shot;
use record::RecordFault;

/// The fingerprint a cache's records carry (16 hex digits): FNV-1a over the record layout and
/// hairlod versions, every character's model fingerprint with the shot's settings
/// ([`CharacterModel::fingerprint`]: groom rest data, head mesh, environment, settings,
/// material) and the shot's camera path, frame count, frame rate, image size (the levels
/// follow the camera and the pixels), settling time and frame budget. The drawing style
/// (shading, line coverage, views) is not in it: one cache renders in any style.
pub fn run_fingerprint(shot: &Shot, characters: &[CharacterModel]) -> String {
    let mut hash = Fnv1a::new();
    hash.write(
        format!(
            "hairlod-cache {RECORD_VERSION} {}",
            env!("CARGO_PKG_VERSION")
        )
        .as_bytes(),
    );
    for character in characters {
        hash.write(character.fingerprint(&shot.settings).as_bytes());
    }
    hash.write(
        format!(
            "{:?}|{}|{}|{}x{}|{}|{:?}",
            shot.camera,
            shot.frames,
            shot.fps,
            shot.width,
            shot.height,
            shot.settle_seconds,
            shot.budget
        )
        .as_bytes(),
    );
    hash.hex()
}

/// A folder of frame records for one run (see the module docs).
#[derive(Debug, Clone)]
pub struct SimulationCache {
    dir: PathBuf,
    fingerprint: String,
}

impl SimulationCache {
    /// The cache in `dir` for the run whose fingerprint is `fingerprint`, creating the folder
    /// when missing (an error names it when it cannot be).
    pub fn create(dir: impl AsRef<Path>, fingerprint: String) -> Result<Self> {
        let dir = dir.as_ref().to_path_buf();
        std::fs::create_dir_all(&dir).map_err(|e| PipelineError::Cache {
            path: dir.clone(),
            frame: None,
            why: format!("cannot create the cache folder: {e}"),
        })?;
        Ok(SimulationCache { dir, fingerprint })
    }

    /// The cache in `dir` (which must exist) for the run whose fingerprint is `fingerprint`.
    pub fn open(dir: impl AsRef<Path>, fingerprint: String) -> Result<Self> {
        let dir = dir.as_ref().to_path_buf();
        if !dir.is_dir() {
            return Err(PipelineError::Cache {
                path: dir,
                frame: None,
                why: "no such cache folder (simulate the shot into it first: hairlod simulate \
                      SCENE --cache DIR)"
                    .into(),
            });
        }
        Ok(SimulationCache { dir, fingerprint })
    }

    /// The cache's folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The run fingerprint its records carry.
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }

    /// Where frame `frame`'s record lives.
    pub fn record_path(&self, frame: usize) -> PathBuf {
        self.dir.join(format!("frame_{frame:05}.hlc"))
    }

    /// Where the checkpoint of the state after `frame` frames lives (the one a simulation chunk
    /// starting at `frame` resumes from).
    pub fn checkpoint_path(&self, frame: usize) -> PathBuf {
        self.dir.join(format!("checkpoint_{frame:05}.json"))
    }

    /// Writes `record` atomically under its frame's name (a killed writer leaves the previous
    /// record or none, never half of one); returns its size [bytes].
    pub fn write(&self, record: &FrameRecord) -> Result<u64> {
        let path = self.record_path(record.frame);
        let bytes = record.encode(&self.fingerprint);
        write_file_atomically(&path, |file| std::io::Write::write_all(file, &bytes)).map_err(
            |e| PipelineError::Cache {
                path: path.clone(),
                frame: Some(record.frame),
                why: format!("cannot write the record: {e}"),
            },
        )?;
        Ok(bytes.len() as u64)
    }

    /// Reads frame `frame`'s record; refuses a missing record, one of another run (naming both
    /// fingerprints), of another frame, layout or version, and a damaged or truncated one.
    pub fn read(&self, frame: usize) -> Result<FrameRecord> {
        let path = self.record_path(frame);
        let fail = |why: String| PipelineError::Cache {
            path: path.clone(),
            frame: Some(frame),
            why,
        };
        let bytes = std::fs::read(&path).map_err(|e| {
            fail(if e.kind() == std::io::ErrorKind::NotFound {
                "the record is missing: the cache does not hold this frame (simulate the chunk \
                 that holds it)"
                    .into()
            } else {
                format!("cannot read the record: {e}")
            })
        })?;
        FrameRecord::decode(&bytes, &self.fingerprint, frame).map_err(|fault| {
            fail(match fault {
                RecordFault::Broken(why) => why,
                RecordFault::Foreign(theirs) => format!(
                    "the record is of another run (fingerprint {theirs}, this scene's {}): \
                     another scene, settings or hairlod version simulated it; simulate again",
                    self.fingerprint
                ),
                RecordFault::OtherFrame(other) => {
                    format!("the file holds frame {other}'s record, not this frame's")
                }
            })
        })
    }
}

/// What [`simulate`] shows the caller after each frame.
pub struct SimulatedFrame<'a> {
    /// The frame's record, as written.
    pub record: &'a FrameRecord,
    /// The record's size [bytes].
    pub bytes: u64,
}

/// Drives `frame_loop` (no renderer) to its end, writing each frame's record into `cache`:
/// the skeletons the frame draws ([`DrawnSource::gather_drawn`]), the head poses and the
/// report. `on_frame` sees each record; an error from it stops the run. Returns the run's
/// target (to checkpoint) with every frame's report.
pub fn simulate<R: Runnable + DrawnSource>(
    mut frame_loop: FrameLoop<'_, R>,
    cache: &SimulationCache,
    mut on_frame: impl FnMut(SimulatedFrame<'_>) -> Result<()>,
) -> Result<crate::run::RunResult<R>> {
    let mut drawn = ActiveSkeletons::new();
    while let Some(output) = frame_loop.step(None)? {
        let report = *output.report;
        let target = frame_loop.target_mut();
        target.gather_drawn(&mut drawn)?;
        let record = FrameRecord {
            frame: report.frame,
            report,
            head_poses: target.head_poses(),
            drawn,
        };
        let bytes = cache.write(&record)?;
        on_frame(SimulatedFrame {
            record: &record,
            bytes,
        })?;
        drawn = record.drawn;
    }
    Ok(frame_loop.finish())
}

#[cfg(test)]
mod tests;
