//! Strand thinning: a strand group small on screen draws only as many of its strands as its
//! screen width needs, a stochastic simplification (Cook, Halstead, Planck & Ryu 2007) of the
//! strand level. Strands leave in their dissolve order, so the ones kept are spread evenly over
//! the group and a group that grows on screen takes them back one by one.
//!
//! A strand drawn as a 1-pixel line covers one pixel column of its group's footprint, so the
//! pixels a group covers saturate once a few strands cross each column: beyond that, strands
//! only change which one is in front. Thinning keeps `strands_per_pixel` strands per pixel of
//! the group's projected width. What it cannot keep is *which* strand shows in each pixel: close
//! to the camera, where a group is tens of pixels wide, halving the strands redraws half the
//! pixels from other strands, so the rule leaves near groups whole (see `docs/render.md`).
//! Self-shadowing counts every strand: the light passes weigh each drawn strand's opacity by the
//! inverse of its group's drawn fraction.

use crate::batches::GpuChain;
use crate::inputs::StrandSet;
use crate::settings::{StrandStyle, StrandThinning};

/// A chain's strands: how many follow it, and the largest root offset among them [m] (half the
/// group's width).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct StrandSpan {
    pub count: u32,
    pub radius: f32,
}

/// The strand span of every chain up to the largest one a strand follows.
pub(crate) fn strand_spans(strands: &StrandSet<'_>) -> Vec<StrandSpan> {
    let chains = strands
        .strand_chain
        .iter()
        .map(|&chain| chain as usize + 1)
        .max()
        .unwrap_or(0);
    let mut spans = vec![StrandSpan::default(); chains];
    for (&chain, offset) in strands.strand_chain.iter().zip(strands.strand_root_offsets) {
        let span = &mut spans[chain as usize];
        span.count += 1;
        span.radius = span.radius.max(offset.length());
    }
    spans
}

/// The fraction of `span`'s strands drawn at `distance` [m] through a focal length of `focal`
/// [pixels]: `max(1, k·2r·f/d)/n`, at most 1 (1 for a chain without strands).
pub(crate) fn drawn_fraction(
    span: StrandSpan,
    distance: f32,
    focal: f32,
    strands_per_pixel: f32,
) -> f32 {
    if span.count == 0 {
        return 1.0;
    }
    let width_pixels = 2.0 * span.radius * focal / distance.max(1e-6);
    let needed = (strands_per_pixel * width_pixels).max(1.0);
    (needed / span.count as f32).min(1.0)
}

/// Thins the strand chains of a frame's chain table: each chain's coverage is scaled by its
/// drawn fraction (the batches then draw that prefix of its ranked strands) and its shadow
/// weight set to the inverse. `distances` [m] are the chains' root distances. Where the
/// thinning raises widths, each drawn strand is widened ([`raised_width_scale`]) and drawn as a
/// ribbon once wider than a pixel.
pub(crate) fn thin_chains(
    chains: &mut [GpuChain],
    spans: &[StrandSpan],
    distances: &[f32],
    focal: f32,
    thinning: StrandThinning,
    style: StrandStyle,
) {
    let StrandThinning::ByScreenWidth {
        strands_per_pixel,
        raise_widths,
    } = thinning
    else {
        return;
    };
    for ((chain, span), &distance) in chains.iter_mut().zip(spans).zip(distances) {
        let fraction = drawn_fraction(*span, distance, focal, strands_per_pixel);
        if fraction >= 1.0 {
            continue;
        }
        chain.coverage *= fraction;
        chain.shadow_weight = 1.0 / fraction;
        let drawn = style.ribbon_pixels(focal, distance);
        if let (true, Some(pixels)) = (raise_widths, drawn) {
            let group = 2.0 * span.radius * focal / distance.max(1e-6);
            chain.width_scale = raised_width_scale(pixels, group, fraction);
            if pixels * chain.width_scale > 1.0 {
                chain.thin = 0;
            }
        }
    }
}

/// How much wider a strand drawn `pixels` wide is drawn when a fraction `fraction` of its
/// group's strands is drawn, the group `group_pixels` wide on screen: `min(1/φ, max(g/p, 1))`.
///
/// Strands spread over a group `g` pixels wide leave a pixel column uncovered with probability
/// `(1 − p/g)^n ≈ e^{−n·p/g}` for `n` strands `p` wide; `φ·n` strands `p/φ` wide leave the same
/// share, so the group covers what all its strands cover. A strand wider than its group covers
/// the group on its own, so the width stops at the group's.
pub(crate) fn raised_width_scale(pixels: f32, group_pixels: f32, fraction: f32) -> f32 {
    let widest = (group_pixels / pixels.max(1e-6)).max(1.0);
    (1.0 / fraction.max(1e-6)).min(widest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn span(count: u32, radius: f32) -> StrandSpan {
        StrandSpan { count, radius }
    }

    #[test]
    fn a_group_draws_k_strands_per_pixel_of_its_projected_width() {
        // 100 strands, 5 mm radius, focal 1000 px: at d = 2 m the group is 2·0.005·1000/2 = 5 px
        // wide, and k = 4 keeps 20 strands, a fifth.
        let fraction = drawn_fraction(span(100, 0.005), 2.0, 1000.0, 4.0);
        assert!((fraction - 0.2).abs() < 1e-6, "{fraction}");
        // Twice as far, half as wide: half as many.
        let fraction = drawn_fraction(span(100, 0.005), 4.0, 1000.0, 4.0);
        assert!((fraction - 0.1).abs() < 1e-6, "{fraction}");
    }

    #[test]
    fn near_groups_stay_whole_and_far_ones_keep_one_strand() {
        // At 0.2 m the group is 50 px wide: 200 strands needed, all 100 drawn.
        assert_eq!(drawn_fraction(span(100, 0.005), 0.2, 1000.0, 4.0), 1.0);
        // At 1 km it is 0.01 px wide: one strand.
        assert_eq!(drawn_fraction(span(100, 0.005), 1000.0, 1000.0, 4.0), 0.01);
        // A chain no strand follows is left alone.
        assert_eq!(drawn_fraction(span(0, 0.0), 1000.0, 1000.0, 4.0), 1.0);
    }

    #[test]
    fn spans_count_each_chains_strands_and_their_widest_offset() {
        let chains = [0, 2, 2, 0, 2];
        let offsets = [
            Vec2::new(0.001, 0.0),
            Vec2::new(0.0, 0.003),
            Vec2::new(0.004, 0.0),
            Vec2::new(0.0, -0.002),
            Vec2::ZERO,
        ];
        let shades = [0.5; 5];
        let set = StrandSet {
            strand_chain: &chains,
            strand_root_offsets: &offsets,
            strand_shades: &shades,
        };
        let spans = strand_spans(&set);
        assert_eq!(spans.len(), 3);
        assert_eq!(spans[0], span(2, 0.002));
        assert_eq!(spans[1], span(0, 0.0));
        assert_eq!(spans[2], span(3, 0.004));
    }

    #[test]
    fn thinning_scales_coverage_and_weighs_shadows_back() {
        let mut chains = [
            GpuChain {
                coverage: 1.0,
                shadow_weight: 1.0,
                width_scale: 1.0,
                ..GpuChain::default()
            },
            GpuChain {
                coverage: 0.5, // fading in: both fractions apply
                shadow_weight: 1.0,
                width_scale: 1.0,
                ..GpuChain::default()
            },
        ];
        let spans = [span(100, 0.005), span(100, 0.005)];
        let thinning = StrandThinning::ByScreenWidth {
            strands_per_pixel: 4.0,
            raise_widths: false,
        };
        let style = StrandStyle::default();
        thin_chains(&mut chains, &spans, &[0.2, 2.0], 1000.0, thinning, style);
        assert_eq!((chains[0].coverage, chains[0].shadow_weight), (1.0, 1.0));
        assert!((chains[1].coverage - 0.1).abs() < 1e-6);
        assert!((chains[1].shadow_weight - 5.0).abs() < 1e-5);
        assert_eq!(chains[1].width_scale, 1.0, "widths left alone");
        // Off leaves the table as it is.
        let before = chains;
        thin_chains(
            &mut chains,
            &spans,
            &[9.0, 9.0],
            1000.0,
            StrandThinning::Off,
            style,
        );
        assert_eq!(chains, before);
    }

    #[test]
    fn raised_widths_stand_for_the_strands_left_out_up_to_the_group() {
        // A 1-pixel strand drawn for a fifth of its group, the group 5 px wide: 5× wider, as
        // wide as the group. For a tenth of a 20 px group: 10×. For a hundredth of a 3 px
        // group: the group's 3 px, not 100.
        assert!((raised_width_scale(1.0, 5.0, 0.2) - 5.0).abs() < 1e-5);
        assert!((raised_width_scale(1.0, 20.0, 0.1) - 10.0).abs() < 1e-4);
        assert!((raised_width_scale(1.0, 3.0, 0.01) - 3.0).abs() < 1e-5);
        // A strand already wider than its group is never narrowed.
        assert_eq!(raised_width_scale(2.0, 1.0, 0.1), 1.0);
    }

    #[test]
    fn raising_widths_widens_thinned_ribbons_and_leaves_lines() {
        let chain = GpuChain {
            coverage: 1.0,
            shadow_weight: 1.0,
            width_scale: 1.0,
            thin: 1,
            ..GpuChain::default()
        };
        let spans = [span(100, 0.005)];
        let thinning = StrandThinning::ByScreenWidth {
            strands_per_pixel: 4.0,
            raise_widths: true,
        };
        // At 2 m through 1000 px the group is 5 px wide and a fifth of it is drawn: its 1-pixel
        // strands (80 µm project to 0.04 px, raised to the 1 px minimum) become 5 px ribbons.
        // Lines stay lines, one pixel wide.
        for (style, width_scale, thin) in [
            (StrandStyle::default(), 5.0, 0),
            (StrandStyle::Lines, 1.0, 1),
        ] {
            let mut chains = [chain];
            thin_chains(&mut chains, &spans, &[2.0], 1000.0, thinning, style);
            assert!(
                (chains[0].width_scale - width_scale).abs() < 1e-4,
                "{style:?}: {:?}",
                chains[0]
            );
            assert_eq!(chains[0].thin, thin, "{style:?}");
            assert!((chains[0].coverage - 0.2).abs() < 1e-6);
        }
    }

    #[test]
    fn bad_densities_are_named() {
        for k in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let error = StrandThinning::ByScreenWidth {
                strands_per_pixel: k,
                raise_widths: true,
            }
            .validate()
            .unwrap_err()
            .to_string();
            assert!(error.contains("strands per pixel"), "{error}");
        }
    }
}
