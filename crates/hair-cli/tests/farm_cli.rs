//! `hairlod simulate`, `hairlod render --from-cache` and `hairlod farm`: a shot simulated in
//! chained chunks and rendered from the cache in chunks, in reverse order, writes the same PNG
//! bytes as one `hairlod render`; bad caches and chunks are refused naming the file and frame.
//! (`.ci/farm_check.sh` runs a generated template with the real OpenJD runner.)

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{BINARY, folder, hairlod};

/// A shaking, wind-blown wavy groom on a zoom-out: its sections change level and blend.
const SCENE: &str = "[groom]\npreset = \"wavy\"\nsection_count = 24\nstrands_per_group = 6\n\
     rest_pose = \"grown\"\n[dynamics]\nsettle_seconds = 0.0\n\
     [motion]\nkind = \"shake\"\namplitude_degrees = 20.0\npeak_speed = 3.0\n\
     [wind]\nspeed = 2.0\ngusts = 1.0\n\
     [camera]\npath = \"zoom-out\"\ndistance = 0.5\nend_distance = 6.0\n\
     [lod]\npixel_tolerance = 2.0\nblend_time = 0.05\n\
     [frames]\ncount = 6\nfps = 60\nsize = \"96x64\"\n";

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every PNG of `dir`, by name, with its bytes.
fn pngs(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).unwrap())
        })
        .collect();
    files.sort();
    files
}

/// The arguments of `hairlod render SCENE --from-cache CACHE --out OUT` followed by `extra`.
fn from_cache<'a>(
    scene: &'a Path,
    cache: &'a Path,
    out: &'a Path,
    extra: &[&'a str],
) -> Vec<&'a str> {
    let mut args = vec![
        "render",
        path(scene),
        "--from-cache",
        path(cache),
        "--out",
        path(out),
    ];
    args.extend_from_slice(extra);
    args
}

/// Runs the binary expecting it to fail; returns what it printed.
fn fails(args: &[&str]) -> String {
    let output = Command::new(BINARY).args(args).output().unwrap();
    assert!(!output.status.success(), "hairlod {args:?} succeeded");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn chunks_simulated_and_rendered_from_the_cache_make_the_frames_of_one_render() {
    let dir = folder("farm-chunks");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let straight = dir.join("straight");
    hairlod(&["render", path(&scene), "--out", path(&straight)]);

    let cache = dir.join("cache");
    // The second chunk cannot run before the first: it names the checkpoint it needs.
    let error = fails(&[
        "simulate",
        path(&scene),
        "--cache",
        path(&cache),
        "--chunk",
        "2/2",
    ]);
    assert!(
        error.contains("checkpoint_00003.json") && error.contains("chunk 1/2"),
        "{error}"
    );
    for chunk in ["1/2", "2/2"] {
        hairlod(&[
            "simulate",
            path(&scene),
            "--cache",
            path(&cache),
            "--chunk",
            chunk,
        ]);
    }
    for frame in 0..6 {
        let record = cache.join(format!("frame_{frame:05}.hlc"));
        assert!(record.is_file(), "no record of frame {frame}");
    }
    // Rendered in reverse chunk order, each chunk a process of its own.
    let cached = dir.join("cached");
    for chunk in ["3/3", "2/3", "1/3"] {
        hairlod(&from_cache(&scene, &cache, &cached, &["--chunk", chunk]));
    }
    let (a, b) = (pngs(&straight), pngs(&cached));
    assert_eq!(a.len(), 6);
    assert_eq!(
        a.iter().map(|f| &f.0).collect::<Vec<_>>(),
        b.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(
            x == y,
            "{name} from the cache differs from the straight render"
        );
    }

    // What the cache refuses, naming the file and frame.
    let other_scene = dir.join("other.toml");
    std::fs::write(&other_scene, SCENE.replace("96x64", "96x48")).unwrap();
    let out = dir.join("refused");
    let error = fails(&from_cache(&other_scene, &cache, &out, &[]));
    assert!(
        error.contains("frame_00000.hlc") && error.contains("another run"),
        "{error}"
    );
    let record = cache.join("frame_00004.hlc");
    let bytes = std::fs::read(&record).unwrap();
    std::fs::write(&record, &bytes[..bytes.len() / 2]).unwrap();
    let error = fails(&from_cache(&scene, &cache, &out, &["--frames", "4..6"]));
    assert!(
        error.contains("frame_00004.hlc")
            && error.contains("frame 4")
            && error.contains("truncated"),
        "{error}"
    );
    std::fs::remove_file(&record).unwrap();
    let error = fails(&from_cache(&scene, &cache, &out, &["--chunk", "3/3"]));
    assert!(
        error.contains("frame 4") && error.contains("missing"),
        "{error}"
    );
    let error = fails(&from_cache(&scene, &cache, &out, &["--chunk", "4/3"]));
    assert!(error.contains("chunk 4 of 3 is out of range"), "{error}");
    let error = fails(&from_cache(
        &scene,
        &cache,
        &out,
        &["--chunk", "1/3", "--frames", "0..2"],
    ));
    assert!(error.contains("give one"), "{error}");
    // No frame was written by a refused run.
    assert!(!out.exists() || pngs(&out).is_empty());
}

#[test]
fn farm_writes_a_template_per_scene() {
    let dir = folder("farm-template");
    let scene = dir.join("shot.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let job = dir.join("job.yaml");
    hairlod(&[
        "farm",
        path(&scene),
        "--out",
        path(&job),
        "--simulation-chunks",
        "2",
        "--render-chunks",
        "3",
    ]);
    let text = std::fs::read_to_string(&job).unwrap();
    for needle in [
        "jobtemplate-2023-09",
        "Simulate-2",
        "Render-1",
        "dependsOn: \"Simulate-1\"",
        "\"{{Task.Param.Chunk}}/{{Param.RenderChunks}}\"",
        // PATH defaults are relative to the template's folder (OpenJD joins them to it).
        "default: \"shot.toml\"",
        "default: \"shot.cache\"",
    ] {
        assert!(text.contains(needle), "no {needle} in\n{text}");
    }
    // Several scenes: one template each in a folder.
    let second = dir.join("second.toml");
    std::fs::write(&second, SCENE).unwrap();
    let jobs: PathBuf = dir.join("jobs");
    hairlod(&["farm", path(&scene), path(&second), "--out", path(&jobs)]);
    assert!(jobs.join("shot.job.yaml").is_file() && jobs.join("second.job.yaml").is_file());
    // More chunks than frames is refused.
    let error = fails(&[
        "farm",
        path(&scene),
        "--out",
        path(&job),
        "--render-chunks",
        "7",
    ]);
    assert!(error.contains("7 chunks for a shot of 6 frames"), "{error}");
}
