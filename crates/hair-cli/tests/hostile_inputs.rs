//! Inputs issue 50 found getting through, through the binary: a one-section groom (documented as
//! valid) builds; a groom file a scene could not use fails `hairlod groom --file`, naming the
//! file and the scale, after its fit report; a failed export names its path once; a TressFX 2.0
//! text file is named as one; a render banner names a file groom's file. The grooms are small
//! synthetic files written here.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

use common::BINARY;

fn run(args: &[&str]) -> Output {
    Command::new(BINARY).args(args).output().unwrap()
}

fn text(output: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// An OBJ groom of 20 straight strands, 10 cm long at `scale` = 1 (times `scale` in the file),
/// rooted over the top of the head, at `dir/name`.
fn obj_groom(dir: &Path, name: &str, scale: f32) -> PathBuf {
    let mut obj = String::new();
    for k in 0..20 {
        let angle = k as f32 * 2.399;
        let (x, z) = (0.04 * angle.cos(), 0.04 * angle.sin());
        for j in 0..4 {
            let t = j as f32 / 3.0;
            let p = [x * (1.0 + t), 0.1 - 0.1 * t, z * (1.0 + t)].map(|c| c * scale);
            obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
        let base = 4 * k + 1;
        obj += &format!("l {} {} {} {}\n", base, base + 1, base + 2, base + 3);
    }
    let path = dir.join(name);
    std::fs::write(&path, obj).unwrap();
    path
}

#[test]
fn a_one_section_groom_builds_and_exports_hanging() {
    let dir = common::folder("hostile_one_section");
    let export = dir.join("one.obj");
    let output = run(&[
        "groom",
        "--preset",
        "straight",
        "--sections",
        "1",
        "--strands-per-group",
        "1",
        "--export",
        export.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("sections               1"), "{stdout}");
    assert!(stderr.contains("hung the groom"), "{stderr}");
    let obj = std::fs::read_to_string(&export).unwrap();
    // One section: 5 strand groups of one strand each.
    assert_eq!(obj.lines().filter(|l| l.starts_with("l ")).count(), 5);
}

#[test]
fn a_groom_file_a_scene_cannot_use_fails_naming_the_file_and_the_scale() {
    let dir = common::folder("hostile_groom_file");
    // Centimetres read as metres (25 m across), and a groom under 5 mm across.
    for (name, scale, reason) in [
        ("centimetres.obj", 100.0, "m across at groom.scale = 1"),
        ("tiny.obj", 0.02, "every curve is shorter than 0.005 m"),
    ] {
        let path = obj_groom(&dir, name, scale);
        let file = path.to_str().unwrap();
        let output = run(&["groom", "--file", file, "--json"]);
        let (stdout, stderr) = text(&output);
        assert!(!output.status.success(), "{name}: exit 0\n{stdout}{stderr}");
        assert!(stderr.contains(&format!("{file} was fitted")), "{stderr}");
        assert!(stderr.contains("at --scale 1"), "{stderr}");
        assert!(stderr.contains(reason), "{stderr}");
        // The fit report still comes out, with why the rest pose is missing.
        let report: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(report["fit"]["strands"], 20, "{report}");
        assert!(report["rest_pose"].is_null(), "{report}");
        assert!(
            report["rest_pose_error"]
                .as_str()
                .is_some_and(|why| why.contains(reason)),
            "{report}"
        );
    }
    // In metres it builds, and exits 0.
    let path = obj_groom(&dir, "metres.obj", 1.0);
    let output = run(&["groom", "--file", path.to_str().unwrap()]);
    assert!(output.status.success(), "{:?}", text(&output));
}

#[test]
fn a_failed_export_names_its_path_once() {
    let dir = common::folder("hostile_export");
    let path = dir.join("no-such-folder").join("groom.obj");
    let output = run(&[
        "groom",
        "--preset",
        "straight",
        "--sections",
        "2",
        "--strands-per-group",
        "1",
        "--rest-pose",
        "grown",
        "--export",
        path.to_str().unwrap(),
    ]);
    let (_, stderr) = text(&output);
    assert!(!output.status.success(), "{stderr}");
    let named = format!("writing {}", path.display());
    assert_eq!(stderr.matches(&named).count(), 1, "{stderr}");
}

#[test]
fn a_tressfx_2_text_file_is_named_as_one() {
    let dir = common::folder("hostile_tfx_text");
    let path = dir.join("fibermesh.tfx");
    std::fs::write(
        &path,
        "version 2.0\nscale 1.0\nnumStrands 1\nis sorted 1\n\
         strand 0 numVerts 2 texcoord 0.000000 000000\n0.0, 0.0, 0.0\n0.0, 1.0, 0.0\n",
    )
    .unwrap();
    let output = run(&["groom", "--file", path.to_str().unwrap()]);
    let (_, stderr) = text(&output);
    assert!(!output.status.success(), "{stderr}");
    assert!(stderr.contains(path.to_str().unwrap()), "{stderr}");
    assert!(
        stderr.contains("`version 2.0` (a TressFX 2.0 text file)"),
        "{stderr}"
    );
    assert!(stderr.contains("OBJ polylines"), "{stderr}");
    assert!(!stderr.contains("unsupported TressFX version"), "{stderr}");
}

#[test]
fn the_render_banner_names_a_file_groom_by_its_file() {
    let dir = common::folder("hostile_banner");
    obj_groom(&dir, "groom.obj", 1.0);
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[groom]\nfile = \"groom.obj\"\n\
         [frames]\ncount = 1\nsize = \"32x24\"\n",
    )
    .unwrap();
    let out = dir.join("frames");
    let output = run(&[
        "render",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&output);
    assert!(output.status.success(), "{stdout}{stderr}");
    let banner = stderr
        .lines()
        .find(|line| line.starts_with("rendering frames"))
        .unwrap_or_else(|| panic!("no banner: {stderr}"));
    assert!(
        banner.contains("the groom file ") && banner.contains("groom.obj"),
        "{banner}"
    );
    assert!(!banner.contains("paper-curly"), "{banner}");
}
