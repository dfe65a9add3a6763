//! Per-strand lengths and tip scales: a strand of length ½ stops halfway down its chain, and a
//! strand whose offset scales to 0 at the tip meets its chain there.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{StrandSet, StrandShapes};

/// A vertical chain from y = 0.1 to y = −0.1 at x = 0 (binormal +X), one strand on it offset
/// 0.04 m along +X, drawn with `length` and `tip_scale`; returns whether the pixels at the given
/// points are drawn.
fn drawn_at(length: f32, tip_scale: f32, points: &[Vec3]) -> Vec<bool> {
    let chains = vertical_chain(0.1, 9);
    let mut renderer = single_sample_renderer(None);
    renderer
        .upload_strands_with_shapes(
            &StrandSet {
                strand_chain: &[0],
                strand_root_offsets: &[Vec2::new(0.0, 0.04)],
                strand_shades: &[0.5],
            },
            &StrandShapes {
                strand_lengths: &[length],
                strand_tip_scales: &[tip_scale],
            },
        )
        .unwrap();
    let mut settings = settings(200, 200, 3.0);
    settings.shadows = hair_render::SelfShadowing::off();
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    points
        .iter()
        .map(|&p| {
            let (x, y) = pixel_of(&settings, p).unwrap();
            is_lit(image.get_pixel(x, y))
        })
        .collect()
}

#[test]
fn a_half_length_strand_stops_halfway() {
    let (upper, lower) = (Vec3::new(0.04, 0.05, 0.0), Vec3::new(0.04, -0.05, 0.0));
    assert_eq!(drawn_at(1.0, 1.0, &[upper, lower]), [true, true]);
    assert_eq!(drawn_at(0.5, 1.0, &[upper, lower]), [true, false]);
}

/// With tip scale 0 the offset is 0.04·(1 − u): at u = ¾ (y = −0.05) the strand is at
/// x = 0.01, not at 0.04.
#[test]
fn a_tip_scale_gathers_the_strand_towards_its_chain() {
    let (parallel, gathered) = (Vec3::new(0.04, -0.05, 0.0), Vec3::new(0.01, -0.05, 0.0));
    assert_eq!(drawn_at(1.0, 1.0, &[parallel, gathered]), [true, false]);
    assert_eq!(drawn_at(1.0, 0.0, &[parallel, gathered]), [false, true]);
}
