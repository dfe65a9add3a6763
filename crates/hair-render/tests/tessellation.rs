//! Tessellation around a cluster tube follows its projected ring: a tube drawn with a half-pixel
//! chord error (half the default) covers the pixels of a finely tessellated one but for a band no
//! wider than the chord error along each silhouette edge, and a coarse chord error visibly does not.

mod common;

use common::*;
use glam::Vec3;
use hair_render::{ClusterSet, FrameSettings, Renderer, ShadingMode, surfaces::RING_RADIUS_FACTOR};

/// Ring radius on screen [pixels].
const RING_PIXELS: f32 = 8.0;

/// Pixels that show the tube (the cluster code colour; the background is black).
fn tube_mask(image: &image::RgbaImage) -> Vec<bool> {
    image.pixels().map(|p| p.0[0] > 128).collect()
}

/// A straight tube across the image seen side on, single-sampled and colour-coded, rendered with
/// chord error `epsilon` [pixels] (and up to 64 segments around).
fn render_tube(renderer: &mut Renderer, epsilon: f32) -> (Vec<bool>, f32) {
    // Along +X, the node frame turned 45° about it from the view direction (+Z): the ring's
    // control directions, where a polygon of 4 puts its vertices, are then off the silhouette.
    let half = 0.25;
    let mut chains = Chains::default();
    for k in 0..6 {
        let x = -half + 2.0 * half * k as f32 / 5.0;
        chains.positions.push(Vec3::new(x, 0.0, 0.0));
        let normal = Vec3::new(0.0, 1.0, 1.0).normalize();
        chains.normals.push(normal);
        chains.binormals.push(Vec3::X.cross(normal));
    }
    chains.offsets = vec![0, 6];
    let mut settings: FrameSettings = settings(256, 128, 1.0);
    settings.mode = ShadingMode::LevelColors;
    settings.tessellation.max_around_segments = 64;
    settings.tessellation.max_chord_error_pixels = epsilon;
    let distance = settings.camera.position.length();
    let focal = settings.camera.focal_length_pixels(settings.height);
    let radius = RING_PIXELS * distance / focal / RING_RADIUS_FACTOR;
    renderer
        .upload_clusters(&ClusterSet {
            cluster_chain: &[0],
            cluster_root_radii: &[radius],
            cluster_tip_radii: &[radius],
        })
        .unwrap();
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let length_pixels = 2.0 * half * focal / distance;
    (tube_mask(&image), length_pixels)
}

/// The polygon of a ring of radius R lies between R·cos(π/n) and R, so the silhouette of the
/// tessellated tube stays within ε of the fine one along both edges: the pixel centres covered by
/// one and not the other lie in two bands of width ≤ ε and length L, at most 2·ε·L pixels (plus
/// the two open ends, each within a ring diameter). A 4-pixel chord error must exceed its own
/// half-pixel bound, so the test also fails if the chord error is not applied.
#[test]
fn tube_silhouette_stays_within_the_chord_error() {
    let mut renderer = single_sample_renderer(None);
    let (fine, length) = render_tube(&mut renderer, 0.01);
    let covered = fine.iter().filter(|&&c| c).count() as f32;
    // The fine tube is about 2R wide over its length.
    assert!(
        (covered / (2.0 * RING_PIXELS * length) - 1.0).abs() < 0.2,
        "{covered} pixels for a {length}-pixel tube"
    );
    let differing = |mask: &[bool]| mask.iter().zip(&fine).filter(|(a, b)| a != b).count() as f32;
    let ends = 2.0 * 2.0 * RING_PIXELS;
    let (half_pixel, _) = render_tube(&mut renderer, 0.5);
    let bound = 2.0 * 0.5 * length + ends;
    assert!(
        differing(&half_pixel) <= bound,
        "{} pixels differ at 0.5 px, bound {bound}",
        differing(&half_pixel)
    );
    let (coarse, _) = render_tube(&mut renderer, 4.0);
    eprintln!(
        "differing pixels: {} at 0.5 px, {} at 4 px (bound {bound}, tube {length} px long)",
        differing(&half_pixel),
        differing(&coarse)
    );
    assert!(
        differing(&coarse) > bound,
        "{} pixels differ at 4 px, bound {bound}",
        differing(&coarse)
    );
}
