//! USD text `BasisCurves`: what [`UsdCurvesWriter`] writes reads back bit for bit (one frame, and
//! every frame of an animation at its time code); the layer's `upAxis` and `metersPerUnit` come
//! before the reader's axes; hand-written files with the syntax Pixar's tools write (nested prims,
//! other prim types, metadata, relationships, variant sets, indexed primvars) read; every broken
//! file names its line; the writer refuses bad curves before writing. The two `#[ignore]`d tests
//! are steps of `tests/usd_check.py`, the check against Pixar's USD, which `.ci/run` runs (they
//! need the files the script writes with Pixar's library between them).

use std::path::PathBuf;

use glam::Vec3;

use super::real_data::data_file;
use super::round_trips::bits;
use super::scratch_dir;
use crate::cyhair::tests::sample_curves;
use crate::{
    Curves, ImportAxes, ImportOptions, UsdCurvesWriter, read_curves_file, read_mesh_file,
    read_tfx_file, read_usda, read_usda_at, read_usda_file, read_usda_file_at, write_usda_curves,
    write_usda_curves_string,
};

/// Sample curves with values that are hard to write as text: -0, tiny, huge, many digits.
fn hard_curves() -> Curves {
    let mut curves = sample_curves();
    curves.points[1].x = -0.0;
    curves.points[2] = Vec3::new(1e-30, -3.4e38, 7.123_456_7);
    curves.points[3].z = f32::from_bits(1); // the smallest subnormal
    curves.points[4] = Vec3::new(0.1 + 0.2, 1.0 / 3.0, -123_456_790.0);
    curves
}

/// Three frames of the sample curves' points, each moved and scaled differently.
fn frames() -> Vec<Vec<Vec3>> {
    let base = hard_curves().points;
    (0..3)
        .map(|f| {
            base.iter()
                .map(|&p| p * (1.0 - f as f32 / 7.0) + Vec3::new(0.0, 0.01 * f as f32, 0.0))
                .collect()
        })
        .collect()
}

pub(crate) fn animated_writer() -> UsdCurvesWriter {
    let curves = hard_curves();
    let mut writer = UsdCurvesWriter::new(
        &curves.offsets,
        curves.widths.as_deref(),
        curves.colors.as_deref(),
    )
    .unwrap()
    .with_time_codes_per_second(30.0)
    .unwrap();
    for frame in frames() {
        writer.push_frame(&frame).unwrap();
    }
    writer
}

fn message<T: std::fmt::Debug>(result: Result<T, crate::FormatError>) -> String {
    result.unwrap_err().to_string()
}

/// Writes `curves` as USD text into `dir`, reads them back strictly and through the dispatcher:
/// every bit the same.
fn usda_round_trip(dir: &std::path::Path, name: &str, curves: &Curves) {
    let path = dir.join(name);
    write_usda_curves(&path, curves).unwrap();
    let read = read_usda_file(&path, &ImportOptions::strict()).unwrap();
    assert_eq!(bits(&read), bits(curves), "{name}");
    assert!(read.skipped.is_empty());
    let dispatched = read_curves_file(&path, &ImportOptions::default()).unwrap();
    assert_eq!(bits(&dispatched), bits(curves), "{name}");
}

#[test]
fn written_usda_reads_back_bit_for_bit() {
    let dir = scratch_dir("usda-round-trip");
    let bare = Curves {
        widths: None,
        colors: None,
        ..hard_curves()
    };
    usda_round_trip(&dir, "hard.usda", &hard_curves());
    usda_round_trip(&dir, "bare.usd", &bare);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_reads_back_from_usda_bit_for_bit() {
    let dir = scratch_dir("usda-round-trip-mohawk");
    let mohawk = read_tfx_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::default()).unwrap();
    usda_round_trip(&dir, "mohawk.usda", &mohawk);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_frame_reads_back_at_its_time_code() {
    let writer = animated_writer();
    assert_eq!(writer.frame_count(), 3);
    let text = writer.to_usda_string().unwrap();
    for line in [
        "    startTimeCode = 0\n",
        "    endTimeCode = 2\n",
        "    timeCodesPerSecond = 30\n",
        "    metersPerUnit = 1\n",
        "    upAxis = \"Y\"\n",
        "    point3f[] points.timeSamples = {\n",
        "        2: [(",
    ] {
        assert!(text.contains(line), "{line:?} missing from\n{text}");
    }
    let bytes = text.as_bytes();
    let options = ImportOptions::strict();
    let expected = |points: &Vec<Vec3>| Curves {
        points: points.clone(),
        ..hard_curves()
    };
    let frames = frames();
    for (t, points) in frames.iter().enumerate() {
        let read = read_usda_at(bytes, t as f64, &options).unwrap();
        assert_eq!(bits(&read), bits(&expected(points)), "frame {t}");
    }
    // No time: the earliest sample. Before the first and after the last: held.
    let first = bits(&expected(&frames[0]));
    assert_eq!(bits(&read_usda(bytes, &options).unwrap()), first);
    assert_eq!(bits(&read_usda_at(bytes, -4.0, &options).unwrap()), first);
    let last = read_usda_at(bytes, 10.0, &options).unwrap();
    assert_eq!(bits(&last), bits(&expected(&frames[2])));
    // Between samples: linear.
    let half = read_usda_at(bytes, 1.5, &options).unwrap();
    for (i, p) in half.points.iter().enumerate() {
        let mid = frames[1][i].lerp(frames[2][i], 0.5);
        assert!((*p - mid).abs().max_element() <= 1e-6 * mid.abs().max_element().max(1.0));
    }
    // The same through a file, written atomically.
    let dir = scratch_dir("usda-frames");
    let path = dir.join("anim.usda");
    writer.write(&path).unwrap();
    let read = read_usda_file_at(&path, 2.0, &options).unwrap();
    assert_eq!(bits(&read), bits(&expected(&frames[2])));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A file in the style Pixar's tools write: Z up, centimetres, curves under an Xform beside a
/// mesh, with relationships, variant sets, dictionaries, a `class`, and primvars of every
/// interpolation.
pub(crate) const PIXAR_STYLE: &str = r#"#usda 1.0
(
    customLayerData = {
        string creator = "hand"
        dictionary nested = { int[] a = [1, 2] }
    }
    defaultPrim = "root"
    metersPerUnit = 0.01
    subLayers = [@./none.usda@ (offset = 1)]
    upAxis = "Z"
)

def Xform "root" (
    kind = "component"
    prepend apiSchemas = ["MaterialBindingAPI"]
)
{
    double3 xformOp:translate = (0, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    rel material:binding = </root/mat>

    def Mesh "head" (references = @head.usda@</head>)
    {
        int[] faceVertexCounts = [3]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    }

    def BasisCurves "guides" (
        doc = "two linear curves"
    )
    {
        uniform token type = "linear"
        uniform token wrap = "pinned"
        int[] curveVertexCounts = [2, 3]
        point3f[] points = [(0, 0, 0), (0, 0, 10),
            (10, 20, 30), (10, 20, 40), (10, 25, 50)]
        float[] widths = [0.5, 0.25] (
            interpolation = "uniform"
        )
        color3f[] primvars:displayColor = [(1, 0, 0)] (
            interpolation = "constant"
        )
        custom string note = "a } in a string"
    }

    variantSet "look" = {
        "long" {
            def BasisCurves "ignored" { }
        }
    }

    def Scope "more"
    {
        def BasisCurves "strands"
        {
            uniform token type = "linear"
            int[] curveVertexCounts.timeSamples = {
                0: [2],
            }
            point3f[] points.timeSamples = {
                0: [(5, 5, 5), (5, 5, 6)],
                10: [(7, 7, 7), (7, 7, 8)],
            }
            float[] primvars:widths = [1, 2] (
                interpolation = "vertex"
            )
            int[] primvars:widths:indices = [1, 0]
            color3f[] primvars:displayColor = [(0, 1, 0), (0, 0, 1)] (
                interpolation = "vertex"
            )
        }
    }
}

class BasisCurves "template"
{
    int[] curveVertexCounts = [2]
    point3f[] points = [(1, 1, 1), (2, 2, 2)]
}
"#;

#[test]
fn the_layer_axes_and_units_come_before_the_readers() {
    let read = read_usda(PIXAR_STYLE.as_bytes(), &ImportOptions::strict()).unwrap();
    // Centimetres to metres in f64, then Z up to Y up.
    let stage = |p: Vec3| {
        let m = (p.as_dvec3() * 0.01).as_vec3();
        Vec3::new(m.x, m.z, -m.y)
    };
    let file_points = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::new(10.0, 20.0, 30.0),
        Vec3::new(10.0, 20.0, 40.0),
        Vec3::new(10.0, 25.0, 50.0),
        Vec3::new(5.0, 5.0, 5.0),
        Vec3::new(5.0, 5.0, 6.0),
    ];
    let expected: Vec<Vec3> = file_points.iter().map(|&p| stage(p)).collect();
    assert_eq!(read.points, expected);
    // File +Z (up) is +Y, in metres.
    assert_eq!(read.points[1], Vec3::new(0.0, 0.1, 0.0));
    assert_eq!(read.offsets, [0, 2, 5, 7]);
    let widths: Vec<f32> = [0.5, 0.5, 0.25, 0.25, 0.25, 2.0, 1.0]
        .iter()
        .map(|&w: &f32| (f64::from(w) * 0.01) as f32)
        .collect();
    assert_eq!(read.widths, Some(widths));
    let red = Vec3::X;
    assert_eq!(
        read.colors,
        Some(vec![red, red, red, red, red, Vec3::Y, Vec3::Z])
    );
    // At time 10 the second prim's later sample; the reader's axes apply after the file's.
    let axes = ImportAxes {
        mirror_x: true,
        ..ImportAxes::default()
    };
    let read = read_usda_at(
        PIXAR_STYLE.as_bytes(),
        10.0,
        &ImportOptions::with_axes(axes),
    )
    .unwrap();
    assert_eq!(read.points[5], axes.point(stage(Vec3::splat(7.0))));
    assert_eq!(read.points[0], Vec3::ZERO);
    assert_eq!(read.points[4], axes.point(stage(file_points[4])));
}

#[test]
fn a_layer_without_units_is_in_centimetres_as_in_usd() {
    let text = "#usda 1.0\ndef BasisCurves \"c\" {\n uniform token type = \"linear\"\n \
                int[] curveVertexCounts = [2]\n point3f[] points = [(0, 0, 0), (0, 100, 0)]\n}\n";
    let read = read_usda(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!(read.points, [Vec3::ZERO, Vec3::Y]);
    assert_eq!((read.widths, read.colors), (None, None));
}

/// A small valid file: the prim at line 2, its points at line 5.
const SMALL: &str = "#usda 1.0\ndef BasisCurves \"c\" {\n    uniform token type = \"linear\"\n    \
                     int[] curveVertexCounts = [2, 2]\n    point3f[] points = [(0, 0, 0), \
                     (0, 1, 0),\n        (1, 0, 0), (1, 1, 0)]\n}\n";

/// `SMALL` with `from` replaced by `to`, read.
fn small_with(from: &str, to: &str) -> String {
    assert!(SMALL.contains(from), "{from}");
    message(read_usda(
        SMALL.replace(from, to).as_bytes(),
        &ImportOptions::default(),
    ))
}

#[test]
fn broken_files_name_the_line() {
    assert!(read_usda(SMALL.as_bytes(), &ImportOptions::strict()).is_ok());
    let truncated = &SMALL[..SMALL.find("(1, 0, 0)").unwrap() + 4];
    assert_eq!(
        message(read_usda(truncated.as_bytes(), &ImportOptions::default())),
        "<memory>: line 6: the file ends where a number was expected (truncated?)"
    );
    assert_eq!(
        message(read_usda(
            &SMALL.as_bytes()[..SMALL.len() - 2],
            &Default::default()
        )),
        "<memory>: line 7: the file ends where a property, a child prim or `}` closing prim \
         \"c\" of line 2 was expected (truncated?)"
    );
    assert_eq!(
        small_with("[2, 2]", "[2, 3]"),
        "<memory>: line 4: the curveVertexCounts of BasisCurves \"c\" add up to 5 points, but \
         its points (line 5) hold 4"
    );
    assert_eq!(
        small_with("[2, 2]", "[2, -2]"),
        "<memory>: line 4: curveVertexCounts[1] of BasisCurves \"c\" is negative (-2)"
    );
    assert_eq!(
        small_with("(1, 0, 0)", "(1, nan, 0)"),
        "<memory>: curve 1, point 0 at line 6: position [1, NaN, 0] is not finite"
    );
    assert_eq!(
        small_with("(0, 1, 0)", "(0, -inf, 0)"),
        "<memory>: curve 0, point 1 at line 5: position [0, -inf, 0] is not finite"
    );
    assert_eq!(
        small_with("(0, 1, 0)", "(0, 1 0)"),
        "<memory>: line 5: expected `,` between the 3-vector's numbers, found `0`"
    );
    assert_eq!(
        small_with("(0, 1, 0)", "(0, one, 0)"),
        "<memory>: line 5: a 3-vector's number: expected a number, found `one`"
    );
    assert_eq!(
        small_with("\"linear\"", "\"cubic\""),
        "<memory>: line 3: BasisCurves \"c\" has type \"cubic\" (basis \"bezier\"); only \
         \"linear\" curves are read (convert the curves to linear polylines first)"
    );
    assert_eq!(
        small_with("    uniform token type = \"linear\"\n", ""),
        "<memory>: line 2: BasisCurves \"c\" has type \"cubic\" (basis \"bezier\", USD's \
         fallback when `type` is not authored); only \"linear\" curves are read (convert the \
         curves to linear polylines first)"
    );
    assert_eq!(
        small_with("\"linear\"", "\"spiral\""),
        "<memory>: line 3: BasisCurves \"c\" has an unknown type \"spiral\" (allowed: \"linear\")"
    );
    assert_eq!(
        small_with(
            "\"linear\"\n",
            "\"linear\"\n    uniform token wrap = \"periodic\"\n"
        ),
        "<memory>: line 4: BasisCurves \"c\" has wrap \"periodic\"; only open curves \
         (\"nonperiodic\", \"pinned\") are read"
    );
    assert_eq!(
        small_with("int[] curveVertexCounts", "float[] curveVertexCounts"),
        "<memory>: line 4: `curveVertexCounts` of BasisCurves \"c\" has type `float[]`; \
         expected `int[]`"
    );
    assert_eq!(
        small_with(
            "    int[] curveVertexCounts = [2, 2]\n",
            "    int[] curveVertexCounts = [2, 2]\n    float[] widths = [1, 2, 3]\n"
        ),
        "<memory>: line 5: widths of BasisCurves \"c\" has 3 values, but interpolation \
         \"vertex\" needs 4 (one per point)"
    );
    assert_eq!(
        small_with("    int[] curveVertexCounts = [2, 2]\n", ""),
        "<memory>: line 2: BasisCurves \"c\" has no curveVertexCounts value"
    );
    assert_eq!(
        small_with("#usda 1.0\n", "#usda 1.0\n(\n    upAxis = \"X\"\n)\n"),
        "<memory>: line 3: upAxis `\"X\"` is not supported (allowed: \"Y\" or \"Z\")"
    );
    assert_eq!(
        small_with("#usda 1.0\n", "#usda 1.0\n(\n    metersPerUnit = -1\n)\n"),
        "<memory>: line 3: metersPerUnit `-1` is invalid (allowed: a finite number > 0)"
    );
    assert_eq!(
        small_with("[(0, 0, 0),", "[(0, 0, 0)]\n    ]"),
        "<memory>: line 6: expected a property, a child prim or `}`, found `]`"
    );
    assert_eq!(
        small_with("def BasisCurves \"c\" {", "def BasisCurves c {"),
        "<memory>: line 2: expected the prim's name in quotes, found `c`"
    );
    assert_eq!(
        message(read_usda(b"PXR-USDC\x00\x00", &Default::default())),
        "<memory>: not a USD text file: found \"PXR-USDC\" (a binary crate file: read it with \
         `read_usdc`, or name it .usdc or .usd) at byte 0, expected \"#usda 1.0\""
    );
    assert_eq!(
        message(read_usda(b"#usda 1.0\n", &Default::default())),
        "<memory>: no usable curve: the file has 0 curves, 0 of them skipped"
    );
    let dir = scratch_dir("usda-errors");
    let path = dir.join("broken.usda");
    std::fs::write(&path, SMALL.replace("[2, 2]", "[2, 3]")).unwrap();
    let error = message(read_curves_file(&path, &ImportOptions::default()));
    assert!(
        error.starts_with(&format!("{}: line 4: ", path.display())),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn degenerate_usda_curves_are_skipped_or_refused() {
    let text = SMALL.replace("(1, 1, 0)", "(1, 0, 0)");
    let read = read_usda(text.as_bytes(), &ImportOptions::default()).unwrap();
    assert_eq!((read.curve_count(), read.skipped.len()), (1, 1));
    assert_eq!(
        message(read_usda(text.as_bytes(), &ImportOptions::strict())),
        "<memory>: curve 1 at line 6: segment 0 has zero length (strict reading)"
    );
}

#[test]
fn the_writer_refuses_bad_curves_before_writing() {
    let dir = scratch_dir("usda-refused");
    let path = dir.join("refused.usda");
    let mut curves = sample_curves();
    curves.points[3].y = f32::NAN;
    let error = write_usda_curves(&path, &curves).unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
    assert!(
        error
            .to_string()
            .ends_with("frame 0, point 3 is not finite: [0.01, NaN, 0]"),
        "{error}"
    );
    assert!(!path.exists());
    let mut writer = UsdCurvesWriter::new(&[0, 2, 5], None, None).unwrap();
    assert!(writer.write(&path).is_err(), "no frame yet");
    let error = writer.push_frame(&[Vec3::ZERO; 4]).unwrap_err();
    assert_eq!(error.to_string(), "frame 0 has 4 points; the curves have 5");
    let mut frame = [Vec3::X; 5];
    frame[4].z = f32::INFINITY;
    assert!(writer.push_frame(&frame).is_err());
    assert_eq!(writer.frame_count(), 0);
    assert!(!path.exists());
    let error = UsdCurvesWriter::new(&[0, 2, 3], None, None).unwrap_err();
    assert_eq!(
        error.to_string(),
        "curve 1 has 1 points; a linear BasisCurves curve needs at least 2"
    );
    assert!(UsdCurvesWriter::new(&[0, 2], Some(&[0.1, -0.1]), None).is_err());
    assert!(UsdCurvesWriter::new(&[0, 2], None, Some(&[Vec3::X])).is_err());
    assert!(writer.clone().with_prim_name("2 bad").is_err());
    assert!(writer.clone().with_time_codes_per_second(0.0).is_err());
    // A refused write leaves an existing file as it was.
    std::fs::write(&path, "old").unwrap();
    assert!(
        UsdCurvesWriter::new(&[0, 2], None, None)
            .unwrap()
            .write(&path)
            .is_err()
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The directory `tests/usd_check.py` gives the two steps below.
fn check_dir() -> PathBuf {
    PathBuf::from(std::env::var("HAIRLOD_USD_CHECK_DIR").expect("HAIRLOD_USD_CHECK_DIR"))
}

/// `[[x, y, z] bits]` of some points, as JSON.
fn points_json(points: &[Vec3]) -> serde_json::Value {
    points
        .iter()
        .map(|p| p.to_array().map(f32::to_bits).to_vec())
        .collect()
}

/// Step 1 of `tests/usd_check.py`: our files and the bits of every value written.
#[test]
#[ignore = "a step of tests/usd_check.py"]
fn usd_check_write() {
    let dir = check_dir();
    let curves = hard_curves();
    write_usda_curves(dir.join("ours_single.usda"), &curves).unwrap();
    animated_writer()
        .write(dir.join("ours_animated.usda"))
        .unwrap();
    let expected = serde_json::json!({
        "counts": curves.iter().map(|c| c.len()).collect::<Vec<_>>(),
        "single": points_json(&curves.points),
        "frames": frames().iter().map(|f| points_json(f)).collect::<Vec<_>>(),
        "widths": curves.widths.iter().flatten().map(|w| w.to_bits()).collect::<Vec<_>>(),
        "colors": points_json(curves.colors.as_deref().unwrap_or_default()),
    });
    std::fs::write(dir.join("ours.json"), expected.to_string()).unwrap();
}

/// Step 3 of `tests/usd_check.py`: the files Pixar's USD wrote, read at each time the script
/// lists, give the bits it wrote.
#[test]
#[ignore = "a step of tests/usd_check.py"]
fn usd_check_read() {
    let dir = check_dir();
    let expected: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("pixar.json")).unwrap()).unwrap();
    for case in expected.as_array().unwrap() {
        let file = dir.join(case["file"].as_str().unwrap());
        let time = case["time"].as_f64();
        let options = ImportOptions::strict();
        if case["mesh"].as_bool() == Some(true) {
            // A Mesh, .usda or .usdc, through the openusd crate.
            let mesh = read_mesh_file(&file, &options).unwrap_or_else(|e| panic!("{e}"));
            let what = file.display();
            assert_eq!(points_json(&mesh.positions), case["points"], "{what}");
            let triangles: Vec<[u32; 3]> =
                serde_json::from_value(case["triangles"].clone()).unwrap();
            assert_eq!(mesh.triangles, triangles, "{what}");
            println!(
                "{what} (Mesh): {} triangles, {} points equal",
                mesh.triangle_count(),
                mesh.vertex_count()
            );
            continue;
        }
        // By extension at the default time: .usdc goes through the openusd crate.
        let read = match time {
            Some(t) => read_usda_file_at(&file, t, &options),
            None => read_curves_file(&file, &options),
        }
        .unwrap_or_else(|e| panic!("{e}"));
        let what = format!("{} at {time:?}", file.display());
        assert_eq!(points_json(&read.points), case["points"], "{what}");
        let offsets: Vec<u32> = serde_json::from_value(case["offsets"].clone()).unwrap();
        assert_eq!(read.offsets, offsets, "{what}");
        let widths: Option<Vec<u32>> = serde_json::from_value(case["widths"].clone()).unwrap();
        let read_widths = read
            .widths
            .as_ref()
            .map(|w| w.iter().map(|x| x.to_bits()).collect());
        assert_eq!(read_widths, widths, "{what}");
        println!(
            "{what}: {} curves, {} points equal",
            read.curve_count(),
            read.point_count()
        );
    }
}

#[test]
fn a_string_of_one_frame_writes_plain_points() {
    let text = write_usda_curves_string(&hard_curves()).unwrap();
    assert!(text.contains("    point3f[] points = [(0, 0, 0), (-0.0, 0.01, 0.001), (1e-30, "));
    assert!(!text.contains("timeSamples") && !text.contains("startTimeCode"));
}
