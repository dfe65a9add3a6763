//! `hairlod bench CROWD` end to end, through the binary: the crowd's four modes run interleaved
//! frame by frame on one renderer (all-strands first, the yardstick of the others), then the two
//! frame-budget methods side by side; each run makes what it makes alone: the LODs choose, frame
//! by frame, the levels `hairlod render` chooses for the same crowd. A crowd render split by a
//! checkpoint writes the frames of one run straight through.

mod common;

use common::{assert_levels_as_alone, bench_and_render, folder, frame_numbers, hairlod, levels};

/// Two small heads (12 sections, 10 cm of hair), one shaking, one in wind, the camera moving in
/// over 4 frames at 15 Hz, 128×80, automatic levels at 2 px.
const SCENE: &str = "version = 2\n\
    [camera]\npath = \"keyframes\"\nfov_degrees = 35.0\nkeyframes = [\n\
    { time = 0.0, position = [0.0, 0.1, 2.0], target = [0.0, 0.0, -1.0] },\n\
    { time = 0.2, position = [0.1, 0.1, 0.6], target = [0.0, 0.0, -1.0] },\n]\n\
    [lod]\nmode = \"auto\"\npixel_tolerance = 2.0\n\
    [frames]\ncount = 4\nfps = 15.0\nsize = \"128x80\"\n\
    [output]\njson = \"report.json\"\n\
    [[character]]\nname = \"curly\"\nposition = [0.0, 0.0, 0.0]\nyaw_degrees = 180.0\n\
    groom = { preset = \"curly\", section_count = 12, hair_length = 0.1 }\n\
    motion = { kind = \"shake\", amplitude_degrees = 30.0, peak_speed = 4.0 }\n\
    [[character]]\nname = \"wavy\"\nposition = [0.3, 0.0, -0.5]\nyaw_degrees = 160.0\n\
    groom = { preset = \"wavy\", section_count = 12, hair_length = 0.1 }\n\
    wind = { speed = 3.0, gusts = 2.0, direction = [1.0, 0.0, 0.3], seed = 2 }\n";

#[test]
fn interleaved_crowd_runs_choose_what_each_run_alone_chooses() {
    let (bench, render) = bench_and_render(&folder("crowd_bench"), SCENE);

    let modes = bench["modes"].as_array().unwrap();
    let names: Vec<&str> = modes.iter().map(|m| m["mode"].as_str().unwrap()).collect();
    assert_eq!(names, ["LODs", "Strands", "Clusters", "Patches"]);
    for run in modes {
        assert_eq!(frame_numbers(run), [0, 1, 2, 3], "{}", run["mode"]);
    }
    assert_levels_as_alone(&modes[0], &render);
    // The fixed levels hold all 24 sections at their level: [patches, clusters, strands].
    for (run, expected) in modes[1..].iter().zip(["[0,0,24]", "[0,24,0]", "[24,0,0]"]) {
        for frame in levels(run) {
            assert_eq!(frame, expected, "{}", run["mode"]);
        }
    }
    // Against the all-strands frames: the all-strands run is its own yardstick, the coarse
    // levels are not.
    let against = bench["against_strands"].as_array().unwrap();
    assert_eq!(against[1]["mode"], "Strands");
    assert_eq!(against[1]["mean_ssim"].as_f64(), Some(1.0));
    assert_eq!(against[1]["mean_luma_error"].as_f64(), Some(0.0));
    for a in [&against[2], &against[3]] {
        let ssim = a["mean_ssim"].as_f64().unwrap();
        assert!(ssim > 0.0 && ssim < 1.0, "{}: SSIM {ssim}", a["mode"]);
    }
    // Both budget methods ran every frame.
    let budgets = bench["budgets"].as_array().unwrap();
    assert_eq!(budgets.len(), 2);
    for (report, _) in budgets.iter().map(|b| (&b[0], &b[1])) {
        assert_eq!(report["frames"].as_u64(), Some(4), "{report}");
    }
}

/// A crowd render split by a checkpoint (`--frames 0..2 --checkpoint`, then `--resume`) writes
/// PNGs byte-identical to one run straight through.
#[test]
fn a_crowd_render_split_by_a_checkpoint_writes_the_same_frames() {
    let dir = folder("crowd_resume");
    let scene = dir.join("crowd.toml");
    std::fs::write(
        &scene,
        SCENE.replace("[output]\njson = \"report.json\"\n", ""),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let (straight, split, checkpoints) = (
        dir.join("straight"),
        dir.join("split"),
        dir.join("checkpoints"),
    );
    hairlod(&["render", scene, "--out", straight.to_str().unwrap()]);
    let first = hairlod(&[
        "render",
        scene,
        "--out",
        split.to_str().unwrap(),
        "--frames",
        "0..2",
        "--checkpoint",
        checkpoints.to_str().unwrap(),
    ]);
    let checkpoint = checkpoints.join("checkpoint_00002.json");
    assert!(checkpoint.exists(), "{first}");
    hairlod(&[
        "render",
        scene,
        "--out",
        split.to_str().unwrap(),
        "--resume",
        checkpoint.to_str().unwrap(),
    ]);
    for k in 0..4 {
        let name = format!("frame_{k:05}.png");
        let (a, b) = (
            std::fs::read(straight.join(&name)).unwrap(),
            std::fs::read(split.join(&name)).unwrap(),
        );
        assert!(a == b, "{name} differs");
    }
}
