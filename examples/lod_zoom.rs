//! The camera zooms out from the face while a wind blows, described as a scene file and run
//! through the frame loop (no rendering): prints, every few frames, how many sections are
//! patches, clusters and strand groups, and what each stage cost.

use hairlod::SceneFile;
use hairlod::run::{RunOptions, run_shot};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let shot = SceneFile::parse(
        r#"
        [groom]
        preset = "curly"
        [wind]
        speed = 1.0
        direction = [1.0, 0.0, 0.0]
        [camera]
        path = "zoom-out"    # from 0.5 m to 8 m, geometrically
        distance = 0.5
        end_distance = 8.0
        azimuth_degrees = 17.0
        elevation_degrees = 8.6
        fov_degrees = 34.4
        [dynamics]
        settle_seconds = 0.0
        [frames]
        count = 60
        "#,
    )?
    .resolve()?;
    let scene = shot.build_scene()?;
    println!("frame  distance  patches clusters strands  changes  nodes   lod ms  dyn ms  col ms");
    let options = RunOptions::whole(&shot, shot.settings);
    run_shot(&shot, &scene, options, None, |frame| {
        let report = frame.report;
        let index = report.frame;
        if index % 6 == 0 || index == shot.frames - 1 {
            let [p, c, s] = report.sections_at;
            let t = report.times;
            let distance = frame.camera.position.distance(frame.camera.target);
            println!(
                "{index:>5}  {distance:>6.2} m  {p:>7} {c:>8} {s:>7}  {:>7}  {:>5}  {:>6.2}  {:>6.2}  {:>6.2}",
                report.level_changes,
                report.simulated_nodes,
                t.lod * 1e3,
                t.dynamics * 1e3,
                t.collision * 1e3
            );
        }
        Ok(())
    })?;
    Ok(())
}
