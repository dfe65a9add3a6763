//! Checkpoint and resume: N frames straight, and N/2 frames, a checkpoint written to a file and
//! read back, then the other N/2 frames, give bit-identical states and images, at 1 and at 2
//! threads (and the same at both). The scene exercises everything that evolves: automatic levels
//! with switches and blends under a zoom-out, a shaking head, gusting wind and collision.

use hairlod::Scene;
use hairlod::pipeline::{Checkpoint, PipelineRenderer, PipelineState};
use hairlod::render::RendererOptions;
use hairlod::run::{RunOptions, View, run_shot};
use hairlod::scene_file::SceneFile;
use hairlod::shot::Shot;
use std::sync::OnceLock;

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

/// The shot's scene, built (and its groom hung) once for every run of this file: the runs
/// compare what evolves from it, not its building.
fn scene() -> Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| shot().build_scene().unwrap()).clone()
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
        let scene = scene();
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
    let scene = scene();
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

/// Writes the checkpoint JSON `value` to `name` in the test's folder and resumes `shot` from it:
/// the error, or `None` when it resumes.
fn resume_error(
    shot: &Shot,
    scene: &hairlod::Scene,
    value: &serde_json::Value,
    name: &str,
) -> Option<String> {
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, serde_json::to_string(value).unwrap()).unwrap();
    let checkpoint = match Checkpoint::read(&path) {
        Ok(checkpoint) => checkpoint,
        Err(error) => return Some(error.to_string()),
    };
    shot.pipeline(scene, shot.settings, Some(checkpoint))
        .err()
        .map(|error| error.to_string())
}

/// The checkpoint JSON `value` with its state's checksum made right again (as an editor that
/// knew the hash would), so that the state's own checks are what refuse it.
fn resealed(value: &serde_json::Value) -> serde_json::Value {
    let state: PipelineState = serde_json::from_value(value["state"].clone()).unwrap();
    let fingerprint = value["scene_fingerprint"].as_str().unwrap().to_string();
    serde_json::to_value(Checkpoint::new(fingerprint, state)).unwrap()
}

#[test]
fn an_edited_checkpoint_is_refused_naming_the_field() {
    let shot = shot();
    let scene = scene();
    let outcome = run(0..FRAMES / 2, None, 1);
    let original = serde_json::to_value(&outcome.checkpoint).unwrap();
    assert_eq!(
        resume_error(&shot, &scene, &resealed(&original), "unedited.json"),
        None,
        "the unedited checkpoint resumes"
    );
    // The block with the most nodes at this frame (the zoom-out moves sections down the levels).
    let block = ["patch", "cluster", "strand_group"]
        .into_iter()
        .max_by_key(|level| {
            original["state"]["blocks"][level]["state"]["node_positions"]
                .as_array()
                .map_or(0, Vec::len)
        })
        .unwrap();
    let velocities = format!("blocks.{block}.state.node_velocities[5]");
    let positions = format!("blocks.{block}.state.node_positions[5]");
    let memory_field = format!("blocks.{block}.collision_memory.positions");
    type Edit<'a> = Box<dyn Fn(&mut serde_json::Value) + 'a>;
    let edits: [(&str, Edit, &str); 8] = [
        (
            "time 100 s",
            Box::new(|v| v["state"]["time"] = 100.0.into()),
            "time",
        ),
        (
            "time -1 s",
            Box::new(|v| v["state"]["time"] = (-1.0).into()),
            "time",
        ),
        (
            "a fade from 50",
            Box::new(|v| v["state"]["levels"]["shown"][0]["from"] = 50.0.into()),
            "levels.shown[0]",
        ),
        (
            "a velocity of 1e6 m/s",
            Box::new(|v| {
                v["state"]["blocks"][block]["state"]["node_velocities"][5] =
                    serde_json::json!([1e6, 0.0, 0.0])
            }),
            velocities.as_str(),
        ),
        (
            "a node 10 m from its root",
            Box::new(|v| {
                v["state"]["blocks"][block]["state"]["node_positions"][5] =
                    serde_json::json!([10.0, 0.0, 0.0])
            }),
            positions.as_str(),
        ),
        (
            "the collision memory one entry short",
            Box::new(|v| {
                let memory = &mut v["state"]["blocks"][block]["collision_memory"];
                memory["positions"].as_array_mut().unwrap().pop();
            }),
            memory_field.as_str(),
        ),
        (
            "the choices one entry short",
            Box::new(|v| {
                v["state"]["choices"].as_array_mut().unwrap().pop();
            }),
            "choices",
        ),
        (
            "a negative pixel tolerance",
            Box::new(|v| v["state"]["pixel_tolerance"] = (-2.0).into()),
            "pixel_tolerance",
        ),
    ];
    for (what, edit, field) in edits {
        let mut edited = original.clone();
        edit(&mut edited);
        // Edited without resealing: the checksum refuses it.
        let error = resume_error(&shot, &scene, &edited, "edited.json")
            .unwrap_or_else(|| panic!("{what} resumed"));
        assert!(error.contains("state_checksum"), "{what}: {error}");
        // Resealed: the state's own check refuses it, naming the field.
        let error = resume_error(&shot, &scene, &resealed(&edited), "resealed.json")
            .unwrap_or_else(|| panic!("{what} (resealed) resumed"));
        assert!(error.contains(field), "{what}: {error}");
    }
    // A selector depth of -5 m is a depth the selector can hold (a section behind the camera):
    // only the checksum refuses it.
    let mut edited = original.clone();
    edited["state"]["selector_depths"][0] = (-5.0).into();
    let error =
        resume_error(&shot, &scene, &edited, "depth.json").expect("an edited depth resumed");
    assert!(error.contains("state_checksum"), "{error}");
}

/// Every number of the state's JSON, as a path of keys and indices.
fn number_paths(value: &serde_json::Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match value {
        serde_json::Value::Number(_) => out.push(path.clone()),
        serde_json::Value::Array(items) => {
            for (k, item) in items.iter().enumerate() {
                path.push(k.to_string());
                number_paths(item, path, out);
                path.pop();
            }
        }
        serde_json::Value::Object(fields) => {
            for (key, item) in fields {
                path.push(key.clone());
                number_paths(item, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

/// Random numbers of a checkpoint's state set to random values, resealed (the checksum made
/// right), then resumed from: each resumes or is refused, never panics; an edit that breaks an
/// invariant the check knows (a time, a count) is refused. Fixed seed, bounded cases.
#[test]
fn randomly_edited_checkpoints_resume_or_are_refused_without_panicking() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let shot = shot();
    let scene = scene();
    let pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let original = serde_json::to_value(pipeline.checkpoint().unwrap()).unwrap();
    let mut paths = Vec::new();
    number_paths(&original["state"], &mut vec!["state".into()], &mut paths);
    assert!(paths.len() > 1000, "{} numbers", paths.len());
    let values = prop::sample::select(vec![
        -1.0,
        0.0,
        0.5,
        2.0,
        100.0,
        1e6,
        -1e6,
        3.4e38,
        -3.4e38,
        1e-30,
        4294967296.0,
    ]);
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 64,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[3; 32]),
    );
    runner
        .run(
            &(any::<prop::sample::Index>(), values),
            |(index, number)| {
                let path = &paths[index.index(paths.len())];
                let mut edited = original.clone();
                let mut slot = &mut edited;
                for key in path {
                    slot = match slot {
                        serde_json::Value::Array(items) => {
                            &mut items[key.parse::<usize>().unwrap()]
                        }
                        other => &mut other[key.as_str()],
                    };
                }
                *slot = serde_json::json!(number);
                // Integers that do not fit their field are a parse error; either way no panic.
                let resealed =
                    match serde_json::from_value::<PipelineState>(edited["state"].clone()) {
                        Ok(_) => resealed(&edited),
                        Err(_) => edited,
                    };
                let _ = resume_error(&shot, &scene, &resealed, "fuzzed.json");
                Ok(())
            },
        )
        .unwrap();
}
