//! The main (camera) pass: the head, then the strands, clusters and patches, drawn into the
//! render target from the frame's prepared groups and batches.

use crate::head::GpuMesh;
use crate::items::PreparedItems;
use crate::pipelines::Pipelines;
use crate::settings::{FrameSettings, LineCoverage, LineShading};
use crate::target::RenderTarget;

/// What the main pass needs from the frame's settings, prepared before it begins.
#[derive(Debug, Clone, Copy)]
struct PreparedMain {
    background: wgpu::Color,
    line_shading: LineShading,
    line_coverage: LineCoverage,
}

/// The camera pass and the head it draws.
#[derive(Debug)]
pub(crate) struct MainPass {
    head: Option<GpuMesh>,
    /// This frame's clear colour and line pipelines.
    prepared: PreparedMain,
}

impl MainPass {
    /// Without a head.
    pub fn new() -> MainPass {
        MainPass {
            head: None,
            prepared: PreparedMain {
                background: wgpu::Color::BLACK,
                line_shading: LineShading::default(),
                line_coverage: LineCoverage::default(),
            },
        }
    }

    /// Replaces the head mesh drawn (`None`: no head).
    pub fn set_head(&mut self, head: Option<GpuMesh>) {
        self.head = head;
    }

    /// Takes this frame's clear colour and line style from `settings`.
    pub fn prepare(&mut self, settings: &FrameSettings) {
        self.prepared = PreparedMain {
            background: wgpu::Color {
                r: f64::from(settings.background.x),
                g: f64::from(settings.background.y),
                b: f64::from(settings.background.z),
                a: 1.0,
            },
            line_shading: settings.line_shading,
            line_coverage: settings.line_coverage,
        };
    }

    /// The pipeline of strands drawn as lines in this frame's line style.
    fn strand_lines<'p>(&self, pipelines: &'p Pipelines) -> &'p wgpu::RenderPipeline {
        let [covered_per_fragment, covered_per_vertex] = &pipelines.strand_lines_covered;
        match (self.prepared.line_shading, self.prepared.line_coverage) {
            (LineShading::PerVertex, LineCoverage::Pixel) => {
                &pipelines.strand_lines_shaded_per_vertex
            }
            (LineShading::PerFragment, LineCoverage::Pixel) => &pipelines.strand_lines,
            (LineShading::PerVertex, LineCoverage::Width) => covered_per_vertex,
            (LineShading::PerFragment, LineCoverage::Width) => covered_per_fragment,
        }
    }

    /// Encodes the pass (after [`MainPass::prepare`]) into `target`, with `scene` as group 0,
    /// `maps` (the shadow maps) as group 2 and `items`' groups and batches.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipelines: &Pipelines,
        target: &RenderTarget,
        scene: &wgpu::BindGroup,
        maps: &wgpu::BindGroup,
        items: &PreparedItems,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("hair-render scene"),
            color_attachments: &[Some(target.color_attachment(self.prepared.background))],
            depth_stencil_attachment: Some(target.depth_attachment()),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, scene, &[]);
        pass.set_bind_group(2, maps, &[]);
        if let Some(head) = &self.head {
            pass.set_pipeline(&pipelines.head);
            pass.set_vertex_buffer(0, head.vertices.slice(..));
            pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..head.index_count, 0, 0..1);
        }
        let [strand_batches, cluster_batches, patch_batches] = &items.batches;
        if !strand_batches.is_empty() {
            pass.set_bind_group(1, &items.groups[0], &[]);
            let mut current = None;
            for batch in strand_batches {
                if current != Some(batch.thin) {
                    pass.set_pipeline(if batch.thin {
                        self.strand_lines(pipelines)
                    } else {
                        &pipelines.strand_ribbons
                    });
                    current = Some(batch.thin);
                }
                let vertices = if batch.thin {
                    batch.line_vertices()
                } else {
                    batch.ribbon_vertices()
                };
                pass.draw(0..vertices, batch.items.clone());
            }
        }
        for (surfaces, group, batches, is_cluster) in [
            (&pipelines.clusters, &items.groups[1], cluster_batches, true),
            (&pipelines.patches, &items.groups[2], patch_batches, false),
        ] {
            if batches.is_empty() {
                continue;
            }
            pass.set_bind_group(1, group, &[]);
            let mut current = None;
            for batch in batches {
                if current != Some(batch.dissolving) {
                    pass.set_pipeline(surfaces.for_batch(batch.dissolving));
                    current = Some(batch.dissolving);
                }
                let bands = if is_cluster { batch.around_segments } else { 1 };
                pass.draw(0..batch.surface_vertices(bands), batch.items.clone());
            }
        }
    }
}
