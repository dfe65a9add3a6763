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

/// Writes `scene` (a scene file's text) into `dir`, runs `hairlod bench` on it and `hairlod
/// render` on it alone (the scene's `[output] json` names the render's report), and returns the
/// bench's JSON report and the render's.
pub fn bench_and_render(dir: &Path, scene: &str) -> (serde_json::Value, serde_json::Value) {
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let bench_json = dir.join("bench.json");
    hairlod(&[
        "bench",
        path.to_str().unwrap(),
        "--json",
        bench_json.to_str().unwrap(),
    ]);
    let out = dir.join("render");
    hairlod(&[
        "render",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    (read_json(&bench_json), read_json(&out.join("report.json")))
}

/// The frame numbers of a run's report, in order.
pub fn frame_numbers(run: &serde_json::Value) -> Vec<u64> {
    run["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|frame| frame["frame"].as_u64().unwrap())
        .collect()
}

/// Asserts that an interleaved LODs run chose, frame by frame, the levels `render` (the same
/// scene rendered alone) chose, and that the levels change within the shot (so that the
/// comparison can fail).
pub fn assert_levels_as_alone(lods: &serde_json::Value, render: &serde_json::Value) {
    let chosen = levels(lods);
    assert_eq!(
        chosen,
        levels(render),
        "the LODs chose other levels in the bench"
    );
    assert!(
        chosen.iter().any(|l| l != &chosen[0]),
        "the levels never change: {chosen:?}"
    );
}
