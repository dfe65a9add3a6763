//! A body file whose mesh moves through time samples (USD `points.timeSamples`) drives the
//! roots: moved only rigidly, it gives the same roots and motion as the same rigid motion given
//! as `[motion] kind = "keyframes"` on the still mesh, within the samples' interpolation error;
//! and a topology that changes between samples is refused with its error. The files are written
//! here: a sphere, 60 strands on its cap, and the sphere's samples.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{Quat, Vec3};
use hairlod::core::Curves;
use hairlod::{Level, SceneFile, Shot};

/// Radius of the sphere [m].
const RADIUS: f32 = 0.1;

/// Angular speed of the rigid turn about +Y [rad/s] and the drift along +X [m/s].
const SPIN: f32 = 0.6;
const DRIFT: f32 = 0.02;

/// Time codes per second of the samples, and their count (0..=24: one second).
const CODES_PER_SECOND: f32 = 24.0;
const CODES: usize = 24;

/// A UV sphere: 12 rings × 16 segments, counter-clockwise seen from outside.
fn sphere() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (rings, segments) = (12, 16);
    let mut points = vec![Vec3::Y * RADIUS];
    for ring in 1..rings {
        let polar = std::f32::consts::PI * ring as f32 / rings as f32;
        for segment in 0..segments {
            let azimuth = std::f32::consts::TAU * segment as f32 / segments as f32;
            points.push(
                RADIUS
                    * Vec3::new(
                        polar.sin() * azimuth.cos(),
                        polar.cos(),
                        -polar.sin() * azimuth.sin(),
                    ),
            );
        }
    }
    points.push(-Vec3::Y * RADIUS);
    let bottom = points.len() as u32 - 1;
    let at = |ring: u32, segment: u32| 1 + (ring - 1) * segments + segment % segments;
    let mut triangles = Vec::new();
    for segment in 0..segments {
        triangles.push([0, at(1, segment), at(1, segment + 1)]);
        for ring in 1..rings - 1 {
            let (a, b) = (at(ring, segment), at(ring, segment + 1));
            let (c, d) = (at(ring + 1, segment), at(ring + 1, segment + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
        triangles.push([at(rings - 1, segment), bottom, at(rings - 1, segment + 1)]);
    }
    (points, triangles)
}

/// The rigid pose at time `t` [s]: turned `SPIN·t` about +Y, moved `DRIFT·t` along +X.
fn pose(t: f32) -> (Quat, Vec3) {
    (Quat::from_rotation_y(SPIN * t), Vec3::X * DRIFT * t)
}

/// A USD layer with the sphere as one `Mesh`: its points at every code when `animated`, else
/// its rest points; `counts_at` gives a sample its own faceVertexCounts (a topology change).
fn usd(animated: bool, counts_at: Option<usize>) -> String {
    let (points, triangles) = sphere();
    let list = |points: &[Vec3]| {
        let mut out = String::from("[");
        for p in points {
            write!(out, "({}, {}, {}), ", p.x, p.y, p.z).unwrap();
        }
        out.push(']');
        out
    };
    let counts = vec!["3"; triangles.len()].join(", ");
    let indices: Vec<String> = triangles.iter().flatten().map(u32::to_string).collect();
    let mut text = format!(
        "#usda 1.0\n(\n    timeCodesPerSecond = {CODES_PER_SECOND}\n    upAxis = \"Y\"\n    \
         metersPerUnit = 1\n)\n\ndef Mesh \"body\"\n{{\n"
    );
    match counts_at {
        None => writeln!(text, "    int[] faceVertexCounts = [{counts}]").unwrap(),
        Some(code) => {
            let fewer = vec!["3"; triangles.len() - 1].join(", ");
            writeln!(
                text,
                "    int[] faceVertexCounts.timeSamples = {{ 0: [{counts}], {code}: [{fewer}] }}"
            )
            .unwrap()
        }
    }
    writeln!(
        text,
        "    int[] faceVertexIndices = [{}]",
        indices.join(", ")
    )
    .unwrap();
    if animated {
        text.push_str("    point3f[] points.timeSamples = {\n");
        for code in 0..=CODES {
            let (rotation, translation) = pose(code as f32 / CODES_PER_SECOND);
            let moved: Vec<Vec3> = points.iter().map(|&p| rotation * p + translation).collect();
            writeln!(text, "        {code}: {},", list(&moved)).unwrap();
        }
        text.push_str("    }\n");
    } else {
        writeln!(text, "    point3f[] points = {}", list(&points)).unwrap();
    }
    text.push_str("}\n");
    text
}

/// 60 strands of 8 points, 1.5 cm apart along the sphere's normal, rooted on its upper cap.
fn groom() -> Curves {
    let mut curves = Curves {
        offsets: vec![0],
        ..Curves::default()
    };
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    for k in 0..60 {
        let y = 1.0 - (k as f32 + 0.5) / 60.0 * 0.6;
        let r = (1.0 - y * y).sqrt();
        let normal = Vec3::new(
            r * (golden * k as f32).cos(),
            y,
            r * (golden * k as f32).sin(),
        );
        for i in 0..8 {
            curves.points.push(normal * (RADIUS + 0.015 * i as f32));
        }
        curves.offsets.push(curves.points.len() as u32);
    }
    curves
}

/// The files in a fresh folder of the test `name`: `groom.hair`, `moving.usda`, `still.usda`.
fn files(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hairlod-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    hairlod::formats::write_hair(dir.join("groom.hair"), &groom()).unwrap();
    std::fs::write(dir.join("moving.usda"), usd(true, None)).unwrap();
    std::fs::write(dir.join("still.usda"), usd(false, None)).unwrap();
    dir
}

/// The shot of the groom on `body` with `motion` (scene text), strands, collision on through the
/// hierarchies (a deforming body always collides through them: a field would be built again
/// every frame), so both runs find contacts the same way.
fn shot(dir: &Path, body: &str, motion: &str) -> Shot {
    let text = format!(
        "[groom]\nfile = \"{}\"\nstrands_per_section = 5\nchildren_per_strand = 0\n\
         [body]\nfile = \"{}\"\n{motion}\n[lod]\nmode = \"strands\"\n[dynamics]\ncollision_broad_phase = \"hierarchies\"\n\
         [camera]\ntarget = [0.0, 0.0, 0.0]\ndistance = 0.8\n[frames]\ncount = 30\n\
         size = \"160x90\"\n",
        dir.join("groom.hair").display(),
        dir.join(body).display()
    );
    SceneFile::parse(&text).unwrap().resolve().unwrap()
}

#[test]
fn a_rigidly_sampled_body_moves_the_hair_as_the_same_keyframed_motion() {
    let dir = files("rigid-samples");
    let moving = shot(&dir, "moving.usda", "");
    // The body file's first sample is frame 0, which shows the state one step in (at run time
    // 1/fps, fps = 60 by default): code c plays at run time c/24 + 1/60 s.
    let mut keys = String::from("[motion]\nkind = \"keyframes\"\nkeyframes = [\n");
    for code in 0..=CODES {
        let t = code as f32 / CODES_PER_SECOND;
        writeln!(
            keys,
            "  {{ time = {}, rotation_degrees = [0.0, {}, 0.0], translation = [{}, 0.0, 0.0] }},",
            f64::from(t) + 1.0 / 60.0,
            (SPIN * t).to_degrees(),
            DRIFT * t
        )
        .unwrap();
    }
    keys.push(']');
    let keyed = shot(&dir, "still.usda", &keys);
    let moving_scene = moving.build_scene().unwrap();
    let keyed_scene = keyed.build_scene().unwrap();
    assert!(keyed_scene.body_motion.is_none());
    // The shot reads the body for its own frames: 30 frames at 60 Hz are 0.5 s, codes 0..=12 of
    // the file's 0..=24 at 24 per second, and code 13 after them (the window interpolates as
    // the whole file does; the run never reads past it).
    let motion = moving_scene.body_motion.as_ref().expect("a moving body");
    assert_eq!(motion.times().len(), 14);
    let last = motion.times()[13];
    assert!((last - (13.0 / 24.0 + 1.0 / 60.0)).abs() < 1e-9, "{last}");
    let mut a = moving
        .pipeline(&moving_scene, moving.settings, None)
        .unwrap();
    let mut b = keyed.pipeline(&keyed_scene, keyed.settings, None).unwrap();
    // Between samples the mesh's vertices move on chords, the keyframed head on arcs: a point
    // at radius r sags by at most r·Δθ²/8 (Δθ = SPIN/24 rad per sample), 7.8 µm on the sphere.
    // The turn is about a fixed axis, so a lerped triangle's frame is the arc's exactly.
    let dtheta = SPIN / CODES_PER_SECOND;
    let root_bound = RADIUS * dtheta * dtheta / 8.0 + 1e-6;
    let (mut roots, mut nodes) = (0.0f32, 0.0f32);
    for frame in 0..moving.frames {
        a.advance(&moving.camera(frame)).unwrap();
        b.advance(&keyed.camera(frame)).unwrap();
        let (pa, pb) = (
            &a.block(Level::StrandGroup).state.node_positions,
            &b.block(Level::StrandGroup).state.node_positions,
        );
        assert_eq!(pa.len(), pb.len());
        let per_chain = pa.len() / a.block(Level::StrandGroup).chains.len();
        for (k, (p, q)) in pa.iter().zip(pb).enumerate() {
            let d = p.distance(*q);
            nodes = nodes.max(d);
            if k % per_chain == 0 {
                roots = roots.max(d);
            }
        }
    }
    eprintln!("roots within {roots} m (bound {root_bound}), nodes within {nodes} m");
    assert!(
        roots <= root_bound,
        "roots {roots} m apart, bound {root_bound}"
    );
    // The chains answer the roots' few micrometres through their springs and contacts: a tenth
    // of a millimetre bounds that with room (measured 34 µm, the same as with collision off).
    assert!(nodes <= 1e-4, "nodes {nodes} m apart");
    // The hair moved: half a second of the turn carries the cap's roots centimetres.
    let moved = a.block(Level::StrandGroup).state.node_positions[0]
        .distance(moving_scene.groom.skeletons.root_positions[0]);
    assert!(moved > 0.005, "the first root moved {moved} m");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_body_whose_topology_changes_between_samples_is_refused_naming_it() {
    let dir = files("topology-change");
    std::fs::write(dir.join("changing.usda"), usd(true, Some(12))).unwrap();
    let error = shot(&dir, "changing.usda", "")
        .build_scene()
        .unwrap_err()
        .to_string();
    assert!(error.contains("body.file"), "{error}");
    assert!(error.contains("changing.usda"), "{error}");
    assert!(error.contains("/body"), "{error}");
    assert!(error.contains("12"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}
