//! Render cost and look of self-shadowing: the paper-curly groom (rest pose) at each level,
//! 1280×720 with 4× MSAA, camera at 0.8 m, with and without self-shadowing, renders interleaved
//! so that both see the same machine load; prints the median of each and writes the strand-level
//! images.
//!
//! `cargo run --release -p hair-render --example shadow_cost -- [RENDERS] [OUT_DIR]`
//! (default 7 renders each, images to the system's temporary folder).

use std::time::Instant;

use glam::Vec3;
use hair_core::{Level, Scene};
use hair_render::{
    ActiveSkeletons, Camera, FrameSettings, Renderer, RendererOptions, SelfShadowing,
};

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let renders: usize = args
        .next()
        .map(|a| a.parse())
        .transpose()?
        .unwrap_or(7)
        .max(1);
    let out = args
        .next()
        .map(std::path::PathBuf::from)
        .unwrap_or_else(std::env::temp_dir);
    let scene = Scene::preset("paper-curly")?;
    let groom = &scene.groom;
    let mut renderer = Renderer::new(&RendererOptions::from_env()?)?;
    println!("adapter: {}", renderer.adapter_report());
    renderer.upload_groom(groom)?;
    renderer.set_head_mesh(Some(&scene.head.mesh))?;
    let camera = Camera::orbit(
        Vec3::new(0.0, -0.01, 0.0),
        0.8,
        150f32.to_radians(),
        8f32.to_radians(),
        35f32.to_radians(),
    );
    let shadowed = FrameSettings::new(1280, 720, camera);
    let unshadowed = FrameSettings {
        shadows: SelfShadowing::off(),
        ..shadowed
    };
    let mut active = ActiveSkeletons::new();
    println!("level     | shadows off | shadows on | ratio  ({renders} renders each, median)");
    for level in [Level::StrandGroup, Level::Cluster, Level::Patch] {
        active.gather_rest_pose(groom, level)?;
        // One warm-up of each (pipelines, buffers, shadow maps).
        renderer.render(&active.frame(), &unshadowed)?;
        renderer.render(&active.frame(), &shadowed)?;
        let (mut off, mut on) = (Vec::new(), Vec::new());
        for _ in 0..renders {
            for (settings, times) in [(&unshadowed, &mut off), (&shadowed, &mut on)] {
                let started = Instant::now();
                renderer.render(&active.frame(), settings)?;
                times.push(started.elapsed().as_secs_f64());
            }
        }
        let (off, on) = (median(off), median(on));
        println!(
            "{:<9} | {:>8.1} ms | {:>7.1} ms | {:.2}×",
            level.name(),
            off * 1e3,
            on * 1e3,
            on / off
        );
        for (name, settings) in [("off", &unshadowed), ("on", &shadowed)] {
            let path = out.join(format!("shadows-{}-{name}.png", level.name()));
            hair_render::output::write_png_atomic(
                &renderer.render(&active.frame(), settings)?,
                &path,
            )?;
        }
    }
    Ok(())
}
