//! `hairlod render` end to end, through the binary: a scene file at automatic levels with a
//! shaking head, colour-coded by level, shows more than one level and a head that moves; a run
//! split by a checkpoint writes the same frames as one run straight through; bad scene files and
//! flags get errors that name the field.

use std::path::{Path, PathBuf};
use std::process::Command;

const BINARY: &str = env!("CARGO_BIN_EXE_hairlod");

/// A fresh folder under the target's temporary directory.
fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("render_scene_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small scene: the curly groom seen from the side at 1.1 m, 4 frames at 30 Hz, 256×160,
/// automatic levels, colour-coded, the head doing `motion`.
fn scene(dir: &Path, motion: &str) -> PathBuf {
    let path = dir.join("scene.toml");
    let text = format!(
        "version = 2\n\
         [groom]\npreset = \"curly\"\n\
         [motion]\nkind = \"{motion}\"\namplitude_degrees = 30.0\npeak_speed = 4.0\n\
         [camera]\npath = \"fixed\"\ndistance = 1.1\nazimuth_degrees = 80.0\nelevation_degrees = 5.0\n\
         [lod]\nmode = \"auto\"\npixel_tolerance = 2.0\n\
         [dynamics]\nsettle_seconds = 0.25\n\
         [frames]\ncount = 4\nfps = 30\nsize = \"256x160\"\n\
         [output]\ncolor_coded = true\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs the binary; panics with its output when it fails.
fn hairlod(args: &[&str]) -> String {
    let output = Command::new(BINARY).args(args).output().unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(output.status.success(), "hairlod {args:?} failed:\n{text}");
    text
}

fn frame(dir: &Path, index: usize) -> image::RgbaImage {
    let path = dir.join(format!("frame_{index:05}.png"));
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// Which level colours appear (strands yellow, clusters red, patches blue: the renderer's
/// defaults, written unlit in the colour-coded mode), in more than 20 pixels each.
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
    counts.map(|n| n > 20)
}

/// The pixels showing the head: its colour-code grey (linear 0.2, unlit), r = g = b.
fn head_mask(image: &image::RgbaImage) -> Vec<bool> {
    image
        .pixels()
        .map(|p| {
            let [r, g, b, _] = p.0;
            r == g && g == b && (100..=150).contains(&r)
        })
        .collect()
}

/// Pixels where the head is in one image and not the other.
fn head_change(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    head_mask(a)
        .iter()
        .zip(head_mask(b))
        .filter(|(x, y)| **x != *y)
        .count()
}

#[test]
fn a_shaking_head_at_automatic_levels_shows_several_levels_and_moves() {
    let shaking = folder("shake");
    let out = shaking.join("frames");
    let text = hairlod(&[
        "render",
        scene(&shaking, "shake").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
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
    let head_pixels = head_mask(&images[0]).iter().filter(|h| **h).count();
    assert!(head_pixels > 500, "the head is drawn: {head_pixels} pixels");

    // The same scene with the head still: only the hair's settling moves the head's outline.
    let still = folder("still");
    let still_out = still.join("frames");
    hairlod(&[
        "render",
        scene(&still, "still").to_str().unwrap(),
        "--out",
        still_out.to_str().unwrap(),
    ]);
    let moving = head_change(&images[0], &images[3]);
    let resting = head_change(&frame(&still_out, 0), &frame(&still_out, 3));
    // 30° of shake seen from the side moves the face's outline by tens of pixels along its
    // height: hundreds of pixels change, against the few that settling hair uncovers.
    assert!(
        moving > 200 && moving > 4 * resting,
        "head pixels changed: shaking {moving}, still {resting}"
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
    // A checkpoint of another scene is refused, naming the mismatch.
    let other = dir.join("other.toml");
    std::fs::write(&other, "[groom]\npreset = \"wavy\"\n[frames]\ncount = 4\n").unwrap();
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
    assert!(!output.status.success() && error.contains("voxels"), "{error}");
}
