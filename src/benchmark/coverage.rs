//! Sub-pixel strand coverage against a supersampled reference (issue 18's measure): the strand
//! level drawn with 1-pixel lines that cover the whole pixel ([`LineCoverage::Pixel`]) and with
//! lines that cover their width's share of it ([`LineCoverage::Width`]), each compared by SSIM
//! (luma) with a reference rendered `factor` times larger on both axes and box-filtered down in
//! linear light. The reference draws every strand with its own width's share of each fine pixel,
//! so as `factor` grows it tends to the image of fibres of their true width; the plain
//! supersampled render (whole-pixel lines at the fine size, a quarter of a final pixel wide at
//! `factor` 4) is measured against too.

use std::time::Instant;

use glam::Vec3;
use hair_render::{Camera, FrameSettings, LineCoverage, Renderer, SkeletonFrame};
use serde::Serialize;

use crate::metrics::{luma, ssim};
use crate::pipeline::Result;

/// One view's measure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoverageMeasure {
    /// SSIM against the reference whose lines cover their width, lines covering whole pixels.
    pub ssim_pixel: f64,
    /// The same, lines covering their width's share.
    pub ssim_width: f64,
    /// SSIM against the plain supersampled reference (whole-pixel lines at the fine size), lines
    /// covering whole pixels.
    pub plain_ssim_pixel: f64,
    /// The same, lines covering their width's share.
    pub plain_ssim_width: f64,
    /// Render time of the whole-pixel frame (upload, draw, readback; median of 3) [ms].
    pub ms_pixel: f64,
    /// Render time of the covered frame (median of 3) [ms].
    pub ms_width: f64,
}

/// The measured view: `distance` [m] from the head, half a radian round from the face and
/// 0.15 rad up, 35° field of view.
pub fn coverage_camera(distance: f32) -> Camera {
    Camera::orbit(
        Vec3::new(0.0, -0.01, 0.0),
        distance,
        0.5,
        0.15,
        35f32.to_radians(),
    )
}

/// The four images a [`CoverageMeasure`] compares (RGBA, at the measured size).
#[derive(Debug, Clone)]
pub struct CoverageImages {
    /// Lines covering whole pixels.
    pub pixel: image::RgbaImage,
    /// Lines covering their width's share.
    pub width: image::RgbaImage,
    /// The reference: `factor`× supersampled, lines covering their width's share of the fine
    /// pixels.
    pub reference: image::RgbaImage,
    /// The plain supersampled render: whole-pixel lines at the fine size.
    pub plain: image::RgbaImage,
}

/// Renders `frame` with `settings` at `factor` times its size on both axes and box-filters it
/// down to `settings`' size, averaging each `factor`×`factor` block in linear light (the
/// target's sRGB encoding undone and redone).
pub fn supersampled(
    renderer: &mut Renderer,
    frame: &SkeletonFrame,
    settings: &FrameSettings,
    factor: u32,
) -> Result<image::RgbaImage> {
    let fine = FrameSettings {
        width: settings.width * factor,
        height: settings.height * factor,
        ..*settings
    };
    let image = renderer.render(frame, &fine)?;
    Ok(box_filter(&image, factor))
}

/// The mean of each `factor`×`factor` block of `image` in linear light.
pub fn box_filter(image: &image::RgbaImage, factor: u32) -> image::RgbaImage {
    let (width, height) = (image.width() / factor, image.height() / factor);
    let decode = |v: u8| {
        let s = f32::from(v) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    let table: Vec<f32> = (0..=255u8).map(decode).collect();
    let encode = |l: f32| {
        let l = l.clamp(0.0, 1.0);
        let s = if l <= 0.003_130_8 {
            12.92 * l
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let samples = (factor * factor) as f32;
    image::RgbaImage::from_fn(width, height, |x, y| {
        let mut sum = [0f32; 3];
        for dy in 0..factor {
            for dx in 0..factor {
                let p = image.get_pixel(x * factor + dx, y * factor + dy).0;
                for c in 0..3 {
                    sum[c] += table[usize::from(p[c])];
                }
            }
        }
        image::Rgba([
            encode(sum[0] / samples),
            encode(sum[1] / samples),
            encode(sum[2] / samples),
            255,
        ])
    })
}

/// Measures `frame` through `settings` (its strands drawn as lines: sub-pixel ribbons) with and
/// without line coverage against both `factor`× supersampled references; returns the measure
/// and the images.
pub fn measure_coverage(
    renderer: &mut Renderer,
    frame: &SkeletonFrame,
    settings: &FrameSettings,
    factor: u32,
) -> Result<(CoverageMeasure, CoverageImages)> {
    let with = |coverage| FrameSettings {
        line_coverage: coverage,
        ..*settings
    };
    let reference = supersampled(renderer, frame, &with(LineCoverage::Width), factor)?;
    let plain = supersampled(renderer, frame, &with(LineCoverage::Pixel), factor)?;
    let mut timed = |coverage| -> Result<(image::RgbaImage, f64)> {
        let settings = with(coverage);
        // One render first, so that the timed ones find their buffers and pipelines warm; the
        // median of three.
        let image = renderer.render(frame, &settings)?;
        let mut times = [0.0; 3];
        for time in &mut times {
            let started = Instant::now();
            renderer.render(frame, &settings)?;
            *time = started.elapsed().as_secs_f64() * 1e3;
        }
        times.sort_by(f64::total_cmp);
        Ok((image, times[1]))
    };
    let (pixel, ms_pixel) = timed(LineCoverage::Pixel)?;
    let (width, ms_width) = timed(LineCoverage::Width)?;
    let [l_pixel, l_width, l_reference, l_plain] = [&pixel, &width, &reference, &plain].map(luma);
    let measure = CoverageMeasure {
        ssim_pixel: ssim(&l_pixel, &l_reference),
        ssim_width: ssim(&l_width, &l_reference),
        plain_ssim_pixel: ssim(&l_pixel, &l_plain),
        plain_ssim_width: ssim(&l_width, &l_plain),
        ms_pixel,
        ms_width,
    };
    let images = CoverageImages {
        pixel,
        width,
        reference,
        plain,
    };
    Ok((measure, images))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 block of black and white averages to half the light, which sRGB encodes as 188
    /// (`1.055·0.5^(1/2.4) − 0.055 = 0.7354`), not 128.
    #[test]
    fn the_box_filter_averages_in_linear_light() {
        let image = image::RgbaImage::from_fn(4, 2, |x, y| {
            let v = if (x + y) % 2 == 0 { 255 } else { 0 };
            image::Rgba([v, v, v, 255])
        });
        let small = box_filter(&image, 2);
        assert_eq!(small.dimensions(), (2, 1));
        for p in small.pixels() {
            assert_eq!(p.0, [188, 188, 188, 255]);
        }
    }
}
