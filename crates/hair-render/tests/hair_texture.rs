//! The hair texture of clusters and patches (§6): shades that vary along the hair, and strands
//! that end at their own lengths (alpha-to-coverage under MSAA), against the former stripes that
//! are constant along the hair and solid to the tip.

mod common;

use common::*;
use glam::Vec3;
use hair_render::{ClusterSet, PatchSet, SelfShadowing, SurfaceTexture};

/// Renders one cluster (radius 0.03 m) or one patch (0.08 m wide) on the chain with `texture`
/// (4× MSAA, no shadows, no highlight, light from the camera's side) and returns the image and settings.
fn render(
    cluster: bool,
    texture: SurfaceTexture,
) -> (image::RgbaImage, hair_render::FrameSettings) {
    let mut renderer = renderer();
    if cluster {
        renderer
            .upload_clusters(&ClusterSet {
                cluster_chain: &[0],
                cluster_root_radii: &[0.03],
                cluster_tip_radii: &[0.03],
            })
            .unwrap();
    } else {
        renderer
            .upload_patches(&PatchSet {
                patch_chain: &[0],
                patch_widths: &[0.08],
            })
            .unwrap();
    }
    let mut settings = settings(256, 256, 1.0);
    settings.shadows = SelfShadowing::off();
    settings.light.direction = Vec3::new(0.3, 0.2, 1.0);
    settings.surface_texture = texture;
    // No highlight: it moves along the tube with the view direction.
    settings.hair.specular = 0.0;
    let image = renderer
        .render(&vertical_chain(0.15, 7).frame(), &settings)
        .unwrap();
    (image, settings)
}

/// Standard deviation of the luma [levels] along the surface's axis from v = 0.1 to v = 0.6
/// (x = 4 mm off the axis, inside one fine strand of the texture).
fn luma_spread_along(image: &image::RgbaImage, settings: &hair_render::FrameSettings) -> f32 {
    let lumas: Vec<f32> = (0..60)
        .filter_map(|i| {
            let y = 0.15 - 0.3 * (0.1 + 0.5 * i as f32 / 59.0);
            let (px, py) = pixel_of(settings, Vec3::new(0.004, y, 0.03))?;
            Some(luma(image.get_pixel(px, py)))
        })
        .collect();
    let mean = lumas.iter().sum::<f32>() / lumas.len() as f32;
    (lumas.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / lumas.len() as f32).sqrt()
}

/// Along a straight tube or strip under a directional light the diffuse Kajiya-Kay colour is
/// the same everywhere (one tangent, one normal per line along it; the highlight is off): with stripes the luma along the axis
/// is constant (within a level), with the hair texture it varies (the shade drifts along each
/// strand over a seventh of the length, 0.25 of the colour range: several levels).
#[test]
fn the_hair_texture_varies_along_the_hair() {
    for cluster in [true, false] {
        let (hair, settings) = render(cluster, SurfaceTexture::Hair);
        let (stripes, _) = render(cluster, SurfaceTexture::Stripes);
        if let Some(dir) = std::env::var_os("HAIRLOD_TEXTURE_IMAGES") {
            let dir = std::path::PathBuf::from(dir);
            hair.save(dir.join(format!("texture-hair-{cluster}.png")))
                .unwrap();
            stripes
                .save(dir.join(format!("texture-stripes-{cluster}.png")))
                .unwrap();
        }
        let (along_hair, along_stripes) = (
            luma_spread_along(&hair, &settings),
            luma_spread_along(&stripes, &settings),
        );
        assert!(
            along_stripes < 1.0,
            "cluster {cluster}: stripes {along_stripes}"
        );
        assert!(
            along_hair > 2.0,
            "cluster {cluster}: hair texture {along_hair}"
        );
    }
}

/// Strands of the texture end at their own lengths (up to 30 % short): over the last 30 % of the
/// surface, fewer samples are covered than with the stripes, which run solid to the tip.
#[test]
fn the_hair_texture_breaks_up_the_tips() {
    for cluster in [true, false] {
        let (hair, settings) = render(cluster, SurfaceTexture::Hair);
        let (stripes, _) = render(cluster, SurfaceTexture::Stripes);
        let (_, top) = pixel_of(&settings, Vec3::new(0.0, 0.15 - 0.3 * 0.7, 0.0)).unwrap();
        let (_, bottom) = pixel_of(&settings, Vec3::new(0.0, -0.15, 0.0)).unwrap();
        let coverage = |image: &image::RgbaImage| -> f32 {
            (top..bottom)
                .flat_map(|y| (0..image.width()).map(move |x| (x, y)))
                .map(|(x, y)| luma(image.get_pixel(x, y)))
                .sum()
        };
        let (with_hair, with_stripes) = (coverage(&hair), coverage(&stripes));
        assert!(
            with_hair < 0.85 * with_stripes,
            "cluster {cluster}: tip luma {with_hair} vs stripes {with_stripes}"
        );
    }
}
