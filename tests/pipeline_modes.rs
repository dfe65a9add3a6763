//! Changing a running pipeline's level mode and environment (the viewer's "force a level" and
//! its wind and head-motion switches): a forced level reaches every section through the §4.2
//! hand-over and blend with skeletons kept whole, automatic levels choose again afterwards, and
//! the run's fingerprint follows the model it runs.

use glam::Vec3;
use hairlod::core::dynamics::{Environment, HeadMotion, WindField};
use hairlod::core::lod::LodSettings;
use hairlod::pipeline::{LodMode, Pipeline, PipelineSettings};
use hairlod::{Camera, Level, Scene};

/// 16 m away, where automatic levels draw no strand group (see tests/pipeline.rs).
fn far_camera() -> Camera {
    Camera::orbit(Vec3::ZERO, 16.0, 0.5, 0.15, 35f32.to_radians())
}

#[test]
fn a_forced_level_reaches_every_section_and_automatic_levels_return() {
    let scene = Scene::preset("curly").unwrap();
    let sections = scene.groom.section_count();
    // 0.05 s blends: 3 frames at 60 Hz.
    let lod = LodSettings {
        blend_time: 0.05,
        ..LodSettings::default()
    };
    let settings = PipelineSettings {
        lod: LodMode::Auto(lod),
        collision: false,
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene, Environment::default(), settings).unwrap();
    let camera = far_camera();
    for _ in 0..5 {
        pipeline.advance(&camera).unwrap();
    }
    let automatic = pipeline.fingerprint();
    assert!(
        pipeline
            .section_levels()
            .iter()
            .all(|&l| l != Level::StrandGroup)
    );

    pipeline
        .set_lod_mode(LodMode::Fixed(Level::StrandGroup))
        .unwrap();
    assert!(pipeline.selector().is_none());
    assert_ne!(pipeline.fingerprint(), automatic);
    for frame in 0..5 {
        let report = pipeline.advance(&camera).unwrap();
        assert_eq!(report.sections_at, [0, 0, sections], "frame {frame}");
        // The hand-over ends with follow-the-leader: lengths hold to 0.1 % (tests/pipeline.rs).
        let error = hairlod::accuracy::segment_length_error(&pipeline);
        assert!(error < 1e-3, "frame {frame}: segment length error {error}");
    }
    // The blend is over: only strand groups are simulated.
    assert_eq!(pipeline.block(Level::StrandGroup).sections.len(), sections);
    assert!(pipeline.block(Level::Patch).sections.is_empty());

    pipeline.set_lod_mode(LodMode::Auto(lod)).unwrap();
    assert_eq!(pipeline.fingerprint(), automatic);
    let mut last = None;
    for _ in 0..5 {
        last = Some(pipeline.advance(&camera).unwrap());
    }
    let last = last.unwrap();
    assert_eq!(last.sections_at[2], 0, "{last:?}");
}

#[test]
fn a_new_environment_drives_the_next_frames_and_changes_the_fingerprint() {
    let scene = Scene::preset("curly").unwrap();
    let settings = PipelineSettings {
        lod: LodMode::Fixed(Level::Cluster),
        collision: false,
        ..PipelineSettings::default()
    };
    let still = Environment::default();
    let mut calm = Pipeline::new(scene.clone(), still.clone(), settings).unwrap();
    let mut windy = Pipeline::new(scene, still.clone(), settings).unwrap();
    let before = windy.fingerprint();
    let wind = Environment {
        wind: WindField::Constant(Vec3::new(3.0, 0.0, 0.0)),
        head: HeadMotion::Still(windy.head_pose()),
        ..still
    };
    windy.set_environment(wind.clone()).unwrap();
    assert_ne!(windy.fingerprint(), before);
    assert_eq!(windy.environment(), &wind);
    let camera = Camera::default();
    for _ in 0..10 {
        calm.advance(&camera).unwrap();
        windy.advance(&camera).unwrap();
    }
    // Wind along +X pushes the hair along +X.
    let mean_x = |pipeline: &Pipeline| {
        let positions = &pipeline.block(Level::Cluster).state.node_positions;
        positions.iter().map(|p| p.x).sum::<f32>() / positions.len() as f32
    };
    assert!(
        mean_x(&windy) > mean_x(&calm) + 1e-4,
        "{} vs {}",
        mean_x(&windy),
        mean_x(&calm)
    );
}
