//! Popping with blended transitions against instant switching (rendered, small scene): the image
//! change of a level switch, measured with the camera and the skeletons held still
//! (`advance_measured`), is spread over the blend instead of landing in one frame.

use glam::Vec3;
use hairlod::core::dynamics::Environment;
use hairlod::core::lod::LodSettings;
use hairlod::pipeline::{LodMode, Pipeline, PipelineRenderer, PipelineSettings};
use hairlod::popping::{PoppingFrame, advance_measured, compare_popping};
use hairlod::render::RendererOptions;
use hairlod::{Camera, GroomParams, HeadParams, Level, Scene};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;
/// Frames before the switch (fine levels at a 1-pixel tolerance).
const BEFORE: usize = 3;
/// Frames from the switch on: the blend (0.25 s at 60 Hz = 15 frames) and a few after it.
const AFTER: usize = 20;

fn scene() -> Scene {
    let groom = GroomParams {
        section_count: 12,
        strands_per_group: 6,
        ..GroomParams::preset("straight").unwrap()
    };
    Scene::new(&HeadParams::default(), &groom).unwrap()
}

/// A still camera in front of the face, a little to the side and above.
fn camera() -> Camera {
    Camera::orbit(Vec3::ZERO, 0.7, 0.5, 0.15, 35f32.to_radians())
}

/// Runs the scene with `blend_time` [s]: fine levels at a 1-pixel tolerance, then the tolerance
/// raised to 1,000 pixels (every section as coarse as the rules allow) with the camera still, so
/// the only reason for the switch, and for any pop, is the level change. Returns every frame's
/// measure and the levels before and after.
fn run(renderer: &mut PipelineRenderer, blend_time: f32) -> (Vec<PoppingFrame>, [Vec<Level>; 2]) {
    let lod = LodSettings {
        pixel_tolerance: 1.0,
        image_width: WIDTH,
        image_height: HEIGHT,
        blend_time,
        ..LodSettings::default()
    };
    let settings = PipelineSettings {
        lod: LodMode::Auto(lod),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene(), Environment::default(), settings).unwrap();
    pipeline.settle(0.5).unwrap();
    renderer.bind(&pipeline).unwrap();
    let camera = camera();
    let mut frames = Vec::new();
    let mut levels = [Vec::new(), Vec::new()];
    for frame in 0..BEFORE + AFTER {
        if frame == BEFORE {
            levels[0] = pipeline.section_levels().to_vec();
            pipeline.set_pixel_tolerance(1000.0).unwrap();
        }
        let (_, measured, _) =
            advance_measured(&mut pipeline, renderer, &camera, WIDTH, HEIGHT).unwrap();
        frames.push(measured);
    }
    levels[1] = pipeline.section_levels().to_vec();
    (frames, levels)
}

#[test]
fn a_blended_switch_spreads_its_image_change_over_the_blend() {
    let options = RendererOptions::from_env().unwrap();
    let mut renderer = PipelineRenderer::new(&options, &scene()).unwrap();
    let (blended, levels_blended) = run(&mut renderer, 0.25);
    let (instant, levels_instant) = run(&mut renderer, 0.0);

    // The same switch in both runs, in the frame the tolerance changed and in no other after the
    // first (which picks the starting levels outright): levels are chosen on the current level's
    // skeletons, which blending does not touch.
    assert_eq!(levels_blended, levels_instant);
    let switched = levels_instant[0]
        .iter()
        .zip(&levels_instant[1])
        .filter(|(a, b)| a != b)
        .count();
    assert!(switched > 0, "the tolerance change switched no section");
    assert!(blended[BEFORE].switched && instant[BEFORE].switched);
    let comparison = compare_popping(&blended, &instant);
    assert!(comparison.same_switch_frames);

    // Instant switching changes the image only where a section switched level or visibility:
    // the level-of-detail stage of any other frame draws exactly what the frame before drew (same
    // skeletons, levels and camera), so its change is exactly 0.
    let pop = instant[BEFORE].lod_change;
    assert!(
        pop > 1e-4,
        "the switch changed too little to measure: {pop}"
    );
    for (t, frame) in instant.iter().enumerate().skip(1) {
        if !frame.switched {
            assert_eq!(frame.lod_change, 0.0, "instant, frame {t}");
        }
    }

    // Blending: the staged dissolve raises the new level's coverage by 2/15 per frame over the
    // first half of the blend and lowers the old one's by 1/15 per frame over the whole blend.
    // Each pixel the swap changes flips about once, when its screen-door threshold (sixteenths)
    // or its strand's rank passes the coverage: at most 3 of 16 Bayer thresholds per step of
    // 2/15, and 1/15 of the strands. So no frame of the blend should change more than about
    // 3/16 + 1/15 ≈ 1/4 of the instant pop; 1/2 leaves room for the hair's motion over the
    // blend, which changes what the swap would change.
    let blend = &blended[BEFORE..];
    let peak = blend.iter().map(|f| f.lod_change).fold(0.0, f64::max);
    assert!(
        peak < 0.5 * pop,
        "blended peak {peak} against the instant pop {pop}"
    );
    // Over the frames where a switch or a visibility change started in either run (sections near
    // the occlusion limit come into view or leave it while the hair settles; they fade too), the
    // mean change and the popping ratio are lower with blending, by the same reasoning.
    assert!(comparison.blended.lod_change < 0.5 * comparison.instant.lod_change);
    assert!(comparison.blended.ratio < comparison.instant.ratio);
    // The change is spread, not skipped: over the blend the level decisions change about as
    // much as the swap (each pixel flips about once; the hair moving under the dissolve makes it
    // a little more or less).
    let spread: f64 = blend.iter().map(|f| f.lod_change).sum();
    assert!(
        (0.5 * pop..2.0 * pop).contains(&spread),
        "blended total {spread} against the instant pop {pop}"
    );
}
