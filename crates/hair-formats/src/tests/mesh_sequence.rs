//! Meshes over time: the USD fixture `tests/data/mesh_sequence.usda` / `.usdc` (written by Pixar's
//! `usd-core` through `tests/make_usd_mesh_sequence_fixture.py`) read in both encodings and
//! compared point for point with what `usd-core` itself evaluated (`mesh_sequence.json`); the
//! Alembic fixture `tests/data/mesh_sequence.abc` (written by PyAlembic through
//! `tests/make_alembic_mesh_fixture.py`) against the values its docstring derives; the choice of
//! reader by extension; and what the readers refuse, with the file, prim and time code named.

use glam::{DMat4, DVec3, Vec3};
use hair_core::MeshSequence;

use crate::{
    ImportOptions, read_alembic_mesh_sequence_file, read_mesh_sequence_file, read_usd_mesh_file,
    read_usd_mesh_sequence, read_usd_mesh_sequence_file,
};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");

fn data(name: &str) -> String {
    format!("{DATA}/{name}")
}

/// Asserts `actual` is `expected` within 1e-5 of the sample's largest coordinate.
fn assert_points(actual: &[Vec3], expected: &[Vec3], what: &str) {
    assert_eq!(actual.len(), expected.len(), "{what}");
    let scale = expected
        .iter()
        .map(|p| p.abs().max_element())
        .fold(1e-3f32, f32::max);
    for (i, (a, e)) in actual.iter().zip(expected).enumerate() {
        assert!(
            (*a - *e).abs().max_element() <= 1e-5 * scale,
            "{what}, point {i}: read {a}, expected {e}"
        );
    }
}

/// The fixture's points as `usd-core` evaluated them (centimetres, Z up), in metres, +Y up:
/// (x, y, z) cm → (x, z, −y) / 100 m.
fn usd_core_samples() -> (Vec<f64>, Vec<Vec<Vec3>>) {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data("mesh_sequence.json")).unwrap())
            .unwrap();
    assert_eq!(json["time_codes_per_second"], 24.0);
    assert_eq!(json["meters_per_unit"], 0.01);
    assert_eq!(json["up_axis"], "Z");
    let mut codes = Vec::new();
    let mut samples = Vec::new();
    for sample in json["samples"].as_array().unwrap() {
        codes.push(sample["time_code"].as_f64().unwrap());
        let points = sample["points"].as_array().unwrap().iter().map(|p| {
            let c = |i: usize| p[i].as_f64().unwrap() * 0.01;
            Vec3::new(c(0) as f32, c(2) as f32, -c(1) as f32)
        });
        samples.push(points.collect());
    }
    (codes, samples)
}

fn check_usd_fixture(sequence: &MeshSequence, name: &str) {
    let (codes, samples) = usd_core_samples();
    // The union of the samples of /body's translate (10, 16) and rotateXYZ (10, 13, 16) and of
    // /body/skin's points (10, 12, 14).
    assert_eq!(codes, [10.0, 12.0, 13.0, 14.0, 16.0]);
    let seconds: Vec<f64> = codes.iter().map(|c| c / 24.0).collect();
    assert_eq!(sequence.times(), seconds.as_slice(), "{name}");
    // /body/skin: 5 points, a quad and a triangle; /ground: 3 points, a triangle.
    assert_eq!(sequence.vertex_count(), 8, "{name}");
    assert_eq!(sequence.triangles().len(), 4, "{name}");
    for (s, expected) in samples.iter().enumerate() {
        let what = format!("{name}, time code {}", codes[s]);
        assert_points(sequence.sample_positions(s), expected, &what);
    }
    // /ground, (0, 0, 0), (100, 0, 0), (0, 100, 0) cm counter-clockwise about +Z: its normal is
    // +Z, which is +Y after the Z-up conversion.
    let mesh = sequence.mesh_at(0.5);
    assert!(
        (mesh.normals[7] - Vec3::Y).length() < 1e-6,
        "{}",
        mesh.normals[7]
    );
    assert!(sequence.is_animated());
}

#[test]
fn the_usd_fixture_reads_as_usd_core_evaluates_it_in_both_encodings() {
    for name in ["mesh_sequence.usda", "mesh_sequence.usdc"] {
        let sequence = read_usd_mesh_sequence_file(data(name), &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        check_usd_fixture(&sequence, name);
        let by_extension = read_mesh_sequence_file(data(name), &ImportOptions::default()).unwrap();
        assert_eq!(by_extension, sequence);
    }
}

/// The still reader applies the same transforms at the default time: every attribute of the
/// fixture is time-sampled, so the default time is each one's earliest sample, time code 10, where
/// `usd-core` put the points of the JSON's first sample.
#[test]
fn the_still_reader_places_the_fixture_through_its_transforms_at_the_default_time() {
    let (_, samples) = usd_core_samples();
    for name in ["mesh_sequence.usda", "mesh_sequence.usdc"] {
        let mesh = read_usd_mesh_file(data(name), &ImportOptions::default()).unwrap();
        assert_points(&mesh.positions, &samples[0], name);
        assert_eq!(mesh.triangles.len(), 4);
    }
}

/// A mirroring transform turns the surface inside out as USD draws it: the triangle (0, 0, 0),
/// (1, 0, 0), (0, 1, 0) faces +Z, and under `scale (1, 1, −1)` faces −Z (its points do not move;
/// the windings are reversed), in both readers.
#[test]
fn a_mirroring_transform_reverses_the_windings() {
    let text = "#usda 1.0\n(\n    metersPerUnit = 1\n)\n\ndef Mesh \"m\"\n{\n    \
                int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, 2]\n    \
                point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n    \
                float3 xformOp:scale = (1, 1, -1)\n    \
                uniform token[] xformOpOrder = [\"xformOp:scale\"]\n}\n";
    let mesh = crate::read_usd_mesh(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(mesh.positions, [Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(mesh.normals, [Vec3::NEG_Z; 3]);
    let sequence = read_usd_mesh_sequence(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(sequence.mesh_at(0.0).normals, [Vec3::NEG_Z; 3]);
}

/// The Alembic fixture's quad at sample `i` (the generator's `quad(i)`), through `/body`:
/// T(10 i, 0, 0) · Rz(90 i°).
fn alembic_quad(i: usize) -> Vec<Vec3> {
    let y = 0.5 * i as f64;
    let world = DMat4::from_translation(DVec3::new(10.0 * i as f64, 0.0, 0.0))
        * DMat4::from_rotation_z((90.0 * i as f64).to_radians());
    [
        (0.0, y),
        (1.0, y),
        (1.0 + i as f64, 1.0 + y),
        (0.0, 1.0 + y),
    ]
    .iter()
    .map(|&(x, y)| world.transform_point3(DVec3::new(x, y, 0.0)).as_vec3())
    .collect()
}

#[test]
fn the_alembic_fixture_reads_every_sample_through_its_transform() {
    let path = data("mesh_sequence.abc");
    let sequence = read_alembic_mesh_sequence_file(&path, &ImportOptions::default()).unwrap();
    // Uniform sampling from 0.5 s, 1/24 s apart.
    let times = [0.5, 0.5 + 1.0 / 24.0, 0.5 + 2.0 / 24.0];
    assert_eq!(sequence.times().len(), 3);
    for (t, e) in sequence.times().iter().zip(times) {
        assert!((t - e).abs() < 1e-12, "{t} vs {e}");
    }
    // The quad (4 points, 2 triangles), then /still's triangle.
    assert_eq!(sequence.vertex_count(), 7);
    assert_eq!(sequence.triangles().len(), 3);
    let still = [
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::new(0.0, 1.0, 5.0),
        Vec3::new(1.0, 0.0, 5.0),
    ];
    for i in 0..3 {
        let mut expected = alembic_quad(i);
        expected.extend(still);
        assert_points(
            sequence.sample_positions(i),
            &expected,
            &format!("sample {i}"),
        );
    }
    // The docstring's two worked values.
    assert_points(
        &sequence.sample_positions(1)[2..3],
        &[Vec3::new(8.5, 2.0, 0.0)],
        "sample 1, point 2",
    );
    assert_points(
        &sequence.sample_positions(2)[2..3],
        &[Vec3::new(17.0, -2.0, 0.0)],
        "sample 2, point 2",
    );
    // Both faces are clockwise seen from +Z in the file (Alembic's front): their normals are +Z.
    for time in times {
        let mesh = sequence.mesh_at(time);
        for normal in &mesh.normals {
            assert!((*normal - Vec3::Z).length() < 1e-5, "{time} s: {normal}");
        }
    }
    let by_extension = read_mesh_sequence_file(&path, &ImportOptions::default()).unwrap();
    assert_eq!(by_extension, sequence);
}

#[test]
fn formats_without_animation_are_one_sample_at_time_zero() {
    let dir = super::scratch_dir("mesh-sequence");
    let obj = dir.join("tri.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let sequence = read_mesh_sequence_file(&obj, &ImportOptions::default()).unwrap();
    assert_eq!(sequence.times(), [0.0]);
    assert_eq!(sequence.sample_positions(0), [Vec3::ZERO, Vec3::X, Vec3::Y]);
    let error = read_mesh_sequence_file(dir.join("body.ply"), &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(error.contains("unknown file extension `ply`"), "{error}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A text layer with one mesh `/body/m` under an Xform, its body lines given.
fn layer(mesh: &str, xform: &str) -> String {
    format!(
        "#usda 1.0\n(\n    timeCodesPerSecond = 12\n)\n\ndef Xform \"body\"\n{{\n{xform}\n    \
         def Mesh \"m\"\n    {{\n{mesh}\n    }}\n}}\n"
    )
}

const TRIANGLE: &str = "int[] faceVertexCounts = [3]\nint[] faceVertexIndices = [0, 1, 2]";

/// The error of reading `text` from a file (each call its own directory: tests run in parallel).
fn error_of(text: &str) -> String {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = super::scratch_dir(&format!("mesh-sequence-errors-{call}"));
    let path = dir.join("broken.usda");
    std::fs::write(&path, text).unwrap();
    let error = read_usd_mesh_sequence_file(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    std::fs::remove_dir_all(dir).unwrap();
    // The file is named first.
    assert!(error.contains("broken.usda: "), "{error}");
    error
}

#[test]
fn text_layers_resolve_defaults_rates_and_held_samples() {
    // A translate at time codes 6 and 18 (12 per second): 0.5 s and 1.5 s; points held.
    let text = layer(
        &format!("{TRIANGLE}\npoint3f[] points = [(0, 0, 0), (100, 0, 0), (0, 100, 0)]"),
        "double3 xformOp:translate.timeSamples = { 6: (0, 0, 0), 18: (200, 0, 0) }\n\
         uniform token[] xformOpOrder = [\"xformOp:translate\"]",
    );
    let sequence = read_usd_mesh_sequence(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(sequence.times(), [0.5, 1.5]);
    // Centimetres (USD's fallback metersPerUnit): 200 cm is 2 m.
    assert_eq!(sequence.sample_positions(1)[0], Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(sequence.point_at(0, 1.0), Vec3::new(1.0, 0.0, 0.0));
    // No samples at all: one sample at time 0.
    let still = layer(
        &format!("{TRIANGLE}\npoint3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]"),
        "",
    );
    let sequence = read_usd_mesh_sequence(still.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(sequence.times(), [0.0]);
}

/// With `framesPerSecond` and no `timeCodesPerSecond`, USD's rate is `framesPerSecond` (the
/// generator prints `usd-core`'s `GetTimeCodesPerSecond()`: 12): time codes 6 and 18 are 0.5 s
/// and 1.5 s, in a crate file written by `usd-core` and in text.
#[test]
fn the_rate_falls_back_to_frames_per_second() {
    let path = data("mesh_frames_per_second.usdc");
    let sequence = read_usd_mesh_sequence_file(&path, &ImportOptions::default()).unwrap();
    assert_eq!(sequence.times(), [0.5, 1.5]);
    // (2, 0, 0) cm at time code 18.
    assert_eq!(sequence.sample_positions(1)[1], Vec3::new(0.02, 0.0, 0.0));
    let text = format!(
        "#usda 1.0\n(\n    framesPerSecond = 12\n)\n\ndef Mesh \"tri\"\n{{\n{TRIANGLE}\n\
         point3f[] points.timeSamples = {{ 6: [(0, 0, 0), (1, 0, 0), (0, 1, 0)], 18: [(0, 0, \
         0), (2, 0, 0), (0, 1, 0)] }}\n}}\n"
    );
    let sequence = read_usd_mesh_sequence(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(sequence.times(), [0.5, 1.5]);
}

#[test]
fn a_topology_that_changes_is_refused_with_the_prim_and_time_code() {
    let text = layer(
        "int[] faceVertexCounts.timeSamples = { 1: [3], 2: [4] }\n\
         int[] faceVertexIndices.timeSamples = { 1: [0, 1, 2], 2: [0, 1, 2, 3] }\n\
         point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]",
        "",
    );
    let error = error_of(&text);
    assert!(error.contains("USD /body/m: "), "{error}");
    assert!(
        error.contains("the topology changes between samples"),
        "{error}"
    );
    assert!(error.contains("at time code 2 differ"), "{error}");
}

/// The same refusal from a binary crate file written by `usd-core` (no line to name there).
#[test]
fn a_crate_file_whose_topology_changes_is_refused_with_the_prim_and_time_code() {
    let path = data("mesh_topology_change.usdc");
    let error = read_usd_mesh_sequence_file(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        error
            .contains("mesh_topology_change.usdc: USD /blob: the topology changes between samples"),
        "{error}"
    );
    assert!(
        error.contains("at time code 2 differ from those at time code 1"),
        "{error}"
    );
}

#[test]
fn a_points_count_that_changes_is_refused_with_the_prim_and_time_code() {
    let text = layer(
        &format!(
            "{TRIANGLE}\npoint3f[] points.timeSamples = {{ 0: [(0, 0, 0), (1, 0, 0), (0, 1, 0)], \
             3: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)] }}"
        ),
        "",
    );
    let error = error_of(&text);
    assert!(
        error.contains("USD /body/m: has 4 points at time code 3, but 3 at time code 0"),
        "{error}"
    );
}

#[test]
fn an_unsupported_xform_op_is_refused_by_name() {
    let text = layer(
        &format!("{TRIANGLE}\npoint3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]"),
        "double3 xformOp:shear = (1, 0, 0)\n\
         uniform token[] xformOpOrder = [\"xformOp:shear\"]",
    );
    let error = error_of(&text);
    assert!(error.contains("USD /body.xformOpOrder: "), "{error}");
    assert!(
        error.contains("the op type \"shear\" is not supported"),
        "{error}"
    );
    // An op named in the order but not authored.
    let text = layer(
        &format!("{TRIANGLE}\npoint3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]"),
        "uniform token[] xformOpOrder = [\"xformOp:translate\"]",
    );
    let error = error_of(&text);
    assert!(
        error.contains("names \"xformOp:translate\", but the prim has no attribute"),
        "{error}"
    );
}

#[test]
fn a_time_code_that_is_not_finite_is_refused() {
    let text = layer(
        &format!(
            "{TRIANGLE}\npoint3f[] points.timeSamples = {{ 1e999: [(0, 0, 0), (1, 0, 0), (0, 1, \
             0)] }}"
        ),
        "",
    );
    let error = error_of(&text);
    assert!(error.contains("time code `1e999` is not finite"), "{error}");
}

#[test]
fn an_alembic_topology_that_changes_is_refused_with_the_object_and_time() {
    let path = data("mesh_topology_change.abc");
    let error = read_alembic_mesh_sequence_file(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("mesh_topology_change.abc: Alembic /blob: "),
        "{error}"
    );
    // The second sample, at 1/24 s.
    assert!(
        error.contains("the topology changes between samples: at 0.041666"),
        "{error}"
    );
}

/// A time window keeps the samples within it and the first after it, with the same positions
/// as the whole file's (USD: codes 10, 12, 13, 14, 16 at 24 per second; a window of 2.5 codes
/// ends at code 12.5, so codes 10, 12 and 13 are read. Alembic: 0.5 s and 1/24 s apart; a
/// window of 0 s keeps the first sample and the one after). A cap under the sequence's size
/// refuses it with the file, its samples, points and size; a cap at its size reads it.
#[test]
fn a_time_window_trims_a_sequence_and_a_memory_cap_refuses_one_too_large() {
    use crate::SequenceLimits;
    let window = |seconds: f64| ImportOptions {
        sequence: SequenceLimits {
            seconds: Some(seconds),
            max_bytes: None,
        },
        ..ImportOptions::default()
    };
    for name in ["mesh_sequence.usda", "mesh_sequence.usdc"] {
        let whole = read_usd_mesh_sequence_file(data(name), &ImportOptions::default()).unwrap();
        let trimmed = read_usd_mesh_sequence_file(data(name), &window(2.5 / 24.0)).unwrap();
        assert_eq!(trimmed.times(), &whole.times()[..3], "{name}");
        for s in 0..3 {
            assert_eq!(trimmed.sample_positions(s), whole.sample_positions(s));
        }
        // 5 samples of 8 points, 12 bytes each: 480 bytes.
        let capped = |max_bytes: u64| ImportOptions {
            sequence: SequenceLimits {
                seconds: None,
                max_bytes: Some(max_bytes),
            },
            ..ImportOptions::default()
        };
        assert!(read_usd_mesh_sequence_file(data(name), &capped(480)).is_ok());
        let error = read_usd_mesh_sequence_file(data(name), &capped(479))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(name) && error.contains("5 samples of 8 points"),
            "{error}"
        );
    }
    let path = data("mesh_sequence.abc");
    let whole = read_alembic_mesh_sequence_file(&path, &ImportOptions::default()).unwrap();
    let trimmed = read_alembic_mesh_sequence_file(&path, &window(0.0)).unwrap();
    assert_eq!(trimmed.times(), &whole.times()[..2]);
    assert_eq!(trimmed.sample_positions(1), whole.sample_positions(1));
    let bad = read_alembic_mesh_sequence_file(&path, &window(-1.0))
        .unwrap_err()
        .to_string();
    assert!(bad.contains("sequence.seconds"), "{bad}");
}
