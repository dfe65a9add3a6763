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
