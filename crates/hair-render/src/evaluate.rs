//! The evaluation pass: strands' B-splines computed on the GPU by the same WGSL code the vertex
//! shader runs, read back for comparison with the CPU reference ([`crate::bspline`]).

use glam::Vec3;

use crate::batches::ChainOrder;
use crate::buffers::check_binding_size;
use crate::device::GpuContext;
use crate::error::{RenderError, Result, invalid};
use crate::pipelines::Pipelines;
use crate::target::map_and_read;

/// Threads per workgroup of the evaluation pass (`@workgroup_size` in `evaluate.wgsl`).
const EVALUATE_WORKGROUP: u32 = 64;

/// Checks a request for `samples_per_strand` points on each of `strand_count` strands against
/// the device's `max_bytes` per storage binding; returns the number of points.
pub(crate) fn check_request(
    strand_count: u64,
    samples_per_strand: u32,
    max_bytes: u64,
) -> Result<u64> {
    let total = strand_count * u64::from(samples_per_strand);
    if samples_per_strand == 0 || total > u64::from(u32::MAX) {
        return Err(invalid(format!(
            "cannot evaluate {samples_per_strand} samples for each of {strand_count} strands"
        )));
    }
    check_binding_size(
        &format!("{samples_per_strand} evaluated points for each of {strand_count} strands"),
        total * 16,
        max_bytes,
    )?;
    Ok(total)
}

/// Puts strand-major points in chain-sorted order (`samples` per strand) back in upload order.
pub(crate) fn to_upload_order(sorted: &[Vec3], order: &ChainOrder, samples: u32) -> Vec<Vec3> {
    let samples = samples as usize;
    let mut points = vec![Vec3::NAN; sorted.len()];
    for (position, &input) in order.sorted_to_input.iter().enumerate() {
        let input = input as usize;
        points[input * samples..(input + 1) * samples]
            .copy_from_slice(&sorted[position * samples..(position + 1) * samples]);
    }
    points
}

/// Runs the evaluation pass over `total` points, with `scene` as group 0 (its globals written
/// for the evaluation) and `strands` as group 1, and reads the points back in chain-sorted
/// order (`NaN` for strands without nodes).
pub(crate) fn dispatch(
    gpu: &GpuContext,
    pipelines: &Pipelines,
    scene: &wgpu::BindGroup,
    strands: &wgpu::BindGroup,
    total: u64,
) -> Result<Vec<Vec3>> {
    let device = &gpu.device;
    let bytes = total * 16;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hair-render evaluated points"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hair-render evaluated points readback"),
        size: bytes,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let output_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hair-render evaluation output"),
        layout: &pipelines.evaluate_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: output.as_entire_binding(),
        }],
    });
    let groups = total.div_ceil(u64::from(EVALUATE_WORKGROUP));
    let max_groups = u64::from(device.limits().max_compute_workgroups_per_dimension);
    let groups_x = groups.min(max_groups) as u32;
    let groups_y = groups.div_ceil(max_groups) as u32;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("hair-render evaluate"),
    });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("hair-render evaluate"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipelines.evaluate);
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(1, strands, &[]);
        pass.set_bind_group(2, &output_group, &[]);
        pass.dispatch_workgroups(groups_x, groups_y, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, bytes);
    gpu.queue.submit([encoder.finish()]);
    let data = map_and_read(device, &readback)?;
    if data.len() as u64 != bytes {
        return Err(RenderError::Gpu(
            "evaluated points came back with the wrong size".into(),
        ));
    }
    let values: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&data);
    Ok(values
        .iter()
        .map(|v| {
            if v[3] > 0.5 {
                Vec3::new(v[0], v[1], v[2])
            } else {
                Vec3::NAN
            }
        })
        .collect())
}
