//! Clusters and patches on whatever adapter is found (and on both Mesa backends): their screen
//! coverage from the skeleton, LOD colour coding with exactly the colours of the levels present,
//! textured shading within the hair colour range, and inactive chains drawing nothing.

mod common;

use std::collections::BTreeSet;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{BackendChoice, ClusterSet, LevelColors, PatchSet, Renderer, ShadingMode};

/// Three vertical chains 0.3 m long, at x = -0.15 (strands), 0 (cluster) and 0.15 (patch), with
/// node frames whose binormal is +X (so a patch faces the camera on +Z); then a second cluster
/// chain at x = 0.3.
fn three_levels() -> Chains {
    let mut chains = Chains::default();
    for x in [-0.15f32, 0.0, 0.15, 0.3] {
        for k in 0..6 {
            chains
                .positions
                .push(Vec3::new(x, 0.15 - 0.06 * k as f32, 0.0));
            // Tangent -Y = normal × binormal with normal -Z, binormal +X.
            chains.normals.push(Vec3::NEG_Z);
            chains.binormals.push(Vec3::X);
        }
    }
    chains.offsets = (0..=4).map(|c| 6 * c).collect();
    chains
}

const CLUSTER_RADIUS: f32 = 0.04;
const PATCH_WIDTH: f32 = 0.08;

/// Five strands on chain 0, clusters on chains 1 and 3, a patch on chain 2.
fn upload(renderer: &mut Renderer) {
    let mut strands = Strands::default();
    for s in 0..5 {
        strands.push(0, Vec2::new(0.0, -0.02 + 0.01 * s as f32), 0.2 * s as f32);
    }
    renderer.upload_strands(&strands.set()).unwrap();
    renderer
        .upload_clusters(&ClusterSet {
            cluster_chain: &[3, 1],
            cluster_root_radii: &[CLUSTER_RADIUS; 2],
            cluster_tip_radii: &[CLUSTER_RADIUS; 2],
        })
        .unwrap();
    renderer
        .upload_patches(&PatchSet {
            patch_chain: &[2],
            patch_widths: &[PATCH_WIDTH],
        })
        .unwrap();
}

fn rgb(color: Vec3) -> [u8; 3] {
    [srgb8(color.x), srgb8(color.y), srgb8(color.z)]
}

fn colors_of(image: &image::RgbaImage) -> BTreeSet<[u8; 3]> {
    image.pixels().map(|p| [p.0[0], p.0[1], p.0[2]]).collect()
}

/// Without multisampling every pixel is exactly one code colour or the background, so the set of
/// colours in the image is the set of levels present (plus the background). Emptying a chain
/// removes its geometry; a cluster drawn after an inactive one still shows (instanced draws start
/// past the skipped items).
fn color_coded_render_has_exactly_the_levels_present(backend: BackendChoice) {
    let mut renderer = single_sample_renderer(Some(backend));
    upload(&mut renderer);
    let chains = three_levels();
    let mut settings = settings(320, 160, 2.0);
    settings.camera.position = Vec3::new(0.075, 0.0, 1.0);
    settings.camera.target = Vec3::new(0.075, 0.0, 0.0);
    settings.mode = ShadingMode::LevelColors;
    let codes = LevelColors::default();
    let background = [0u8; 3];

    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let expected: BTreeSet<[u8; 3]> = [
        background,
        rgb(codes.strands),
        rgb(codes.clusters),
        rgb(codes.patches),
    ]
    .into();
    assert_eq!(colors_of(&image), expected, "all three levels");

    // Clusters inactive: their chains have no nodes.
    let mut no_clusters = Chains {
        positions: chains.positions[..18].to_vec(),
        normals: chains.normals[..18].to_vec(),
        binormals: chains.binormals[..18].to_vec(),
        offsets: vec![0, 6, 6, 12, 12],
    };
    no_clusters.positions.drain(6..12);
    no_clusters.normals.drain(6..12);
    no_clusters.binormals.drain(6..12);
    let image = renderer.render(&no_clusters.frame(), &settings).unwrap();
    let expected: BTreeSet<[u8; 3]> = [background, rgb(codes.strands), rgb(codes.patches)].into();
    assert_eq!(colors_of(&image), expected, "strands and patches only");

    // Only the second cluster (chain 3) active: item 1 in chain order is drawn alone.
    let mut last_cluster = chains.clone();
    last_cluster.positions.drain(0..18);
    last_cluster.normals.drain(0..18);
    last_cluster.binormals.drain(0..18);
    last_cluster.offsets = vec![0, 0, 0, 0, 6];
    let image = renderer.render(&last_cluster.frame(), &settings).unwrap();
    let expected: BTreeSet<[u8; 3]> = [background, rgb(codes.clusters)].into();
    assert_eq!(colors_of(&image), expected, "one cluster");
    let (x, y) = pixel_of(&settings, Vec3::new(0.3, 0.0, 0.0)).unwrap();
    assert_eq!(image.get_pixel(x, y).0[..3], rgb(codes.clusters));
}

#[test]
fn color_coded_render_has_exactly_the_levels_present_on_vulkan() {
    color_coded_render_has_exactly_the_levels_present(BackendChoice::Vulkan);
}

#[test]
fn color_coded_render_has_exactly_the_levels_present_on_gl() {
    color_coded_render_has_exactly_the_levels_present(BackendChoice::Gl);
}

/// The tube is the periodic cubic B-spline of 4 points on a circle of radius r: its cross-section
/// lies between 0.648 r and r·2/3 from the axis (at the knots (P₀ + 4P₁ + P₂)/6 = 2r/3). The strip
/// is linear across: exactly w/2 either side of the chain. Inside those radii the pixels are hair,
/// outside (with a pixel of margin) background.
fn surfaces_cover_their_screen_region(mut renderer: Renderer) {
    upload(&mut renderer);
    let chains = three_levels();
    let mut settings = settings(512, 256, 2.0);
    settings.camera.position = Vec3::new(0.075, 0.0, 1.0);
    settings.camera.target = Vec3::new(0.075, 0.0, 0.0);
    settings.mode = ShadingMode::LevelColors;
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let codes = LevelColors::default();
    let pixels_per_metre = settings.camera.focal_length_pixels(settings.height); // at 1 m
    for (centre, inner, outer, color, what) in [
        (
            0.0f32,
            0.62 * CLUSTER_RADIUS,
            0.70 * CLUSTER_RADIUS,
            codes.clusters,
            "cluster",
        ),
        (
            0.15,
            0.5 * PATCH_WIDTH,
            0.5 * PATCH_WIDTH,
            codes.patches,
            "patch",
        ),
    ] {
        for y_world in [0.1f32, 0.0, -0.1] {
            let (cx, y) = pixel_of(&settings, Vec3::new(centre, y_world, 0.0)).unwrap();
            let inner_px = (inner * pixels_per_metre) as i64 - 1;
            let outer_px = (outer * pixels_per_metre).ceil() as i64 + 1;
            for dx in -inner_px..=inner_px {
                let x = (cx as i64 + dx) as u32;
                assert_eq!(
                    image.get_pixel(x, y).0[..3],
                    rgb(color),
                    "{what}: pixel ({x}, {y}) inside is not hair"
                );
            }
            for x in [cx as i64 - outer_px, cx as i64 + outer_px] {
                assert!(
                    !is_lit(image.get_pixel(x as u32, y)),
                    "{what}: pixel ({x}, {y}) outside is drawn"
                );
            }
        }
    }
}

#[test]
fn surfaces_cover_their_screen_region_on_vulkan() {
    surfaces_cover_their_screen_region(renderer_on(BackendChoice::Vulkan));
}

#[test]
fn surfaces_cover_their_screen_region_on_gl() {
    surfaces_cover_their_screen_region(renderer_on(BackendChoice::Gl));
}

/// sRGB 8-bit back to linear.
fn linear(value: u8) -> f32 {
    let v = f32::from(value) / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// With specular off, a surface pixel is `base · (ambient + light · kd · sin(T, L) · occlusion)`
/// with `base` between the dark and light hair colours and occlusion in 0.35..1: every hair pixel
/// of the patch and the tube lies between `dark · ambient` and `light · (ambient + 1)` channel by
/// channel, and the stripe texture gives many different shades.
#[test]
fn surfaces_are_textured_in_the_hair_colour_range() {
    let mut renderer = renderer();
    upload(&mut renderer);
    let chains = three_levels();
    let mut settings = settings(512, 256, 2.0);
    settings.camera.position = Vec3::new(0.075, 0.0, 1.0);
    settings.camera.target = Vec3::new(0.075, 0.0, 0.0);
    settings.light.ambient = Vec3::splat(0.1);
    settings.light.direction = Vec3::new(0.3, 0.2, 1.0);
    settings.hair.specular = 0.0;
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let (dark, light) = (settings.hair.dark_color, settings.hair.light_color);
    let low = dark * 0.1;
    let high = light * 1.1;
    let mut shades = BTreeSet::new();
    for centre in [0.0f32, 0.15] {
        let (cx, y) = pixel_of(&settings, Vec3::new(centre, 0.0, 0.0)).unwrap();
        for x in cx - 6..=cx + 6 {
            let p = image.get_pixel(x, y).0;
            for c in 0..3 {
                let value = linear(p[c]);
                // One 8-bit step of slack either side.
                assert!(
                    value >= low[c] - 0.004 && value <= high[c] + 0.004,
                    "pixel ({x}, {y}) channel {c} = {value} outside {}..{}",
                    low[c],
                    high[c]
                );
            }
            shades.insert(p);
        }
    }
    assert!(
        shades.len() >= 8,
        "only {} shades: no texture",
        shades.len()
    );
}
