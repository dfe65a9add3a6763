//! `hairlod bench SCENE` end to end, through the binary: the five runs (LODs, Strands, Clusters,
//! Patches, LODs switching instantly) are interleaved frame by frame on one renderer, and each
//! makes what it makes alone: the LODs choose, frame by frame, the levels `hairlod render`
//! chooses for the same scene.

mod common;

use common::{assert_levels_as_alone, bench_and_render, folder, frame_numbers, levels};

/// A small scene: a short curly groom (12 sections, 10 cm), the head shaking, the camera zooming
/// out from 0.5 m to 3 m over 4 frames at 15 Hz, 128×80, automatic levels at 2 px.
const SCENE: &str = "version = 2\n\
    [groom]\npreset = \"curly\"\nsection_count = 12\nhair_length = 0.1\n\
    [motion]\nkind = \"shake\"\namplitude_degrees = 30.0\npeak_speed = 4.0\n\
    [camera]\npath = \"zoom-out\"\ndistance = 0.5\nend_distance = 3.0\n\
    azimuth_degrees = 0.0\nelevation_degrees = 0.0\n\
    [lod]\nmode = \"auto\"\npixel_tolerance = 2.0\n\
    [frames]\ncount = 4\nfps = 15\nsize = \"128x80\"\n\
    [output]\njson = \"report.json\"\n";

#[test]
fn interleaved_runs_choose_what_each_run_alone_chooses() {
    let (bench, render) = bench_and_render(&folder("bench_scene"), SCENE);

    // Every run made the shot's four frames, in order.
    let modes = bench["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 4);
    for run in modes.iter().chain([&bench["lods_instant_switching"]]) {
        assert_eq!(frame_numbers(run), [0, 1, 2, 3], "{}", run["mode"]);
    }
    // The interleaved LODs chose the levels the render alone chose, frame by frame.
    assert_levels_as_alone(&modes[0], &render);
    // The fixed levels hold every section at their level: [patches, clusters, strands].
    for (run, expected) in modes[1..].iter().zip(["[0,0,12]", "[0,12,0]", "[12,0,0]"]) {
        for frame in levels(run) {
            assert_eq!(frame, expected, "{}", run["mode"]);
        }
    }
    // SSIM against the Strands frames of the same frame: below 1 for a coarser level.
    let ssim = &bench["mean_ssim_against_strands"];
    for key in ["lods", "clusters", "patches"] {
        let value = ssim[key].as_f64().unwrap();
        assert!(value > 0.0 && value < 1.0, "{key}: SSIM {value}");
    }
}
