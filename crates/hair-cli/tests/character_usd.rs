//! A USD character as a DCC tool writes one runs through `hairlod render` with automatic levels,
//! and its `hair.usda` carries the hair on the body's time line with the body beside it.
//!
//! The character is written here: a Z-up stage in centimetres at 24 time codes per second,
//! codes 1..=48; `/character` an Xform that nods (a time-sampled `rotateX` about the neck at the
//! origin), `/character/head` a quad-and-triangle sphere whose `points` squash and stretch about
//! the neck (volume kept), and `/groom` a linear `BasisCurves` rooted on the head's faces at code
//! 1. The references:
//!
//! - the exported body at code `c` is the analytic head: rest point `p` squashed by
//!   `s(c) = 1 + 0.06·sin(2π·(c − 1)/24)` (z·s, x and y by 1/√s), turned by
//!   `θ(c) = 10°·sin(π·(c − 1)/24)` about x, then Z-up centimetres to Y-up metres
//!   (`(x, y, z) → 0.01·(x, z, −y)`);
//! - every exported root stays on its code-1 barycentric point: at code 1 each root's closest
//!   point on the exported body, its triangle, barycentric coordinates and the root's offset in
//!   the triangle's frame (first edge, in-plane perpendicular, normal); at code `c` the root must
//!   lie at that barycentric point plus the offset turned with the triangle (the bar:
//!   0.5 mm).

mod common;

use std::f64::consts::PI;
use std::fmt::Write as _;

use common::{folder, hairlod};
use glam::{DMat3, DVec3, Vec3};
use hairlod::formats::{read_usd_mesh_sequence_file, read_usda_file_at};

/// Time codes per second and the codes written (1..=CODES).
const RATE: f64 = 24.0;
const CODES: usize = 48;
/// Head radius and its centre's height above the neck [cm].
const RADIUS: f64 = 10.0;
const CENTRE: f64 = 12.0;
/// Rings and segments of the sphere.
const RINGS: usize = 12;
const SEGMENTS: usize = 20;

/// Squash of code `code`: the scale along z.
fn squash(code: f64) -> f64 {
    1.0 + 0.06 * (2.0 * PI * (code - 1.0) / RATE).sin()
}

/// Nod of code `code` [degrees] about x.
fn nod(code: f64) -> f64 {
    10.0 * (PI * (code - 1.0) / RATE).sin()
}

/// The head's rest points [cm, Z-up] and faces (quads, triangles at the poles; counter-clockwise
/// seen from outside).
fn head() -> (Vec<DVec3>, Vec<Vec<u32>>) {
    let mut points = vec![DVec3::new(0.0, 0.0, CENTRE + RADIUS)];
    for ring in 1..RINGS {
        let polar = PI * ring as f64 / RINGS as f64;
        for segment in 0..SEGMENTS {
            let azimuth = 2.0 * PI * segment as f64 / SEGMENTS as f64;
            points.push(DVec3::new(
                RADIUS * polar.sin() * azimuth.cos(),
                RADIUS * polar.sin() * azimuth.sin(),
                CENTRE + RADIUS * polar.cos(),
            ));
        }
    }
    points.push(DVec3::new(0.0, 0.0, CENTRE - RADIUS));
    let bottom = points.len() as u32 - 1;
    let at = |ring: usize, segment: usize| (1 + (ring - 1) * SEGMENTS + segment % SEGMENTS) as u32;
    let mut faces = Vec::new();
    for s in 0..SEGMENTS {
        faces.push(vec![0, at(1, s), at(1, s + 1)]);
        for ring in 1..RINGS - 1 {
            faces.push(vec![
                at(ring, s),
                at(ring + 1, s),
                at(ring + 1, s + 1),
                at(ring, s + 1),
            ]);
        }
        faces.push(vec![at(RINGS - 1, s), bottom, at(RINGS - 1, s + 1)]);
    }
    (points, faces)
}

/// `p` [cm, Z-up, rest] at code `code` in the stage's frame: squashed about the neck, then
/// nodded.
fn animated(p: DVec3, code: f64) -> DVec3 {
    let s = squash(code);
    let squashed = DVec3::new(p.x / s.sqrt(), p.y / s.sqrt(), p.z * s);
    DMat3::from_rotation_x(nod(code).to_radians()) * squashed
}

/// Z-up centimetres to hairlod's Y-up metres.
fn to_hairlod(p: DVec3) -> DVec3 {
    0.01 * DVec3::new(p.x, p.z, -p.y)
}

fn list(points: impl Iterator<Item = DVec3>) -> String {
    let mut out = String::from("[");
    for p in points {
        write!(out, "({}, {}, {}), ", p.x, p.y, p.z).unwrap();
    }
    out.push(']');
    out
}

/// The character's USD text.
fn character() -> String {
    let (points, faces) = head();
    let mut text = format!(
        "#usda 1.0\n(\n    defaultPrim = \"character\"\n    metersPerUnit = 0.01\n    \
         upAxis = \"Z\"\n    timeCodesPerSecond = {RATE}\n    startTimeCode = 1\n    \
         endTimeCode = {CODES}\n)\n\ndef Xform \"character\"\n{{\n    \
         float xformOp:rotateX.timeSamples = {{\n"
    );
    for code in 1..=CODES {
        writeln!(text, "        {code}: {},", nod(code as f64)).unwrap();
    }
    text.push_str(
        "    }\n    uniform token[] xformOpOrder = [\"xformOp:rotateX\"]\n\n    \
         def Mesh \"head\"\n    {\n",
    );
    let counts: Vec<String> = faces.iter().map(|f| f.len().to_string()).collect();
    let indices: Vec<String> = faces.iter().flatten().map(u32::to_string).collect();
    writeln!(
        text,
        "        int[] faceVertexCounts = [{}]",
        counts.join(", ")
    )
    .unwrap();
    writeln!(
        text,
        "        int[] faceVertexIndices = [{}]",
        indices.join(", ")
    )
    .unwrap();
    text.push_str("        point3f[] points.timeSamples = {\n");
    for code in 1..=CODES {
        let s = squash(code as f64);
        let squashed = points
            .iter()
            .map(|p| DVec3::new(p.x / s.sqrt(), p.y / s.sqrt(), p.z * s));
        writeln!(text, "            {code}: {},", list(squashed)).unwrap();
    }
    text.push_str("        }\n    }\n}\n\n");
    // The groom: on every face of the upper cap (polar angle under 60°), three strands rooted on
    // the face's first fan triangle, 12 points 1 cm apart along the sphere's normal.
    let mut counts = Vec::new();
    let mut curve_points = Vec::new();
    for face in faces.iter().filter(|f| {
        let centre: DVec3 = f.iter().map(|&v| points[v as usize]).sum::<DVec3>() / f.len() as f64;
        centre.z - CENTRE > RADIUS * 0.5
    }) {
        let [a, b, c] = [0, 1, 2].map(|k| points[face[k] as usize]);
        for w in [[0.4, 0.3, 0.3], [0.6, 0.2, 0.2], [0.2, 0.2, 0.6]] {
            let root = a * w[0] + b * w[1] + c * w[2];
            let normal = (root - DVec3::new(0.0, 0.0, CENTRE)).normalize();
            counts.push(12.to_string());
            curve_points.extend((0..12).map(|k| root + normal * k as f64));
        }
    }
    writeln!(
        text,
        "def BasisCurves \"groom\"\n{{\n    int[] curveVertexCounts = [{}]\n    \
         point3f[] points = {}\n    uniform token type = \"linear\"\n    \
         float[] widths = [0.01] (\n        interpolation = \"constant\"\n    )\n}}",
        counts.join(", "),
        list(curve_points.into_iter())
    )
    .unwrap();
    text
}

/// The closest point to `p` on triangle `t` as barycentric coordinates (brute force: inside the
/// triangle's plane projection, else the closest of the three edges).
fn closest_barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> DVec3 {
    let n = (b - a).cross(c - a);
    let area = n.length_squared();
    let q = p - n * (p - a).dot(n) / area;
    let w = DVec3::new(
        (c - b).cross(q - b).dot(n) / area,
        (a - c).cross(q - c).dot(n) / area,
        (b - a).cross(q - a).dot(n) / area,
    );
    if w.min_element() >= 0.0 {
        return w;
    }
    let edge = |u: DVec3, v: DVec3| ((p - u).dot(v - u) / (v - u).length_squared()).clamp(0.0, 1.0);
    let candidates = [
        {
            let t = edge(a, b);
            DVec3::new(1.0 - t, t, 0.0)
        },
        {
            let t = edge(b, c);
            DVec3::new(0.0, 1.0 - t, t)
        },
        {
            let t = edge(c, a);
            DVec3::new(t, 0.0, 1.0 - t)
        },
    ];
    candidates
        .into_iter()
        .min_by(|x, y| {
            let at = |w: DVec3| (a * w.x + b * w.y + c * w.z - p).length();
            at(*x).total_cmp(&at(*y))
        })
        .unwrap()
}

/// The triangle's frame: first edge, in-plane perpendicular, normal (columns).
fn frame([a, b, c]: [DVec3; 3]) -> DMat3 {
    let x = (b - a).normalize();
    let z = (b - a).cross(c - a).normalize();
    DMat3::from_cols(x, z.cross(x), z)
}

fn dvec(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

#[test]
fn a_usd_character_exports_hair_on_the_body_time_line_with_roots_on_their_points() {
    let dir = folder("character-usd");
    std::fs::write(dir.join("character.usda"), character()).unwrap();
    let scene = dir.join("character.toml");
    std::fs::write(
        &scene,
        "version = 2\n[groom]\nfile = \"character.usda\"\nchildren_per_strand = 0\n\
         strands_per_section = 10\n[body]\nfile = \"character.usda\"\n[lod]\nmode = \"auto\"\n\
         [frames]\ncount = 48\nfps = 24\nsize = \"160x90\"\n[output]\nusd = true\n",
    )
    .unwrap();
    let out = dir.join("out");
    hairlod(&[
        "render",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let export = out.join("hair.usda");
    let text = std::fs::read_to_string(&export).unwrap();
    for line in [
        "startTimeCode = 1\n",
        "endTimeCode = 48\n",
        "timeCodesPerSecond = 24\n",
    ] {
        assert!(text.contains(line), "hair.usda lacks {line:?}");
    }

    // The body beside the hair: the file's own codes, the analytic head in hairlod's units.
    let body = read_usd_mesh_sequence_file(&export, &Default::default()).unwrap();
    assert_eq!(body.clock().time_codes_per_second, Some(RATE));
    let codes: Vec<f64> = body
        .times()
        .iter()
        .map(|t| (t * RATE * 1e6).round() / 1e6)
        .collect();
    assert_eq!(codes, (1..=CODES).map(|c| c as f64).collect::<Vec<_>>());
    let (rest, faces) = head();
    let mut body_error = 0.0f64;
    for (sample, &code) in codes.iter().enumerate() {
        // The quads are fans: the vertices keep their order, so compare vertex by vertex.
        for (p, q) in rest.iter().zip(body.sample_positions(sample)) {
            body_error = body_error.max((to_hairlod(animated(*p, code)) - dvec(*q)).length());
        }
    }
    // f32 points 0.25 m from the origin: a few ulps (3e-8 m) each through the reader's and the
    // writer's conversions.
    assert!(
        body_error <= 1e-6,
        "the exported body is {body_error} m off the analytic head"
    );
    assert_eq!(
        body.triangles().len(),
        faces.iter().map(|f| f.len() - 2).sum::<usize>()
    );

    // The roots on their code-1 points.
    let triangle = |sample: usize, t: usize| -> [DVec3; 3] {
        let positions = body.sample_positions(sample);
        body.triangles()[t].map(|v| dvec(positions[v as usize]))
    };
    let first = read_usda_file_at(&export, 1.0, &Default::default()).unwrap();
    let roots: Vec<DVec3> = first.offsets[..first.curve_count()]
        .iter()
        .map(|&start| dvec(first.points[start as usize]))
        .collect();
    assert!(roots.len() >= 100, "{} strands exported", roots.len());
    let attachments: Vec<(usize, DVec3, DVec3)> = roots
        .iter()
        .map(|&root| {
            let (t, w, distance) = (0..body.triangles().len())
                .map(|t| {
                    let corners = triangle(0, t);
                    let w = closest_barycentric(root, corners);
                    let point = corners[0] * w.x + corners[1] * w.y + corners[2] * w.z;
                    (t, w, (root - point).length())
                })
                .min_by(|a, b| a.2.total_cmp(&b.2))
                .unwrap();
            let corners = triangle(0, t);
            let point = corners[0] * w.x + corners[1] * w.y + corners[2] * w.z;
            assert!(
                distance < 1e-3,
                "a root lies {distance} m off the body at code 1"
            );
            (t, w, frame(corners).transpose() * (root - point))
        })
        .collect();
    let (mut worst, mut moved) = (0.0f64, 0.0f64);
    for (sample, &code) in codes.iter().enumerate() {
        let curves = read_usda_file_at(&export, code, &Default::default()).unwrap();
        assert_eq!(curves.offsets, first.offsets, "code {code}");
        for (strand, &(t, w, offset)) in attachments.iter().enumerate() {
            let corners = triangle(sample, t);
            let expected =
                corners[0] * w.x + corners[1] * w.y + corners[2] * w.z + frame(corners) * offset;
            let root = dvec(curves.points[curves.offsets[strand] as usize]);
            worst = worst.max((root - expected).length());
            moved = moved.max((root - roots[strand]).length());
        }
    }
    eprintln!("roots within {worst} m of their code-1 points; moved up to {moved} m");
    assert!(
        worst <= 5e-4,
        "a root is {worst} m off its point (bar 0.5 mm)"
    );
    assert!(moved > 5e-3, "the roots moved only {moved} m");
}

/// `--usd-guides` writes the groom file's own strands only: the 240 curves of the character's
/// groom, not the 960 it draws with 3 children grown around each; without it, all 960.
#[test]
fn usd_guides_writes_the_groom_files_own_strands_only() {
    let dir = folder("character-usd-guides");
    std::fs::write(dir.join("character.usda"), character()).unwrap();
    let scene = dir.join("character.toml");
    std::fs::write(
        &scene,
        "version = 2\n[groom]\nfile = \"character.usda\"\nchildren_per_strand = 3\n\
         strands_per_section = 10\n[body]\nfile = \"character.usda\"\n[lod]\nmode = \"auto\"\n\
         [frames]\ncount = 2\nfps = 24\nsize = \"160x90\"\n",
    )
    .unwrap();
    let curves_written = |name: &str, flag: &str| {
        let out = dir.join(name);
        hairlod(&[
            "render",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            flag,
        ]);
        read_usda_file_at(out.join("hair.usda"), 1.0, &Default::default())
            .unwrap()
            .curve_count()
    };
    assert_eq!(curves_written("guides", "--usd-guides"), 240);
    assert_eq!(curves_written("all", "--usd"), 960);
}
