//! Strand thinning (`StrandThinning::ByScreenWidth`) on the paper-curly groom at rest, drawn as
//! strands: far away it keeps the pixels the hair covers and the light it lets through (its
//! shadows weigh each drawn strand for those left out), while drawing a fraction of the strands.

mod common;

use hairlod::Scene;
use hairlod::benchmark::coverage::coverage_camera;
use hairlod::render::{ActiveSkeletons, FrameSettings, Renderer, SkeletonFrame, StrandThinning};

/// Pixels of `image` that differ from `bare` (the same view without hair), and their mean luma
/// in `image` [0, 1].
fn hair_pixels(image: &image::RgbaImage, bare: &image::RgbaImage) -> (usize, f64) {
    let (mut count, mut luma) = (0usize, 0.0f64);
    for (p, q) in image.pixels().zip(bare.pixels()) {
        if p.0[..3] != q.0[..3] {
            count += 1;
            luma += (0.2126 * f64::from(p.0[0])
                + 0.7152 * f64::from(p.0[1])
                + 0.0722 * f64::from(p.0[2]))
                / 255.0;
        }
    }
    (count, luma / count.max(1) as f64)
}

/// A renderer with the paper-curly groom's strands at rest, and the same chains all inactive
/// (the head alone).
fn curly_at_rest() -> (Renderer, ActiveSkeletons, ActiveSkeletons) {
    let scene = Scene::preset("paper-curly").unwrap();
    let (renderer, active) = common::strands_at_rest(&scene);
    let mut bare = ActiveSkeletons::new();
    for _ in 0..scene.groom.skeletons.chain_count() {
        bare.push_inactive_chain();
    }
    (renderer, active, bare)
}

fn render(
    renderer: &mut Renderer,
    frame: &SkeletonFrame<'_>,
    settings: &FrameSettings,
) -> image::RgbaImage {
    renderer.render(frame, settings).unwrap()
}

/// At 640×360 (focal length 571 px) a strand group about 1 cm wide is 2 px wide at 3 m, so
/// 4 strands per pixel keep about 8 of its 83 strands. A pixel column crossed by the `n`
/// strands of a group spread over `w` columns stays uncovered with probability `e^{−n/w}`:
/// 4 per column leave 1.8 % of the columns the whole group covers (`e^{−83/2}` ≈ 0). At the
/// fringes of the hair a column crosses only the edge of a group, where its strands are
/// sparser than `n/w`, so the bound allows 7 % in all (4.7 % were lost when written).
/// The light stays: the deep opacity maps count the strands left out through the weights of
/// the strands drawn. The strand in front of a pixel sits deeper in the hair when the ones
/// before it are left out, so the thinned hair is a little darker (2.6 % in mean luma when
/// written); 5 % bounds it.
#[test]
fn thinned_far_hair_covers_and_shades_like_all_its_strands() {
    let (mut renderer, active, bare) = curly_at_rest();
    let settings = FrameSettings::new(640, 360, coverage_camera(3.0));
    let thinned_settings = FrameSettings {
        strand_thinning: StrandThinning::ByScreenWidth {
            strands_per_pixel: 4.0,
            raise_widths: false,
        },
        ..settings
    };
    let head_only = render(&mut renderer, &bare.frame(), &settings);
    let whole = render(&mut renderer, &active.frame(), &settings);
    let thinned = render(&mut renderer, &active.frame(), &thinned_settings);
    let (whole_pixels, whole_luma) = hair_pixels(&whole, &head_only);
    let (thinned_pixels, thinned_luma) = hair_pixels(&thinned, &head_only);
    eprintln!(
        "hair pixels {whole_pixels} whole, {thinned_pixels} thinned; mean luma {whole_luma:.4}, {thinned_luma:.4}"
    );
    assert!(
        whole_pixels > 2000,
        "the groom covers {whole_pixels} pixels"
    );
    assert_ne!(whole, thinned, "thinning changed nothing at 3 m");
    assert!(
        thinned_pixels as f64 >= 0.93 * whole_pixels as f64,
        "thinned hair covers {thinned_pixels} of {whole_pixels} pixels"
    );
    assert!(
        (thinned_luma - whole_luma).abs() <= 0.05 * whole_luma,
        "mean hair luma {thinned_luma:.4} thinned against {whole_luma:.4}"
    );
}

/// Close up every group is tens of pixels wide and needs more than its strands: thinning draws
/// them all, and the frame is the same bit for bit.
#[test]
fn near_hair_is_not_thinned() {
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut renderer, active) = common::strands_at_rest(&scene);
    let settings = FrameSettings::new(640, 360, coverage_camera(0.1));
    let whole = render(&mut renderer, &active.frame(), &settings);
    let thinned = render(
        &mut renderer,
        &active.frame(),
        &FrameSettings {
            strand_thinning: StrandThinning::ByScreenWidth {
                strands_per_pixel: 4.0,
                raise_widths: false,
            },
            ..settings
        },
    );
    assert!(whole == thinned, "thinning changed a close-up");
}

/// Thinned hard (1 strand per pixel of a group's width: about 2 of a group's 83 strands at 3 m),
/// the strands left cover much less than all of them: a column crossed by `n/w` strands of a
/// group stays uncovered with probability `e^{−n/w}`, 37 % at one per column. Widened to stand
/// for those left out (`raise_widths`: `1/φ` times a strand's pixel, at most the group's width),
/// each strand covers its group's columns, and the hair covers what all its strands cover.
#[test]
fn widened_thin_strands_cover_what_all_the_strands_cover() {
    let (mut renderer, active, bare) = curly_at_rest();
    let settings = FrameSettings::new(640, 360, coverage_camera(3.0));
    let thinned = |raise_widths| FrameSettings {
        strand_thinning: StrandThinning::ByScreenWidth {
            strands_per_pixel: 1.0,
            raise_widths,
        },
        ..settings
    };
    let head_only = render(&mut renderer, &bare.frame(), &settings);
    let whole = render(&mut renderer, &active.frame(), &settings);
    let kept = render(&mut renderer, &active.frame(), &thinned(false));
    let widened = render(&mut renderer, &active.frame(), &thinned(true));
    let (whole_pixels, _) = hair_pixels(&whole, &head_only);
    let (kept_pixels, _) = hair_pixels(&kept, &head_only);
    let (widened_pixels, _) = hair_pixels(&widened, &head_only);
    eprintln!("hair pixels: {whole_pixels} whole, {kept_pixels} thinned, {widened_pixels} widened");
    assert!(
        whole_pixels > 2000,
        "the groom covers {whole_pixels} pixels"
    );
    // Measured when written: 4310 whole, 3836 thinned (11 % lost, the groups overlap one
    // another), 4271 widened (0.9 % lost). Widening must win back most of the loss (at least
    // two thirds: switched off, it wins back none) and come within the 7 % of the test above.
    let lost = |pixels: usize| whole_pixels.saturating_sub(pixels) as f64;
    assert!(
        lost(kept_pixels) > 0.05 * whole_pixels as f64,
        "thinned to one strand per pixel, the hair still covers {kept_pixels} of {whole_pixels} pixels"
    );
    assert!(
        lost(widened_pixels) <= lost(kept_pixels) / 3.0,
        "widening won back too little: {widened_pixels} pixels against {kept_pixels} thinned, {whole_pixels} whole"
    );
    assert!(
        (widened_pixels as f64 - whole_pixels as f64).abs() <= 0.07 * whole_pixels as f64,
        "widened, the thinned hair covers {widened_pixels} pixels against {whole_pixels}"
    );
}
