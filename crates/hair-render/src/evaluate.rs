//! The evaluation pass: strands' B-splines computed on the GPU by the same WGSL code the vertex
//! shader runs, read back for comparison with the CPU reference ([`crate::bspline`]).

use glam::Vec3;

use crate::buffers::check_binding_size;
use crate::error::{RenderError, Result, invalid};
use crate::renderer::Renderer;
use crate::scopes::ErrorScopes;
use crate::settings::FrameSettings;
use crate::target::map_and_read;
use crate::uniforms::{GeometryCounts, Globals};

/// Threads per workgroup of the evaluation pass (`@workgroup_size` in `evaluate.wgsl`).
const EVALUATE_WORKGROUP: u32 = 64;

impl Renderer {
    /// Evaluates every strand's B-spline on the GPU (the same WGSL code the vertex shader uses) at
    /// `samples_per_strand` evenly spaced parameters, `u = i / (samples − 1)`; strand-major points
    /// [m], strands in upload order. Strands without nodes give `NaN` points. Meant for checks
    /// against [`crate::bspline`].
    pub fn evaluate_strands(
        &mut self,
        frame: &crate::SkeletonFrame<'_>,
        samples_per_strand: u32,
    ) -> Result<Vec<Vec3>> {
        let strand_count = self.strands.order.item_count() as u64;
        let total = strand_count * u64::from(samples_per_strand);
        if samples_per_strand == 0 || total > u64::from(u32::MAX) {
            return Err(invalid(format!(
                "cannot evaluate {samples_per_strand} samples for each of {strand_count} strands"
            )));
        }
        check_binding_size(
            &format!("{samples_per_strand} evaluated points for each of {strand_count} strands"),
            total * 16,
            self.gpu.device.limits().max_storage_buffer_binding_size,
        )?;
        // Camera and colours do not matter for evaluation; only the counts do.
        let settings = FrameSettings::new(1, 1, crate::camera::Camera::default());
        let counts = self.upload_frame(frame, &settings, samples_per_strand)?;
        if total == 0 {
            return Ok(Vec::new());
        }
        let scope = ErrorScopes::push(&self.gpu.device);
        let result = self.dispatch_evaluation(&settings, counts, total);
        let checked = scope.pop("evaluating strands");
        let sorted = result?;
        checked?;
        // Back from chain-sorted order to upload order.
        let samples = samples_per_strand as usize;
        let mut points = vec![Vec3::NAN; sorted.len()];
        for (position, &input) in self.strands.order.sorted_to_input.iter().enumerate() {
            let input = input as usize;
            points[input * samples..(input + 1) * samples]
                .copy_from_slice(&sorted[position * samples..(position + 1) * samples]);
        }
        Ok(points)
    }

    fn dispatch_evaluation(
        &mut self,
        settings: &FrameSettings,
        counts: GeometryCounts,
        total: u64,
    ) -> Result<Vec<Vec3>> {
        let globals = Globals::new(settings, counts, None);
        self.gpu
            .queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let scene_group = self.scene_bind_group();
        let strand_group = self.item_bind_group(crate::renderer::ItemKind::Strands);
        let device = &self.gpu.device;
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
            layout: &self.pipelines.evaluate_layout,
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
            pass.set_pipeline(&self.pipelines.evaluate);
            pass.set_bind_group(0, &scene_group, &[]);
            pass.set_bind_group(1, &strand_group, &[]);
            pass.set_bind_group(2, &output_group, &[]);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
        }
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, bytes);
        self.gpu.queue.submit([encoder.finish()]);
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
}
