//! Frame time of the paper-curly groom (§8.2: 91 patches, 273 clusters, 37,765 strands) at each
//! level, 1280×720 with 4× MSAA, against the floor of this device: a bare wgpu pass drawing the
//! same number of plain line segments from a prebuilt vertex buffer (no B-splines, no shading,
//! no ribbons). Every measurement includes the per-frame upload and the image readback.
//!
//! `cargo bench -p hair-render --bench render -- --warm-up-time 1 --measurement-time 5`

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use hair_core::{Level, Scene};
use hair_render::target::{COLOR_FORMAT, DEPTH_FORMAT};
use hair_render::{
    ActiveSkeletons, Camera, FrameSettings, LineShading, RenderTarget, Renderer, RendererOptions,
    StrandStyle, bspline,
};
use wgpu::util::DeviceExt;

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

/// The floor pass: line segments from a vertex buffer, one flat colour.
const FLOOR_WGSL: &str = "
@group(0) @binding(0) var<uniform> view_proj: mat4x4<f32>;
@vertex fn vs(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {
    return view_proj * vec4<f32>(p, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(0.3, 0.2, 0.1, 1.0); }
";

struct Floor {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    /// Strip indices with primitive restarts (line strips), or `None` (a line list).
    indices: Option<wgpu::Buffer>,
    count: u32,
    target: RenderTarget,
}

/// The floor's geometry: segments as a line list, or polylines as line strips.
enum FloorGeometry<'a> {
    Segments(&'a [[Vec3; 2]]),
    Strips(&'a [Vec<Vec3>]),
}

impl Floor {
    fn new(renderer: &Renderer, geometry: FloorGeometry<'_>, settings: &FrameSettings) -> Floor {
        let device = &renderer.context().device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("floor"),
            source: wgpu::ShaderSource::Wgsl(FLOOR_WGSL.into()),
        });
        let view_proj = settings
            .camera
            .view_projection(WIDTH as f32 / HEIGHT as f32)
            .to_cols_array();
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("floor view"),
            contents: bytemuck::cast_slice(&view_proj),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("floor"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("floor"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("floor"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("floor"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: match geometry {
                FloorGeometry::Segments(_) => wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineList,
                    ..Default::default()
                },
                FloorGeometry::Strips(_) => wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::LineStrip,
                    strip_index_format: Some(wgpu::IndexFormat::Uint32),
                    ..Default::default()
                },
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: renderer.sample_count(),
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let (flat, strip_indices): (Vec<[f32; 3]>, Option<Vec<u32>>) = match geometry {
            FloorGeometry::Segments(segments) => (
                segments
                    .iter()
                    .flat_map(|s| [s[0].to_array(), s[1].to_array()])
                    .collect(),
                None,
            ),
            FloorGeometry::Strips(strips) => {
                let mut flat = Vec::new();
                let mut indices = Vec::new();
                for strip in strips {
                    for point in strip {
                        indices.push(flat.len() as u32);
                        flat.push(point.to_array());
                    }
                    indices.push(u32::MAX);
                }
                (flat, Some(indices))
            }
        };
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("floor segments"),
            contents: bytemuck::cast_slice(&flat),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = strip_indices.as_ref().map(|indices| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("floor strips"),
                contents: bytemuck::cast_slice(indices),
                usage: wgpu::BufferUsages::INDEX,
            })
        });
        let target = RenderTarget::new(device, WIDTH, HEIGHT, renderer.sample_count())
            .expect("floor target");
        Floor {
            pipeline,
            bind_group,
            vertices,
            count: strip_indices.map_or(flat.len(), |indices| indices.len()) as u32,
            indices,
            target,
        }
    }

    fn draw(&self, renderer: &Renderer) -> image::RgbaImage {
        let gpu = renderer.context();
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("floor"),
                color_attachments: &[Some(self.target.color_attachment(wgpu::Color::BLACK))],
                depth_stencil_attachment: Some(self.target.depth_attachment()),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            match &self.indices {
                Some(indices) => {
                    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..self.count, 0, 0..1);
                }
                None => pass.draw(0..self.count, 0..1),
            }
        }
        self.target.encode_readback(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        self.target.read_image(&gpu.device).expect("floor readback")
    }
}

fn bench_render(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;

    let mut renderer = Renderer::new(&RendererOptions::from_env().expect("HAIRLOD_BACKEND"))
        .expect("a renderer (install mesa-vulkan-drivers)");
    eprintln!("adapter: {}", renderer.adapter_report());
    renderer.upload_groom(groom).expect("upload");
    let camera = Camera::orbit(
        Vec3::new(0.0, -0.01, 0.0),
        0.8,
        150f32.to_radians(),
        8f32.to_radians(),
        35f32.to_radians(),
    );
    let settings = FrameSettings::new(WIDTH, HEIGHT, camera);

    let mut group = c.benchmark_group("render_paper_curly_1280x720");
    let mut active = ActiveSkeletons::new();
    for level in [Level::StrandGroup, Level::Cluster, Level::Patch] {
        active.gather_rest_pose(groom, level).expect("gather");
        group.bench_function(level.name(), |b| {
            b.iter(|| renderer.render(&active.frame(), &settings).expect("render"))
        });
    }
    active
        .gather_rest_pose(groom, Level::StrandGroup)
        .expect("gather");
    // Lines shaded per fragment (the default shades them at the curve points).
    let per_fragment = FrameSettings {
        line_shading: LineShading::PerFragment,
        ..settings
    };
    group.bench_function("strands_shaded_per_fragment", |b| {
        b.iter(|| {
            renderer
                .render(&active.frame(), &per_fragment)
                .expect("render")
        })
    });
    // Strands forced to 1.5-pixel ribbons (the default draws sub-pixel hair as 1-pixel lines).
    let ribbons = FrameSettings {
        strand_style: StrandStyle::Ribbons {
            width: 0.0,
            min_width_pixels: 1.5,
        },
        ..settings
    };
    group.bench_function("strands_as_1.5px_ribbons", |b| {
        b.iter(|| renderer.render(&active.frame(), &ribbons).expect("render"))
    });

    // The floor: as many plain segments as the strand level draws (every strand root is within
    // the full-detail distance here, so each strand gets `max_segments`).
    let segments_per_strand = settings.tessellation.max_segments as usize;
    let frame = active.frame();
    let mut segments = Vec::new();
    let mut strips = Vec::new();
    for group in 0..groom.strands.group_count() {
        let chain = groom.level_chains(Level::StrandGroup).start + group;
        for strand in groom.strands.strands(group) {
            let points = frame.strand_control_points(chain, groom.strands.root_offsets[strand]);
            let curve = bspline::sample(&points, segments_per_strand + 1);
            segments.extend(curve.windows(2).map(|w| [w[0], w[1]]));
            strips.push(curve);
        }
    }
    eprintln!(
        "floor: {} segments ({} strands × {segments_per_strand})",
        segments.len(),
        groom.strands.strand_count()
    );
    let floor = Floor::new(&renderer, FloorGeometry::Segments(&segments), &settings);
    group.bench_function("floor_plain_segments", |b| b.iter(|| floor.draw(&renderer)));
    let floor = Floor::new(&renderer, FloorGeometry::Strips(&strips), &settings);
    group.bench_function("floor_plain_strips", |b| b.iter(|| floor.draw(&renderer)));
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_render
}
criterion_main!(benches);
