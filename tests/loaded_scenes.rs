//! Scenes that read their groom and body from files (`scenes/tressfx-*.toml`, on AMD's TressFX
//! samples: `hairlod::core::samples`): they resolve, load, fit and run through the pipeline with
//! collision and automatic levels; and every way a scene can name a bad file gets an error naming
//! the field and the file. The tests that need the samples are ignored by default (`.ci/run` runs
//! them) and fail naming the file they looked for when it is missing.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use glam::Vec3;

use hairlod::core::dynamics::{Environment, HeadMotion, WindField};
use hairlod::loaded::{LevelRestErrors, LoadedScene, MAX_MEDIAN_ROOT_DISTANCE, rest_errors};
use hairlod::pipeline::LodMode;
use hairlod::{Level, Scene, SceneFile, Shot};

mod common;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The example scenes that read files.
const EXAMPLES: [&str; 2] = ["scenes/tressfx-ratboy.toml", "scenes/tressfx-ponytail.toml"];

/// The folder the example scenes name for the samples, relative to `scenes/`.
const SCENE_DATA: &str = "../../shared/data";

/// The samples' folder, checked to hold every sample file (panics naming the missing one).
fn data_dir() -> String {
    hairlod::core::samples::tressfx_dir().unwrap_or_else(|error| panic!("{error}"));
    hairlod::core::samples::data_dir()
        .to_str()
        .expect("a UTF-8 data folder")
        .to_owned()
}

/// The scene text `text` (of the `scenes/` folder) with its sample paths pointed at the samples'
/// folder ([`data_dir`]: `HAIRLOD_DATA` or the default the scenes name).
fn with_samples(text: &str) -> String {
    text.replace(SCENE_DATA, &data_dir())
}

/// The example scene `example` as shipped, its samples read from [`data_dir`].
fn example_scene(example: &str) -> SceneFile {
    let text = std::fs::read_to_string(repo(example)).unwrap();
    assert!(text.contains(SCENE_DATA), "{example} names no sample");
    SceneFile::parse_in(&with_samples(&text), Some(&repo("scenes")))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Each example scene resolved and built (its groom fitted and its rest pose hung), once for
/// every test of this file, the two side by side: a build takes most of a test's time.
fn built(example: &str) -> &'static (Shot, Scene, LoadedScene) {
    static BUILT: OnceLock<Vec<(Shot, Scene, LoadedScene)>> = OnceLock::new();
    let built = BUILT.get_or_init(|| {
        common::side_by_side(&EXAMPLES, |&example| {
            let shot = example_scene(example).resolve().unwrap();
            let (scene, loaded) = shot
                .build_loaded_scene()
                .unwrap_or_else(|e| panic!("{example}: {e}"));
            let loaded = loaded.expect("a groom file was loaded");
            (shot, scene, loaded)
        })
    });
    let index = EXAMPLES.iter().position(|&e| e == example).unwrap();
    &built[index]
}

/// Each example scene builds (the groom fitted, the body in the head's place) and runs 6 frames of
/// its own motion with collision and automatic levels: every node stays finite, every section
/// has a level every frame, and the mohawk's roots lie on its body.
#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn example_scenes_load_and_run_with_collision_and_automatic_levels() {
    for example in EXAMPLES {
        let (shot, scene, loaded) = built(example);
        let mut shot = shot.clone();
        assert!(shot.groom_file.is_some(), "{example}");
        assert!(shot.settings.collision, "{example}");
        assert!(matches!(shot.settings.lod, LodMode::Auto(_)), "{example}");
        shot.frames = 6;
        let sections = scene.groom.section_count();
        assert_eq!(sections, loaded.report.fit.sections);
        assert_eq!(
            scene.groom.strands.strand_count(),
            loaded.curves.curve_count()
        );
        // Both samples are grooms, not guides: no children grown by default.
        assert_eq!(loaded.report.grown_children, None, "{example}");
        if shot.body_file.is_some() {
            assert!(!scene.head.is_procedural());
            let roots = loaded
                .report
                .roots
                .expect("roots measured against the body");
            assert!(roots.median <= MAX_MEDIAN_ROOT_DISTANCE, "{roots:?}");
            // The body mesh is drawn and collided with: the file's, not the procedural head's.
            assert_eq!(scene.head.mesh.triangles.len(), 25_814);
            assert!(
                loaded.report.occluder_boxes > 0,
                "{example}: no box inside the body"
            );
        }
        let mut pipeline = shot.pipeline(scene, shot.settings, None).unwrap();
        for frame in 0..shot.frames {
            let report = pipeline.advance(&shot.camera(frame)).unwrap();
            assert_eq!(
                report.sections_at.iter().sum::<usize>(),
                sections,
                "{example}"
            );
            for level in Level::ALL {
                let positions = &pipeline.block(level).state.node_positions;
                assert!(
                    positions.iter().all(|p| p.is_finite()),
                    "{example} {level:?}"
                );
            }
        }
        eprintln!("{example}: {sections} sections, {:?}", loaded.report.roots);
    }
}

/// The error of resolving `text` as a scene file in the `scenes/` folder.
fn scene_error(text: &str) -> String {
    SceneFile::parse_in(text, Some(&repo("scenes")))
        .and_then(|file| file.resolve())
        .expect_err(text)
        .to_string()
}

/// The error of building the scene `text` (in the `scenes/` folder), which resolves.
fn build_error(text: &str) -> String {
    let file = SceneFile::parse_in(text, Some(&repo("scenes"))).unwrap_or_else(|e| panic!("{e}"));
    match file.resolve().unwrap().build_scene() {
        Ok(_) => panic!("{text} built"),
        Err(error) => error.to_string(),
    }
}

/// The mohawk's path (in the samples' folder).
fn mohawk() -> String {
    format!("{}/tressfx/ratboy_mohawk.tfx", data_dir())
}

#[test]
fn bad_files_and_keys_without_a_groom_file_are_errors_naming_the_field() {
    // A missing file: the field, the path as given and as resolved.
    let error = scene_error("[groom]\nfile = \"nowhere.tfx\"");
    assert!(
        error.contains("groom.file") && error.contains("nowhere.tfx"),
        "{error}"
    );
    assert!(error.contains("scene file's folder"), "{error}");
    // Keys that need a file.
    let error = scene_error("[groom]\nscale = 0.01");
    assert!(error.contains("groom.scale"), "{error}");
    let error = scene_error("[groom]\nrest_pose = \"loaded\"");
    assert!(error.contains("groom.rest_pose"), "{error}");
    // A body without a groom file: the presets grow on the procedural head.
    let error = scene_error("[body]\nfile = \"example.toml\"");
    assert!(
        error.contains("body.file") && error.contains("groom.file"),
        "{error}"
    );
    // A file the readers do not know: the field, the file and the reader's message.
    let error = build_error("[groom]\nfile = \"example.toml\"");
    assert!(
        error.contains("groom.file") && error.contains("example.toml") && error.contains(".tfx"),
        "{error}"
    );
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn bad_groom_and_body_files_are_errors_naming_the_field_and_the_file() {
    let mohawk = mohawk();
    let error = scene_error(&format!(
        "[groom]\nfile = \"{mohawk}\"\n[body]\nfile = \"nobody.obj\""
    ));
    assert!(
        error.contains("body.file") && error.contains("nobody.obj"),
        "{error}"
    );
    // Bad units and axes.
    let error = scene_error(&format!("[groom]\nfile = \"{mohawk}\"\nscale = -1.0"));
    assert!(error.contains("groom.scale"), "{error}");
    let error = scene_error(&format!("[groom]\nfile = \"{mohawk}\"\nup_axis = \"x\""));
    assert!(error.contains("groom.up_axis"), "{error}");
    // Keys that shape a generated groom.
    let error = scene_error(&format!("[groom]\nfile = \"{mohawk}\"\nhair_length = 0.3"));
    assert!(
        error.contains("groom.hair_length") && error.contains("groom.file"),
        "{error}"
    );
    // A file the readers cannot read as a body: the field, the file and the reader's message.
    let error = build_error(&format!(
        "[groom]\nfile = \"{mohawk}\"\n[body]\nfile = \"{mohawk}\""
    ));
    assert!(
        error.contains("body.file") && error.contains("ratboy_mohawk.tfx"),
        "{error}"
    );
    // Wrong units: centimetres read as metres makes the mohawk 100 times too large.
    let error = build_error(&format!("[groom]\nfile = \"{mohawk}\"\nscale = 100.0"));
    assert!(
        error.contains("groom.scale") && error.contains("ratboy_mohawk.tfx"),
        "{error}"
    );
    // A groom on the wrong body (the mohawk mirrored and turned Z-up): its roots lie far from
    // the surface.
    let error = build_error(&format!(
        "[groom]\nfile = \"{mohawk}\"\nup_axis = \"z\"\n\
         [body]\nfile = \"{}/tressfx/ratboy_body.tfxmesh\"",
        data_dir()
    ));
    assert!(
        error.contains("groom.file") && error.contains("body.file"),
        "{error}"
    );
}

/// After 2 s with the head still and no wind, each level of the loaded grooms (at that level
/// everywhere) has moved at most 5 mm on average from its rest shape: the loaded rest pose is
/// an equilibrium on its body.
#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn loaded_grooms_stay_within_5_mm_after_2_s_at_rest() {
    for example in EXAMPLES {
        let (shot, scene, _) = built(example);
        let mut shot = shot.clone();
        let environment = Environment {
            head: HeadMotion::default(),
            wind: WindField::Calm,
            ..Environment::default()
        };
        // The build hangs the groom under the shot's gravity: the same here.
        assert_eq!(shot.environment.gravity, environment.gravity, "{example}");
        shot.environment = environment;
        let rest = scene
            .groom
            .skeletons
            .rest_positions(&hairlod::RigidTransform::IDENTITY);
        for level in Level::ALL {
            let mut settings = shot.settings;
            settings.lod = LodMode::Fixed(level);
            let mut pipeline = shot.pipeline(scene, settings, None).unwrap();
            pipeline.settle(2.0).unwrap();
            let block = pipeline.block(level);
            let mut moved = Vec::new();
            let mut k = 0;
            for &chain in &block.chains {
                for node in scene.groom.skeletons.nodes(chain) {
                    moved.push(rest[node].distance(block.state.node_positions[k]));
                    k += 1;
                }
            }
            let mean = moved.iter().sum::<f32>() / moved.len() as f32;
            let max = moved.iter().copied().fold(0.0, f32::max);
            eprintln!(
                "{example} {level:?}: mean {:.2} mm, max {:.1} mm after 2 s",
                mean * 1e3,
                max * 1e3
            );
            assert!(mean <= 0.005, "{example} {level:?}: mean {mean} m");
        }
    }
}

/// Builds `shot`'s loaded scene and measures its rest pose against its file, printing the fit
/// report and the errors under `name`; returns the errors and the strand counts (groom, file).
fn rest_errors_of(name: &str, shot: &Shot) -> (LevelRestErrors, usize, usize) {
    let (scene, loaded) = shot.build_loaded_scene().unwrap();
    rest_errors_of_built(name, &scene, &loaded.unwrap())
}

/// [`rest_errors_of`] a scene already built.
fn rest_errors_of_built(
    name: &str,
    scene: &Scene,
    loaded: &LoadedScene,
) -> (LevelRestErrors, usize, usize) {
    let errors = rest_errors(&scene.groom, &loaded.fit, &loaded.curves).unwrap();
    eprintln!("{name}: fit\n{}", loaded.report.fit);
    eprintln!(
        "{name}: rest pose, strands as drawn: {}",
        errors.drawn_strands
    );
    for level in Level::ALL {
        eprintln!("{name}: rest pose, {level:?}: {}", errors.levels[level]);
    }
    (
        errors,
        scene.groom.strands.strand_count(),
        loaded.curves.curve_count(),
    )
}

/// The rest pose of each loaded groom against its file: each curve against the strand drawn for
/// it and against its strand group's, cluster's and patch's models (printed with
/// `-- --nocapture`).
#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn loaded_rest_poses_fit_their_files() {
    for example in EXAMPLES {
        let (_, scene, loaded) = built(example);
        let (errors, strands, curves) = rest_errors_of_built(example, scene, loaded);
        assert_eq!(strands, curves);
        assert!(errors.drawn_strands.is_finite());
        // The real-groom issue's bar for the strands as drawn at rest: mean ≤ 0.5 mm, 95th
        // percentile ≤ 2 mm. Each strand carries its file curve as a residual profile on its
        // rest skeleton, so what is left is sampling: 64 profile entries and 4 tessellation
        // points per skeleton segment, against curves of 16 to 32 points.
        let drawn = errors.drawn_strands;
        assert!(drawn.mean <= 0.5e-3, "{example}: mean {} m", drawn.mean);
        assert!(
            drawn.p95 <= 2e-3,
            "{example}: 95th percentile {} m",
            drawn.p95
        );
        for level in Level::ALL {
            assert!(errors.levels[level].is_finite(), "{example} {level:?}");
        }
    }
}

/// The strand-group model's rest error (each curve against its group's skeleton plus its root
/// offset, without its residual profile) on the mohawk as the example scene fits it (about 50
/// strands per section, 10 per strand group) and fitted as a groom of guides (5 strands per
/// section asked, 1 to 3 per strand group, each with 8 child strands around it). That error is
/// mostly the spread between the strands of a group (the fit's per-node-offset floor is 6.9 mm at
/// 10 strands per group); with a few strands per group the skeleton is one of them or close to
/// them, so the error must fall by far more than half. (The strands as drawn carry their profiles
/// and are within a tenth of a millimetre either way.)
#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn mohawk_as_guides_fits_much_closer_than_fifty_strands_per_section() {
    let text = with_samples(&std::fs::read_to_string(repo("scenes/tressfx-ratboy.toml")).unwrap());
    let guides = text
        .replace("strands_per_section = 50", "strands_per_section = 5")
        .replace("children_per_strand = 0", "children_per_strand = 8");
    // The example scene as shipped (built once for this file), then as guides.
    assert_eq!(EXAMPLES[0], "scenes/tressfx-ratboy.toml");
    let (_, scene, loaded) = built(EXAMPLES[0]);
    let (shipped, strands, curves) = rest_errors_of_built("50 per section", scene, loaded);
    assert_eq!(strands, curves, "50 per section");
    let file = SceneFile::parse_in(&guides, Some(&repo("scenes"))).unwrap();
    let (as_guides, strands, curves) = rest_errors_of("guides", &file.resolve().unwrap());
    assert_eq!(strands, 9 * curves, "guides");
    let means = [shipped, as_guides].map(|errors| errors.levels[Level::StrandGroup].mean);
    assert!(means[1] < 0.5 * means[0], "{means:?}");
}

/// The mohawk thinned to every 25th strand (89 guides, as a DCC export of guides would hold) on
/// its body, in a scene with no `[camera]`: children are grown by default, and the camera frames
/// the whole body (every corner of the body's and groom's bounds in the first frame), where the
/// procedural head's default camera (0.8 m from the origin) sees the body's middle only.
#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_as_guides_grows_children_and_its_body_is_framed() {
    let dir = data_dir();
    let mohawk = hairlod::formats::read_curves_file(
        format!("{dir}/tressfx/ratboy_mohawk.tfx"),
        &hairlod::formats::ImportOptions::default(),
    )
    .unwrap();
    let mut guides = hairlod::core::Curves {
        offsets: vec![0],
        ..Default::default()
    };
    for curve in (0..mohawk.curve_count()).step_by(25) {
        let range = mohawk.offsets[curve] as usize..mohawk.offsets[curve + 1] as usize;
        guides.points.extend_from_slice(&mohawk.points[range]);
        guides.offsets.push(guides.points.len() as u32);
    }
    let out = std::env::temp_dir().join(format!("hairlod-guides-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let file = out.join("mohawk-guides.hair");
    hairlod::formats::write_hair(&file, &guides).unwrap();
    let text = format!(
        "[groom]\nfile = \"{}\"\npreset = \"curly\"\nstrands_per_section = 5\n\
         [body]\nfile = \"{dir}/tressfx/ratboy_body.tfxmesh\"\n[frames]\nsize = \"640x360\"\n",
        file.display()
    );
    let mut shot = SceneFile::parse(&text).unwrap().resolve().unwrap();
    let unframed = shot.camera(0);
    let (scene, loaded, framing) = shot.build_framed_scene().unwrap();
    let loaded = loaded.unwrap();
    let grown = loaded.report.grown_children.expect("guides are sparse");
    assert!(grown.per_strand >= 1, "{grown:?}");
    let loaded = loaded.curves.curve_count();
    assert!(loaded <= guides.curve_count());
    assert_eq!(
        scene.groom.strands.strand_count(),
        loaded * (grown.per_strand + 1)
    );
    let framing = framing.expect("no [camera]: framed");
    let camera = shot.camera(0);
    let aspect = 640.0 / 360.0;
    let corners: Vec<Vec3> = (0..8)
        .map(|c| {
            let pick = |bit: usize, lo: f32, hi: f32| if c & bit == 0 { lo } else { hi };
            Vec3::new(
                pick(1, framing.min.x, framing.max.x),
                pick(2, framing.min.y, framing.max.y),
                pick(4, framing.min.z, framing.max.z),
            )
        })
        .collect();
    assert!(
        corners
            .iter()
            .all(|&p| camera.sphere_in_frustum(p, 0.0, aspect))
    );
    // The default camera did not see the whole body.
    assert!(
        !corners
            .iter()
            .all(|&p| unframed.sphere_in_frustum(p, 0.0, aspect))
    );
    eprintln!("{grown:?}; {framing:?}");
    std::fs::remove_dir_all(&out).unwrap();
}
