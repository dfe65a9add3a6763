//! Tests of resolving a scene file into a shot: defaults, ranges and the errors that name a field.

use glam::Vec3;
use hair_collide::BroadPhase;

use super::*;

fn error_of(text: &str) -> String {
    SceneFile::parse(text).unwrap_err().to_string()
}

#[test]
fn an_empty_file_is_the_defaults() {
    let shot = SceneFile::parse("").unwrap().resolve().unwrap();
    assert_eq!(shot.frames, 12);
    assert_eq!((shot.width, shot.height), (1280, 720));
    assert_eq!(shot.groom, GroomParams::preset("paper-curly").unwrap());
    assert!(matches!(shot.settings.lod, LodMode::Auto(_)));
    assert!(shot.settings.collision);
    assert_eq!(shot.settings.broad_phase, BroadPhase::FieldContacts);
    // 60 Hz: the integrator's own recommendation.
    assert_eq!(
        shot.settings.dynamics,
        SimulationSettings::recommended(IntegratorKind::DEFAULT)
    );
    assert!(shot.outputs.shaded && !shot.outputs.color_coded);
}

#[test]
fn substeps_adapt_up_to_max_substeps_scaled_to_the_frame_rate() {
    let dynamics = |text: &str| {
        SceneFile::parse(text)
            .unwrap()
            .resolve()
            .unwrap()
            .settings
            .dynamics
    };
    // XPBD by default: 8 substeps per 1/60 s, doubled up to 32 where the hair moves fast.
    let default = dynamics("");
    assert_eq!((default.substeps, default.max_substeps()), (8, 32));
    // At 120 Hz the substep stays as long: 4 per frame, up to 16.
    let fast = dynamics("[frames]\nfps = 120");
    assert_eq!((fast.substeps, fast.max_substeps()), (4, 16));
    // A limit not above the substeps is a fixed count.
    let fixed = dynamics("[dynamics]\nsubsteps = 16\nmax_substeps = 16");
    assert_eq!((fixed.substeps, fixed.adaptive), (16, None));
    let raised = dynamics("[dynamics]\nsubsteps = 16");
    assert_eq!((raised.substeps, raised.max_substeps()), (16, 32));
    // The other integrators take a fixed count unless a limit is given.
    let implicit = dynamics("[dynamics]\nintegrator = \"linear-implicit\"");
    assert_eq!((implicit.substeps, implicit.adaptive), (4, None));
    let adaptive = dynamics("[dynamics]\nintegrator = \"linear-implicit\"\nmax_substeps = 16");
    assert_eq!(adaptive.max_substeps(), 16);
}

#[test]
fn strand_thinning_is_off_unless_asked_for_and_only_in_automatic_mode() {
    let shot = |text: &str| SceneFile::parse(text).unwrap().resolve().unwrap();
    assert_eq!(
        shot("").settings.strand_thinning(),
        hair_render::StrandThinning::Off
    );
    assert_eq!(
        shot("[lod]\nstrands_per_pixel = 4.0")
            .settings
            .strand_thinning(),
        hair_render::StrandThinning::ByScreenWidth {
            strands_per_pixel: 4.0,
            raise_widths: false,
        }
    );
    // A fixed level is a reference: every strand is drawn.
    assert_eq!(
        shot("[lod]\nmode = \"strands\"\nstrands_per_pixel = 4.0")
            .settings
            .strand_thinning(),
        hair_render::StrandThinning::Off
    );
}

#[test]
fn bad_values_name_the_field_and_the_range() {
    for (text, field, range) in [
        ("[wind]\nspeed = -1.0", "wind.speed", "0..=100"),
        (
            "[camera]\nfov_degrees = 200.0",
            "camera.fov_degrees",
            "1..=170",
        ),
        (
            "[camera]\ndistance = nan",
            "camera.distance",
            "0.001..=10000 m",
        ),
        ("[frames]\ncount = 0", "frames.count", "1..=1000000"),
        ("[frames]\nsize = \"big\"", "frames.size", "WIDTHxHEIGHT"),
        ("[groom]\npreset = \"afro\"", "groom.preset", "paper-curly"),
        ("[groom]\nhair_length = -0.2", "groom.hair_length", "> 0"),
        (
            "[groom]\nrest_pose = \"floating\"",
            "groom.rest_pose",
            "hanging",
        ),
        ("[lod]\nmode = \"voxels\"", "lod.mode", "auto"),
        ("[lod]\nbudget_ms = 0.0", "lod.budget_ms", "> 0"),
        (
            "[lod]\nstrands_per_pixel = -1.0",
            "lod.strands_per_pixel",
            "0..=1000",
        ),
        (
            "[lod]\nocclusion_test = \"raycast\"",
            "lod.occlusion_test",
            "ends",
        ),
        (
            "[dynamics]\nintegrator = \"rk4\"",
            "dynamics.integrator",
            "position-based",
        ),
        ("[dynamics]\nsubsteps = 0", "dynamics.substeps", "1..=10000"),
        (
            "[dynamics]\nmax_substeps = 0",
            "dynamics.max_substeps",
            "1..=10000",
        ),
        ("[motion]\nkind = \"dance\"", "motion.kind", "shake"),
        (
            "[motion]\nkind = \"keyframes\"",
            "motion.keyframes",
            "at least one",
        ),
        ("version = 1", "version", "2"),
        ("[groom]\nfile = \"x.tfx\"", "groom.file", "no such file"),
        (
            "[groom]\nfile = \".\"",
            "groom.file",
            "is a folder, not a file",
        ),
        (
            "[groom]\nfile = \"x.tfx\"\nscale = 0.0",
            "groom.file",
            "no such file",
        ),
        ("[groom]\nscale = 0.01", "groom.scale", "groom.file"),
        ("[body]\nkind = \"mesh\"", "body.kind", "body.file"),
        ("[body]\nkind = \"sphere\"", "body.kind", "mesh"),
        (
            "[output]\nshading = \"phong\"",
            "output.shading",
            "marschner",
        ),
        (
            "[output]\nline_coverage = \"area\"",
            "output.line_coverage",
            "width",
        ),
        (
            "[output]\nclusters = \"cylinders\"",
            "output.clusters",
            "tube",
        ),
    ] {
        let error = error_of(text);
        assert!(
            error.contains(field) && error.contains(range),
            "{text:?}: {error}"
        );
    }
}

#[test]
fn every_fixed_choice_field_takes_its_enum_names_and_lists_them_when_wrong() {
    use crate::scene_file::{BodyKind, CameraPathKind, LodModeKind, MotionKind};
    use hair_core::lod::{BudgetMethod, ErrorModel, OcclusionTest};
    use hair_render::{ClusterGeometry, LineCoverage, ShadingModel};
    // (table, key, the enum's names): each field deserializes straight into its enum.
    let fields: [(&str, &str, &[&str]); 17] = [
        ("groom", "preset", &hair_core::GroomPreset::NAMES),
        ("groom", "up_axis", &hair_formats::UpAxis::NAMES),
        ("groom", "rest_pose", &RestPose::NAMES),
        ("body", "kind", &BodyKind::NAMES),
        ("body", "up_axis", &hair_formats::UpAxis::NAMES),
        ("motion", "kind", &MotionKind::NAMES),
        ("camera", "path", &CameraPathKind::NAMES),
        ("lod", "mode", &LodModeKind::NAMES),
        ("lod", "error_model", &ErrorModel::NAMES),
        ("lod", "budget_method", &BudgetMethod::NAMES),
        ("lod", "occlusion_test", &OcclusionTest::NAMES),
        ("lod", "drawn_as", &crate::pipeline::DrawnAs::NAMES),
        ("dynamics", "integrator", &IntegratorKind::NAMES),
        ("dynamics", "collision_broad_phase", &BroadPhase::NAMES),
        ("output", "shading", &ShadingModel::NAMES),
        ("output", "line_coverage", &LineCoverage::NAMES),
        ("output", "clusters", &ClusterGeometry::NAMES),
    ];
    for (table, key, names) in fields {
        for name in names {
            let file: SceneFile = toml::from_str(&format!("[{table}]\n{key} = \"{name}\""))
                .unwrap_or_else(|error| panic!("{table}.{key} = {name:?}: {error}"));
            assert_ne!(
                file,
                SceneFile::default(),
                "{table}.{key} = {name:?} was dropped"
            );
        }
        // The whole message: the field path, the value, every allowed name, the line.
        let error = error_of(&format!("[{table}]\n{key} = \"bogus\""));
        assert_eq!(
            error,
            format!(
                "{table}.{key} = \"bogus\": expected one of {} (line 2)",
                names.join(", ")
            )
        );
    }
    // Within a crowd's character, the path says which one.
    let error =
        error_of("[[character]]\nposition = [0.0, 0.0, 0.0]\n[character.groom]\npreset = \"afro\"");
    assert!(
        error.starts_with("character[0].groom.preset = \"afro\""),
        "{error}"
    );
    // Not a string at all, and a key that is none of the table's, also name the field.
    let error = error_of("[lod]\nmode = 3");
    assert!(error.starts_with("lod.mode: "), "{error}");
    let error = error_of("[lod]\nmodes = \"auto\"");
    assert!(
        error.starts_with("lod.modes: unknown field `modes`"),
        "{error}"
    );
}

#[test]
fn the_output_table_sets_the_draw_style() {
    use hair_render::{ClusterGeometry, HairShading, LineCoverage};
    let plain = SceneFile::parse("").unwrap().resolve().unwrap();
    assert_eq!(plain.outputs.style(), crate::pipeline::DrawStyle::default());
    let text = "[output]\nshading = \"marschner\"\nline_coverage = \"width\"";
    let style = SceneFile::parse(text)
        .unwrap()
        .resolve()
        .unwrap()
        .outputs
        .style();
    assert!(matches!(style.hair_shading, HairShading::Marschner(_)));
    assert_eq!(style.line_coverage, LineCoverage::Width);
    assert_eq!(style.cluster_geometry, ClusterGeometry::Impostor);
    let tubes = SceneFile::parse("[output]\nclusters = \"tube\"")
        .unwrap()
        .resolve()
        .unwrap()
        .outputs
        .style();
    assert_eq!(tubes.cluster_geometry, ClusterGeometry::Tube);
}

#[test]
fn a_hanging_groom_needs_no_settling_and_a_grown_one_settles_a_second() {
    // The default: hanging, settled 0 s (it starts at rest); grown: 1 s unless told.
    let shot = SceneFile::parse("").unwrap().resolve().unwrap();
    assert_eq!(
        (shot.rest_pose, shot.settle_seconds),
        (RestPose::Hanging, 0.0)
    );
    let grown = "[groom]\nrest_pose = \"grown\"";
    let shot = SceneFile::parse(grown).unwrap().resolve().unwrap();
    assert_eq!(
        (shot.rest_pose, shot.settle_seconds),
        (RestPose::Grown, 1.0)
    );
    let told = format!("{grown}\n[dynamics]\nsettle_seconds = 0.25");
    let shot = SceneFile::parse(&told).unwrap().resolve().unwrap();
    assert_eq!(shot.settle_seconds, 0.25);
}

/// `usd_strands` names which strands `hair.usda` holds and writes the file; an unknown one is
/// an error naming the key.
#[test]
fn usd_strands_write_the_file_and_unknown_ones_are_errors() {
    let shot = SceneFile::parse("[output]\nusd_strands = \"guides\"")
        .unwrap()
        .resolve()
        .unwrap();
    assert!(shot.outputs.usd);
    assert_eq!(
        shot.outputs.usd_strands,
        crate::usd_export::UsdStrands::Guides
    );
    let plain = SceneFile::parse("[output]\nusd = true")
        .unwrap()
        .resolve()
        .unwrap();
    assert_eq!(
        plain.outputs.usd_strands,
        crate::usd_export::UsdStrands::All
    );
    assert!(error_of("[output]\nusd_strands = \"some\"").contains("usd_strands"));
}

#[test]
fn unknown_keys_and_wrong_types_are_errors() {
    assert!(error_of("[frames]\ncont = 3").contains("cont"));
    assert!(error_of("colour = 1").contains("colour"));
    assert!(error_of("[frames]\ncount = \"many\"").contains("count"));
}

#[test]
fn keyframed_head_and_camera_resolve() {
    let text = "[motion]\nkind = \"keyframes\"\nkeyframes = [\
        { time = 0.0 }, { time = 1.0, rotation_degrees = [0.0, 90.0, 0.0] }]\n\
        [camera]\npath = \"keyframes\"\nkeyframes = [\
        { time = 0.0, position = [0.0, 0.0, 1.0] }, { time = 2.0, position = [0.0, 0.0, 3.0] }]\n\
        [frames]\nfps = 1\ncount = 3\n";
    let shot = SceneFile::parse(text).unwrap().resolve().unwrap();
    // Frame k shows the state at (k + 1)/fps: frame 0 at t = 1 s, half-way in time between
    // the camera's keys, so half-way between them: z = 2 m. Frame 1 at t = 2 s is the last
    // key, z = 3 m.
    assert!((shot.camera(0).position.z - 2.0).abs() < 1e-6);
    assert!((shot.camera(1).position.z - 3.0).abs() < 1e-6);
    // At t = 1 s the head has turned 90° about Y: +Z goes to +X.
    let turned = shot
        .environment
        .head
        .transform_at(1.0)
        .transform_vector(Vec3::Z);
    assert!((turned - Vec3::X).length() < 1e-5, "{turned}");
}

#[test]
fn the_shipped_scenes_parse_and_the_example_sets_every_table() {
    let example = SceneFile::parse(include_str!("../../../scenes/example.toml")).unwrap();
    let shot = example.resolve().unwrap();
    assert_eq!(shot.groom.section_count, 60);
    assert_eq!((shot.frames, shot.width, shot.height), (24, 960, 540));
    assert!(shot.outputs.shaded && shot.outputs.color_coded && shot.outputs.contact_sheet);
    assert!(matches!(shot.environment.wind, WindField::Gusting { .. }));
    assert_eq!(example.json_output(), Some("report.json"));
    for (text, table) in [
        (include_str!("../../../scenes/paper-table1.toml"), 1),
        (include_str!("../../../scenes/paper-table2.toml"), 2),
    ] {
        let shot = SceneFile::parse(text).unwrap().resolve().unwrap();
        assert_eq!(shot.paper_table, Some(table));
        assert_eq!(shot.frames, 60);
        // The paper's camera: 0.45 m to 12 m, 0.5 rad azimuth, 0.15 rad elevation.
        assert!((shot.camera.azimuth - 0.5).abs() < 1e-6);
        assert!((shot.camera.elevation - 0.15).abs() < 1e-6);
        let first = shot.camera(0);
        let last = shot.camera(59);
        assert!((first.position.distance(first.target) - 0.45).abs() < 1e-5);
        assert!((last.position.distance(last.target) - 12.0).abs() < 1e-4);
    }
}
