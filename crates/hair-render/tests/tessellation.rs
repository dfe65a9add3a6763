//! Tessellation around a cluster tube follows its projected ring: a tube drawn with a half-pixel
//! chord error (half the default) covers the pixels of a finely tessellated one but for a band no
//! wider than the chord error along each silhouette edge, and a coarse chord error visibly does not.
//! A cluster drawn as an impostor (the default) covers the fine tube's pixels and shades them as
//! the tube does.

mod common;

use common::*;
use glam::Vec3;
use hair_render::{
    ClusterGeometry, ClusterSet, FrameSettings, Renderer, SelfShadowing, ShadingMode,
    SurfaceTexture, surfaces::RING_RADIUS_FACTOR,
};

/// Ring radius on screen [pixels].
const RING_PIXELS: f32 = 8.0;

/// Pixels that show the tube (the cluster code colour; the background is black).
fn tube_mask(image: &image::RgbaImage) -> Vec<bool> {
    image.pixels().map(|p| p.0[0] > 128).collect()
}

/// A straight tube across the image seen side on, single-sampled and colour-coded, rendered with
/// chord error `epsilon` [pixels] (and up to 64 segments around).
fn render_tube(renderer: &mut Renderer, epsilon: f32) -> (Vec<bool>, f32) {
    let (image, length) = render_cluster(renderer, epsilon, ClusterGeometry::Tube, None);
    (tube_mask(&image), length)
}

/// The straight cluster of [`render_tube`] drawn as `geometry`, colour-coded, or shaded with
/// `shading`'s texture (no shadows); returns the image and the tube's length [pixels].
fn render_cluster(
    renderer: &mut Renderer,
    epsilon: f32,
    geometry: ClusterGeometry,
    shading: Option<SurfaceTexture>,
) -> (image::RgbaImage, f32) {
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
    if let Some(texture) = shading {
        settings.mode = ShadingMode::Shaded;
        settings.surface_texture = texture;
        settings.shadows = SelfShadowing::off();
    }
    settings.cluster_geometry = geometry;
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
    (image, length_pixels)
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

/// An impostor is the tube's silhouette: a band of the ring's mean radius (0.657 of the control
/// radius) on each side of the axis, where the ring runs at 0.648–0.667 of it, so each edge lies
/// within 0.015 · 1.5 · R ≈ 0.12 px of the fine tube's here (R = 8 px): the pixel centres covered by
/// one and not the other fit in the half-pixel bound of the tessellated tube's test, 2·0.5·L plus
/// the open ends. An impostor of the wrong width (or none) differs by 2·R·L ≫ that.
#[test]
fn impostor_covers_the_tube_silhouette() {
    let mut renderer = single_sample_renderer(None);
    let (fine, length) = render_tube(&mut renderer, 0.01);
    let (impostor, _) = render_cluster(&mut renderer, 0.5, ClusterGeometry::Impostor, None);
    let impostor = tube_mask(&impostor);
    let differing = impostor.iter().zip(&fine).filter(|(a, b)| a != b).count() as f32;
    let covered = impostor.iter().filter(|&&c| c).count() as f32;
    let bound = 2.0 * 0.5 * length + 2.0 * 2.0 * RING_PIXELS;
    eprintln!("impostor: {covered} pixels covered, {differing} differ from the fine tube");
    assert!(
        differing <= bound,
        "{differing} pixels differ from the fine tube, bound {bound}"
    );
}

/// Shaded (Kajiya-Kay, the stripe texture around, no shadows), the impostor's pixels have the
/// fine tube's colours: it rebuilds the tube's normal and its angle around in the node frame
/// per fragment. Pixels inside both silhouettes, at least a pixel from either edge, differ by at
/// most a few 8-bit steps on average (1.0 when measured, largest 10: the B-spline ring is not
/// quite a circle, and its parameter not quite the angle). With the texture's angle a quarter
/// turn off, the mean difference was 10.7.
#[test]
fn impostor_shades_as_the_tube() {
    let mut renderer = single_sample_renderer(None);
    let stripes = Some(SurfaceTexture::Stripes);
    let (tube, _) = render_cluster(&mut renderer, 0.01, ClusterGeometry::Tube, stripes);
    let (impostor, _) = render_cluster(&mut renderer, 0.5, ClusterGeometry::Impostor, stripes);
    let (width, height) = tube.dimensions();
    let inside = |image: &image::RgbaImage, x: u32, y: u32| {
        (x.saturating_sub(1)..=(x + 1).min(width - 1)).all(|i| {
            (y.saturating_sub(1)..=(y + 1).min(height - 1))
                .all(|j| image.get_pixel(i, j).0[..3].iter().any(|&c| c > 0))
        })
    };
    let (mut sum, mut count, mut largest) = (0.0f64, 0usize, 0u8);
    for y in 0..height {
        for x in 0..width {
            if inside(&tube, x, y) && inside(&impostor, x, y) {
                let (a, b) = (tube.get_pixel(x, y).0, impostor.get_pixel(x, y).0);
                for c in 0..3 {
                    let d = a[c].abs_diff(b[c]);
                    sum += f64::from(d);
                    largest = largest.max(d);
                }
                count += 1;
            }
        }
    }
    let mean = sum / (3 * count.max(1)) as f64;
    eprintln!("{count} pixels compared: mean difference {mean:.2}, largest {largest} (8-bit)");
    assert!(count > 1000, "only {count} pixels inside both");
    assert!(mean < 3.0, "mean difference {mean:.2} of 255");
}
