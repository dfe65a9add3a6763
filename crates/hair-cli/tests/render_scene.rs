//! `hairlod render` end to end, through the binary: a scene file at automatic levels with a
//! shaking head, colour-coded by level, shows more than one level; the head mesh is drawn where
//! the simulation moves it (checked against the projected displacement); a run
//! split by a checkpoint writes the same frames as one run straight through; bad scene files and
//! flags get errors that name the field.

use hairlod::core::representation::drawn::strand_last_point;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

use common::{BINARY, hairlod};

/// A fresh folder under the target's temporary directory.
fn folder(name: &str) -> PathBuf {
    common::folder(&format!("render_scene_{name}"))
}

/// The head swaying sideways: 5 cm along +X over the first 0.2 s, then held.
const SWAY: &str = "kind = \"keyframes\"\nkeyframes = [{ time = 0.0 }, \
                    { time = 0.2, translation = [0.05, 0.0, 0.0] }]\n";

/// A small scene: a short curly groom (12 sections, 10 cm) seen from the front at 1.1 m, 4 frames
/// at 15 Hz, 256×160, automatic levels, colour-coded, the head doing `motion` (`shake`, `still`
/// or `sway`).
fn scene(dir: &Path, motion: &str) -> PathBuf {
    let motion = match motion {
        "sway" => SWAY.to_string(),
        kind => format!("kind = \"{kind}\"\namplitude_degrees = 30.0\npeak_speed = 4.0\n"),
    };
    let path = dir.join("scene.toml");
    let text = format!(
        "version = 2\n\
         [groom]\npreset = \"curly\"\nsection_count = 12\nhair_length = 0.1\n\
         [motion]\n{motion}\
         [camera]\npath = \"fixed\"\ndistance = 1.1\nazimuth_degrees = 0.0\nelevation_degrees = 0.0\n\
         [lod]\nmode = \"auto\"\npixel_tolerance = 2.0\n\
         [dynamics]\nsettle_seconds = 1.0\n\
         [frames]\ncount = 4\nfps = 15\nsize = \"256x160\"\n\
         [output]\ncolor_coded = true\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn frame(dir: &Path, index: usize) -> image::RgbaImage {
    let path = dir.join(format!("frame_{index:05}.png"));
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// Which level colours appear (strands yellow, clusters red, patches blue: the renderer's
/// defaults, written unlit in the colour-coded mode), in more than 8 pixels each. Nothing else in
/// the frame has these saturated colours (the background and head are grey, and edges blend a
/// level's colour only towards grey), so a handful of pixels is a level on screen, not noise: a
/// fading level draws only the strands its coverage shows, a few pixels at 256×160.
fn levels_seen(image: &image::RgbaImage) -> [bool; 3] {
    let mut counts = [0usize; 3];
    for p in image.pixels() {
        let [r, g, b, _] = p.0;
        if r > 200 && g > 200 && b < 60 {
            counts[2] += 1;
        } else if r > 200 && g < 60 && b < 60 {
            counts[1] += 1;
        } else if b > 200 && r < 60 && g < 60 {
            counts[0] += 1;
        }
    }
    counts.map(|n| n > 8)
}

#[test]
fn a_shaking_head_at_automatic_levels_shows_several_levels() {
    let shaking = folder("shake");
    let out = shaking.join("frames");
    let text = hairlod(&[
        "render",
        scene(&shaking, "shake").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--level",
        "auto",
        "--color-code",
        "--motion",
        "shake",
    ]);
    let images: Vec<_> = (0..4).map(|k| frame(&out, k)).collect();
    // More than one level over the frames (the face and part line stay at least clusters, the
    // rest may go coarser).
    let mut seen = [false; 3];
    for image in &images {
        for (s, l) in seen.iter_mut().zip(levels_seen(image)) {
            *s |= l;
        }
    }
    assert!(
        seen.iter().filter(|s| **s).count() >= 2,
        "levels seen (patches, clusters, strands): {seen:?}\n{text}"
    );
}

/// The x centroid [pixels] of the head's pixels in rows that show no hair in either image (the
/// neck and chin, which the hair's own motion cannot cover or uncover).
fn bare_head_centroid(image: &image::RgbaImage, other: &image::RgbaImage) -> f64 {
    let (width, height) = image.dimensions();
    let is_hair = |p: &image::Rgba<u8>| {
        let [r, g, b, _] = p.0;
        r > 200 || g > 200 || b > 200
    };
    let (mut sum, mut count) = (0.0, 0usize);
    for y in 0..height {
        let hair_row =
            (0..width).any(|x| is_hair(image.get_pixel(x, y)) || is_hair(other.get_pixel(x, y)));
        if hair_row {
            continue;
        }
        for x in 0..width {
            let [r, g, b, _] = image.get_pixel(x, y).0;
            if r == g && g == b && (100..=150).contains(&r) {
                sum += f64::from(x) + 0.5;
                count += 1;
            }
        }
    }
    assert!(
        count > 100,
        "too few bare head pixels ({count}) to place the head"
    );
    sum / count as f64
}

#[test]
fn the_head_mesh_is_drawn_where_the_simulation_moves_it() {
    let dir = folder("sway");
    let out = dir.join("frames");
    hairlod(&[
        "render",
        scene(&dir, "sway").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let (first, third) = (frame(&out, 0), frame(&out, 2));
    let shift = bare_head_centroid(&third, &first) - bare_head_centroid(&first, &third);
    println!("bare head shift {shift:.3} px");
    // Frame k is drawn at t = (k + 1)/15 s, so the head has moved from 5 cm·(1/15)/0.2 to
    // 5 cm·(3/15)/0.2, by 3.33 cm, across the view. Seen from 1.1 m with a 35° vertical field of
    // view over 160 pixels (focal length 80/tan 17.5° = 253.7 px), that is 0.0333·253.7/1.1 =
    // 7.7 pixels to the right (+X is to the camera's right from the front). Pixel rounding and
    // the neck's depth of a few cm allow one pixel.
    let expected = 0.05 * (2.0 / 3.0) * (80.0 / 17.5f64.to_radians().tan()) / 1.1;
    assert!(
        (shift - expected).abs() < 1.0,
        "the bare head moved {shift:.2} px, expected {expected:.2}"
    );
}

#[test]
fn a_run_split_by_a_checkpoint_writes_the_same_frames() {
    let dir = folder("resume");
    let scene = scene(&dir, "shake");
    let scene = scene.to_str().unwrap();
    let straight = dir.join("straight");
    let split = dir.join("split");
    let checkpoints = dir.join("checkpoints");
    hairlod(&["render", scene, "--out", straight.to_str().unwrap()]);
    let first = hairlod(&[
        "render",
        scene,
        "--out",
        split.to_str().unwrap(),
        "--frames",
        "0..2",
        "--checkpoint",
        checkpoints.to_str().unwrap(),
    ]);
    let checkpoint = checkpoints.join("checkpoint_00002.json");
    assert!(checkpoint.exists(), "{first}");
    hairlod(&[
        "render",
        scene,
        "--out",
        split.to_str().unwrap(),
        "--resume",
        checkpoint.to_str().unwrap(),
    ]);
    for k in 0..4 {
        assert_eq!(frame(&straight, k), frame(&split, k), "frame {k}");
    }
    // A checkpoint of another scene is refused, naming the mismatch (a small wavy groom in its
    // grown shape, so that the refusal is not waiting for a full groom to hang).
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        "[groom]\npreset = \"wavy\"\nsection_count = 12\nhair_length = 0.1\nrest_pose = \"grown\"\n\
         [dynamics]\nsettle_seconds = 0.0\n[frames]\ncount = 4\n",
    )
    .unwrap();
    let output = Command::new(BINARY)
        .args(["render", other.to_str().unwrap(), "--out"])
        .arg(dir.join("other"))
        .args(["--resume", checkpoint.to_str().unwrap()])
        .output()
        .unwrap();
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(error.contains("another scene"), "{error}");
}

#[test]
fn bad_scenes_and_flags_name_the_problem() {
    let dir = folder("bad");
    for (text, expected) in [
        ("[camera]\nfov_degrees = 400.0\n", "camera.fov_degrees"),
        ("[wind]\nspeeed = 3.0\n", "speeed"),
        ("[lod]\nmode = \"voxels\"\n", "lod.mode"),
    ] {
        let path = dir.join("bad.toml");
        std::fs::write(&path, text).unwrap();
        let output = Command::new(BINARY)
            .args(["render", path.to_str().unwrap(), "--out"])
            .arg(dir.join("frames"))
            .output()
            .unwrap();
        let error = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{text}");
        assert!(error.contains(expected), "{text}: {error}");
    }
    let output = Command::new(BINARY)
        .args(["render", "--out"])
        .arg(dir.join("frames"))
        .args(["--level", "voxels"])
        .output()
        .unwrap();
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && error.contains("voxels"),
        "{error}"
    );
}

#[test]
fn every_frame_writes_every_strand_as_cyhair_and_usd() {
    // Automatic levels with a shaking head: sections at clusters or patches are handed over to
    // strand groups for the export, so every frame has every strand of the groom.
    let dir = folder("hair");
    let scene = scene(&dir, "shake");
    let out = dir.join("out");
    hairlod(&[
        "render",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--hair",
        "--usd",
    ]);
    let file = hairlod::SceneFile::read(&scene).unwrap();
    let built = file.resolve().unwrap().build_scene().unwrap();
    let strands = built.groom.strands.strand_count();
    let nodes = built.groom.skeletons.chain_node_count(0);
    let mut frames = Vec::new();
    for k in 0..4 {
        let path = out.join("hair").join(format!("frame_{k:05}.hair"));
        let curves = hairlod::formats::read_hair_file(&path, &Default::default())
            .unwrap_or_else(|error| panic!("{}: {error}", path.display()));
        assert_eq!(curves.curve_count(), strands, "frame {k}");
        // Two points per skeleton segment along the B-spline, root included, up to the strand's
        // length: the last point is where the strand ends (`strand_last_point`).
        let segments = 2 * (nodes - 1);
        for curve in 0..curves.curve_count() {
            let length = built.groom.strands.length(curve);
            assert_eq!(
                curves.range(curve).len(),
                strand_last_point(length, segments) + 1,
                "frame {k}, strand {curve} of length {length}"
            );
        }
        assert!(curves.points.iter().all(|p| p.is_finite()));
        frames.push(curves);
    }
    // The USD file holds the same strands, a time sample per frame (time code = frame).
    let usd = out.join("hair.usda");
    for (k, hair) in frames.iter().enumerate() {
        let curves = hairlod::formats::read_usda_file_at(&usd, k as f64, &Default::default())
            .unwrap_or_else(|error| panic!("{}: {error}", usd.display()));
        assert_eq!(curves.offsets, hair.offsets, "frame {k}");
        assert_eq!(curves.points, hair.points, "frame {k}");
    }
    // The head shakes, so the strands move between frames.
    let moved = frames[0]
        .points
        .iter()
        .zip(&frames[3].points)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(moved > 1e-3, "the strands moved {moved} m");
}

/// `--shading marschner` and `--line-coverage width` reach the renderer: the shaded frame of a
/// still head changes with each (the head's own pixels do not), and a bad value is refused
/// with the values allowed.
#[test]
fn shading_and_line_coverage_flags_change_the_hair() {
    let dir = folder("looks");
    let path = scene(&dir, "still");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("[output]\ncolor_coded = true\n", "");
    std::fs::write(&path, text).unwrap();
    let render = |name: &str, flags: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            path.to_str().unwrap(),
            "--frames",
            "1",
            "--level",
            "strands",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(flags);
        hairlod(&args);
        frame(&out, 0)
    };
    let plain = render("plain", &[]);
    let marschner = render("marschner", &["--shading", "marschner"]);
    let covered = render("covered", &["--line-coverage", "width"]);
    let changed = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
    };
    let (by_shading, by_coverage) = (changed(&plain, &marschner), changed(&plain, &covered));
    println!("pixels changed: {by_shading} by the shading, {by_coverage} by the coverage");
    // The groom covers a few thousand of the 40,960 pixels at 1.1 m.
    assert!(by_shading > 500 && by_coverage > 500);
    let output = Command::new(BINARY)
        .args(["render", "--shading", "phong"])
        .output()
        .unwrap();
    let error = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        error.contains("marschner") && error.contains("kajiya-kay"),
        "{error}"
    );
}
