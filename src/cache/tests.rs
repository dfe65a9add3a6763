//! Simulation caches: frames rendered from a cache are, bit for bit, the frames the simulating
//! process renders (a lone character and a crowd, from the start or from any frame, in any
//! order), and a cache refuses what is not its own.

use std::sync::Arc;

use super::*;
use crate::crowd::{Crowd, CrowdModel, CrowdRenderer, run_crowd};
use crate::pipeline::PipelineRenderer;
use crate::render::RendererOptions;
use crate::run::{RunOptions, View, run_frames, run_shot};
use crate::scene_file::SceneFile;

/// A shaking, wind-blown wavy groom seen on a zoom-out: its sections change level and blend;
/// `more` adds to the scene file (a deforming body).
fn shot(more: &str) -> Shot {
    SceneFile::parse(&format!(
        "{more}[groom]\npreset = \"wavy\"\nsection_count = 24\nstrands_per_group = 6\n\
         rest_pose = \"grown\"\n[dynamics]\nsettle_seconds = 0.0\n\
         [motion]\nkind = \"shake\"\namplitude_degrees = 20.0\npeak_speed = 3.0\n\
         [wind]\nspeed = 2.0\ngusts = 1.0\n\
         [camera]\npath = \"zoom-out\"\ndistance = 0.5\nend_distance = 6.0\n\
         [lod]\npixel_tolerance = 2.0\nblend_time = 0.05\n\
         [frames]\ncount = 6\nfps = 60\nsize = \"96x64\"\n",
    ))
    .and_then(|file| file.resolve())
    .unwrap()
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hairlod-cache-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    dir
}

#[test]
fn frames_from_the_cache_are_the_simulating_process_frames() {
    cached_frames_are_the_simulating_process_frames("");
}

/// A talking head: the cache's frames draw the body deformed at each record's time and the
/// strands shifted onto the roots it carries, as the simulating process draws them.
#[test]
fn a_deforming_heads_frames_from_the_cache_are_the_simulating_process_frames() {
    cached_frames_are_the_simulating_process_frames("[body]\nanimation = \"talk\"\n");
}

/// Simulates `shot(more)` into a cache and renders it from there, whole, as a chunk and frame by
/// frame backwards; every image must be the one the simulating process rendered.
fn cached_frames_are_the_simulating_process_frames(more: &str) {
    let shot = shot(more);
    let scene = shot.build_scene().unwrap();
    let options = RendererOptions::from_env().unwrap();
    let views = [View::Shaded, View::LevelColors];

    // The frames rendered as the run simulates.
    let mut renderer = PipelineRenderer::new(&options, &scene).unwrap();
    let mut straight = Vec::new();
    let mut levels_changed = 0;
    run_shot(
        &shot,
        &scene,
        RunOptions::whole(&shot, shot.settings),
        Some((&mut renderer, &views)),
        |frame| {
            straight.push(frame.images.to_vec());
            levels_changed += frame.report.level_changes;
            Ok(())
        },
    )
    .unwrap();
    assert!(levels_changed > 0, "the shot changes levels");

    // Simulated into a cache, without a renderer.
    let dir = temp_dir(if more.is_empty() {
        "lone"
    } else {
        "lone-deforming"
    });
    let model = CharacterModel::new(Arc::new(scene.clone()), shot.environment.clone());
    let fingerprint = run_fingerprint(&shot, std::slice::from_ref(&model));
    let cache = SimulationCache::create(&dir, fingerprint.clone()).unwrap();
    let pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let frame_loop = FrameLoop::new(&shot, pipeline, 0..shot.frames, None).unwrap();
    let mut sizes = Vec::new();
    simulate(frame_loop, &cache, |frame| {
        sizes.push(frame.bytes);
        Ok(())
    })
    .unwrap();
    assert_eq!(sizes.len(), shot.frames);

    // Rendered from the cache on fresh renderers: the whole shot, then its second half alone
    // (a render chunk), then its frames in reverse, one chunk each.
    let from_cache = |frames: std::ops::Range<usize>| {
        let mut renderer = PipelineRenderer::new(&options, &scene).unwrap();
        let run = CachedRun::new(
            cache.clone(),
            std::slice::from_ref(&model),
            shot.settings,
            frames.start,
        )
        .unwrap();
        let mut images = Vec::new();
        run_frames(
            &shot,
            run,
            frames,
            None,
            Some((&mut renderer, &views)),
            |frame| {
                images.push(frame.images.to_vec());
                Ok(())
            },
        )
        .unwrap();
        images
    };
    assert!(
        from_cache(0..shot.frames) == straight,
        "the cached frames differ"
    );
    assert!(
        from_cache(3..shot.frames) == straight[3..],
        "a chunk's frames differ"
    );
    for frame in (0..shot.frames).rev() {
        assert!(
            from_cache(frame..frame + 1)[0] == straight[frame],
            "frame {frame} rendered alone differs"
        );
    }

    // What the cache refuses: a missing frame, another run's records.
    std::fs::remove_file(cache.record_path(4)).unwrap();
    let error = cache.read(4).unwrap_err().to_string();
    assert!(
        error.contains("frame 4") && error.contains("missing"),
        "{error}"
    );
    let foreign = SimulationCache::open(&dir, "00000000deadbeef".into()).unwrap();
    let error = foreign.read(2).unwrap_err().to_string();
    assert!(
        error.contains("another run") && error.contains(&fingerprint),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_crowd_renders_from_its_cache_bit_for_bit() {
    let shot = SceneFile::parse(
        "[groom]\npreset = \"straight\"\nsection_count = 8\nstrands_per_group = 4\n\
         rest_pose = \"grown\"\n[dynamics]\nsettle_seconds = 0.0\n\
         [frames]\ncount = 4\nsize = \"96x64\"\n\
         [[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"shake\" }\n\
         [[character]]\nposition = [0.4, 0.0, -0.3]\nmotion = { kind = \"nod\" }\n",
    )
    .and_then(|file| file.resolve())
    .unwrap();
    let model = CrowdModel::build(&shot).unwrap();
    let options = RendererOptions::from_env().unwrap();
    let views = [View::Shaded];
    let mut renderer = CrowdRenderer::new(&options, &model).unwrap();
    let mut straight = Vec::new();
    run_crowd(
        &model,
        RunOptions::whole(&shot, shot.settings),
        Some((&mut renderer, &views)),
        |frame| {
            straight.push(frame.images[0].clone());
            Ok(())
        },
    )
    .unwrap();

    let dir = temp_dir("crowd");
    let characters: Vec<CharacterModel> = model.members.iter().map(|m| m.model()).collect();
    let cache = SimulationCache::create(&dir, run_fingerprint(&shot, &characters)).unwrap();
    let crowd = Crowd::new(&model, shot.settings).unwrap();
    let frame_loop = FrameLoop::new(&shot, crowd, 0..shot.frames, None).unwrap();
    simulate(frame_loop, &cache, |frame| {
        assert_eq!(frame.record.head_poses.len(), 2, "one pose per character");
        Ok(())
    })
    .unwrap();

    let mut renderer = CrowdRenderer::new(&options, &model).unwrap();
    let run = CachedRun::<CrowdRenderer>::new(cache, &characters, shot.settings, 0).unwrap();
    let mut cached = Vec::new();
    run_frames(
        &shot,
        run,
        0..shot.frames,
        None,
        Some((&mut renderer, &views)),
        |frame| {
            cached.push(frame.images[0].clone());
            Ok(())
        },
    )
    .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert!(cached == straight, "the crowd's cached frames differ");
}

#[test]
fn the_fingerprint_follows_the_run_not_the_drawing_style() {
    let shot = shot("");
    let scene = Arc::new(shot.build_scene().unwrap());
    let print = |shot: &Shot| {
        run_fingerprint(
            shot,
            &[CharacterModel::new(scene.clone(), shot.environment.clone())],
        )
    };
    let base = print(&shot);
    assert_eq!(base.len(), 16);
    let mut styled = shot.clone();
    styled.outputs.color_coded = true;
    assert_eq!(print(&styled), base, "the style is not the run's");
    let mut longer = shot.clone();
    longer.frames += 1;
    assert_ne!(print(&longer), base, "the frame count moves the camera");
    let mut larger = shot.clone();
    larger.height *= 2;
    assert_ne!(print(&larger), base, "the image size moves the levels");
    let mut finer = shot.clone();
    finer.settings.dynamics.substeps += 1;
    assert_ne!(print(&finer), base, "the settings are the run's");
}
