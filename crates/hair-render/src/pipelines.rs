//! Shader modules, bind group layouts and pipelines of the renderer.

use crate::shadow_pipelines::{ShadowPipelines, ShadowSources, shadow_maps_layout};
use crate::target::{COLOR_FORMAT, DEPTH_FORMAT};

/// WGSL shared by every pipeline: globals, node and chain storage buffers, the B-spline and
/// Kajiya-Kay and Marschner shading.
const COMMON_WGSL: &str = concat!(
    include_str!("shaders/common.wgsl"),
    include_str!("shaders/bspline.wgsl"),
    include_str!("shaders/marschner.wgsl"),
    include_str!("shaders/chain_curve_types.wgsl")
);
/// The chain-curve compute pass.
const CHAIN_CURVES_WGSL: &str = include_str!("shaders/chain_curves.wgsl");
/// The strand storage buffer (group 1).
const STRAND_ITEMS_WGSL: &str = include_str!("shaders/strand_items.wgsl");
/// The shadow maps (group 2) and their lookup.
const SHADOWS_WGSL: &str = include_str!("shaders/shadows.wgsl");
/// Strand ribbons and lines.
const STRANDS_WGSL: &str = include_str!("shaders/strands.wgsl");
/// Cluster tubes and patch strips.
const SURFACES_WGSL: &str = include_str!("shaders/surfaces.wgsl");
/// The hair texture of clusters and patches.
const HAIR_TEXTURE_WGSL: &str = include_str!("shaders/hair_texture.wgsl");
/// The head mesh.
const HEAD_WGSL: &str = include_str!("shaders/head.wgsl");
/// The evaluation compute pass.
const EVALUATE_WGSL: &str = include_str!("shaders/evaluate.wgsl");

/// Bytes per head vertex: position then normal, 3 floats each.
pub(crate) const HEAD_VERTEX_STRIDE: u64 = 24;

/// Every pipeline and layout the renderer uses.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Group 0: globals (binding 0), nodes (1), chain table (2).
    pub scene_layout: wgpu::BindGroupLayout,
    /// Group 1 of strands: the strands (binding 0), this frame's chain-curve samples (1), the
    /// residual profiles (2), the strands drawn (3) and the strands' root shifts (4).
    pub strand_items_layout: wgpu::BindGroupLayout,
    /// Group 1 of clusters and patches: their static records (binding 0).
    pub items_layout: wgpu::BindGroupLayout,
    /// Group 1 of the chain-curve pass: the samples it writes (binding 0).
    pub chain_curves_layout: wgpu::BindGroupLayout,
    pub chain_curves: wgpu::ComputePipeline,
    /// Group 2 of the evaluation pass: the output points (binding 0).
    pub evaluate_layout: wgpu::BindGroupLayout,
    pub strand_ribbons: wgpu::RenderPipeline,
    /// Strands as lines, shaded per fragment ([`crate::LineShading::PerFragment`]).
    pub strand_lines: wgpu::RenderPipeline,
    /// Strands as lines, shaded at the curve points ([`crate::LineShading::PerVertex`]).
    pub strand_lines_shaded_per_vertex: wgpu::RenderPipeline,
    /// The two line pipelines covering their width's share of a pixel
    /// ([`crate::LineCoverage::Width`]): per fragment, per vertex.
    pub strand_lines_covered: [wgpu::RenderPipeline; 2],
    pub clusters: SurfacePipelines,
    pub patches: SurfacePipelines,
    pub head: wgpu::RenderPipeline,
    pub evaluate: wgpu::ComputePipeline,
    /// Group 2 of the hair and head pipelines: the shadow maps.
    pub shadow_maps_layout: wgpu::BindGroupLayout,
    /// The light passes of self-shadowing.
    pub shadows: ShadowPipelines,
}

/// The two pipelines of a surface kind (clusters or patches).
#[derive(Debug)]
pub(crate) struct SurfacePipelines {
    /// Chains drawn whole: no `discard` in the fragment shader, so depth is tested before shading.
    pub opaque: wgpu::RenderPipeline,
    /// Chains fading in or out (coverage below 1): screen-door `discard`.
    pub dissolving: wgpu::RenderPipeline,
}

impl SurfacePipelines {
    /// The pipeline for a batch.
    pub fn for_batch(&self, dissolving: bool) -> &wgpu::RenderPipeline {
        if dissolving {
            &self.dissolving
        } else {
            &self.opaque
        }
    }
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

fn shader(device: &wgpu::Device, label: &str, parts: &[&str]) -> wgpu::ShaderModule {
    let source = format!("{COMMON_WGSL}\n{}", parts.join("\n"));
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

impl Pipelines {
    /// Compiles the shaders and builds the pipelines for `sample_count`-times MSAA; covered
    /// strand lines pick their samples through the fragment's `sample_mask` output where
    /// `sample_mask_output` is true and there are several samples, and keep or drop whole
    /// fragments otherwise. Errors surface through the caller's error scope.
    pub fn new(device: &wgpu::Device, sample_count: u32, sample_mask_output: bool) -> Pipelines {
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
            ],
        });
        let items_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hair-render items"),
            entries: &[storage_entry(0, true, geometry_stages)],
        });
        let strand_items_layout =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("hair-render strand items"),
                entries: &[
                    storage_entry(0, true, geometry_stages),
                    storage_entry(1, true, geometry_stages),
                    storage_entry(2, true, geometry_stages),
                    storage_entry(3, true, geometry_stages),
                    storage_entry(4, true, geometry_stages),
                ],
            });
        let chain_curves_layout =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("hair-render chain curves"),
                entries: &[storage_entry(0, false, wgpu::ShaderStages::COMPUTE)],
            });
        let evaluate_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hair-render evaluation output"),
            entries: &[storage_entry(0, false, wgpu::ShaderStages::COMPUTE)],
        });
        let shadow_maps_layout = shadow_maps_layout(device);
        // The head takes no items: no group 1, the shadow maps at group 2.
        let head_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hair-render head"),
            bind_group_layouts: &[Some(&scene_layout), None, Some(&shadow_maps_layout)],
            immediate_size: 0,
        });
        let strand_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hair-render strands"),
            bind_group_layouts: &[
                Some(&scene_layout),
                Some(&strand_items_layout),
                Some(&shadow_maps_layout),
            ],
            immediate_size: 0,
        });
        let surface_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hair-render surfaces"),
            bind_group_layouts: &[
                Some(&scene_layout),
                Some(&items_layout),
                Some(&shadow_maps_layout),
            ],
            immediate_size: 0,
        });
        let chain_curves_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("hair-render chain curves"),
                bind_group_layouts: &[Some(&scene_layout), Some(&chain_curves_layout)],
                immediate_size: 0,
            });
        let evaluate_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("hair-render evaluate"),
                bind_group_layouts: &[
                    Some(&scene_layout),
                    Some(&strand_items_layout),
                    Some(&evaluate_layout),
                ],
                immediate_size: 0,
            });

        let strands_module = shader(
            device,
            "hair-render strands",
            &[STRAND_ITEMS_WGSL, SHADOWS_WGSL, STRANDS_WGSL],
        );
        let surfaces_module = shader(
            device,
            "hair-render surfaces",
            &[SHADOWS_WGSL, SURFACES_WGSL, HAIR_TEXTURE_WGSL],
        );
        let head_module = shader(device, "hair-render head", &[SHADOWS_WGSL, HEAD_WGSL]);
        let evaluate_module = shader(
            device,
            "hair-render evaluate",
            &[STRAND_ITEMS_WGSL, EVALUATE_WGSL],
        );

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
        // Surfaces turn their hair texture's coverage (alpha) into MSAA samples, so their
        // silhouettes break up like strands without `discard` (which would cost early depth).
        let surface_multisample = wgpu::MultisampleState {
            alpha_to_coverage_enabled: sample_count > 1,
            ..multisample
        };
        let hair_pipeline = |label: &str,
                             layout: &wgpu::PipelineLayout,
                             module: &wgpu::ShaderModule,
                             vertex_entry: &str,
                             fragment_entry: &str,
                             topology,
                             cull_mode: Option<wgpu::Face>| {
            let multisample = if fragment_entry.starts_with("fs_surface") {
                surface_multisample
            } else {
                multisample
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some(vertex_entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: depth.clone(),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(fragment_entry),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        let strand_ribbons = hair_pipeline(
            "hair-render strand ribbons",
            &strand_layout,
            &strands_module,
            "vs_strand_ribbon",
            "fs_strand",
            strip,
            None,
        );
        let strand_lines = hair_pipeline(
            "hair-render strand lines",
            &strand_layout,
            &strands_module,
            "vs_strand_line",
            "fs_strand",
            wgpu::PrimitiveTopology::LineStrip,
            None,
        );
        let strand_lines_shaded_per_vertex = hair_pipeline(
            "hair-render strand lines shaded per vertex",
            &strand_layout,
            &strands_module,
            "vs_strand_line_shaded",
            "fs_strand_line",
            wgpu::PrimitiveTopology::LineStrip,
            None,
        );
        let (per_fragment_covered, per_vertex_covered) = if sample_mask_output && sample_count > 1 {
            ("fs_strand_covered", "fs_strand_line_covered")
        } else {
            ("fs_strand_kept", "fs_strand_line_kept")
        };
        let strand_lines_covered = [
            (
                "hair-render strand lines, covered",
                "vs_strand_line",
                per_fragment_covered,
            ),
            (
                "hair-render strand lines shaded per vertex, covered",
                "vs_strand_line_shaded",
                per_vertex_covered,
            ),
        ]
        .map(|(label, vertex, fragment)| {
            hair_pipeline(
                label,
                &strand_layout,
                &strands_module,
                vertex,
                fragment,
                wgpu::PrimitiveTopology::LineStrip,
                None,
            )
        });
        // With multisampling the screen door goes through alpha-to-coverage (a dropped pixel gets
        // alpha 0, so no sample), which spares the dropped fragments their shading; single-sampled
        // targets discard them.
        let dissolving_entry = if sample_count > 1 {
            "fs_surface_dissolving_coverage"
        } else {
            "fs_surface_dissolving"
        };
        let surface_pipelines = |kind: &str, vertex_entry: &str, cull_mode| SurfacePipelines {
            opaque: hair_pipeline(
                &format!("hair-render {kind}"),
                &surface_layout,
                &surfaces_module,
                vertex_entry,
                "fs_surface",
                strip,
                cull_mode,
            ),
            dissolving: hair_pipeline(
                &format!("hair-render {kind} dissolving"),
                &surface_layout,
                &surfaces_module,
                vertex_entry,
                dissolving_entry,
                strip,
                cull_mode,
            ),
        };
        let clusters = surface_pipelines("clusters", "vs_cluster", cluster_cull_mode());
        let shadows = ShadowPipelines::new(
            device,
            &ShadowSources {
                strands_module: &strands_module,
                surfaces_module: &surfaces_module,
                strand_layout: &strand_layout,
                surface_layout: &surface_layout,
                // Always culled: the opacity pass puts a tube's whole optical depth on the faces
                // towards the light (whatever `HAIRLOD_CLUSTER_CULL` says for the camera pass).
                cluster_cull_mode: Some(wgpu::Face::Back),
            },
        );
        let patches = surface_pipelines("patches", "vs_patch", None);

        let head_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let head = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("hair-render head"),
            layout: Some(&head_layout),
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

        let chain_curves_module = shader(device, "hair-render chain curves", &[CHAIN_CURVES_WGSL]);
        let chain_curves = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("hair-render chain curves"),
            layout: Some(&chain_curves_pipeline_layout),
            module: &chain_curves_module,
            entry_point: Some("cs_chain_curves"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });

        Pipelines {
            scene_layout,
            strand_items_layout,
            items_layout,
            chain_curves_layout,
            chain_curves,
            evaluate_layout,
            strand_ribbons,
            strand_lines,
            strand_lines_shaded_per_vertex,
            strand_lines_covered,
            clusters,
            patches,
            head,
            evaluate,
            shadow_maps_layout,
            shadows,
        }
    }
}

/// Environment variable that turns off back-face culling of cluster tubes (`none`), for
/// comparison: the culled and unculled images agree (`tests/cluster_culling.rs`).
pub const CLUSTER_CULL_ENV: &str = "HAIRLOD_CLUSTER_CULL";

/// Cluster tubes are closed around their skeleton and wound counter-clockwise seen from outside,
/// so their back faces are always behind a front face of the same tube and can be culled: on
/// llvmpipe this halves the cost of clusters filling a close-up 1280×720 frame (0.39 s to 0.21 s)
/// and changes 0.06 % of its pixels (where a tube's open end shows its inside). `none` in
/// [`CLUSTER_CULL_ENV`] draws both sides.
fn cluster_cull_mode() -> Option<wgpu::Face> {
    match std::env::var(CLUSTER_CULL_ENV).as_deref() {
        Ok("none") => None,
        _ => Some(wgpu::Face::Back),
    }
}
