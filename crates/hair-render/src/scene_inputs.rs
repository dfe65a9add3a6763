//! A frame's scene inputs on the GPU (group 0 of every pass): the globals, the skeleton nodes
//! and the chain table with each chain's tessellation, packed on the CPU and uploaded.

use crate::batches::{GpuChain, chain_table};
use crate::buffers::GrowableBuffer;
use crate::device::GpuContext;
use crate::inputs::{GpuNode, SkeletonFrame, pack_nodes};
use crate::items::HairItems;
use crate::pipelines::Pipelines;
use crate::settings::FrameSettings;
use crate::shadows::bounding_sphere;
use crate::thinning::thin_chains;
use crate::uniforms::Globals;

/// Margin around the active nodes' bounding sphere for the light's view [m]: strands, tubes and
/// strips reach at most a section's half width (1.8 cm on paper-curly) from their
/// skeleton.
const HAIR_BOUNDS_MARGIN: f32 = 0.03;

/// The globals, nodes and chain table of the frame, and the CPU scratch they are packed in.
#[derive(Debug)]
pub(crate) struct SceneInputs {
    /// The camera pass's globals (binding 0 of group 0).
    globals: wgpu::Buffer,
    nodes: GrowableBuffer,
    chains: GrowableBuffer,
    /// Group 0 of the camera pass and the compute passes; `None` after a buffer was replaced.
    bind_group: Option<wgpu::BindGroup>,
    node_scratch: Vec<GpuNode>,
    chain_scratch: Vec<GpuChain>,
    /// Root distance to the camera of each chain this frame [m].
    chain_distances: Vec<f32>,
    /// A sphere around this frame's hair [m] (centre, radius), for the light's view.
    hair_bounds: Option<(glam::Vec3, f32)>,
}

impl SceneInputs {
    /// Empty buffers.
    pub fn new(device: &wgpu::Device) -> SceneInputs {
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hair-render globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let storage = wgpu::BufferUsages::STORAGE;
        SceneInputs {
            globals,
            nodes: GrowableBuffer::new(device, "hair-render nodes", storage),
            chains: GrowableBuffer::new(device, "hair-render chains", storage),
            bind_group: None,
            node_scratch: Vec::new(),
            chain_scratch: Vec::new(),
            chain_distances: Vec::new(),
            hair_bounds: None,
        }
    }

    /// This frame's chain table (after [`SceneInputs::pack`]).
    pub fn chain_table(&self) -> &[GpuChain] {
        &self.chain_scratch
    }

    /// Root distance to the camera of each chain this frame [m].
    pub fn chain_distances(&self) -> &[f32] {
        &self.chain_distances
    }

    /// A sphere around this frame's hair [m] (centre, radius); `None` without nodes.
    pub fn hair_bounds(&self) -> Option<(glam::Vec3, f32)> {
        self.hair_bounds
    }

    /// Packs `frame`'s nodes and chain table (each chain's tessellation, thinned by `items`'
    /// strand spans) on the CPU; returns the chain-curve samples the frame needs.
    pub fn pack(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
        items: &HairItems,
    ) -> u32 {
        pack_nodes(frame, &mut self.node_scratch);
        self.hair_bounds = bounding_sphere(
            self.node_scratch
                .iter()
                .map(|node| glam::Vec3::from_slice(&node.position[..3])),
            HAIR_BOUNDS_MARGIN,
        );
        // A ribbon no wider than a pixel covers what a 1-pixel line does, at a fraction of the
        // rasterization cost: such strands are drawn as lines.
        let focal = settings.camera.focal_length_pixels(settings.height);
        let style = settings.strand_style;
        let is_thin = |distance: f32| {
            style
                .ribbon_pixels(focal, distance)
                .is_none_or(|p| p <= 1.0)
        };
        let samples = chain_table(
            frame,
            &settings.tessellation,
            settings.cluster_geometry,
            settings.camera.position,
            focal,
            items.chain_ring_radii(),
            is_thin,
            &mut self.chain_scratch,
            &mut self.chain_distances,
        );
        thin_chains(
            &mut self.chain_scratch,
            items.chain_strand_spans(),
            &self.chain_distances,
            focal,
            settings.strand_thinning,
            style,
        );
        samples
    }

    /// Uploads the packed nodes and chain table; returns whether a buffer was replaced (so that
    /// bind groups naming them elsewhere are rebuilt).
    pub fn upload(&mut self, gpu: &GpuContext) -> bool {
        let (device, queue) = (&gpu.device, &gpu.queue);
        let mut replaced =
            self.nodes
                .write(device, queue, bytemuck::cast_slice(&self.node_scratch));
        replaced |= self
            .chains
            .write(device, queue, bytemuck::cast_slice(&self.chain_scratch));
        if replaced {
            self.bind_group = None;
        }
        replaced
    }

    /// Writes the camera pass's globals.
    pub fn write_globals(&self, queue: &wgpu::Queue, globals: &Globals) {
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(globals));
    }

    /// Group 0 of the camera pass and the compute passes: the globals with this frame's nodes
    /// and chains.
    pub fn bind_group(&mut self, device: &wgpu::Device, pipelines: &Pipelines) -> wgpu::BindGroup {
        if let Some(group) = &self.bind_group {
            return group.clone();
        }
        let group = self.bind_group_with(device, pipelines, &self.globals);
        self.bind_group = Some(group.clone());
        group
    }

    /// A group 0 over `globals` (another pass's, such as the light passes') with this frame's
    /// nodes and chains.
    pub fn bind_group_with(
        &self,
        device: &wgpu::Device,
        pipelines: &Pipelines,
        globals: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hair-render scene"),
            layout: &pipelines.scene_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.nodes.buffer().as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.chains.buffer().as_entire_binding(),
                },
            ],
        })
    }
}
