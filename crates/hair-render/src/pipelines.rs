//! Shader modules, bind group layouts and pipelines of the renderer.

use crate::target::{COLOR_FORMAT, DEPTH_FORMAT};

/// WGSL shared by every pipeline: globals, node/strand storage buffers, the B-spline.
const COMMON_WGSL: &str = concat!(
    include_str!("shaders/common.wgsl"),
    include_str!("shaders/bspline.wgsl")
);
/// Strand ribbons and lines.
const STRANDS_WGSL: &str = include_str!("shaders/strands.wgsl");
/// The head mesh.
const HEAD_WGSL: &str = include_str!("shaders/head.wgsl");
/// The evaluation compute pass.
const EVALUATE_WGSL: &str = include_str!("shaders/evaluate.wgsl");

/// Bytes per head vertex: position then normal, 3 floats each.
pub(crate) const HEAD_VERTEX_STRIDE: u64 = 24;

/// Every pipeline and layout the renderer uses.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Group 0: globals (binding 0), nodes (1), chain offsets (2), strands (3).
    pub scene_layout: wgpu::BindGroupLayout,
    /// Group 1 of the evaluation pass: the output points (binding 0).
    pub evaluate_layout: wgpu::BindGroupLayout,
    pub strand_ribbons: wgpu::RenderPipeline,
    pub strand_lines: wgpu::RenderPipeline,
    pub head: wgpu::RenderPipeline,
    pub evaluate: wgpu::ComputePipeline,
}

fn storage_entry(
    binding: u32,
    read_only: bool,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn shader(device: &wgpu::Device, label: &str, body: &str) -> wgpu::ShaderModule {
    let source = format!("{COMMON_WGSL}\n{body}");
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

impl Pipelines {
    /// Compiles the shaders and builds the pipelines for `sample_count`-times MSAA.
    /// Errors surface through the caller's error scope.
    pub fn new(device: &wgpu::Device, sample_count: u32) -> Pipelines {
        let geometry_stages = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::COMPUTE;
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hair-render scene"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_entry(1, true, geometry_stages),
                storage_entry(2, true, geometry_stages),
                storage_entry(3, true, geometry_stages),
            ],
        });
        let evaluate_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hair-render evaluation output"),
            entries: &[storage_entry(0, false, wgpu::ShaderStages::COMPUTE)],
        });
        let render_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hair-render render"),
            bind_group_layouts: &[Some(&scene_layout)],
            immediate_size: 0,
        });
        let evaluate_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("hair-render evaluate"),
                bind_group_layouts: &[Some(&scene_layout), Some(&evaluate_layout)],
                immediate_size: 0,
            });

        let strands_module = shader(device, "hair-render strands", STRANDS_WGSL);
        let head_module = shader(device, "hair-render head", HEAD_WGSL);
        let evaluate_module = shader(device, "hair-render evaluate", EVALUATE_WGSL);

        let depth = Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        });
        let multisample = wgpu::MultisampleState {
            count: sample_count,
            mask: !0,
            alpha_to_coverage_enabled: false,
        };
        let targets = [Some(wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let strand_pipeline = |label: &str, entry_point: &str, topology| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&render_layout),
                vertex: wgpu::VertexState {
                    module: &strands_module,
                    entry_point: Some(entry_point),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: depth.clone(),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &strands_module,
                    entry_point: Some("fs_strand"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let strand_ribbons = strand_pipeline(
            "hair-render strand ribbons",
            "vs_strand_ribbon",
            wgpu::PrimitiveTopology::TriangleStrip,
        );
        let strand_lines = strand_pipeline(
            "hair-render strand lines",
            "vs_strand_line",
            wgpu::PrimitiveTopology::LineStrip,
        );

        let head_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let head = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("hair-render head"),
            layout: Some(&render_layout),
            vertex: wgpu::VertexState {
                module: &head_module,
                entry_point: Some("vs_head"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: HEAD_VERTEX_STRIDE,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &head_attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: Some(wgpu::Face::Back),
                ..wgpu::PrimitiveState::default()
            },
            depth_stencil: depth,
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &head_module,
                entry_point: Some("fs_head"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });

        let evaluate = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("hair-render evaluate"),
            layout: Some(&evaluate_pipeline_layout),
            module: &evaluate_module,
            entry_point: Some("cs_evaluate"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });

        Pipelines {
            scene_layout,
            evaluate_layout,
            strand_ribbons,
            strand_lines,
            head,
            evaluate,
        }
    }
}
