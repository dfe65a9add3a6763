//! The per-frame uniform block (`Globals` in `shaders/common.wgsl`), packed from the frame settings.

use glam::Vec3;

use crate::material::HairShading;
use crate::settings::{
    ClusterGeometry, FrameSettings, LineCoverage, ShadingMode, StrandStyle, SurfaceTexture,
};
use crate::shadows::SelfShadowing;

/// Counts the shaders need to bound their reads.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GeometryCounts {
    pub strands: u32,
    pub chains: u32,
    pub nodes: u32,
    /// Samples per strand of the evaluation pass (0 when drawing).
    pub samples_per_strand: u32,
    /// MSAA samples per pixel of the target (0 outside a draw).
    pub samples_per_pixel: u32,
}

/// Byte layout of `Globals` in `common.wgsl` (std140-compatible: a matrix and 16-byte vectors).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Globals {
    view_proj: [[f32; 4]; 4],
    camera_position: [f32; 4],
    light_direction: [f32; 4],
    light_color: [f32; 4],
    ambient: [f32; 4],
    hair_dark: [f32; 4],
    hair_light: [f32; 4],
    head_color: [f32; 4],
    strand_code_color: [f32; 4],
    cluster_code_color: [f32; 4],
    patch_code_color: [f32; 4],
    head_code_color: [f32; 4],
    viewport: [f32; 4],
    shading: [f32; 4],
    ribbon: [f32; 4],
    counts: [u32; 4],
    light_view_proj: [[f32; 4]; 4],
    shadow: [f32; 4],
    shadow_layers: [f32; 4],
    shadow_surfaces: [f32; 4],
    hair_model: [f32; 4],
    line_coverage: [f32; 4],
}

/// What the light passes of self-shadowing need besides the settings (see [`crate::shadows`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ShadowFrame {
    /// The light's orthographic view-projection.
    pub light_view_proj: glam::Mat4,
    /// Depth range of the light view [m].
    pub depth_range: f32,
    /// Side of a shadow-map texel [m].
    pub texel_size: f32,
    /// Side of the maps this frame [texels].
    pub resolution: u32,
    /// Mean strands per cluster and per patch (uploaded strands over uploaded surfaces).
    pub strands_per_cluster: f32,
    pub strands_per_patch: f32,
}

fn v4(v: Vec3) -> [f32; 4] {
    v.extend(0.0).to_array()
}

impl Globals {
    /// Packs (validated) settings and counts; `shadow` is `None` without self-shadowing.
    pub fn new(
        settings: &FrameSettings,
        counts: GeometryCounts,
        shadow: Option<&ShadowFrame>,
    ) -> Globals {
        let aspect = settings.width as f32 / settings.height as f32;
        let (half_width, min_half_pixels) = match settings.strand_style {
            StrandStyle::Lines => (0.0, 0.0),
            StrandStyle::Ribbons {
                width,
                min_width_pixels,
            } => (0.5 * width, 0.5 * min_width_pixels),
        };
        let color_coded = match settings.mode {
            ShadingMode::Shaded => 0.0,
            ShadingMode::LevelColors => 1.0,
        };
        Globals {
            view_proj: settings.camera.view_projection(aspect).to_cols_array_2d(),
            camera_position: settings.camera.position.extend(1.0).to_array(),
            light_direction: v4(settings.light.direction.normalize()),
            light_color: v4(settings.light.color),
            ambient: v4(settings.light.ambient),
            hair_dark: v4(settings.hair.dark_color),
            hair_light: v4(settings.hair.light_color),
            head_color: v4(settings.head_color),
            strand_code_color: v4(settings.level_colors.strands),
            cluster_code_color: v4(settings.level_colors.clusters),
            patch_code_color: v4(settings.level_colors.patches),
            head_code_color: v4(settings.level_colors.head),
            viewport: [settings.width as f32, settings.height as f32, 0.0, 0.0],
            shading: [
                settings.hair.diffuse,
                settings.hair.specular,
                settings.hair.specular_exponent,
                color_coded,
            ],
            ribbon: [
                half_width,
                min_half_pixels,
                settings.camera.focal_length_pixels(settings.height),
                match settings.surface_texture {
                    SurfaceTexture::Hair => 1.0,
                    SurfaceTexture::Stripes => 0.0,
                },
            ],
            counts: [
                counts.strands,
                counts.chains,
                counts.nodes,
                counts.samples_per_strand,
            ],
            light_view_proj: shadow
                .map_or(glam::Mat4::IDENTITY, |s| s.light_view_proj)
                .to_cols_array_2d(),
            shadow: match shadow {
                Some(frame) => [
                    1.0,
                    frame.depth_range,
                    strand_optical_depth(&settings.shadows, frame.texel_size),
                    0.0,
                ],
                None => [0.0; 4],
            },
            shadow_layers: settings.shadows.layer_ends,
            shadow_surfaces: {
                let per_strand = settings.shadows.hair_width * settings.shadows.strand_opacity;
                let (clusters, patches) =
                    shadow.map_or((0.0, 0.0), |s| (s.strands_per_cluster, s.strands_per_patch));
                [
                    clusters * per_strand,
                    patches * per_strand,
                    settings.shadows.along_stride as f32,
                    SHADOW_AROUND_SEGMENTS as f32,
                ]
            },
            hair_model: match settings.hair.shading {
                HairShading::KajiyaKay => [0.0; 4],
                HairShading::Marschner(model) => {
                    [1.0, model.shift, model.width, model.refractive_index]
                }
            },
            line_coverage: [
                match (settings.line_coverage, settings.strand_style) {
                    (LineCoverage::Width, StrandStyle::Ribbons { width, .. }) => width,
                    _ => 0.0,
                },
                counts.samples_per_pixel as f32,
                match settings.cluster_geometry {
                    ClusterGeometry::Impostor => 1.0,
                    ClusterGeometry::Tube => 0.0,
                },
                0.0,
            ],
        }
    }

    /// The globals of the light passes: drawn through the light's view.
    pub fn for_light_passes(&self) -> Globals {
        Globals {
            view_proj: self.light_view_proj,
            shadow: [self.shadow[0], self.shadow[1], self.shadow[2], 1.0],
            ..*self
        }
    }
}

/// Most segments around a cluster tube in the light passes (a hexagon is within 13 % of the ring
/// radius, and the shadow map's texels are larger than most tubes' chord error).
pub(crate) const SHADOW_AROUND_SEGMENTS: u32 = 6;

/// Optical depth a strand line adds to each texel of side `texel_size` [m] it crosses: the
/// fraction `w/s` of the texel the fibre covers times the fraction of the light it stops (capped
/// at 1 for fibres wider than a texel).
pub(crate) fn strand_optical_depth(shadows: &SelfShadowing, texel_size: f32) -> f32 {
    (shadows.hair_width / texel_size.max(1e-9)).min(1.0) * shadows.strand_opacity
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_two_matrices_and_twenty_vectors() {
        assert_eq!(std::mem::size_of::<Globals>(), 2 * 64 + 20 * 16);
    }
}
