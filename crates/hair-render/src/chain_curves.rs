//! The chain-curve pass (compute): each chain's curve evaluated once per sample slot, into the
//! samples buffer the chain's strands read.

use crate::batches::CHAIN_SAMPLE_BYTES;
use crate::buffers::GrowableBuffer;
use crate::pipelines::Pipelines;

/// Threads per workgroup of the chain-curve pass (`@workgroup_size` in `chain_curves.wgsl`).
const CHAIN_CURVES_WORKGROUP: u64 = 64;

/// The chain-curve pass: the samples it writes, its bind group and this frame's dispatch.
#[derive(Debug)]
pub(crate) struct ChainCurvePass {
    /// This frame's chain-curve samples (written by this pass, read by strands).
    samples: GrowableBuffer,
    /// Group 1 of the pass: the samples; `None` after the buffer was replaced.
    bind_group: Option<wgpu::BindGroup>,
    /// This frame's workgroups (x, y); `None` when the frame draws no strands.
    dispatch: Option<(u32, u32)>,
}

impl ChainCurvePass {
    /// An empty samples buffer.
    pub fn new(device: &wgpu::Device) -> ChainCurvePass {
        ChainCurvePass {
            samples: GrowableBuffer::new(
                device,
                "hair-render chain samples",
                wgpu::BufferUsages::STORAGE,
            ),
            bind_group: None,
            dispatch: None,
        }
    }

    /// The samples buffer (binding 1 of the strand items).
    pub fn samples(&self) -> &wgpu::Buffer {
        self.samples.buffer()
    }

    /// Makes the samples buffer hold `samples` chain samples; returns whether it was replaced.
    pub fn reserve(&mut self, device: &wgpu::Device, samples: u32) -> bool {
        let replaced = self
            .samples
            .reserve(device, u64::from(samples) * CHAIN_SAMPLE_BYTES);
        if replaced {
            self.bind_group = None;
        }
        replaced
    }

    /// Prepares this frame's dispatch over `chains` chains of `slots` sample slots each, or
    /// none when `draws_strands` is false (no strand reads the samples).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        pipelines: &Pipelines,
        chains: u32,
        slots: u32,
        draws_strands: bool,
    ) {
        if !draws_strands {
            self.dispatch = None;
            return;
        }
        // One thread per (chain, point slot); threads past a chain's points return at once.
        let threads = u64::from(chains) * u64::from(slots);
        let groups = threads.div_ceil(CHAIN_CURVES_WORKGROUP);
        let max_groups = u64::from(device.limits().max_compute_workgroups_per_dimension);
        self.dispatch = Some((
            groups.min(max_groups) as u32,
            groups.div_ceil(max_groups) as u32,
        ));
        if self.bind_group.is_none() {
            self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render chain curves"),
                layout: &pipelines.chain_curves_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.samples.buffer().as_entire_binding(),
                }],
            }));
        }
    }

    /// Encodes the pass (after [`ChainCurvePass::prepare`]) reading `scene` (group 0).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &Pipelines,
        scene: &wgpu::BindGroup,
    ) {
        let (Some((groups_x, groups_y)), Some(samples)) = (self.dispatch, &self.bind_group) else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hair-render chain curves"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipelines.chain_curves);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, samples, &[]);
        pass.dispatch_workgroups(groups_x, groups_y, 1);
    }
}
