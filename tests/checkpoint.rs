//! Checkpoint and resume: N frames straight, and N/2 frames, a checkpoint written to a file and
//! read back, then the other N/2 frames, give bit-identical states and images, at 1 and at 2
//! threads (and the same at both). The scene exercises everything that evolves: automatic levels
//! with switches and blends under a zoom-out, a shaking head, gusting wind and collision.

use hairlod::pipeline::{Checkpoint, PipelineRenderer, PipelineState};
use hairlod::render::RendererOptions;
use hairlod::run::{RunOptions, View, run_shot};
use hairlod::scene_file::SceneFile;
use hairlod::shot::Shot;

const FRAMES: usize = 8;

fn shot() -> Shot {
    SceneFile::parse(
        "[groom]\npreset = \"curly\"\n\
         [motion]\nkind = \"shake\"\namplitude_degrees = 25.0\npeak_speed = 3.0\n\
         [wind]\nspeed = 2.0\ngusts = 1.0\n\
         [camera]\npath = \"zoom-out\"\ndistance = 0.5\nend_distance = 6.0\nazimuth_degrees = 30.0\n\
         [lod]\npixel_tolerance = 2.0\nblend_time = 0.05\n\
         [dynamics]\nsettle_seconds = 0.1\n\
         [frames]\ncount = 8\nfps = 60\nsize = \"96x64\"\n",
    )
    .unwrap()
    .resolve()
    .unwrap()
}

/// What a run leaves to compare: the final state, every frame's image and its report without
/// the wall-clock times.
struct Outcome {
    checkpoint: Checkpoint,
    state: PipelineState,
    images: Vec<image::RgbaImage>,
    levels: Vec<[usize; 3]>,
    level_changes: usize,
}

/// Runs `frames` of the shot, from `checkpoint` when given, on `threads` threads.
fn run(frames: std::ops::Range<usize>, checkpoint: Option<Checkpoint>, threads: usize) -> Outcome {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let shot = shot();
        let scene = shot.build_scene().unwrap();
        let mut renderer =
            PipelineRenderer::new(&RendererOptions::from_env().unwrap(), &scene).unwrap();
        let options = RunOptions {
            frames,
            resume: checkpoint,
            ..RunOptions::whole(&shot, shot.settings)
        };
        let mut images = Vec::new();
        let mut levels = Vec::new();
        let mut level_changes = 0;
        let result = run_shot(
            &shot,
            &scene,
            options,
            Some((&mut renderer, &[View::LevelColors])),
            |frame| {
                images.push(frame.images[0].clone());
                levels.push(frame.report.sections_at);
                level_changes += frame.report.level_changes;
                Ok(())
            },
        )
        .unwrap();
        Outcome {
            checkpoint: result.pipeline.checkpoint().unwrap(),
            state: result.pipeline.state().unwrap(),
            images,
            levels,
            level_changes,
        }
    })
}

#[test]
fn a_resumed_run_is_bit_identical_to_an_uninterrupted_one_at_any_thread_count() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let mut straight_states = Vec::new();
    for threads in [1, 2] {
        let straight = run(0..FRAMES, None, threads);
        // The run switches levels (so blocks are rebuilt and state handed over) and collides.
        assert!(
            straight.level_changes > 0,
            "no level switch: {:?}",
            straight.levels
        );
        let first = run(0..FRAMES / 2, None, threads);
        let path = dir.join(format!("checkpoint_{threads}.json"));
        first.checkpoint.write(&path).unwrap();
        let read = Checkpoint::read(&path).unwrap();
        assert_eq!(
            read.state, first.state,
            "the file round trip changes the state"
        );
        let second = run(FRAMES / 2..FRAMES, Some(read), threads);
        assert_eq!(
            second.state, straight.state,
            "{threads} thread(s): final states differ"
        );
        let images: Vec<_> = first.images.iter().chain(&second.images).collect();
        for (k, (a, b)) in images.iter().zip(&straight.images).enumerate() {
            assert!(*a == b, "{threads} thread(s): frame {k} differs");
        }
        let levels: Vec<_> = first.levels.iter().chain(&second.levels).copied().collect();
        assert_eq!(levels, straight.levels);
        straight_states.push(straight.state);
    }
    assert_eq!(
        straight_states[0], straight_states[1],
        "1 and 2 threads give different states"
    );
}

#[test]
fn a_checkpoint_of_another_scene_or_a_damaged_state_is_refused() {
    let shot = shot();
    let scene = shot.build_scene().unwrap();
    let pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let checkpoint = pipeline.checkpoint().unwrap();

    // Another groom seed: another scene.
    let mut other = shot.clone();
    other.groom.seed += 1;
    let other_scene = other.build_scene().unwrap();
    let error = other
        .pipeline(&other_scene, other.settings, Some(checkpoint.clone()))
        .err()
        .expect("another scene is refused")
        .to_string();
    assert!(error.contains("another scene"), "{error}");

    // Other settings (a fixed level): another run.
    let mut fixed = shot.settings;
    fixed.lod = hairlod::LodMode::Fixed(hairlod::Level::Patch);
    let error = shot
        .pipeline(&scene, fixed, Some(checkpoint.clone()))
        .err()
        .expect("other settings are refused")
        .to_string();
    assert!(error.contains("another scene"), "{error}");

    // A state whose node arrays were cut short.
    let mut damaged = checkpoint.clone();
    damaged.state.blocks.strand_group.state.node_positions.pop();
    let error = shot
        .pipeline(&scene, shot.settings, Some(damaged))
        .err()
        .expect("a damaged state is refused")
        .to_string();
    assert!(error.contains("node_positions"), "{error}");

    // A NaN in the state.
    let mut poisoned = checkpoint;
    poisoned.state.blocks.strand_group.state.node_velocities[3].x = f32::NAN;
    let error = shot
        .pipeline(&scene, shot.settings, Some(poisoned))
        .err()
        .expect("a NaN is refused")
        .to_string();
    assert!(error.contains("not finite"), "{error}");
}
