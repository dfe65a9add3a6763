//! Sub-pixel strand lines covering their width's share of a pixel (`LineCoverage::Width`): the
//! light a row of separate strands sends to the image is that share of what whole-pixel lines
//! send, with and without multisampling; overlapping strands add up.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{
    BackendChoice, FrameSettings, LineCoverage, Renderer, SelfShadowing, StrandStyle,
};

/// The image's summed linear light (red channel, sRGB decoded).
fn linear_sum(image: &image::RgbaImage) -> f64 {
    image
        .pixels()
        .map(|p| {
            let s = f64::from(p.0[0]) / 255.0;
            if s <= 0.04045 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            }
        })
        .sum()
}

/// `rows` chains 0.1 m long, one above the other 0.12 m apart, each with `count` vertical strands
/// `spacing` apart [m], around the origin.
fn strand_rows(renderer: &mut Renderer, rows: usize, count: usize, spacing: f32) -> Chains {
    let mut chains = Chains::default();
    let mut strands = Strands::default();
    for row in 0..rows {
        let y = 0.12 * (row as f32 - 0.5 * (rows - 1) as f32);
        let chain = chains.push_line(
            Vec3::new(0.0, y + 0.05, 0.0),
            Vec3::new(0.0, y - 0.05, 0.0),
            3,
        );
        for i in 0..count {
            let x = spacing * (i as f32 - 0.5 * (count - 1) as f32);
            strands.push(chain, Vec2::new(0.0, x), 0.5);
        }
    }
    renderer.upload_strands(&strands.set()).unwrap();
    chains
}

/// Lines of hair width `w` at 1 m in a 600-pixel-high image with a 35° field of view cover
/// `c = w·f/z` of a pixel, `f = 300/tan(17.5°) = 951.5` px. With `w` = 631 µm, `c` = 0.60.
/// Five rows of 180 strands 4 mm (3.8 px) apart, so that no two share a pixel, 95 px long: the
/// covered image holds `c` of the whole-pixel image's light. A strand keeps `⌊c·n + ξ⌋` of a
/// pixel's n samples, ξ uniform and the strand's own: with 4 samples 2 or 3 (variance 0.24), so
/// over 900 strands the ratio's standard deviation is `√0.24/(2.4·√900)` = 0.7 %;
/// single-sampled or on GL a strand is kept whole with probability c, `√(0.4/(0.6·900))` =
/// 2.7 %. The lines' ends add about 1 % (a pixel of 95). Bound: 10 % (3.7 σ single-sampled).
#[test]
fn covered_lines_send_their_share_of_the_light() {
    // On GL the covered lines keep or drop whole fragments (no sample mask): the same mean.
    for renderer in [
        renderer_on(BackendChoice::Vulkan),
        single_sample_renderer(Some(BackendChoice::Vulkan)),
        renderer_on(BackendChoice::Gl),
    ] {
        let mut renderer = renderer;
        let chains = strand_rows(&mut renderer, 5, 180, 0.004);
        let mut settings = settings(800, 600, 1.0);
        let focal = 300.0 / (17.5f32.to_radians()).tan();
        let width = 0.6 / focal;
        settings.strand_style = StrandStyle::Ribbons {
            width,
            min_width_pixels: 1.0,
        };
        settings.shadows = SelfShadowing::off();
        diffuse_light_from_x(&mut settings);
        let mut render = |coverage| {
            let settings = FrameSettings {
                line_coverage: coverage,
                ..settings
            };
            linear_sum(&renderer.render(&chains.frame(), &settings).unwrap())
        };
        let whole = render(LineCoverage::Pixel);
        let covered = render(LineCoverage::Width);
        let ratio = covered / whole;
        eprintln!(
            "{}, {} samples: covered / whole light = {ratio:.4}",
            renderer.adapter_report(),
            renderer.sample_count()
        );
        // 900 lines of about 95 px at `0.4·(0.1 + 1)` each, at least half of that.
        assert!(
            whole > 900.0 * 95.0 * 0.4 * 1.1 * 0.5,
            "whole-pixel lines lit: {whole}"
        );
        assert!(
            (ratio - 0.6).abs() < 0.1 * 0.6,
            "ratio {ratio}, expected 0.60"
        );
    }
}

/// Strands covering c of a pixel each, k of them over one another, leave `(1 − c)^k` of the
/// pixel's samples uncovered when their samples are picked independently (different strands
/// hash to different samples): 10 strands at the same place with c = 0.3 cover
/// `1 − 0.7¹⁰ = 97 %`, where hardware alpha-to-coverage (one fixed pattern per alpha) would
/// leave 30 %. 10 strands 10 µm apart (0.01 px) at 1 m, 4× MSAA: the light is at least 90 % of
/// one whole-pixel line's (97 % minus the quantisation of ⌊c·n + ξ⌋, which keeps the mean).
#[test]
fn overlapping_covered_strands_add_up() {
    let mut renderer = renderer();
    if renderer.sample_count() < 4 {
        return;
    }
    let focal = 300.0 / (17.5f32.to_radians()).tan();
    let mut settings = settings(800, 600, 1.0);
    settings.strand_style = StrandStyle::Ribbons {
        width: 0.3 / focal,
        min_width_pixels: 1.0,
    };
    settings.shadows = SelfShadowing::off();
    diffuse_light_from_x(&mut settings);
    let one = strand_rows(&mut renderer, 1, 1, 0.0);
    let whole = linear_sum(&renderer.render(&one.frame(), &settings).unwrap());
    let ten = strand_rows(&mut renderer, 1, 10, 1e-5);
    let covered = FrameSettings {
        line_coverage: LineCoverage::Width,
        ..settings
    };
    let light = linear_sum(&renderer.render(&ten.frame(), &covered).unwrap());
    eprintln!(
        "ten covered strands / one whole line = {:.3}",
        light / whole
    );
    assert!(
        light / whole > 0.9 && light / whole < 1.02,
        "{}",
        light / whole
    );
}
