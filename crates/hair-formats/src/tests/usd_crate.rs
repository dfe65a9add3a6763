//! USD through the `openusd` crate: layers written with the crate's own writers (binary with
//! `CrateWriter`, text with `TextWriter`) read back exactly: `BasisCurves` of `.usdc` (and the
//! same layer as `.usda` through the project's parser, which gives the same curves), `Mesh` prims
//! of both encodings; `.usd` is sniffed; every broken file is refused by message; huge counts in
//! a crate file are refused before the crate allocates. The random and mutated crate files are
//! targets of `fuzz.rs`.

use std::io::Cursor;

use glam::Vec3;
use openusd::sdf::{self, SpecType, Specifier, Value};
use openusd::usda::TextWriter;
use openusd::usdc::CrateWriter;
use openusd::{gf, tf};

use super::scratch_dir;
use crate::{
    ImportOptions, read_curves_file, read_mesh_file, read_usd_curves, read_usd_mesh,
    read_usd_mesh_file, read_usda, read_usdc,
};

/// An attribute: name, USD type name, value, interpolation.
type Attr = (&'static str, &'static str, Value, Option<&'static str>);

/// A layer with `upAxis`, `metersPerUnit` and prims `(name, type, attributes)` under the root.
fn layer(up: &str, meters_per_unit: f64, prims: Vec<(&str, &str, Vec<Attr>)>) -> sdf::Data {
    let mut data = sdf::Data::new();
    let root = sdf::Path::abs_root();
    let names: Vec<tf::Token> = prims.iter().map(|p| p.0.into()).collect();
    let spec = data.create_spec(root.clone(), SpecType::PseudoRoot);
    spec.add("primChildren", Value::TokenVec(names));
    spec.add("upAxis", Value::Token(up.into()));
    spec.add("metersPerUnit", Value::Double(meters_per_unit));
    for (name, type_name, attrs) in prims {
        let path = root.append_path(name).unwrap();
        let spec = data.create_spec(path.clone(), SpecType::Prim);
        spec.add("specifier", Value::Specifier(Specifier::Def));
        spec.add("typeName", Value::Token(type_name.into()));
        let properties: Vec<tf::Token> = attrs.iter().map(|a| a.0.into()).collect();
        spec.add("propertyChildren", Value::TokenVec(properties));
        for (attr, attr_type, value, interpolation) in attrs {
            let spec = data.create_spec(path.append_property(attr).unwrap(), SpecType::Attribute);
            spec.add("typeName", Value::Token(attr_type.into()));
            spec.add("default", value);
            if let Some(interpolation) = interpolation {
                spec.add("interpolation", Value::Token(interpolation.into()));
            }
        }
    }
    data
}

fn crate_bytes(data: &sdf::Data) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    CrateWriter::write(data, &mut out).unwrap();
    out.into_inner()
}

fn text_bytes(data: &sdf::Data) -> Vec<u8> {
    TextWriter::write_to_string(data).unwrap().into_bytes()
}

fn points_value(points: &[Vec3]) -> Value {
    Value::Vec3fVec(
        points
            .iter()
            .map(|p| gf::Vec3f::from(p.to_array()))
            .collect(),
    )
}

fn token(t: &str) -> Value {
    Value::Token(t.into())
}

/// Two linear curves of 3 and 2 points, with vertex widths, Y up in metres.
fn curve_points() -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.1, 0.25, -0.0),
        Vec3::new(1e-30, 3.4e38, 7.123_456_7),
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.0 / 3.0, 0.1 + 0.2, -5.5),
    ]
}

const CURVE_WIDTHS: [f32; 5] = [0.01, 0.02, 0.005, 0.25, 1.0 / 3.0];

fn curves_attrs(points: &[Vec3], counts: &[i32]) -> Vec<Attr> {
    vec![
        ("type", "token", token("linear"), None),
        (
            "curveVertexCounts",
            "int[]",
            Value::IntVec(counts.to_vec()),
            None,
        ),
        ("points", "point3f[]", points_value(points), None),
        (
            "widths",
            "float[]",
            Value::FloatVec(CURVE_WIDTHS[..points.len().min(5)].to_vec()),
            Some("vertex"),
        ),
    ]
}

/// A `.usdc` file of one `BasisCurves` prim with two curves (a fuzz seed).
pub(crate) fn crate_curves_bytes() -> Vec<u8> {
    crate_bytes(&curves_layer(curves_attrs(&curve_points(), &[3, 2])))
}

fn curves_layer(attrs: Vec<Attr>) -> sdf::Data {
    layer("Y", 1.0, vec![("hair", "BasisCurves", attrs)])
}

/// A quad and a triangle sharing an edge: 5 points.
fn mesh_points() -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(2.0, 0.5, 0.0),
    ]
}

fn mesh_attrs(counts: &[i32], indices: &[i32]) -> Vec<Attr> {
    vec![
        ("points", "point3f[]", points_value(&mesh_points()), None),
        (
            "faceVertexCounts",
            "int[]",
            Value::IntVec(counts.to_vec()),
            None,
        ),
        (
            "faceVertexIndices",
            "int[]",
            Value::IntVec(indices.to_vec()),
            None,
        ),
    ]
}

fn mesh_layer(attrs: Vec<Attr>) -> sdf::Data {
    layer("Y", 1.0, vec![("body", "Mesh", attrs)])
}

/// A `.usdc` file of one `Mesh` prim, a quad and a triangle (a fuzz seed).
pub(crate) fn crate_mesh_bytes() -> Vec<u8> {
    crate_bytes(&mesh_layer(mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, 4, 2])))
}

/// The same mesh as `.usda`, written by the crate (a fuzz seed).
pub(crate) fn text_mesh_bytes() -> Vec<u8> {
    text_bytes(&mesh_layer(mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, 4, 2])))
}

fn message<T: std::fmt::Debug>(result: Result<T, crate::FormatError>) -> String {
    result.unwrap_err().to_string()
}

#[test]
fn crate_curves_read_back_exactly_and_match_the_text_parser() {
    let data = curves_layer(curves_attrs(&curve_points(), &[3, 2]));
    let binary = crate_bytes(&data);
    assert!(binary.starts_with(b"PXR-USDC"));
    let curves = read_usdc(&binary, &ImportOptions::strict()).unwrap();
    assert_eq!(curves.offsets, [0, 3, 5]);
    let bits = |p: &[Vec3]| -> Vec<[u32; 3]> {
        p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
    };
    assert_eq!(bits(&curves.points), bits(&curve_points()));
    assert_eq!(curves.widths.as_deref(), Some(&CURVE_WIDTHS[..]));
    assert_eq!(curves.colors, None);
    // The same layer as text, through the project's parser: the same curves.
    let text = text_bytes(&data);
    let parsed = read_usda(&text, &ImportOptions::strict()).unwrap();
    assert_eq!(parsed, curves);
    assert_eq!(read_usd_curves(&text, &Default::default()).unwrap(), curves);
    assert_eq!(
        read_usd_curves(&binary, &Default::default()).unwrap(),
        curves
    );
}

#[test]
fn crate_curves_take_the_layer_units_and_constant_widths() {
    let points = [Vec3::new(100.0, 0.0, 0.0), Vec3::new(100.0, 0.0, 50.0)];
    let attrs = vec![
        ("type", "token", token("linear"), None),
        ("curveVertexCounts", "int[]", Value::IntVec(vec![2]), None),
        ("points", "point3f[]", points_value(&points), None),
        (
            "primvars:widths",
            "float[]",
            Value::FloatVec(vec![0.5]),
            Some("constant"),
        ),
        (
            "primvars:displayColor",
            "color3f[]",
            points_value(&[Vec3::new(0.25, 0.5, 1.0)]),
            None,
        ),
    ];
    let bytes = crate_bytes(&layer("Z", 0.01, vec![("a", "BasisCurves", attrs)]));
    let curves = read_usdc(&bytes, &Default::default()).unwrap();
    // Centimetres to metres, then Z up to Y up: (x, y, z) → (x, z, −y).
    assert_eq!(
        curves.points,
        [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 0.5, 0.0)]
    );
    assert_eq!(curves.widths, Some(vec![0.005, 0.005]));
    assert_eq!(curves.colors, Some(vec![Vec3::new(0.25, 0.5, 1.0); 2]));
}

#[test]
fn crate_curves_read_the_first_time_sample() {
    let mut data = curves_layer(curves_attrs(&curve_points(), &[3, 2]));
    let points = sdf::path("/hair.points").unwrap();
    let later: Vec<Vec3> = curve_points().iter().map(|p| *p + Vec3::X).collect();
    let spec = data.spec_mut(&points).unwrap();
    spec.remove("default");
    spec.add(
        "timeSamples",
        Value::TimeSamples(vec![
            (2.0, points_value(&later)),
            (1.0, points_value(&curve_points())),
        ]),
    );
    let curves = read_usdc(&crate_bytes(&data), &Default::default()).unwrap();
    assert_eq!(curves.points, curve_points());
}

#[test]
fn meshes_read_back_from_both_encodings() {
    let expected_triangles = [[0, 1, 2], [0, 2, 3], [1, 4, 2]];
    for bytes in [crate_mesh_bytes(), text_mesh_bytes()] {
        let mesh = read_usd_mesh(&bytes, &ImportOptions::default()).unwrap();
        assert_eq!(mesh.positions, mesh_points());
        assert_eq!(mesh.triangles, expected_triangles);
        assert!(
            mesh.normals.iter().all(|n| *n == Vec3::Z),
            "{:?}",
            mesh.normals
        );
    }
    // Left-handed: the windings reverse.
    let mut attrs = mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, 4, 2]);
    attrs.push(("orientation", "token", token("leftHanded"), None));
    let mesh = read_usd_mesh(&crate_bytes(&mesh_layer(attrs)), &Default::default()).unwrap();
    assert_eq!(mesh.triangles, [[0, 2, 1], [0, 3, 2], [1, 2, 4]]);
}

#[test]
fn usd_files_are_read_by_extension_and_sniffed() {
    let dir = scratch_dir("usd-crate");
    let curves = read_usdc(&crate_curves_bytes(), &Default::default()).unwrap();
    let text = text_bytes(&curves_layer(curves_attrs(&curve_points(), &[3, 2])));
    let options = ImportOptions::default();
    for (name, bytes) in [
        ("binary.usdc", crate_curves_bytes()),
        ("binary.usd", crate_curves_bytes()),
        ("text.usd", text.clone()),
        ("text.usda", text),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(read_curves_file(&path, &options).unwrap(), curves, "{name}");
    }
    for (name, bytes) in [
        ("body.usdc", crate_mesh_bytes()),
        ("body.usd", crate_mesh_bytes()),
        ("text.usd", text_mesh_bytes()),
        ("body.usda", text_mesh_bytes()),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(
            read_mesh_file(&path, &options).unwrap().triangle_count(),
            3,
            "{name}"
        );
    }
    let path = dir.join("neither.usd");
    std::fs::write(&path, "PLY\n").unwrap();
    let error = message(read_curves_file(&path, &options));
    assert!(error.ends_with(
        "neither.usd: not a USD file: found \"PLY\\n\" at byte 0, expected \"#usda 1.0\" (text) \
         or \"PXR-USDC\" (binary)"
    ), "{error}");
    // A text file named .usdc is not a crate file.
    let path = dir.join("text.usdc");
    std::fs::write(&path, text_mesh_bytes()).unwrap();
    let error = message(read_curves_file(&path, &options));
    assert!(
        error.ends_with(
            "text.usdc: not a USD crate file: found \"#usda 1.\" at byte 0, expected \"PXR-USDC\""
        ),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_truncated_crate_file_is_an_error_at_every_length() {
    let bytes = crate_curves_bytes();
    for len in 0..bytes.len() {
        let error = read_usdc(&bytes[..len], &Default::default()).unwrap_err();
        assert!(error.to_string().starts_with("<memory>: "), "{error}");
    }
    assert_eq!(
        message(read_usdc(&bytes[..20], &Default::default())),
        "<memory>: truncated: the crate header's table-of-contents offset at byte 16 needs 8 \
         bytes, but only 4 remain"
    );
    let toc = u64::from_le_bytes(bytes[16..24].try_into().unwrap());
    assert_eq!(
        message(read_usdc(&bytes[..toc as usize + 20], &Default::default())),
        format!(
            "<memory>: section count = 6 at byte {toc} needs 192 bytes from byte {}, but the \
             file has {} bytes (truncated, or a wrong count)",
            toc + 8,
            toc + 20
        )
    );
}

/// The offsets of the structural sections' first counts, and of the section sizes, in the TOC.
fn count_offsets(bytes: &[u8]) -> Vec<usize> {
    let u64_at = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
    let toc = u64_at(16);
    let mut out = vec![16, toc];
    for i in 0..u64_at(toc) {
        let entry = toc + 8 + 32 * i;
        let start = u64_at(entry + 16);
        // The section's start and size, its first count, and the next two (sizes and counts).
        out.extend([entry + 16, entry + 24, start, start + 8, start + 16]);
    }
    out
}

#[test]
fn huge_crate_counts_are_errors_not_allocations() {
    for seed in [crate_curves_bytes(), crate_mesh_bytes()] {
        for at in count_offsets(&seed) {
            for value in [u64::MAX, 1 << 62, 1 << 40, 0xffff_ffff, 1 << 28] {
                let mut bytes = seed.clone();
                bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
                if let Ok(curves) = read_usdc(&bytes, &Default::default()) {
                    // A count the reader never uses (a token count): still the same curves.
                    assert_eq!(curves.point_count(), 5, "u64 at byte {at} = {value}");
                }
                if let Ok(mesh) = read_usd_mesh(&bytes, &Default::default()) {
                    assert_eq!(mesh.vertex_count(), 5, "u64 at byte {at} = {value}");
                }
            }
        }
    }
}

#[test]
fn broken_crate_curves_name_the_prim() {
    let read = |attrs: Vec<Attr>| {
        message(read_usdc(
            &crate_bytes(&curves_layer(attrs)),
            &Default::default(),
        ))
    };
    assert_eq!(
        read(curves_attrs(&curve_points(), &[3, 3])),
        "<memory>: USD /hair: the curveVertexCounts add up to 6, but the prim has 5 points"
    );
    assert_eq!(
        read(curves_attrs(&curve_points(), &[6, -1])),
        "<memory>: USD /hair: curveVertexCounts[1] is negative (-1)"
    );
    let mut nan = curve_points();
    nan[3].y = f32::NAN;
    assert_eq!(
        read(curves_attrs(&nan, &[3, 2])),
        "<memory>: /hair curve 1 (of the file), point 0 at an unknown line: position [1, NaN, 3] \
         is not finite"
    );
    let mut infinite = curve_points();
    infinite[1].x = f32::INFINITY;
    assert!(
        read(curves_attrs(&infinite, &[3, 2])).contains("position [inf, 0.25, -0] is not finite")
    );
    let mut cubic = curves_attrs(&curve_points(), &[3, 2]);
    cubic.remove(0);
    assert_eq!(
        read(cubic),
        "<memory>: USD /hair: has type \"cubic\" (basis \"bezier\"); only \"linear\" curves are \
         read (USD's fallback type is \"cubic\": author `uniform token type = \"linear\"`, or \
         convert the curves to linear polylines first)"
    );
    let mut no_points = curves_attrs(&curve_points(), &[3, 2]);
    no_points.remove(2);
    assert_eq!(read(no_points), "<memory>: USD /hair: has no points value");
    let mut wrong_type = curves_attrs(&curve_points(), &[3, 2]);
    wrong_type[2].2 = Value::FloatVec(vec![1.0; 5]);
    assert_eq!(
        read(wrong_type),
        "<memory>: USD /hair.points: is a FloatVec, expected a point3f[]"
    );
    let mut few_widths = curves_attrs(&curve_points(), &[3, 2]);
    few_widths[3].2 = Value::FloatVec(vec![1.0; 4]);
    assert_eq!(
        read(few_widths),
        "<memory>: USD /hair.widths: has 4 values, but interpolation \"vertex\" needs 5 (one per \
         point)"
    );
    let mesh_only = crate_mesh_bytes();
    assert_eq!(
        message(read_usdc(&mesh_only, &Default::default())),
        "<memory>: USD layer: has no BasisCurves prim (`def BasisCurves`)"
    );
}

#[test]
fn broken_meshes_name_the_prim() {
    let read = |attrs: Vec<Attr>| {
        message(read_usd_mesh(
            &crate_bytes(&mesh_layer(attrs)),
            &Default::default(),
        ))
    };
    assert_eq!(
        read(mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, 5, 2])),
        "<memory>: USD /body: faceVertexIndices[5] = 5 (face 1) names no point (5 points)"
    );
    assert_eq!(
        read(mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, -1, 2])),
        "<memory>: USD /body: faceVertexIndices[5] = -1 (face 1) names no point (5 points)"
    );
    assert_eq!(
        read(mesh_attrs(&[4, 4], &[0, 1, 2, 3, 1, 4, 2])),
        "<memory>: USD /body: the faceVertexCounts add up to 8, but the prim has 7 \
         faceVertexIndices"
    );
    assert_eq!(
        read(mesh_attrs(&[5, 2], &[0, 1, 2, 3, 1, 4, 2])),
        "<memory>: USD /body: face 1 has 2 vertices (a face needs 3 or more)"
    );
    let mut nan = mesh_attrs(&[4, 3], &[0, 1, 2, 3, 1, 4, 2]);
    let mut points = mesh_points();
    points[4].z = f32::NAN;
    nan[0].2 = points_value(&points);
    assert_eq!(
        read(nan),
        "<memory>: /body point 4 at an unknown line: position [2, 0.5, NaN] is not finite"
    );
    assert_eq!(
        message(read_usd_mesh(&crate_curves_bytes(), &Default::default())),
        "<memory>: USD layer: has no Mesh prim (`def Mesh`)"
    );
    assert_eq!(
        message(read_usd_mesh(
            b"#usda 1.0\ndef Mesh \"m\" {\n  int[] faceVertexCounts = [3\n}\n",
            &Default::default()
        )),
        "<memory>: line 4: expected `]` or `,` in the array opened at line 3, found `}`"
    );
    // Text meshes go through the project's parser: the same messages as a crate file's, with
    // the line of the value at fault.
    assert_eq!(
        message(read_usd_mesh(
            b"#usda 1.0\ndef Xform \"body\" {\n  def Mesh \"m\" {\n    int[] faceVertexCounts = [3]\n    \
              int[] faceVertexIndices = [0, 1, 7]\n    point3f[] points = [(0, 0, 0), (1, 0, 0), \
              (0, 1, 0)]\n  }\n}\n",
            &Default::default()
        )),
        "<memory>: USD /body/m: faceVertexIndices[2] = 7 (face 0) names no point (3 points) (at \
         line 5)"
    );
    let dir = scratch_dir("usd-crate-errors");
    let path = dir.join("curves.usda");
    std::fs::write(
        &path,
        text_bytes(&curves_layer(curves_attrs(&curve_points(), &[3, 2]))),
    )
    .unwrap();
    let error = message(read_usd_mesh_file(&path, &Default::default()));
    assert!(
        error.ends_with("curves.usda: USD layer: has no Mesh prim (`def Mesh`)"),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn deep_text_nesting_is_an_error_not_a_stack_overflow() {
    // The project's parser skips values on an explicit stack: 100,000 brackets are only a file
    // that ends too soon.
    let mut text = String::from("#usda 1.0\ndef Mesh \"m\" {\n  int[] a = ");
    text.push_str(&"[".repeat(100_000));
    let error = message(read_usd_mesh(text.as_bytes(), &Default::default()));
    assert_eq!(
        error,
        "<memory>: line 3: the file ends where `]` closing the bracket of line 3 was expected \
         (truncated?)"
    );
}
