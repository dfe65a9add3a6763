//! What a deforming body costs per frame: the talking, nodding procedural head of
//! `scenes/talking-head.toml` built with a 20,480-triangle mesh (80 × 128 bands), run through the
//! frame loop (no rendering), strand level and automatic levels. Prints the medians of the body
//! update (the mesh at the step's end, its tree refitted, pseudonormals, vertex velocities) and
//! of collision with it included, and the dynamics for scale.
//!
//! `cargo run --release --example deforming_body_cost [FRAMES]` (default 120; 2 s at 60 Hz)

use hairlod::SceneFile;
use hairlod::run::{RunOptions, run_shot};

/// The median of `values` [s], in milliseconds.
fn median_ms(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN) * 1e3
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let frames: usize = match std::env::args().nth(1) {
        Some(arg) => arg
            .parse()
            .map_err(|_| format!("FRAMES must be a whole number, not {arg:?}"))?,
        None => 120,
    };
    println!(
        "{:<10} {:>9} {:>6} {:>14} {:>14} {:>12}",
        "levels", "triangles", "nodes", "body update ms", "collision ms", "dynamics ms"
    );
    for lod in ["strands", "auto"] {
        let text = format!(
            "[groom]\npreset = \"straight\"\n[body]\nanimation = \"talk\"\n[motion]\n\
             kind = \"nod\"\namplitude_degrees = 8.0\npeak_speed = 1.0\n[lod]\nmode = \"{lod}\"\n\
             [camera]\ndistance = 0.7\ntarget = [0.0, -0.05, 0.0]\nazimuth_degrees = 50.0\n\
             [frames]\ncount = {frames}\nsize = \"640x360\"\n"
        );
        let mut shot = SceneFile::parse(&text)?.resolve()?;
        shot.head.latitude_bands = 80;
        shot.head.longitude_bands = 128;
        let scene = shot.build_scene()?;
        let triangles = scene.head.mesh.triangles.len();
        let (mut body, mut collision, mut dynamics, mut nodes) =
            (Vec::new(), Vec::new(), Vec::new(), 0);
        run_shot(
            &shot,
            &scene,
            RunOptions::whole(&shot, shot.settings),
            None,
            |frame| {
                body.push(frame.report.body_update);
                collision.push(frame.report.times.collision);
                dynamics.push(frame.report.times.dynamics);
                nodes = frame.report.simulated_nodes;
                Ok(())
            },
        )?;
        println!(
            "{lod:<10} {triangles:>9} {nodes:>6} {:>14.2} {:>14.2} {:>12.2}",
            median_ms(body),
            median_ms(collision),
            median_ms(dynamics)
        );
    }
    Ok(())
}
