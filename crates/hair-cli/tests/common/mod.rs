//! Helpers shared by the tests that run the `hairlod` binary: a fresh folder, a run that must
//! succeed, and the JSON reports it writes.

#![allow(dead_code)] // each test file uses some of them

use std::path::{Path, PathBuf};
use std::process::Command;

/// The binary under test.
pub const BINARY: &str = env!("CARGO_BIN_EXE_hairlod");

/// A fresh (emptied) folder `name` under the target's temporary directory.
pub fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the binary with `args`; panics with its output when it fails, else returns its stdout
/// and stderr.
pub fn hairlod(args: &[&str]) -> String {
    let output = Command::new(BINARY).args(args).output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "hairlod {args:?} failed:\n{text}");
    text
}

/// A JSON file the binary wrote.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Each frame's `sections_at` (`[patches, clusters, strands]`) of a run's report, as text.
pub fn levels(run: &serde_json::Value) -> Vec<String> {
    run["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|frame| frame["sections_at"].to_string())
        .collect()
}
