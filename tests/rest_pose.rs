//! Grooms at rest stay at rest: every preset, hung with [`hang_groom`], at every level, with the
//! head still and no wind, keeps its shape over 2 s of the frame pipeline with collision; the
//! hanging shape hangs like hair (no long strand's tip above its root, not much wider than the
//! head); and it moves under a shake as the settled grown groom does.

mod common;

use std::sync::OnceLock;

use glam::Vec3;
use hairlod::core::PRESET_NAMES;
use hairlod::core::dynamics::{Environment, HeadMotion};
use hairlod::metrics::{luma, ssim};
use hairlod::pipeline::{LodMode, Pipeline, PipelineRenderer, PipelineSettings};
use hairlod::render::{RendererOptions, ShadingMode};
use hairlod::{Camera, HangSettings, Level, Scene, hang_groom};

/// Every preset, hung once for all the tests of this file, each on its own thread (a hang is
/// mostly serial, and the straight and wavy presets take three rounds a level).
fn hung() -> &'static [(&'static str, Scene)] {
    static HUNG: OnceLock<Vec<(&'static str, Scene)>> = OnceLock::new();
    HUNG.get_or_init(|| {
        common::side_by_side(&PRESET_NAMES, |&preset| {
            let mut scene = Scene::preset(preset).unwrap();
            let report = hang_groom(&mut scene, &HangSettings::default()).unwrap();
            eprintln!(
                "{preset}: hung in {:.1} s, {:?} rounds, clamped springs {:?}",
                report.wall_seconds,
                report.rounds,
                report.sag_free.map(|_, r| r.clamped_joints)
            );
            (preset, scene)
        })
    })
}

/// Runs `level` of `scene` for `frames` frames in `environment` (collision on) and calls
/// `visit` with the skeleton nodes after each frame.
fn run(
    scene: &Scene,
    level: Level,
    environment: Environment,
    frames: usize,
    mut visit: impl FnMut(usize, &[Vec3]),
) -> Vec<Vec3> {
    let settings = PipelineSettings {
        lod: LodMode::Fixed(level),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene.clone(), environment, settings).unwrap();
    let start = pipeline.block(level).state.node_positions.clone();
    for frame in 0..frames {
        pipeline.advance(&Camera::default()).unwrap();
        visit(frame, &pipeline.block(level).state.node_positions);
    }
    start
}

#[test]
fn every_preset_at_every_level_stays_where_it_is_drawn() {
    // 2 s at 60 Hz with the head still and calm air.
    for (preset, scene) in hung() {
        for level in Level::ALL {
            let mut end = Vec::new();
            let start = run(scene, level, Environment::default(), 120, |_, nodes| {
                end = nodes.to_vec()
            });
            let distances: Vec<f32> = start
                .iter()
                .zip(&end)
                .map(|(a, b)| a.distance(*b))
                .collect();
            let max = distances.iter().copied().fold(0.0f32, f32::max);
            let mean = distances.iter().sum::<f32>() / distances.len() as f32;
            eprintln!(
                "{preset} {}: mean {mean:.2e} m, max {max:.2e} m",
                level.name()
            );
            assert!(
                mean <= 2e-3,
                "{preset} at {}: moved {mean} m on average",
                level.name()
            );
            assert!(
                max <= 1e-2,
                "{preset} at {}: moved {max} m at most",
                level.name()
            );
        }
    }
}

#[test]
fn hanging_presets_hang_like_hair() {
    for (preset, scene) in hung() {
        common::assert_hangs_like_hair(preset, scene);
    }
}

/// Mean over strand-group tips of the largest distance [m] of the tip from its mean position
/// over frames 60..180 (the second and third seconds) of a 5 rad/s shake (0.5 rad amplitude).
fn tip_motion(scene: &Scene, settle: f32) -> f32 {
    let level = Level::StrandGroup;
    let environment = Environment {
        head: HeadMotion::shake(0.5, 5.0),
        ..Environment::default()
    };
    let settings = PipelineSettings {
        lod: LodMode::Fixed(level),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene.clone(), environment, settings).unwrap();
    pipeline.settle(settle).unwrap();
    // At a fixed level the block holds every chain of the level in order, n nodes each.
    let n = scene.groom.skeletons.chain_node_count(0);
    let chains = scene.groom.level_chains(level).len();
    assert_eq!(pipeline.block(level).node_count(), chains * n);
    let tips: Vec<usize> = (0..chains).map(|chain| chain * n + n - 1).collect();
    let mut paths = vec![Vec::new(); tips.len()];
    for frame in 0..180 {
        pipeline.advance(&Camera::default()).unwrap();
        if frame >= 60 {
            let nodes = &pipeline.block(level).state.node_positions;
            for (path, &tip) in paths.iter_mut().zip(&tips) {
                path.push(nodes[tip]);
            }
        }
    }
    let amplitude = |path: &Vec<Vec3>| {
        let mean = path.iter().sum::<Vec3>() / path.len() as f32;
        path.iter().map(|p| p.distance(mean)).fold(0.0f32, f32::max)
    };
    paths.iter().map(amplitude).sum::<f32>() / paths.len() as f32
}

#[test]
fn hanging_grooms_move_as_the_settled_grown_ones_do() {
    // Same springs, same shape: the equilibrium must not come from stiffer hair. The grown groom
    // settles for 1 s first, as runs of it did before (SETTLE_TIME).
    for (preset, scene) in hung() {
        let grown = Scene::preset(preset).unwrap();
        let before = tip_motion(&grown, 1.0);
        let after = tip_motion(scene, 0.0);
        let ratio = after / before;
        eprintln!("{preset}: tip motion {after:.4} m hanging, {before:.4} m grown: {ratio:.3}");
        assert!(
            (0.8..=1.2).contains(&ratio),
            "{preset}: tips move {ratio}× as much as the settled grown groom's"
        );
    }
}

#[test]
fn a_still_picture_is_what_a_still_head_shows_after_two_seconds() {
    // The rest shape drawn without simulation against the same groom after 2 s of a still head,
    // at every level (strands, clusters, patches), rendered shaded from behind and from the front.
    let (_, scene) = &hung()[0];
    let options = RendererOptions::from_env().unwrap();
    for level in Level::ALL {
        let settings = PipelineSettings {
            lod: LodMode::Fixed(level),
            ..PipelineSettings::default()
        };
        let mut pipeline = Pipeline::new(scene.clone(), Environment::default(), settings).unwrap();
        let mut renderer = PipelineRenderer::new(&options, pipeline.scene()).unwrap();
        let cameras = [0.5f32, std::f32::consts::PI]
            .map(|azimuth| Camera::orbit(Vec3::ZERO, 0.8, azimuth, 0.15, 35f32.to_radians()));
        let mut render = |pipeline: &mut Pipeline, camera: &Camera| {
            let (image, _) = renderer
                .render(pipeline, camera, 320, 180, ShadingMode::Shaded)
                .unwrap();
            luma(&image)
        };
        let at_rest = cameras.map(|camera| render(&mut pipeline, &camera));
        for _ in 0..120 {
            pipeline.advance(&Camera::default()).unwrap();
        }
        for (camera, still) in cameras.iter().zip(&at_rest) {
            let moved = render(&mut pipeline, camera);
            let similarity = ssim(still, &moved);
            eprintln!("paper-curly {}: SSIM {similarity:.4}", level.name());
            assert!(similarity >= 0.98, "{}: SSIM {similarity}", level.name());
        }
    }
}
