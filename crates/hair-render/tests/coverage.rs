//! Dissolving between levels: a chain's coverage decides which of its strands are drawn (those
//! ranked below it, `round(c·n)` of a chain's `n`) and what fraction of a surface's pixels are
//! (screen-door: by `discard` single-sampled, by alpha-to-coverage with MSAA).

mod common;

use common::{Chains, Strands, is_lit, renderer, settings, single_sample_renderer, vertical_chain};
use glam::{Vec2, Vec3};
use hair_render::{PatchSet, SelfShadowing, SkeletonFrame, SurfaceTexture};

/// Lit pixels of a frame of `chains` (one chain, many strands side by side) at `coverage`.
fn lit_pixels(renderer: &mut hair_render::Renderer, chains: &Chains, coverage: f32) -> usize {
    let base = chains.frame();
    let coverages = vec![coverage; base.chain_count()];
    let frame = SkeletonFrame {
        chain_coverage: &coverages,
        chain_gives_way: &[],
        chain_simulated_at: &[],
        ..base
    };
    let image = renderer.render(&frame, &settings(800, 600, 1.0)).unwrap();
    image.pixels().filter(|p| is_lit(p)).count()
}

/// A single-sampled and a 4× MSAA renderer, each holding one patch 0.2 m wide on chain 0.
fn patch_renderers() -> [(&'static str, hair_render::Renderer); 2] {
    [
        ("single-sampled", single_sample_renderer(None)),
        ("4x MSAA", renderer()),
    ]
    .map(|(name, mut renderer)| {
        renderer
            .upload_patches(&PatchSet {
                patch_chain: &[0],
                patch_widths: &[0.2],
            })
            .unwrap();
        (name, renderer)
    })
}

/// Which pixels of a 400×300 frame are lit by `chains`' patch (stripes, no shadows) drawn at
/// `coverage`, giving way or not.
fn patch_pixels(
    renderer: &mut hair_render::Renderer,
    chains: &Chains,
    coverage: f32,
    gives_way: bool,
) -> Vec<bool> {
    let base = chains.frame();
    let coverages = vec![coverage; base.chain_count()];
    let flags = vec![gives_way; base.chain_count()];
    let frame = SkeletonFrame {
        chain_coverage: &coverages,
        chain_gives_way: &flags,
        chain_simulated_at: &[],
        ..base
    };
    let mut settings = settings(400, 300, 1.0);
    settings.shadows = SelfShadowing::off();
    settings.surface_texture = SurfaceTexture::Stripes;
    settings.light.direction = Vec3::new(0.3, 0.2, 1.0);
    let image = renderer.render(&frame, &settings).unwrap();
    image.pixels().map(is_lit).collect()
}

#[test]
fn strand_coverage_draws_that_fraction_of_the_strands() {
    let mut renderer = renderer();
    let mut chains = Chains::default();
    chains.push_line(Vec3::new(0.0, 0.1, 0.0), Vec3::new(0.0, -0.1, 0.0), 4);
    // 150 strands 2 mm apart, about two pixels at this scale (1 m away, 35°, 600 px tall), so
    // the lit area counts the drawn strands.
    let mut strands = Strands::default();
    let count = 150;
    for i in 0..count {
        let x = -0.15 + 0.3 * i as f32 / (count - 1) as f32;
        strands.push(0, Vec2::new(0.0, x), 0.5);
    }
    renderer.upload_strands(&strands.set()).unwrap();
    let full = lit_pixels(&mut renderer, &chains, 1.0);
    let none = lit_pixels(&mut renderer, &chains, 0.0);
    let half = lit_pixels(&mut renderer, &chains, 0.5);
    assert_eq!(none, 0, "coverage 0 draws nothing");
    assert!(full > 1000, "{full} lit pixels at full coverage");
    // Exactly 75 of the 150 strands are drawn (ranks (k + ½)/150 below ½), picked by a hash so
    // they are spread over the row; neighbours' pixels overlap, and fewer neighbours overlap
    // less, so the lit fraction is not exactly ½. A kept count off by four binomial σ (√(150·¼)
    // ≈ 6.1 strands each) would leave 0.5 ± 0.17.
    let fraction = half as f32 / full as f32;
    assert!(
        (0.33..0.67).contains(&fraction),
        "half coverage lit {fraction} of the pixels"
    );
}

/// A patch 0.2 m wide and 0.2 m long facing the camera (stripes: solid to its edges), at
/// coverage 1, 0.5 and 0: the screen door keeps the pixels whose 4×4 Bayer threshold
/// `(b + ½)/16` lies below the coverage, 8 of every 16 at ½. The patch covers about 120×120
/// pixels, so whole 4×4 tiles hold all but its border rows and columns: the kept fraction is ½
/// within the border's share, under 7 % (4 of 120 pixels on each of two axes). Single-sampled the
/// dropped pixels are discarded; with 4× MSAA they return alpha 0, which alpha-to-coverage turns
/// into no sample.
#[test]
fn surface_coverage_keeps_that_fraction_of_the_pixels() {
    for (name, mut renderer) in patch_renderers() {
        // Binormal +X: the strip spans x = ±0.1 m, facing the camera.
        let chains = vertical_chain(0.1, 5);
        let lit = |renderer: &mut hair_render::Renderer, coverage: f32| {
            let pixels = patch_pixels(renderer, &chains, coverage, false);
            pixels.into_iter().filter(|&p| p).count()
        };
        let full = lit(&mut renderer, 1.0);
        let half = lit(&mut renderer, 0.5);
        let none = lit(&mut renderer, 0.0);
        assert!(full > 5000, "{name}: {full} lit pixels at full coverage");
        assert_eq!(none, 0, "{name}: coverage 0 draws nothing");
        let fraction = half as f32 / full as f32;
        assert!(
            (fraction - 0.5).abs() < 0.07,
            "{name}: half coverage lit {fraction} of the pixels"
        );
    }
}

/// A patch giving way (`chain_gives_way`) at coverage `1 − c` keeps exactly the screen-door
/// pixels the same patch coming in at `c` drops: the same geometry rasterizes to the same
/// pixels, the incoming one keeps thresholds below `c` and the outgoing one those at or above
/// it, so the two lit sets are disjoint and together are the whole patch. Single-sampled the
/// partition is exact; with 4× MSAA the pixels on the patch's edge, partly covered, may fall
/// under the lit threshold in both, so the union is within 3 % (its border, about 4·120 of
/// 120² pixels) of the whole.
#[test]
fn a_surface_giving_way_keeps_the_pixels_the_incoming_one_drops() {
    for (name, mut renderer) in patch_renderers() {
        let exact = name == "single-sampled";
        let chains = vertical_chain(0.1, 5);
        let lit = |renderer: &mut hair_render::Renderer, coverage: f32, gives_way: bool| {
            patch_pixels(renderer, &chains, coverage, gives_way)
        };
        let full = lit(&mut renderer, 1.0, false);
        let whole = full.iter().filter(|&&p| p).count();
        assert!(whole > 5000, "{name}: {whole} lit pixels at full coverage");
        // Giving way at coverage 1 is the whole patch too, at 0 nothing.
        assert_eq!(lit(&mut renderer, 1.0, true), full, "{name}");
        assert!(!lit(&mut renderer, 0.0, true).iter().any(|&p| p), "{name}");
        for c in [0.25f32, 0.5, 0.75] {
            let incoming = lit(&mut renderer, c, false);
            let outgoing = lit(&mut renderer, 1.0 - c, true);
            let both = incoming
                .iter()
                .zip(&outgoing)
                .filter(|(a, b)| **a && **b)
                .count();
            let either = incoming
                .iter()
                .zip(&outgoing)
                .filter(|(a, b)| **a || **b)
                .count();
            let kept = outgoing.iter().filter(|&&p| p).count() as f32 / whole as f32;
            assert!(
                (kept - (1.0 - c)).abs() < 0.07,
                "{name}: giving way at {} kept {kept}",
                1.0 - c
            );
            if exact {
                assert_eq!(both, 0, "{name}, c = {c}: pixels in both");
                assert_eq!(either, whole, "{name}, c = {c}: pixels in neither");
            } else {
                assert!(
                    both as f32 <= 0.03 * whole as f32,
                    "{name}, c = {c}: {both} in both"
                );
                let missing = (whole as f32 - either as f32).abs();
                assert!(
                    missing <= 0.03 * whole as f32,
                    "{name}, c = {c}: {either} of {whole}"
                );
            }
        }
    }
}

#[test]
fn bad_coverage_is_rejected() {
    let mut renderer = renderer();
    let mut chains = Chains::default();
    chains.push_line(Vec3::ZERO, Vec3::NEG_Y * 0.1, 3);
    let base = chains.frame();
    for coverages in [vec![1.5f32], vec![f32::NAN], vec![1.0, 1.0]] {
        let frame = SkeletonFrame {
            chain_coverage: &coverages,
            chain_gives_way: &[],
            chain_simulated_at: &[],
            ..base
        };
        let error = renderer.render(&frame, &settings(64, 64, 1.0)).unwrap_err();
        assert!(error.to_string().contains("coverage"), "{error}");
    }
    let frame = SkeletonFrame {
        chain_gives_way: &[false, true],
        chain_simulated_at: &[],
        ..base
    };
    let error = renderer.render(&frame, &settings(64, 64, 1.0)).unwrap_err();
    assert!(error.to_string().contains("give-way flags"), "{error}");
}
