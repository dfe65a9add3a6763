//! Sub-pixel strand coverage (`LineCoverage::Width`) against a 4×4 supersampled reference: the
//! paper-curly groom hanging at rest, drawn as strands at 0.8 m and at 3 m, is closer by SSIM to
//! the reference with its lines covering their width's share of a pixel than with lines covering
//! whole pixels.

mod common;

use hairlod::benchmark::coverage::{coverage_camera, measure_coverage};
use hairlod::render::FrameSettings;
use hairlod::{HangSettings, Scene, hang_groom};

/// At 320×180 an 80 µm fibre is 0.04 px wide at 0.8 m and 0.01 px at 3 m (focal length
/// 285 px), so a whole-pixel line draws it 25–100 times too wide. The reference is rendered at
/// 1280×720 with 4× MSAA (64 samples per final pixel) with every fibre covering its width's
/// share of the fine pixels, so it is the image of fibres of their true width to within its
/// sampling; each view must be closer to it with coverage than without. (The plain
/// supersampled render, whole-pixel lines at the fine size, still draws fibres a quarter of a
/// final pixel wide, 6–25 times too wide: it is printed, not asserted.)
#[test]
fn covered_lines_are_closer_to_the_supersampled_reference() {
    let mut scene = Scene::preset("paper-curly").unwrap();
    hang_groom(&mut scene, &HangSettings::default()).unwrap();
    let (mut renderer, active) = common::strands_at_rest(&scene);
    for distance in [0.8, 3.0] {
        let camera = coverage_camera(distance);
        let settings = FrameSettings::new(320, 180, camera);
        let (measure, _) = measure_coverage(&mut renderer, &active.frame(), &settings, 4).unwrap();
        eprintln!("{distance} m: {measure:?}");
        assert!(measure.ssim_width > measure.ssim_pixel, "{distance} m");
    }
}
