//! Checkpoints: a [`PipelineState`] (a crowd's: one per character) written to a file with what
//! it belongs to (the format's version and the scene's fingerprint), so that a long shot can be
//! split into frame ranges run one after another (`hairlod render SCENE --frames A..B
//! --checkpoint DIR`, then `--resume`). A resumed run is bit-identical to an uninterrupted one,
//! whatever the thread count.
//!
//! The file is JSON: floats are written in their shortest round-tripping form, so every bit of
//! the state comes back. It carries a checksum of its state (FNV-1a, 64 bits, over the state as
//! written), and a read checks the state's values against their invariants when the pipeline
//! resumes from it ([`PipelineState::check`]): an edited or damaged checkpoint is refused, naming
//! the field, instead of resuming silently wrong.

use std::io::Write;
use std::path::Path;

use hair_core::atomic_file::write_file_atomically;
use serde::{Deserialize, Serialize};

use super::error::{PipelineError, Result};
use super::fingerprint::Fnv1a;
use super::state::PipelineState;

/// The `format` field of every checkpoint file.
pub const CHECKPOINT_FORMAT: &str = "hairlod-checkpoint";

/// The version of the checkpoint layout; a file of another version is refused, naming it.
/// Version 2 (2026-12-01) added the state's checksum; version 1 files are refused.
pub const CHECKPOINT_VERSION: u32 = 2;

/// A pipeline state with what it belongs to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Always [`CHECKPOINT_FORMAT`].
    pub format: String,
    /// [`CHECKPOINT_VERSION`] of the writer.
    pub version: u32,
    /// The hairlod version that wrote it (the dynamics may change between versions, so a
    /// checkpoint resumes only on the version that wrote it).
    pub hairlod_version: String,
    /// The fingerprint of the scene, environment and settings it was run with
    /// ([`Pipeline::fingerprint`](super::Pipeline::fingerprint)).
    pub scene_fingerprint: String,
    /// FNV-1a (64 bits, 16 hex digits) of the state as serialized to JSON: a read refuses a
    /// file whose state does not hash to it (edited or damaged).
    pub state_checksum: String,
    /// The state (a crowd's first character's).
    pub state: PipelineState,
    /// A crowd's other characters' states, in the shot's order (empty, and left out of the
    /// file, for a lone character: such files are laid out as before crowds checkpointed).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub others: Vec<PipelineState>,
}

/// The checksum of `state` and `others` ([`Checkpoint::state_checksum`]): FNV-1a over their
/// compact JSON, one after the other, which is the same for every state that reads back with the
/// same bits (floats are written in their shortest round-tripping form, fields in declaration
/// order); a lone character's is its state's alone.
fn state_checksum(
    state: &PipelineState,
    others: &[PipelineState],
) -> std::result::Result<String, serde_json::Error> {
    let mut hash = Fnv1a::new();
    for state in std::iter::once(state).chain(others) {
        hash.write(serde_json::to_string(state)?.as_bytes());
    }
    Ok(hash.hex())
}

impl Checkpoint {
    /// A checkpoint of `state` for the run whose fingerprint is `scene_fingerprint`.
    pub fn new(scene_fingerprint: String, state: PipelineState) -> Self {
        Checkpoint::of_characters(scene_fingerprint, state, Vec::new())
    }

    /// A checkpoint of a crowd's characters' states (`first`, then `others` in the shot's order)
    /// for the run whose fingerprint is `scene_fingerprint`.
    pub fn of_characters(
        scene_fingerprint: String,
        first: PipelineState,
        others: Vec<PipelineState>,
    ) -> Self {
        let state_checksum = state_checksum(&first, &others).unwrap_or_default();
        Checkpoint {
            format: CHECKPOINT_FORMAT.to_string(),
            version: CHECKPOINT_VERSION,
            hairlod_version: env!("CARGO_PKG_VERSION").to_string(),
            scene_fingerprint,
            state_checksum,
            state: first,
            others,
        }
    }

    /// Every character's state, in order (one for a lone character).
    pub fn states(&self) -> impl Iterator<Item = &PipelineState> {
        std::iter::once(&self.state).chain(&self.others)
    }

    /// Writes the checkpoint to `path` atomically, through the project's one atomic writer
    /// ([`write_file_atomically`]: a temporary file named with the process id, synced, renamed
    /// into place, removed on any error), so no half-written checkpoint is ever left under the
    /// name or beside it.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string(self).map_err(|e| PipelineError::Checkpoint {
            path: path.to_path_buf(),
            why: e.to_string(),
        })?;
        write_file_atomically(path, |file| file.write_all(text.as_bytes())).map_err(|e| {
            PipelineError::Checkpoint {
                path: path.to_path_buf(),
                why: format!("cannot write: {}", io_reason(&e, path)),
            }
        })
    }

    /// Reads a checkpoint from `path`; refuses a file that is not a checkpoint, or one of another
    /// layout version or hairlod version.
    pub fn read(path: &Path) -> Result<Checkpoint> {
        let fail = |why: String| PipelineError::Checkpoint {
            path: path.to_path_buf(),
            why,
        };
        let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
        let header: Header =
            serde_json::from_str(&text).map_err(|e| fail(format!("not a checkpoint: {e}")))?;
        if header.format.as_deref() != Some(CHECKPOINT_FORMAT) {
            return Err(fail(match &header.format {
                Some(format) => format!(
                    "not a checkpoint (its format is \"{format}\", expected \"{CHECKPOINT_FORMAT}\")"
                ),
                None => {
                    format!("not a checkpoint (it has no format, expected \"{CHECKPOINT_FORMAT}\")")
                }
            }));
        }
        match header.version {
            Some(CHECKPOINT_VERSION) => {}
            Some(1) => {
                return Err(fail(format!(
                    "checkpoint layout version 1 (written before checkpoints carried a checksum), \
                     this hairlod reads version {CHECKPOINT_VERSION}: run the frames again from \
                     the start, or from a checkpoint this version wrote"
                )));
            }
            Some(version) => {
                return Err(fail(format!(
                    "checkpoint layout version {version}, this hairlod reads version \
                     {CHECKPOINT_VERSION}"
                )));
            }
            None => {
                return Err(fail(format!(
                    "no layout version: this hairlod reads version {CHECKPOINT_VERSION}"
                )));
            }
        }
        let ours = env!("CARGO_PKG_VERSION");
        if header.hairlod_version.as_deref() != Some(ours) {
            return Err(fail(format!(
                "written by hairlod {}, this is hairlod {ours}: a run resumes only on the \
                 version that started it",
                header
                    .hairlod_version
                    .as_deref()
                    .unwrap_or("of no stated version")
            )));
        }
        let checkpoint: Checkpoint =
            serde_json::from_str(&text).map_err(|e| fail(format!("damaged checkpoint: {e}")))?;
        let checksum = state_checksum(&checkpoint.state, &checkpoint.others)
            .map_err(|e| fail(format!("damaged checkpoint: {e}")))?;
        if checksum != checkpoint.state_checksum {
            return Err(fail(format!(
                "state_checksum: the state hashes to {checksum}, the file says {:?}: the \
                 checkpoint was edited or damaged",
                checkpoint.state_checksum
            )));
        }
        Ok(checkpoint)
    }
}

/// The reason of a failed write `error` on `path`, without the path the atomic writer puts
/// before it (the checkpoint error names it already).
fn io_reason(error: &std::io::Error, path: &Path) -> String {
    let text = error.to_string();
    let prefix = format!("writing {}: ", path.display());
    text.strip_prefix(&prefix).unwrap_or(&text).to_string()
}

/// The fields checked before the state is parsed.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u32>,
    hairlod_version: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_that_are_not_checkpoints_are_refused_by_name() {
        let dir = std::env::temp_dir().join(format!("hairlod-ckpt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.json");
        for (text, expected) in [
            ("{\"format\": \"something\"}", "not a checkpoint"),
            (
                "{\"format\": \"hairlod-checkpoint\", \"version\": 99}",
                "version",
            ),
            (
                "{\"format\": \"hairlod-checkpoint\", \"version\": 2, \"hairlod_version\": \"0.0.0\"}",
                "hairlod 0.1",
            ),
            ("not json", "not a checkpoint"),
            (
                "{\"format\": \"hairlod-checkpoint\", \"version\": 1}",
                "layout version 1 (written before checkpoints carried a checksum)",
            ),
        ] {
            std::fs::write(&path, text).unwrap();
            let error = Checkpoint::read(&path).unwrap_err().to_string();
            assert!(error.contains(expected), "{text}: {error}");
            assert!(error.contains("bad.json"), "{error}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
