//! Per-strand lengths, tip scales and residual profiles: a strand of length ½ stops halfway down
//! its chain, a strand whose offset scales to 0 at the tip meets its chain there, and a strand
//! with a profile is drawn where its residuals put it.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{StrandSet, StrandShapes};

/// A vertical chain from y = 0.1 to y = −0.1 at x = 0 (binormal +X), one strand on it offset
/// 0.04 m along +X, drawn with `length` and `tip_scale`; returns whether the pixels at the given
/// points are drawn.
fn drawn_at(length: f32, tip_scale: f32, points: &[Vec3]) -> Vec<bool> {
    drawn_with(Vec2::new(0.0, 0.04), length, tip_scale, &[], points)
}

/// [`drawn_at`] with the root offset `offset` and a residual `profile` (none when empty).
fn drawn_with(
    offset: Vec2,
    length: f32,
    tip_scale: f32,
    profile: &[Vec3],
    points: &[Vec3],
) -> Vec<bool> {
    let chains = vertical_chain(0.1, 9);
    let mut renderer = single_sample_renderer(None);
    renderer
        .upload_strands_with_shapes(
            &StrandSet {
                strand_chain: &[0],
                strand_root_offsets: &[offset],
                strand_shades: &[0.5],
            },
            &StrandShapes {
                strand_lengths: &[length],
                strand_tip_scales: &[tip_scale],
                strand_profiles: if profile.is_empty() { &[] } else { &[0] },
                profiles: profile,
            },
        )
        .unwrap();
    lit_at(&mut renderer, &chains.frame(), points)
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

/// A profile whose residual grows linearly from 0 at the root to 0.08 m along B̂ at the tip. On
/// this chain T̂ = −Y and the node normal is N = −Z, already perpendicular to T̂, so N̂ = −Z and
/// B̂ = T̂ × N̂ = X: the strand's point at u is C(u) + 0.08·u·X (C from the CPU B-spline of the
/// nodes: a clamped cubic is not parametrised by length near its ends), through x = 0.02 and
/// x = 0.06 at u = ¼ and ¾, and not where the plain offset 0.04 puts a strand at those heights.
#[test]
fn a_profile_moves_the_strand_in_the_chains_frame() {
    let n = hair_core::PROFILE_SAMPLES;
    let profile: Vec<Vec3> = (0..n)
        .map(|j| Vec3::new(0.0, 0.08 * j as f32 / (n - 1) as f32, 0.0))
        .collect();
    let chain = vertical_chain(0.1, 9);
    let at = |u: f32| {
        let (c, _) = hair_render::bspline::evaluate(&chain.positions, u).unwrap();
        (c + Vec3::X * 0.08 * u, c + Vec3::X * 0.04)
    };
    let ((upper, upper_plain), (lower, lower_plain)) = (at(0.25), at(0.75));
    let points = [upper, lower, upper_plain, lower_plain];
    assert_eq!(
        drawn_with(Vec2::ZERO, 1.0, 1.0, &profile, &points),
        [true, true, false, false]
    );
    assert_eq!(drawn_at(1.0, 1.0, &points), [false, false, true, true]);
    // A constant residual (0, 0.04, 0) draws what the root offset (0, 0.04) draws.
    let constant = vec![Vec3::new(0.0, 0.04, 0.0); n];
    assert_eq!(
        drawn_with(Vec2::ZERO, 1.0, 1.0, &constant, &points),
        [false, false, true, true]
    );
}
