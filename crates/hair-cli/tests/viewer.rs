//! `hairlod view` end to end, through the binary, in a real window: under the session's display,
//! or under an Xvfb server the test starts when `DISPLAY` is unset (CI installs `xvfb`). One
//! scripted run of the paper-curly scene checks the window's screenshots: the hair is drawn, the
//! HUD's text is there, the colour-code key turns the hair into the level colours, pausing keeps
//! two screenshots identical, and an orbit drag moves the head. Without any display the viewer
//! fails with a message that points to `hairlod render`.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BINARY: &str = env!("CARGO_BIN_EXE_hairlod");

/// Window size of the scripted run [pixels]: small, for a modest test time on a CPU rasterizer.
const WIDTH: u32 = 480;
const HEIGHT: u32 = 270;
/// The HUD's corner of the window [pixels]: the top-left box it is drawn in, at most.
const HUD_WIDTH: u32 = 370;
const HUD_HEIGHT: u32 = 140;

/// A fresh folder under the target's temporary directory.
fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("viewer_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// An Xvfb server this test started; stopped when dropped.
struct Xvfb(Child);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The X display to run the viewer on: `DISPLAY` when set, else a fresh Xvfb server on a free
/// display number (returned, to be stopped). Panics with what to install when neither exists.
fn display() -> (String, Option<Xvfb>) {
    if let Ok(display) = std::env::var("DISPLAY")
        && !display.is_empty()
    {
        return (display, None);
    }
    for number in 90..130 {
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
        if socket.exists() || Path::new(&format!("/tmp/.X{number}-lock")).exists() {
            continue;
        }
        let child = Command::new("Xvfb")
            .args([
                &format!(":{number}"),
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        let server = match child {
            Ok(child) => Xvfb(child),
            Err(error) => panic!(
                "DISPLAY is unset and Xvfb cannot be started ({error}): install xvfb \
                 (apt-get install xvfb) or run the tests under a display"
            ),
        };
        let started = Instant::now();
        while started.elapsed() < Duration::from_secs(10) {
            if socket.exists() {
                return (format!(":{number}"), Some(server));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    panic!("no Xvfb server came up on displays :90 to :129");
}

/// Runs the binary on `display`; returns its output.
fn hairlod(display: &str, args: &[&str]) -> std::process::Output {
    Command::new(BINARY)
        .args(args)
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap()
}

fn text(output: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn open(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// Pixels outside the HUD's corner that pass `test`.
fn count_outside_hud(image: &image::RgbaImage, test: impl Fn([u8; 3]) -> bool) -> usize {
    image
        .enumerate_pixels()
        .filter(|(x, y, _)| *x >= HUD_WIDTH || *y >= HUD_HEIGHT)
        .filter(|(_, _, p)| test([p.0[0], p.0[1], p.0[2]]))
        .count()
}

/// The level colours (strands yellow, clusters red, patches blue; unlit in the colour-coded
/// mode), as the render tests read them.
fn is_level_color([r, g, b]: [u8; 3]) -> bool {
    let yellow = r > 200 && g > 200 && b < 60;
    let red = r > 200 && g < 60 && b < 60;
    let blue = b > 200 && r < 60 && g < 60;
    yellow || red || blue
}

/// The colour-coded head: flat grey 0.2 (linear), 124 in sRGB.
fn is_coded_head([r, g, b]: [u8; 3]) -> bool {
    [r, g, b].iter().all(|c| c.abs_diff(124) <= 6)
}

/// The background: 0.02, 0.02, 0.03 (linear), about 39, 39, 48 in sRGB.
fn is_background([r, g, b]: [u8; 3]) -> bool {
    r.abs_diff(39) <= 4 && g.abs_diff(39) <= 4 && b.abs_diff(48) <= 4
}

/// The x, y centroid [pixels] of the colour-coded head's pixels outside the HUD's corner.
fn head_centroid(image: &image::RgbaImage) -> (f64, f64, usize) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0usize);
    for (x, y, p) in image.enumerate_pixels() {
        if (x >= HUD_WIDTH || y >= HUD_HEIGHT) && is_coded_head([p.0[0], p.0[1], p.0[2]]) {
            sx += f64::from(x);
            sy += f64::from(y);
            n += 1;
        }
    }
    (sx / n.max(1) as f64, sy / n.max(1) as f64, n)
}

#[test]
fn a_scripted_viewer_run_draws_hair_and_hud_and_obeys_the_keys() {
    let (display, _server) = display();
    let dir = folder("scripted");
    let script = dir.join("script.txt");
    // Frame 0 is egui's sizing pass (no HUD yet); from frame 1 the HUD is drawn.
    std::fs::write(
        &script,
        "3 screenshot shaded.png\n\
         4 key c                   # colour-code by level\n\
         4 screenshot coded.png\n\
         5 key space               # pause\n\
         6 screenshot paused_a.png\n\
         8 screenshot paused_b.png\n\
         9 drag left 160 0         # orbit the camera (still paused)\n\
         9 screenshot orbited.png\n",
    )
    .unwrap();
    // The paper-curly groom (the default) seen from its right side, where the face shows.
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "version = 2\n[camera]\npath = \"fixed\"\nazimuth_degrees = 90.0\n",
    )
    .unwrap();
    let size = format!("{WIDTH}x{HEIGHT}");
    let checkpoint = dir.join("checkpoint.json");
    let output = hairlod(
        &display,
        &[
            "view",
            scene.to_str().unwrap(),
            "--size",
            &size,
            "--frames",
            "10",
            "--screenshot",
            dir.join("last.png").to_str().unwrap(),
            "--script",
            script.to_str().unwrap(),
            "--checkpoint-on-exit",
            checkpoint.to_str().unwrap(),
        ],
    );
    let log = text(&output);
    assert!(output.status.success(), "hairlod view failed:\n{log}");

    let shaded = open(&dir.join("shaded.png"));
    let coded = open(&dir.join("coded.png"));
    assert_eq!(shaded.dimensions(), (WIDTH, HEIGHT), "{log}");
    let pixels = (WIDTH * HEIGHT) as usize;
    // Hair is drawn: in the shaded frame a good part of the view is neither background nor
    // level colours; the colour-coded frame shows the hair in level colours.
    let drawn = count_outside_hud(&shaded, |p| !is_background(p));
    assert!(
        drawn > pixels / 20,
        "{drawn} drawn pixels of {pixels}\n{log}"
    );
    assert_eq!(count_outside_hud(&shaded, is_level_color), 0, "{log}");
    let coded_hair = count_outside_hud(&coded, is_level_color);
    assert!(
        coded_hair > pixels / 50,
        "{coded_hair} level-coloured pixels after `c`\n{log}"
    );
    // The HUD's text: light grey glyphs (not brown hair) on its dark box in the top-left corner.
    let hud_text = shaded
        .enumerate_pixels()
        .filter(|(x, y, p)| {
            let [r, g, b, _] = p.0;
            *x < HUD_WIDTH && *y < HUD_HEIGHT && r.min(g).min(b) > 180 && r.abs_diff(b) < 30
        })
        .count();
    assert!(hud_text > 300, "{hud_text} HUD text pixels\n{log}");
    // Paused: the frame and the HUD stay as they are.
    let paused_a = open(&dir.join("paused_a.png"));
    let paused_b = open(&dir.join("paused_b.png"));
    assert!(paused_a == paused_b, "two paused screenshots differ\n{log}");
    // The orbit drag turns the camera from the side towards the face: the head moves in the
    // image.
    let orbited = open(&dir.join("orbited.png"));
    let before = head_centroid(&paused_b);
    let after = head_centroid(&orbited);
    assert!(before.2 > 100 && after.2 > 100, "{before:?} {after:?}");
    let moved = ((after.0 - before.0).powi(2) + (after.1 - before.1).powi(2)).sqrt();
    assert!(
        moved > 10.0,
        "the head moved {moved:.1} pixels: {before:?} -> {after:?}"
    );
    assert!(dir.join("last.png").exists(), "{log}");
    // Closing wrote the checkpoint of the paused run (frames 0..5 stepped), and `render` goes
    // on from it.
    let state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    assert_eq!(state["state"]["frame"], 5, "{log}");
    let out = dir.join("resumed");
    let resumed = hairlod(
        &display,
        &[
            "render",
            scene.to_str().unwrap(),
            "--size",
            &size,
            "--resume",
            checkpoint.to_str().unwrap(),
            "--frames",
            "5..6",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(resumed.status.success(), "{}", text(&resumed));
    assert!(out.join("frame_00005.png").exists(), "{}", text(&resumed));
}

#[test]
fn without_a_display_the_viewer_says_to_use_render() {
    let output = Command::new(BINARY)
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let log = text(&output);
    assert!(!output.status.success(), "{log}");
    assert!(
        log.contains("cannot open a window") && log.contains("hairlod render"),
        "{log}"
    );
    assert!(!log.contains("panicked"), "{log}");
}
