//! The renderer: static strand data uploaded once, skeleton nodes per frame, images out.

use glam::Vec3;
use hair_core::TriangleMesh;

use crate::buffers::GrowableBuffer;
use crate::device::{AdapterReport, DeviceOptions, GpuContext, acquire_device};
use crate::error::{RenderError, Result, invalid};
use crate::head::{GpuMesh, upload_mesh, validate_mesh};
use crate::inputs::{GpuNode, SkeletonFrame, StrandSet, pack_nodes, pack_strands};
use crate::pipelines::Pipelines;
use crate::settings::{FrameSettings, StrandStyle};
use crate::target::{RenderTarget, map_and_read};
use crate::uniforms::{GeometryCounts, Globals};

/// Options of [`Renderer::new`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct RendererOptions {
    /// Adapter choice and MSAA sample count.
    pub device: DeviceOptions,
}

impl RendererOptions {
    /// The defaults with the backend from `HAIRLOD_BACKEND` (see [`DeviceOptions::from_env`]).
    pub fn from_env() -> Result<RendererOptions> {
        Ok(RendererOptions {
            device: DeviceOptions::from_env()?,
        })
    }
}

/// Threads per workgroup of the evaluation pass (`@workgroup_size` in `evaluate.wgsl`).
const EVALUATE_WORKGROUP: u32 = 64;

/// A headless hair renderer on one device.
///
/// Upload the strands once with [`Renderer::upload_strands`] (and a head with
/// [`Renderer::set_head_mesh`]), then call [`Renderer::render`] per frame with the skeleton nodes:
/// only the nodes and chain offsets travel to the GPU each frame, and the strands' B-splines are
/// evaluated there.
#[derive(Debug)]
pub struct Renderer {
    gpu: GpuContext,
    sample_count: u32,
    pipelines: Pipelines,
    globals: wgpu::Buffer,
    nodes: GrowableBuffer,
    chain_offsets: GrowableBuffer,
    strands: GrowableBuffer,
    /// Bind group of group 0; `None` after a buffer was replaced.
    scene_bind_group: Option<wgpu::BindGroup>,
    strand_count: u32,
    /// Chains the frame must have: the largest `strand_chain` + 1.
    chains_needed: u32,
    head: Option<GpuMesh>,
    target: Option<RenderTarget>,
    node_scratch: Vec<GpuNode>,
}

impl Renderer {
    /// Acquires a device (see [`acquire_device`]) and builds the pipelines.
    pub fn new(options: &RendererOptions) -> Result<Renderer> {
        let gpu = acquire_device(&options.device)?;
        Renderer::with_context(gpu, options.device.sample_count)
    }

    /// Builds a renderer on an already opened device, with `sample_count`-times MSAA.
    pub fn with_context(gpu: GpuContext, sample_count: u32) -> Result<Renderer> {
        let device = &gpu.device;
        let scope = ErrorScopes::push(device);
        let pipelines = Pipelines::new(device, sample_count);
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hair-render globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let storage = wgpu::BufferUsages::STORAGE;
        let nodes = GrowableBuffer::new(device, "hair-render nodes", storage);
        let chain_offsets = GrowableBuffer::new(device, "hair-render chain offsets", storage);
        let strands = GrowableBuffer::new(device, "hair-render strands", storage);
        scope.pop("building the render pipelines")?;
        Ok(Renderer {
            gpu,
            sample_count,
            pipelines,
            globals,
            nodes,
            chain_offsets,
            strands,
            scene_bind_group: None,
            strand_count: 0,
            chains_needed: 0,
            head: None,
            target: None,
            node_scratch: Vec::new(),
        })
    }

    /// The adapter in use.
    pub fn adapter_report(&self) -> &AdapterReport {
        &self.gpu.report
    }

    /// The device and queue, e.g. for benchmarks that draw their own passes.
    pub fn context(&self) -> &GpuContext {
        &self.gpu
    }

    /// MSAA sample count.
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Number of uploaded strands.
    pub fn strand_count(&self) -> usize {
        self.strand_count as usize
    }

    /// Uploads the static strand data, replacing any earlier set.
    pub fn upload_strands(&mut self, strands: &StrandSet<'_>) -> Result<()> {
        strands.validate()?;
        let packed = pack_strands(strands);
        let scope = ErrorScopes::push(&self.gpu.device);
        if self.strands.write(
            &self.gpu.device,
            &self.gpu.queue,
            bytemuck::cast_slice(&packed),
        ) {
            self.scene_bind_group = None;
        }
        scope.pop("uploading strands")?;
        self.strand_count = packed.len() as u32;
        self.chains_needed = strands.strand_chain.iter().max().map_or(0, |&c| c + 1);
        Ok(())
    }

    /// Sets the head mesh drawn with the hair (`None` removes it).
    pub fn set_head_mesh(&mut self, mesh: Option<&TriangleMesh>) -> Result<()> {
        self.head = match mesh {
            None => None,
            Some(mesh) => {
                validate_mesh(mesh)?;
                let scope = ErrorScopes::push(&self.gpu.device);
                let head = upload_mesh(&self.gpu.device, mesh);
                scope.pop("uploading the head mesh")?;
                head
            }
        };
        Ok(())
    }

    /// Renders one frame: uploads `frame`'s nodes, draws the head and the strands, reads the image
    /// back (sRGB RGBA8, `settings.width`×`settings.height`).
    pub fn render(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
    ) -> Result<image::RgbaImage> {
        settings.validate()?;
        let counts = self.upload_frame(frame, 0)?;
        let scope = ErrorScopes::push(&self.gpu.device);
        let result = self.draw(settings, counts);
        let checked = scope.pop("rendering a frame");
        let image = result?;
        checked?;
        Ok(image)
    }

    /// Evaluates every strand's B-spline on the GPU (the same WGSL code the vertex shader uses) at
    /// `samples_per_strand` evenly spaced parameters, `u = i / (samples − 1)`; strand-major points
    /// [m]. Strands without nodes give `NaN` points. Meant for checks against [`crate::bspline`].
    pub fn evaluate_strands(
        &mut self,
        frame: &SkeletonFrame<'_>,
        samples_per_strand: u32,
    ) -> Result<Vec<Vec3>> {
        let total = u64::from(self.strand_count) * u64::from(samples_per_strand);
        let max_bytes = self.gpu.device.limits().max_storage_buffer_binding_size;
        if samples_per_strand == 0 || total * 16 > max_bytes || total > u64::from(u32::MAX) {
            return Err(invalid(format!(
                "cannot evaluate {samples_per_strand} samples for each of {} strands",
                self.strand_count
            )));
        }
        let counts = self.upload_frame(frame, samples_per_strand)?;
        if total == 0 {
            return Ok(Vec::new());
        }
        let scope = ErrorScopes::push(&self.gpu.device);
        let result = self.dispatch_evaluation(counts, total);
        let checked = scope.pop("evaluating strands");
        let points = result?;
        checked?;
        Ok(points)
    }

    /// Validates and uploads the per-frame data; returns the counts for the globals.
    fn upload_frame(
        &mut self,
        frame: &SkeletonFrame<'_>,
        samples_per_strand: u32,
    ) -> Result<GeometryCounts> {
        frame.validate()?;
        let chains = frame.chain_count() as u32;
        if self.chains_needed > chains {
            return Err(invalid(format!(
                "the strands follow chains up to {} but the frame has {chains} chains",
                self.chains_needed - 1
            )));
        }
        pack_nodes(frame, &mut self.node_scratch);
        let scope = ErrorScopes::push(&self.gpu.device);
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let mut replaced =
            self.nodes
                .write(device, queue, bytemuck::cast_slice(&self.node_scratch));
        let offsets: &[u32] = if frame.chain_offsets.is_empty() {
            &[0]
        } else {
            frame.chain_offsets
        };
        replaced |= self
            .chain_offsets
            .write(device, queue, bytemuck::cast_slice(offsets));
        if replaced {
            self.scene_bind_group = None;
        }
        scope.pop("uploading skeleton nodes")?;
        Ok(GeometryCounts {
            strands: self.strand_count,
            chains,
            nodes: frame.node_count() as u32,
            samples_per_strand,
        })
    }

    fn scene_bind_group(&mut self) -> wgpu::BindGroup {
        if let Some(group) = &self.scene_bind_group {
            return group.clone();
        }
        let group = self
            .gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render scene"),
                layout: &self.pipelines.scene_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.globals.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: self.nodes.buffer().as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: self.chain_offsets.buffer().as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: self.strands.buffer().as_entire_binding(),
                    },
                ],
            });
        self.scene_bind_group = Some(group.clone());
        group
    }

    fn draw(
        &mut self,
        settings: &FrameSettings,
        counts: GeometryCounts,
    ) -> Result<image::RgbaImage> {
        let needs_new_target = self
            .target
            .as_ref()
            .is_none_or(|t| t.width() != settings.width || t.height() != settings.height);
        if needs_new_target {
            self.target = None;
            self.target = Some(RenderTarget::new(
                &self.gpu.device,
                settings.width,
                settings.height,
                self.sample_count,
            )?);
        }
        let globals = Globals::new(settings, counts);
        self.gpu
            .queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let bind_group = self.scene_bind_group();
        let Some(target) = self.target.as_ref() else {
            return Err(RenderError::Gpu("render target missing".into()));
        };

        let max_points = settings.tessellation.max_segments + 1;
        let (strand_pipeline, vertices_per_strand) = match settings.strand_style {
            StrandStyle::Lines => (&self.pipelines.strand_lines, max_points),
            StrandStyle::Ribbons { .. } => (&self.pipelines.strand_ribbons, 2 * max_points),
        };
        let background = wgpu::Color {
            r: f64::from(settings.background.x),
            g: f64::from(settings.background.y),
            b: f64::from(settings.background.z),
            a: 1.0,
        };

        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hair-render frame"),
            });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hair-render scene"),
                color_attachments: &[Some(target.color_attachment(background))],
                depth_stencil_attachment: Some(target.depth_attachment()),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &bind_group, &[]);
            if let Some(head) = &self.head {
                pass.set_pipeline(&self.pipelines.head);
                pass.set_vertex_buffer(0, head.vertices.slice(..));
                pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..head.index_count, 0, 0..1);
            }
            if counts.strands > 0 && counts.nodes > 0 {
                pass.set_pipeline(strand_pipeline);
                pass.draw(0..vertices_per_strand, 0..counts.strands);
            }
        }
        target.encode_readback(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        target.read_image(&self.gpu.device)
    }

    fn dispatch_evaluation(&mut self, counts: GeometryCounts, total: u64) -> Result<Vec<Vec3>> {
        // Camera and colours do not matter for evaluation; only the counts do.
        let settings = FrameSettings::new(1, 1, crate::camera::Camera::default());
        let globals = Globals::new(&settings, counts);
        self.gpu
            .queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let bind_group = self.scene_bind_group();
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
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_bind_group(1, &output_group, &[]);
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

/// Validation and out-of-memory error scopes around a group of GPU calls.
struct ErrorScopes {
    out_of_memory: wgpu::ErrorScopeGuard,
    validation: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    fn push(device: &wgpu::Device) -> ErrorScopes {
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        ErrorScopes {
            out_of_memory,
            validation,
        }
    }

    /// Pops both scopes; the first error captured becomes [`RenderError::Gpu`] naming `what`.
    fn pop(self, what: &str) -> Result<()> {
        let validation = pollster::block_on(self.validation.pop());
        let out_of_memory = pollster::block_on(self.out_of_memory.pop());
        match validation.or(out_of_memory) {
            None => Ok(()),
            Some(error) => Err(RenderError::Gpu(format!("{what}: {error}"))),
        }
    }
}
