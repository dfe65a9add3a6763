//! Image metrics shared by the benchmarks, the accuracy sweep and the popping measures: luma,
//! SSIM, PSNR and mean absolute differences.

use serde::{Deserialize, Serialize};

/// Mean absolute difference of two images of the same size, over the RGB channels, in `[0, 1]`.
pub fn mean_abs_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 1.0;
    }
    let mut sum = 0u64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            sum += u64::from(p.0[c].abs_diff(q.0[c]));
        }
    }
    sum as f64 / (255.0 * 3.0 * f64::from(a.width()) * f64::from(a.height())).max(1.0)
}

/// Mean structural similarity (SSIM, on luma) of two images of the same size, in `[−1, 1]` (1:
/// identical), from the `image-compare` crate.
pub fn ssim(a: &image::GrayImage, b: &image::GrayImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 0.0;
    }
    image_compare::gray_similarity_structure(&image_compare::Algorithm::MSSIMSimple, a, b)
        .map(|similarity| similarity.score)
        .unwrap_or(0.0)
}

/// The luma of an RGBA image (what [`ssim`] compares).
pub fn luma(image: &image::RgbaImage) -> image::GrayImage {
    image::DynamicImage::ImageRgba8(image.clone()).to_luma8()
}

/// Mean absolute difference of two luma images of the same size, in `[0, 1]` (1 for different
/// sizes).
pub fn luma_difference(a: &image::GrayImage, b: &image::GrayImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return 1.0;
    }
    let sum: u64 = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| u64::from(p.0[0].abs_diff(q.0[0])))
        .sum();
    sum as f64 / (255.0 * f64::from(a.width()) * f64::from(a.height())).max(1.0)
}

/// Peak signal-to-noise ratio [dB] of two RGBA images of the same size over their RGB channels:
/// `10 · log10(255² / MSE)`, with MSE the mean squared difference of the 8-bit channel values.
/// Infinite for identical images; 0 dB when every channel differs by 255; `NaN` when the sizes
/// differ (no comparison is possible).
pub fn psnr(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    if a.dimensions() != b.dimensions() {
        return f64::NAN;
    }
    let mut sum = 0u64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            let d = u64::from(p.0[c].abs_diff(q.0[c]));
            sum += d * d;
        }
    }
    let count = 3 * u64::from(a.width()) * u64::from(a.height());
    if sum == 0 || count == 0 {
        return f64::INFINITY;
    }
    let mse = sum as f64 / count as f64;
    10.0 * (255.0 * 255.0 / mse).log10()
}

/// Image error of one frame against the reference frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImageError {
    /// Mean SSIM on luma, in `[−1, 1]` (1: identical); see [`ssim`].
    pub ssim: f64,
    /// PSNR over RGB [dB] (infinite: identical); see [`psnr`].
    pub psnr: f64,
}

/// SSIM and PSNR of `image` against `reference` (both RGBA, same size).
pub fn image_error(reference: &image::RgbaImage, image: &image::RgbaImage) -> ImageError {
    ImageError {
        ssim: ssim(&luma(reference), &luma(image)),
        psnr: psnr(reference, image),
    }
}
