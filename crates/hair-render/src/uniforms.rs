//! The per-frame uniform block (`Globals` in `shaders/common.wgsl`), packed from the frame settings.

use glam::Vec3;

use crate::settings::{FrameSettings, ShadingMode, StrandStyle};

/// Counts the shaders need to bound their reads.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GeometryCounts {
    pub strands: u32,
    pub chains: u32,
    pub nodes: u32,
    /// Samples per strand of the evaluation pass (0 when drawing).
    pub samples_per_strand: u32,
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
}

fn v4(v: Vec3) -> [f32; 4] {
    v.extend(0.0).to_array()
}

impl Globals {
    /// Packs (validated) settings and counts.
    pub fn new(settings: &FrameSettings, counts: GeometryCounts) -> Globals {
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
                0.0,
            ],
            counts: [
                counts.strands,
                counts.chains,
                counts.nodes,
                counts.samples_per_strand,
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_a_matrix_and_fifteen_vectors() {
        assert_eq!(std::mem::size_of::<Globals>(), 64 + 15 * 16);
    }
}
