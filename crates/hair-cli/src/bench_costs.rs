//! `hairlod bench costs`: where a paper-table frame's time goes, LODs against Strands. Runs the
//! paper's zoom-out (Table 1, or Table 2 with `--wind`) in both modes through the frame loop,
//! interleaved frame by frame, and draws every frame in several variants, so that each mode and
//! variant sees the same machine load: the bench's default frame (self-shadowing on, maps matched
//! to the hair's screen size, hair-textured surfaces), without shadows, with striped surfaces,
//! with 512² shadow maps whatever the hair's screen size, with maps of at most 256², and an empty
//! frame (no hair: the target's clears, resolve, head and readback alone). Prints each stage's
//! mean per frame [ms] and the default frame's split into upload, encode, device wait and
//! readback copy.

use anyhow::{Context, Result};
use clap::Args;
use hairlod::core::Level;
use hairlod::core::lod::{ErrorModel, LodSettings};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::{
    FrameSettings, RenderTimings, RendererOptions, SelfShadowing, ShadingMode, SurfaceTexture,
};
use hairlod::run::{FrameLoop, RunOptions};

use crate::report::progress_bar;

/// The variants rendered per frame, in the columns' order.
const VARIANTS: [&str; 6] = [
    "default",
    "no shadows",
    "stripes",
    "fixed 512",
    "maps ≤ 256",
    "empty",
];

fn settings_of(variant: usize, base: FrameSettings) -> FrameSettings {
    match variant {
        1 => FrameSettings {
            shadows: SelfShadowing::off(),
            ..base
        },
        2 => FrameSettings {
            surface_texture: SurfaceTexture::Stripes,
            ..base
        },
        3 => FrameSettings {
            shadows: SelfShadowing {
                resolution: 512,
                match_screen: false,
                ..base.shadows
            },
            ..base
        },
        4 => FrameSettings {
            shadows: SelfShadowing {
                resolution: 256,
                ..base.shadows
            },
            ..base
        },
        _ => base,
    }
}

/// Mean per frame of each column [s].
#[derive(Default)]
struct Sums {
    frames: usize,
    lod: f64,
    dynamics: f64,
    collision: f64,
    variants: [f64; VARIANTS.len()],
    split: RenderTimings,
    /// The default frame's render time, frame by frame [s].
    per_frame: Vec<f64>,
}

/// Arguments of `hairlod bench costs`.
#[derive(Debug, Args)]
pub struct CostsArgs {
    /// The shot: air, frames, image size.
    #[command(flatten)]
    pub shot: crate::report::PaperShotArgs,
    /// Screen-space error tolerance of the LODs [pixels] (the paper's error model, `chord`).
    #[arg(long, default_value_t = 8.0)]
    pub pixel_tolerance: f32,
}

/// Runs `hairlod bench costs`.
pub fn run(args: &CostsArgs) -> Result<()> {
    let (wind, tolerance) = (args.shot.wind, args.pixel_tolerance);
    let (width, height) = args.shot.size;
    let shot = args.shot.shot()?;
    let frames = shot.frames;
    let scene = shot.build_scene()?;
    let lod = LodSettings {
        pixel_tolerance: tolerance,
        error_model: ErrorModel::Chord,
        ..shot.lod_settings()
    };
    let mut renderer = PipelineRenderer::new(&RendererOptions::from_env()?, &scene)?;
    renderer.warm_up(&scene)?;
    println!(
        "{} table {}, {frames} frames, {width}x{height}, τ = {tolerance} px, on {}",
        if wind { "wind" } else { "calm" },
        if wind { 2 } else { 1 },
        renderer.renderer().adapter_report()
    );
    let modes = [LodMode::Auto(lod), LodMode::Fixed(Level::StrandGroup)];
    let mut loops = Vec::with_capacity(modes.len());
    for mode in modes {
        let options = RunOptions {
            settings: PipelineSettings {
                lod: mode,
                ..shot.settings
            },
            frames: 0..frames,
            resume: None,
            budget: None,
        };
        loops.push(
            FrameLoop::start(&shot, &scene, options, Some(&mut renderer))
                .with_context(|| format!("the {} run failed to start", mode.column_name()))?,
        );
    }
    let mut sums: Vec<Sums> = modes.iter().map(|_| Sums::default()).collect();
    // Both modes make frame k before either makes k + 1 (through the one frame loop, without
    // its own drawing), and each frame is then drawn in every variant, so that every mode and
    // variant sees the same machine load.
    let bar = progress_bar(frames * modes.len(), "LODs and Strands, frame by frame");
    for frame in 0..frames {
        for ((frame_loop, sums), mode) in loops.iter_mut().zip(&mut sums).zip(&modes) {
            let name = mode.column_name();
            let output = frame_loop
                .step(None)
                .with_context(|| format!("the {name} run failed at frame {frame}"))?
                .with_context(|| format!("the {name} run ended before frame {frame}"))?;
            let (times, camera) = (output.report.times, *output.camera);
            sums.lod += times.lod;
            sums.dynamics += times.dynamics;
            sums.collision += times.collision;
            let pipeline = frame_loop.target_mut();
            let base = renderer
                .style()
                .frame_settings(width, height, &camera, ShadingMode::Shaded);
            // Rotate the order so that no variant always runs first (or last) after the dynamics.
            for k in 0..VARIANTS.len() {
                let variant = (k + frame) % VARIANTS.len();
                let settings = settings_of(variant, base);
                let (_, seconds) = if VARIANTS[variant] == "empty" {
                    renderer.render_without_hair(pipeline, &settings)?
                } else {
                    renderer.render_with_settings(pipeline, &settings)?
                };
                sums.variants[variant] += seconds;
                if variant == 0 {
                    sums.per_frame.push(seconds);
                    let t = renderer.renderer().last_timings();
                    sums.split.upload += t.upload;
                    sums.split.encode += t.encode;
                    sums.split.gpu += t.gpu;
                    sums.split.readback += t.readback;
                }
            }
            sums.frames += 1;
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let mut totals = Vec::new();
    for (sums, mode) in sums.iter().zip(&modes) {
        let n = sums.frames.max(1) as f64;
        let ms = |s: f64| s / n * 1e3;
        println!(
            "\n{}: lod {:.1}, dynamics {:.1}, collision {:.1} ms per frame",
            mode.column_name(),
            ms(sums.lod),
            ms(sums.dynamics),
            ms(sums.collision),
        );
        for (name, value) in VARIANTS.iter().zip(sums.variants) {
            println!("  render {name:<11} {:>8.1} ms", ms(value));
        }
        let s = sums.split;
        println!(
            "  default split: upload {:.1}, encode {:.1}, device {:.1}, readback copy {:.1} ms",
            ms(s.upload),
            ms(s.encode),
            ms(s.gpu),
            ms(s.readback)
        );
        totals.push((
            (sums.lod + sums.dynamics + sums.collision) / n,
            sums.variants.map(|v| v / n),
            &sums.per_frame,
        ));
    }
    println!("\nStrands / LODs, table total (level selection + dynamics + collision + render):");
    let (lods, strands) = (&totals[0], &totals[1]);
    for (k, name) in VARIANTS.iter().enumerate().take(VARIANTS.len() - 1) {
        println!(
            "  {name:<11} {:.2}×  ({:.1} / {:.1} ms)",
            (strands.0 + strands.1[k]) / (lods.0 + lods.1[k]),
            (strands.0 + strands.1[k]) * 1e3,
            (lods.0 + lods.1[k]) * 1e3
        );
    }
    println!(
        "\nthe default frame's render time [ms], frame by frame: frame, distance, LODs, Strands"
    );
    for (frame, (l, s)) in lods.2.iter().zip(strands.2.iter()).enumerate() {
        let camera = shot.camera(frame);
        let distance = camera.position.distance(camera.target);
        println!(
            "  {frame:>3} {distance:>6.2} m {:>8.1} {:>8.1}",
            l * 1e3,
            s * 1e3
        );
    }
    Ok(())
}
