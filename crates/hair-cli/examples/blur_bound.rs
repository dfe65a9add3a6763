//! What a stand-in for strands can score at best by SSIM when it loses the strands' fine detail:
//! the mean SSIM over a shot of the strands frames against themselves blurred (Gaussian, σ in
//! pixels), beside the mean SSIM of other levels' frames of the same shot against them.
//!
//! ```text
//! hairlod render scenes/paper-table1.toml --level strands --out DIR/strands
//! hairlod render scenes/paper-table1.toml --level clusters --out DIR/clusters
//! cargo run --release -p hair-cli --example blur_bound -- DIR/strands DIR/clusters …
//! ```

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use hairlod::metrics::ssim;

const SIGMAS: [f32; 4] = [0.7, 1.5, 2.0, 3.0];

fn frames(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut frames: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| {
            path.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("frame_") && n.ends_with(".png"))
        })
        .collect();
    frames.sort();
    ensure!(!frames.is_empty(), "no frame_*.png in {}", dir.display());
    Ok(frames)
}

fn luma(path: &Path) -> Result<image::GrayImage> {
    Ok(image::open(path)
        .with_context(|| format!("reading {}", path.display()))?
        .to_luma8())
}

fn main() -> Result<()> {
    let dirs: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    ensure!(
        !dirs.is_empty(),
        "usage: blur_bound STRANDS_DIR [OTHER_LEVEL_DIR …]"
    );
    let reference = frames(&dirs[0])?;
    let others: Vec<Vec<PathBuf>> = dirs[1..].iter().map(|d| frames(d)).collect::<Result<_>>()?;
    for (dir, frames) in dirs[1..].iter().zip(&others) {
        ensure!(
            frames.len() == reference.len(),
            "{} has {} frames, {} has {}",
            dir.display(),
            frames.len(),
            dirs[0].display(),
            reference.len()
        );
    }
    let mut blurred = [0f64; SIGMAS.len()];
    let mut levels = vec![0f64; others.len()];
    for (i, path) in reference.iter().enumerate() {
        let strands = luma(path)?;
        for (sum, sigma) in blurred.iter_mut().zip(SIGMAS) {
            *sum += ssim(&strands, &image::imageops::blur(&strands, sigma));
        }
        for (sum, frames) in levels.iter_mut().zip(&others) {
            *sum += ssim(&strands, &luma(&frames[i])?);
        }
    }
    let n = reference.len() as f64;
    println!(
        "mean SSIM against {} ({} frames):",
        dirs[0].display(),
        reference.len()
    );
    for (sum, sigma) in blurred.iter().zip(SIGMAS) {
        println!("  the same frames blurred, σ = {sigma} px: {:.4}", sum / n);
    }
    for (sum, dir) in levels.iter().zip(&dirs[1..]) {
        println!("  {}: {:.4}", dir.display(), sum / n);
    }
    Ok(())
}
