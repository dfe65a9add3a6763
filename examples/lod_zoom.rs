//! The camera zooms out from the face while a gusting wind blows: prints, every few frames, how
//! many sections are patches, clusters and strand groups, and what each stage cost.

use hairlod::core::dynamics::{Environment, WindField};
use hairlod::{Camera, Pipeline, PipelineSettings, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::preset("curly")?;
    let environment = Environment {
        wind: WindField::Constant(glam::Vec3::new(1.0, 0.0, 0.0)),
        ..Environment::default()
    };
    let mut pipeline = Pipeline::new(scene, environment, PipelineSettings::default())?;
    let frames = 60;
    println!("frame  distance  patches clusters strands  changes  nodes   lod ms  dyn ms  col ms");
    for frame in 0..frames {
        // From 0.5 m to 8 m, geometrically.
        let distance = 0.5 * 16f32.powf(frame as f32 / (frames - 1) as f32);
        let camera = Camera::orbit(glam::Vec3::new(0.0, 0.0, 0.0), distance, 0.3, 0.15, 0.6);
        let report = pipeline.advance(&camera)?;
        if frame % 6 == 0 || frame == frames - 1 {
            let [p, c, s] = report.sections_at;
            let t = report.times;
            println!(
                "{frame:>5}  {distance:>6.2} m  {p:>7} {c:>8} {s:>7}  {:>7}  {:>5}  {:>6.2}  {:>6.2}  {:>6.2}",
                report.level_changes,
                report.simulated_nodes,
                t.lod * 1e3,
                t.dynamics * 1e3,
                t.collision * 1e3
            );
        }
    }
    Ok(())
}
