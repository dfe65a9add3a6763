//! The self-shadowing stage of a frame: the light's view of the hair, the light passes' globals
//! and group 0, and the shadow maps they draw (see [`crate::shadow_maps`]).

use crate::device::GpuContext;
use crate::items::PreparedItems;
use crate::pipelines::Pipelines;
use crate::scene_inputs::SceneInputs;
use crate::settings::{FrameSettings, ShadingMode};
use crate::shadow_maps::ShadowMaps;
use crate::shadows::{light_view_projection, map_resolution};
use crate::uniforms::{Globals, ShadowFrame};

/// What the light passes draw this frame, prepared before they begin.
#[derive(Debug)]
struct PreparedLight {
    /// Group 0 of the light passes.
    scene: wgpu::BindGroup,
    /// Tessellation along, this many times coarser than the camera pass's.
    along_stride: u32,
}

/// The light passes and their maps.
#[derive(Debug)]
pub(crate) struct ShadowPass {
    maps: ShadowMaps,
    /// Group 0 of the light passes (light globals, nodes, chains); `None` after a buffer was
    /// replaced.
    light_scene: Option<wgpu::BindGroup>,
    /// This frame's light passes; `None` when the frame is not self-shadowed.
    prepared: Option<PreparedLight>,
}

/// The light's view of a frame's hair (`hair_bounds` [m], centre and radius), when `settings`
/// shade with self-shadowing and there is hair; `strands`, `clusters` and `patches` are the
/// uploaded item counts.
pub(crate) fn shadow_frame(
    settings: &FrameSettings,
    hair_bounds: Option<(glam::Vec3, f32)>,
    strands: usize,
    clusters: usize,
    patches: usize,
) -> Option<ShadowFrame> {
    if !settings.shadows.enabled || settings.mode != ShadingMode::Shaded {
        return None;
    }
    let (centre, radius) = hair_bounds?;
    let (light_view_proj, depth_range) =
        light_view_projection(centre, radius, settings.light.direction);
    // The sphere's diameter on screen [pixels] (unbounded with the camera inside it).
    let distance = centre.distance(settings.camera.position);
    let focal = settings.camera.focal_length_pixels(settings.height);
    let screen_diameter = if distance > radius {
        2.0 * radius * focal / (distance * distance - radius * radius).sqrt()
    } else {
        f32::INFINITY
    };
    let resolution = map_resolution(&settings.shadows, screen_diameter);
    let strands = strands as f32;
    let per = |count: usize| {
        if count > 0 {
            strands / count as f32
        } else {
            0.0
        }
    };
    Some(ShadowFrame {
        light_view_proj,
        depth_range,
        texel_size: 2.0 * radius / resolution as f32,
        resolution,
        strands_per_cluster: per(clusters),
        strands_per_patch: per(patches),
    })
}

impl ShadowPass {
    /// The unshadowed maps and the light globals buffer; no maps of any size yet.
    pub fn new(device: &wgpu::Device, pipelines: &Pipelines) -> ShadowPass {
        ShadowPass {
            maps: ShadowMaps::new(device, &pipelines.shadow_maps_layout),
            light_scene: None,
            prepared: None,
        }
    }

    /// Forgets the light passes' group 0, whose nodes or chains buffer was just replaced.
    pub fn scene_replaced(&mut self) {
        self.light_scene = None;
    }

    /// Prepares the light passes for `shadow` (none for `None`): writes their globals (from the
    /// camera pass's `globals`), makes the maps of its resolution current and builds group 0
    /// over `scene`. Returns group 2 of the camera pass (the maps, or the unshadowed ones).
    pub fn prepare(
        &mut self,
        gpu: &GpuContext,
        pipelines: &Pipelines,
        scene: &SceneInputs,
        shadow: Option<&ShadowFrame>,
        globals: &Globals,
        along_stride: u32,
    ) -> wgpu::BindGroup {
        let Some(frame) = shadow else {
            self.prepared = None;
            return self.maps.unshadowed().clone();
        };
        gpu.queue.write_buffer(
            &self.maps.light_globals,
            0,
            bytemuck::bytes_of(&globals.for_light_passes()),
        );
        let maps_group =
            self.maps
                .prepare(&gpu.device, &pipelines.shadow_maps_layout, frame.resolution);
        let light_scene = match &self.light_scene {
            Some(group) => group.clone(),
            None => {
                let group = scene.bind_group_with(&gpu.device, pipelines, &self.maps.light_globals);
                self.light_scene = Some(group.clone());
                group
            }
        };
        self.prepared = Some(PreparedLight {
            scene: light_scene,
            along_stride,
        });
        maps_group
    }

    /// Encodes the depth and opacity passes (after [`ShadowPass::prepare`]) over the camera
    /// pass's `items`; nothing when the frame is not self-shadowed.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &Pipelines,
        items: &PreparedItems,
    ) {
        let Some(light) = &self.prepared else {
            return;
        };
        self.maps.encode(
            encoder,
            &pipelines.shadows.depth,
            &pipelines.shadows.opacity,
            &light.scene,
            &items.groups,
            &items.batches,
            light.along_stride,
        );
    }
}
