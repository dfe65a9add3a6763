//! The frame pipeline end to end (no rendering): fixed levels and automatic levels run through the
//! same code, transitions keep skeletons intact, results do not depend on the thread count.

use glam::Vec3;
use hairlod::core::dynamics::{Environment, WindField};
use hairlod::core::lod::LodSettings;
use hairlod::pipeline::{LodMode, Pipeline, PipelineSettings};
use hairlod::{Camera, Level, Scene};

fn zoom_camera(frame: usize, frames: usize) -> Camera {
    // 0.5 m to 16 m, geometrically.
    let distance = 0.5 * 32f32.powf(frame as f32 / (frames - 1) as f32);
    Camera::orbit(Vec3::ZERO, distance, 0.5, 0.15, 35f32.to_radians())
}

fn windy() -> Environment {
    Environment {
        wind: WindField::gusting(Vec3::new(1.0, 0.0, -1.5), 1.0, 1.0, 0.5, 3),
        ..Environment::default()
    }
}

/// Largest relative segment-length error over every simulated chain.
fn max_length_error(pipeline: &Pipeline) -> f32 {
    hairlod::accuracy::segment_length_error(pipeline)
}

#[test]
fn fixed_levels_simulate_every_section_at_that_level() {
    let scene = Scene::preset("curly").unwrap();
    let sections = scene.groom.section_count();
    for level in Level::ALL {
        let settings = PipelineSettings {
            lod: LodMode::Fixed(level),
            collision: false,
            ..PipelineSettings::default()
        };
        let mut pipeline = Pipeline::new(scene.clone(), Environment::default(), settings).unwrap();
        let report = pipeline.advance(&Camera::default()).unwrap();
        assert_eq!(report.sections_at[level as usize], sections);
        assert_eq!(report.level_changes, 0);
        let nodes: usize = scene
            .groom
            .level_chains(level)
            .map(|chain| scene.groom.skeletons.chain_node_count(chain))
            .sum();
        assert_eq!(report.simulated_nodes, nodes);
    }
}

#[test]
fn zooming_out_with_levels_keeps_skeletons_whole_and_lowers_detail() {
    let scene = Scene::preset("curly").unwrap();
    let settings = PipelineSettings {
        lod: LodMode::Auto(LodSettings {
            blend_time: 0.1,
            ..LodSettings::default()
        }),
        collision: std::env::var("NOCOL").is_err(),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(scene, Environment::default(), settings).unwrap();
    pipeline.settle(1.0).unwrap();
    let frames = 40;
    let mut first = None;
    let mut last = None;
    let mut changes = 0;
    for frame in 0..frames {
        let report = pipeline.advance(&zoom_camera(frame, frames)).unwrap();
        changes += report.level_changes;
        // Every section is simulated at exactly its current level, plus its previous one while
        // blending.
        let simulated: usize = Level::ALL
            .iter()
            .map(|&l| pipeline.block(l).sections.len())
            .sum();
        assert_eq!(
            simulated,
            report.sections_at.iter().sum::<usize>() + report.blending_sections
        );
        // Follow-the-leader keeps lengths to rounding after every step, transitions included
        // (hand-over ends with a follow-the-leader pass too): 0.1 % is the bound.
        let error = max_length_error(&pipeline);
        assert!(error < 1e-3, "frame {frame}: segment length error {error}");
        if frame == 2 {
            first = Some(report);
        }
        last = Some(report);
    }
    let (first, last) = (first.unwrap(), last.unwrap());
    assert!(changes > 0);
    // Close up most sections are strand groups; 16 m away none is.
    assert!(first.sections_at[2] > first.sections_at[0], "{first:?}");
    assert_eq!(last.sections_at[2], 0, "{last:?}");
    assert!(last.simulated_nodes < first.simulated_nodes);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| -> Vec<Vec3> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let scene = Scene::preset("wavy").unwrap();
            let mut pipeline = Pipeline::new(scene, windy(), PipelineSettings::default()).unwrap();
            for frame in 0..20 {
                pipeline.advance(&zoom_camera(frame, 20)).unwrap();
            }
            Level::ALL
                .iter()
                .flat_map(|&l| pipeline.block(l).state.node_positions.clone())
                .collect()
        })
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one.len(), two.len());
    assert!(
        one.iter()
            .zip(&two)
            .all(|(a, b)| a.to_array() == b.to_array())
    );
}

#[test]
fn a_bad_camera_is_an_error_not_a_panic() {
    let scene = Scene::preset("curly").unwrap();
    let mut pipeline =
        Pipeline::new(scene, Environment::default(), PipelineSettings::default()).unwrap();
    let camera = Camera {
        position: Vec3::NAN,
        ..Camera::default()
    };
    let error = pipeline.advance(&camera).unwrap_err();
    assert!(error.to_string().contains("camera"), "{error}");
}
