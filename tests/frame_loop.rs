//! The frame loop one frame at a time ([`FrameLoop`]): two runs of one scene stepped side by side
//! on one renderer (as `bench paper` interleaves its modes) make, bit for bit, the frames and
//! final states each makes when run alone through [`run_shot`].

use hairlod::core::Level;
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings, PipelineState};
use hairlod::render::RendererOptions;
use hairlod::run::{FrameLoop, RunOptions, View, run_shot};
use hairlod::scene_file::SceneFile;
use hairlod::shot::Shot;

fn shot() -> Shot {
    SceneFile::parse(
        "[groom]\npreset = \"wavy\"\n\
         [motion]\nkind = \"shake\"\namplitude_degrees = 20.0\npeak_speed = 3.0\n\
         [wind]\nspeed = 2.0\ngusts = 1.0\n\
         [camera]\npath = \"zoom-out\"\ndistance = 0.5\nend_distance = 6.0\nazimuth_degrees = 30.0\n\
         [lod]\npixel_tolerance = 2.0\nblend_time = 0.05\n\
         [frames]\ncount = 6\nfps = 60\nsize = \"96x64\"\n",
    )
    .unwrap()
    .resolve()
    .unwrap()
}

/// The shot's own settings (automatic levels) and the same at strands.
fn settings(shot: &Shot) -> [PipelineSettings; 2] {
    [
        shot.settings,
        PipelineSettings {
            lod: LodMode::Fixed(Level::StrandGroup),
            ..shot.settings
        },
    ]
}

#[test]
fn runs_stepped_side_by_side_make_what_each_makes_alone() {
    let shot = shot();
    let scene = shot.build_scene().unwrap();
    let options = RendererOptions::from_env().unwrap();
    let views = [View::Shaded];

    // Each run alone, on a renderer of its own.
    let mut alone: Vec<(Vec<image::RgbaImage>, PipelineState)> = Vec::new();
    for settings in settings(&shot) {
        let mut renderer = PipelineRenderer::new(&options, &scene).unwrap();
        let mut images = Vec::new();
        let result = run_shot(
            &shot,
            &scene,
            RunOptions::whole(&shot, settings),
            Some((&mut renderer, &views)),
            |frame| {
                images.push(frame.images[0].clone());
                Ok(())
            },
        )
        .unwrap();
        alone.push((images, result.pipeline.state().unwrap()));
    }

    // Both stepped in turn, frame by frame, on one renderer.
    let mut renderer = PipelineRenderer::new(&options, &scene).unwrap();
    let mut loops: Vec<FrameLoop<'_>> = settings(&shot)
        .into_iter()
        .map(|settings| {
            FrameLoop::start(
                &shot,
                &scene,
                RunOptions::whole(&shot, settings),
                Some(&mut renderer),
            )
            .unwrap()
        })
        .collect();
    let mut images = [Vec::new(), Vec::new()];
    for frame in 0..shot.frames {
        for (k, frame_loop) in loops.iter_mut().enumerate() {
            let output = frame_loop
                .step(Some((&mut renderer, &views)))
                .unwrap()
                .expect("a frame of the shot");
            assert_eq!(output.report.frame, frame);
            images[k].push(output.images[0].clone());
        }
    }
    for (k, mut frame_loop) in loops.into_iter().enumerate() {
        assert!(
            frame_loop.step(None).unwrap().is_none(),
            "a step after the last frame makes no frame"
        );
        let result = frame_loop.finish();
        assert_eq!(result.run.frames.len(), shot.frames);
        assert_eq!(
            result.pipeline.state().unwrap(),
            alone[k].1,
            "run {k}: states differ"
        );
        for (frame, (a, b)) in images[k].iter().zip(&alone[k].0).enumerate() {
            assert!(a == b, "run {k}: frame {frame} differs from the run alone");
        }
    }
    // The two runs differ (the test would pass vacuously if both drew the same levels).
    assert!(
        images[0] != images[1],
        "the LODs and Strands runs drew the same frames"
    );
}

/// `bench costs` steps the loop without drawing and draws each frame itself, in variants: the
/// frame with the style's own settings is the view's image bit for bit, and the frame without
/// hair keeps the head and loses the hair (it can only uncover background, never add to it).
#[test]
fn a_frame_drawn_in_variants_after_a_step_without_views() {
    let shot = shot();
    let scene = shot.build_scene().unwrap();
    let options = RendererOptions::from_env().unwrap();
    let views = [View::Shaded];
    let mut renderer = PipelineRenderer::new(&options, &scene).unwrap();
    let mut viewed = FrameLoop::start(
        &shot,
        &scene,
        RunOptions::whole(&shot, shot.settings),
        Some(&mut renderer),
    )
    .unwrap();
    let mut bare = FrameLoop::start(
        &shot,
        &scene,
        RunOptions::whole(&shot, shot.settings),
        Some(&mut renderer),
    )
    .unwrap();
    let background = |image: &image::RgbaImage, x: u32, y: u32| {
        let corner = image.get_pixel(0, 0);
        image.get_pixel(x, y) == corner
    };
    for frame in 0..shot.frames {
        let expected = viewed
            .step(Some((&mut renderer, &views)))
            .unwrap()
            .expect("a frame")
            .images[0]
            .clone();
        let camera = *bare.step(None).unwrap().expect("a frame").camera;
        let settings = renderer.style().frame_settings(
            shot.width,
            shot.height,
            &camera,
            hairlod::render::ShadingMode::Shaded,
        );
        let pipeline = bare.target_mut();
        let (with_hair, _) = renderer.render_with_settings(pipeline, &settings).unwrap();
        assert!(
            with_hair == expected,
            "frame {frame}: differs from the view"
        );
        let (without, _) = renderer.render_without_hair(pipeline, &settings).unwrap();
        let (mut covered_with, mut covered_without) = (0, 0);
        for (x, y, _) in without.enumerate_pixels() {
            let (hair_bg, bare_bg) = (background(&with_hair, x, y), background(&without, x, y));
            assert!(
                !hair_bg || bare_bg,
                "frame {frame}: ({x}, {y}) is covered only without the hair"
            );
            covered_with += usize::from(!hair_bg);
            covered_without += usize::from(!bare_bg);
        }
        assert!(
            covered_without > 0,
            "frame {frame}: the head is missing without the hair"
        );
        assert!(
            covered_without < covered_with,
            "frame {frame}: the hair covers nothing ({covered_without} of {covered_with})"
        );
    }
}
