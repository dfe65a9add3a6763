//! Checkpoints: a [`PipelineState`] written to a file with what it belongs to (the format's
//! version and the scene's fingerprint), so that a long shot can be split into frame ranges run
//! one after another (`hairlod render SCENE --frames A..B --checkpoint DIR`, then `--resume`).
//! A resumed run is bit-identical to an uninterrupted one, whatever the thread count.
//!
//! The file is JSON: floats are written in their shortest round-tripping form, so every bit of
//! the state comes back.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::error::{PipelineError, Result};
use super::state::PipelineState;

/// The `format` field of every checkpoint file.
pub const CHECKPOINT_FORMAT: &str = "hairlod-checkpoint";

/// The version of the checkpoint layout; a file of another version is refused.
pub const CHECKPOINT_VERSION: u32 = 1;

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
    /// The state.
    pub state: PipelineState,
}

impl Checkpoint {
    /// A checkpoint of `state` for the run whose fingerprint is `scene_fingerprint`.
    pub fn new(scene_fingerprint: String, state: PipelineState) -> Self {
        Checkpoint {
            format: CHECKPOINT_FORMAT.to_string(),
            version: CHECKPOINT_VERSION,
            hairlod_version: env!("CARGO_PKG_VERSION").to_string(),
            scene_fingerprint,
            state,
        }
    }

    /// Writes the checkpoint to `path` atomically (a temporary file renamed into place: no
    /// half-written checkpoint is ever left under the name).
    pub fn write(&self, path: &Path) -> Result<()> {
        let fail = |why: String| PipelineError::Checkpoint {
            path: path.to_path_buf(),
            why,
        };
        let text = serde_json::to_string(self).map_err(|e| fail(e.to_string()))?;
        let temporary = path.with_extension("partial");
        std::fs::write(&temporary, text).map_err(|e| fail(format!("cannot write: {e}")))?;
        std::fs::rename(&temporary, path).map_err(|e| fail(format!("cannot write: {e}")))
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
            return Err(fail(format!(
                "not a checkpoint (its format is {:?}, expected {CHECKPOINT_FORMAT:?})",
                header.format
            )));
        }
        if header.version != Some(CHECKPOINT_VERSION) {
            return Err(fail(format!(
                "checkpoint layout version {:?}, this hairlod reads version {CHECKPOINT_VERSION}",
                header.version
            )));
        }
        let ours = env!("CARGO_PKG_VERSION");
        if header.hairlod_version.as_deref() != Some(ours) {
            return Err(fail(format!(
                "written by hairlod {:?}, this is hairlod {ours}: a run resumes only on the \
                 version that started it",
                header.hairlod_version
            )));
        }
        serde_json::from_str(&text).map_err(|e| fail(format!("damaged checkpoint: {e}")))
    }
}

/// The fields checked before the state is parsed.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u32>,
    hairlod_version: Option<String>,
}

/// FNV-1a, 64 bits: a fingerprint that is the same on every machine and Rust version (the
/// standard library's hasher promises neither).
pub(crate) struct Fnv1a(u64);

impl Fnv1a {
    /// The empty hash.
    pub(crate) fn new() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    /// Adds `bytes`.
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Adds the bits of `values`.
    pub(crate) fn write_f32s(&mut self, values: impl IntoIterator<Item = f32>) {
        for value in values {
            self.write(&value.to_bits().to_le_bytes());
        }
    }

    /// The hash as 16 hexadecimal digits.
    pub(crate) fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        // FNV-1a 64 of "" and "a" (Fowler, Noll, Vo reference values).
        assert_eq!(Fnv1a::new().hex(), "cbf29ce484222325");
        let mut hash = Fnv1a::new();
        hash.write(b"a");
        assert_eq!(hash.hex(), "af63dc4c8601ec8c");
    }

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
                "{\"format\": \"hairlod-checkpoint\", \"version\": 1, \"hairlod_version\": \"0.0.0\"}",
                "hairlod 0.1",
            ),
            ("not json", "not a checkpoint"),
        ] {
            std::fs::write(&path, text).unwrap();
            let error = Checkpoint::read(&path).unwrap_err().to_string();
            assert!(error.contains(expected), "{text}: {error}");
            assert!(error.contains("bad.json"), "{error}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
