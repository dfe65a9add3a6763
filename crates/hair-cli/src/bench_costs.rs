//! `hairlod bench costs`: where a paper-table frame's time goes, LODs against Strands. Runs the
//! paper's zoom-out (Table 1, or Table 2 with `--wind`) in both modes and renders every frame in
//! several variants, interleaved so that each sees the same machine load: the bench's default
//! frame (self-shadowing on, maps matched to the hair's screen size, hair-textured surfaces),
//! without shadows, with striped surfaces, with 512² shadow maps whatever the hair's screen size,
//! and an empty frame (no hair: the target's clears, resolve, head and readback alone). Prints
//! each stage's mean per frame [ms] and the default frame's split into upload, encode, device
//! wait and readback copy.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use hairlod::core::lod::{ErrorModel, LodSettings};
use hairlod::core::{Level, RigidTransform};
use hairlod::pipeline::{LodMode, PipelineSettings};
use hairlod::render::{
    ActiveSkeletons, FrameSettings, RenderTimings, Renderer, RendererOptions, SelfShadowing,
    SurfaceTexture,
};

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
    prepare: f64,
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
    pub shot: crate::bench_cmd::PaperShotArgs,
    /// Screen-space error tolerance of the LODs [pixels] (the paper's error model, `chord`).
    #[arg(long, default_value_t = 8.0)]
    pub pixel_tolerance: f32,
}

/// Runs `hairlod bench costs`.
pub fn run(args: &CostsArgs) -> Result<()> {
    let (wind, frames, tolerance) = (args.shot.wind, args.shot.frames, args.pixel_tolerance);
    let (width, height) = args.shot.size;
    let shot = args.shot.shot()?;
    let scene = shot.build_scene()?;
    let lod = LodSettings {
        pixel_tolerance: tolerance,
        error_model: ErrorModel::Chord,
        ..shot.lod_settings()
    };
    let mut renderer = Renderer::new(&RendererOptions::from_env()?)?;
    println!(
        "{} table {}, {frames} frames, {width}x{height}, τ = {tolerance} px, on {}",
        if wind { "wind" } else { "calm" },
        if wind { 2 } else { 1 },
        renderer.adapter_report()
    );
    renderer.upload_groom(&scene.groom)?;
    renderer.set_head_mesh(Some(&scene.head.mesh))?;
    renderer.warm_up(&scene.groom)?;
    let mut empty = ActiveSkeletons::new();
    for _ in 0..scene.groom.skeletons.chain_count() {
        empty.push_inactive_chain();
    }
    let mut totals = Vec::new();
    for mode in [LodMode::Auto(lod), LodMode::Fixed(Level::StrandGroup)] {
        let settings = PipelineSettings {
            lod: mode,
            ..shot.settings
        };
        let mut pipeline = shot.pipeline(&scene, settings, None)?;
        renderer.set_head_mesh(Some(&scene.head.mesh))?;
        let mut head_pose = RigidTransform::IDENTITY;
        let mut head_uploads = 0;
        let mut active = ActiveSkeletons::new();
        let mut sums = Sums::default();
        for frame in 0..frames {
            let camera = shot.camera(frame);
            let report = pipeline.advance(&camera)?;
            sums.lod += report.times.lod;
            sums.dynamics += report.times.dynamics;
            sums.collision += report.times.collision;
            let started = Instant::now();
            pipeline.gather_drawn(&mut active)?;
            let pose = pipeline.head_pose();
            if pose != head_pose {
                renderer.set_head_mesh(Some(&scene.head.mesh.posed(&pose)))?;
                head_pose = pose;
                head_uploads += 1;
            }
            sums.prepare += started.elapsed().as_secs_f64();
            let base = FrameSettings::new(width, height, camera);
            // Rotate the order so that no variant always runs first (or last) after the dynamics.
            for k in 0..VARIANTS.len() {
                let variant = (k + frame) % VARIANTS.len();
                let frame_data = if VARIANTS[variant] == "empty" {
                    empty.frame()
                } else {
                    active.frame()
                };
                let started = Instant::now();
                renderer.render(&frame_data, &settings_of(variant, base))?;
                sums.variants[variant] += started.elapsed().as_secs_f64();
                if variant == 0 {
                    sums.per_frame.push(started.elapsed().as_secs_f64());
                    let t = renderer.last_timings();
                    sums.split.upload += t.upload;
                    sums.split.encode += t.encode;
                    sums.split.gpu += t.gpu;
                    sums.split.readback += t.readback;
                }
            }
            sums.frames += 1;
        }
        let n = sums.frames.max(1) as f64;
        let ms = |s: f64| s / n * 1e3;
        println!(
            "\n{} ({head_uploads} head uploads): lod {:.1}, dynamics {:.1}, collision {:.1}, \
             prepare (gather + head) {:.1} ms per frame",
            mode.column_name(),
            ms(sums.lod),
            ms(sums.dynamics),
            ms(sums.collision),
            ms(sums.prepare)
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
        let sim = sums.dynamics + sums.collision;
        totals.push((
            (sim + sums.prepare) / n,
            sums.variants.map(|v| v / n),
            sums.per_frame,
        ));
    }
    println!("\nStrands / LODs, table total (dynamics + collision + prepare + render):");
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
    for (frame, (l, s)) in lods.2.iter().zip(&strands.2).enumerate() {
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
