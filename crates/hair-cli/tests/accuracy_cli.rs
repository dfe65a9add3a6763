//! `hairlod accuracy` end to end, through the binary: the configurations run interleaved frame
//! by frame on one renderer (the reference first), and each is measured on its own frames: adding
//! a configuration to the sweep changes no other configuration's errors.

mod common;

use std::path::Path;

use common::{folder, hairlod, read_json};

/// Runs `hairlod accuracy` on the curly preset (3 frames at 96×54, no integrator sweep) with
/// LODs at `tolerances`; returns the JSON report's points.
fn accuracy(dir: &Path, tolerances: &str) -> Vec<serde_json::Value> {
    let json = dir.join(format!("accuracy-{tolerances}.json"));
    hairlod(&[
        "accuracy",
        "--preset",
        "curly",
        "--frames",
        "3",
        "--size",
        "96x54",
        "--no-integrators",
        "--tolerances",
        tolerances,
        "--json",
        json.to_str().unwrap(),
    ]);
    let report = read_json(&json);
    report["points"].as_array().unwrap().clone()
}

/// Each frame's `(ssim, mean geometric pixel error)` of a point.
fn errors(point: &serde_json::Value) -> Vec<(f64, f64)> {
    point["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|frame| {
            (
                frame["ssim"].as_f64().unwrap(),
                frame["geometric"]["mean_pixels"].as_f64().unwrap(),
            )
        })
        .collect()
}

fn labels(points: &[serde_json::Value]) -> Vec<&str> {
    points
        .iter()
        .map(|p| p["label"].as_str().unwrap())
        .collect()
}

#[test]
fn interleaved_configurations_measure_what_each_makes_alone() {
    let dir = folder("accuracy_cli");
    let one = accuracy(&dir, "2");
    let two = accuracy(&dir, "2,8");
    assert_eq!(
        labels(&one),
        ["Reference", "Strands", "Clusters", "Patches", "LODs 2px"]
    );
    assert_eq!(
        labels(&two),
        [
            "Reference",
            "Strands",
            "Clusters",
            "Patches",
            "LODs 2px",
            "LODs 8px"
        ]
    );
    for point in one.iter().chain(&two) {
        assert!(point["failed"].is_null(), "{point}");
        assert_eq!(errors(point).len(), 3, "{}", point["label"]);
        assert!(point["median_cost"].as_f64().unwrap() > 0.0);
    }
    // The reference against itself: SSIM 1 and no pixel error, every frame.
    assert!(errors(&one[0]).iter().all(|&e| e == (1.0, 0.0)));
    // The coarse levels differ from the reference in the image.
    for point in &one[2..4] {
        assert!(
            errors(point).iter().any(|&(ssim, _)| ssim < 1.0),
            "{} matches the reference exactly",
            point["label"]
        );
    }
    // A sixth configuration interleaved among them changes none of the five's frames, bit for
    // bit (the runs share the renderer, not their state).
    for (alone, beside) in one.iter().zip(&two) {
        assert_eq!(errors(alone), errors(beside), "{}", alone["label"]);
    }
}
