//! The renderer: static strands, clusters and patches uploaded once, skeleton nodes per frame,
//! images out.

use hair_core::TriangleMesh;

use crate::batches::{Batch, CHAIN_SAMPLE_BYTES, ChainOrder, GpuChain, chain_table};
use crate::buffers::{GrowableBuffer, check_binding_size};
use crate::device::{AdapterReport, DeviceOptions, GpuContext, acquire_device};
use crate::error::{RenderError, Result, invalid};
use crate::head::{GpuMesh, upload_mesh, validate_mesh};
use crate::inputs::{GpuNode, SkeletonFrame, StrandSet, pack_nodes, pack_strands};
use crate::pipelines::Pipelines;
use crate::scopes::ErrorScopes;
use crate::settings::{FrameSettings, LineCoverage, LineShading, ShadingMode, StrandStyle};
use crate::shadow_maps::ShadowMaps;
use crate::shadows::{bounding_sphere, light_view_projection, map_resolution};
use crate::strand_shapes::StrandShapes;
use crate::surfaces::{ClusterSet, PatchSet, chain_ring_radii, pack_clusters, pack_patches};
use crate::target::RenderTarget;
use crate::thinning::{StrandSpan, strand_spans, thin_chains};
use crate::timings::RenderTimings;
use crate::uniforms::{GeometryCounts, Globals, ShadowFrame};

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

/// The three kinds of drawn hair geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ItemKind {
    Strands,
    Clusters,
    Patches,
}

/// The static items of one kind on the GPU, sorted by chain, and their bind group.
#[derive(Debug)]
pub(crate) struct Items {
    buffer: GrowableBuffer,
    bind_group: Option<wgpu::BindGroup>,
    pub order: ChainOrder,
}

impl Items {
    fn new(device: &wgpu::Device, label: &'static str) -> Items {
        Items {
            buffer: GrowableBuffer::new(device, label, wgpu::BufferUsages::STORAGE),
            bind_group: None,
            order: ChainOrder::default(),
        }
    }

    /// Replaces the items: `chains` in input order, `packed` their GPU records in input order.
    fn upload<T: bytemuck::Pod>(&mut self, gpu: &GpuContext, chains: &[u32], packed: &[T]) {
        let order = ChainOrder::new(chains);
        let sorted = order.sorted(packed);
        self.upload_sorted(gpu, order, &sorted);
    }

    /// Replaces the items with `sorted`, their GPU records already in `order`'s sorted order.
    fn upload_sorted<T: bytemuck::Pod>(
        &mut self,
        gpu: &GpuContext,
        order: ChainOrder,
        sorted: &[T],
    ) {
        if self
            .buffer
            .write(&gpu.device, &gpu.queue, bytemuck::cast_slice(sorted))
        {
            self.bind_group = None;
        }
        self.order = order;
    }
}

/// A headless hair renderer on one device.
///
/// Upload the static data once ([`Renderer::upload_groom`], or [`Renderer::upload_strands`],
/// [`Renderer::upload_clusters`] and [`Renderer::upload_patches`]; a head with
/// [`Renderer::set_head_mesh`]), then call [`Renderer::render`] per frame with the skeleton nodes:
/// only the nodes and a small per-chain table travel to the GPU each frame, and the B-splines of
/// strands, cluster tubes and patch strips are evaluated there. Items whose chain has fewer than two
/// nodes in the frame (inactive skeletons) are not drawn and cost nothing.
#[derive(Debug)]
pub struct Renderer {
    pub(crate) gpu: GpuContext,
    sample_count: u32,
    pub(crate) pipelines: Pipelines,
    pub(crate) globals: wgpu::Buffer,
    nodes: GrowableBuffer,
    chains: GrowableBuffer,
    /// This frame's chain-curve samples (written by the chain-curve pass, read by strands).
    chain_samples: GrowableBuffer,
    /// The strands' residual profiles (`vec4` per entry, [`hair_core::PROFILE_SAMPLES`] per
    /// profile; binding 2 of the strand items).
    strand_profiles: GrowableBuffer,
    /// Bind group of group 0; `None` after a buffer was replaced.
    scene_bind_group: Option<wgpu::BindGroup>,
    pub(crate) strands: Items,
    clusters: Items,
    patches: Items,
    head: Option<GpuMesh>,
    target: Option<RenderTarget>,
    node_scratch: Vec<GpuNode>,
    chain_scratch: Vec<GpuChain>,
    /// Root distance to the camera of each chain this frame [m].
    chain_distances: Vec<f32>,
    /// Largest cluster ring radius [m] per chain (0 without clusters), from the cluster upload.
    chain_ring_radii: Vec<f32>,
    /// Strand count and width per chain, from the strand upload (for strand thinning).
    chain_strand_spans: Vec<StrandSpan>,
    /// The strands this frame draws, by sorted position (binding 3 of the strand items).
    drawn_strands: GrowableBuffer,
    /// This frame's list for `drawn_strands`.
    drawn_scratch: Vec<u32>,
    /// Draw-order scratch of the front-to-back surface batches.
    order_scratch: Vec<(f32, u32)>,
    /// Self-shadowing's maps and light-pass globals.
    shadow_maps: ShadowMaps,
    /// Group 0 of the light passes (light globals, nodes, chains); `None` after a buffer was
    /// replaced.
    light_scene_bind_group: Option<wgpu::BindGroup>,
    /// A sphere around this frame's hair [m] (centre, radius), for the light's view.
    hair_bounds: Option<(glam::Vec3, f32)>,
    /// Where the last frame's time went.
    timings: RenderTimings,
}

/// Margin around the active nodes' bounding sphere for the light's view [m]: strands, tubes and
/// strips reach at most a section's half width (1.8 cm on paper-curly) from their
/// skeleton.
const HAIR_BOUNDS_MARGIN: f32 = 0.03;

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
        // wgpu 30's GLSL writer assigns the WGSL `sample_mask` output (a u32) to
        // `gl_SampleMask[0]` (an int) without a cast, which Mesa refuses to compile; on GL the
        // covered lines keep or drop whole fragments instead.
        let sample_mask_output = gpu.adapter.get_info().backend != wgpu::Backend::Gl;
        let pipelines = Pipelines::new(device, sample_count, sample_mask_output);
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hair-render globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let storage = wgpu::BufferUsages::STORAGE;
        let nodes = GrowableBuffer::new(device, "hair-render nodes", storage);
        let chains = GrowableBuffer::new(device, "hair-render chains", storage);
        let chain_samples = GrowableBuffer::new(device, "hair-render chain samples", storage);
        let strand_profiles = GrowableBuffer::new(device, "hair-render strand profiles", storage);
        let drawn_strands = GrowableBuffer::new(device, "hair-render drawn strands", storage);
        let strands = Items::new(device, "hair-render strands");
        let clusters = Items::new(device, "hair-render clusters");
        let patches = Items::new(device, "hair-render patches");
        let shadow_maps = ShadowMaps::new(device, &pipelines.shadow_maps_layout);
        scope.pop("building the render pipelines")?;
        Ok(Renderer {
            gpu,
            sample_count,
            pipelines,
            globals,
            nodes,
            chains,
            chain_samples,
            strand_profiles,
            scene_bind_group: None,
            strands,
            clusters,
            patches,
            head: None,
            target: None,
            node_scratch: Vec::new(),
            chain_scratch: Vec::new(),
            chain_distances: Vec::new(),
            chain_ring_radii: Vec::new(),
            chain_strand_spans: Vec::new(),
            drawn_strands,
            drawn_scratch: Vec::new(),
            order_scratch: Vec::new(),
            shadow_maps,
            light_scene_bind_group: None,
            hair_bounds: None,
            timings: RenderTimings::default(),
        })
    }

    /// Where the time of the last [`Renderer::render`] (or [`Renderer::render_to_texture`],
    /// without the wait and the readback) went.
    pub fn last_timings(&self) -> RenderTimings {
        self.timings
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
        self.strands.order.item_count()
    }

    /// Number of uploaded clusters.
    pub fn cluster_count(&self) -> usize {
        self.clusters.order.item_count()
    }

    /// Number of uploaded patches.
    pub fn patch_count(&self) -> usize {
        self.patches.order.item_count()
    }

    /// Uploads the static strand data, replacing any earlier set (full-length strands parallel
    /// to their chains; see [`Renderer::upload_strands_with_shapes`]).
    pub fn upload_strands(&mut self, strands: &StrandSet<'_>) -> Result<()> {
        self.upload_strands_with_shapes(strands, &StrandShapes::default())
    }

    /// Uploads the static strand data with per-strand lengths and tip scales, replacing any
    /// earlier set.
    pub fn upload_strands_with_shapes(
        &mut self,
        strands: &StrandSet<'_>,
        shapes: &StrandShapes<'_>,
    ) -> Result<()> {
        strands.validate()?;
        shapes.validate(strands.strand_count())?;
        let max_bytes = self.gpu.device.limits().max_storage_buffer_binding_size;
        let strand_bytes = std::mem::size_of::<crate::inputs::GpuStrand>() as u64;
        check_binding_size(
            "strands",
            strands.strand_count() as u64 * strand_bytes,
            max_bytes,
        )?;
        // Profiles go up as vec4<f32>: 16 bytes an entry.
        check_binding_size(
            "residual profiles",
            shapes.profiles.len() as u64 * 16,
            max_bytes,
        )?;
        // Ranked within each chain, so that a dissolving chain draws only the strands it shows.
        let order = ChainOrder::with_dissolve_ranks(strands.strand_chain);
        let mut sorted = order.sorted(&pack_strands(strands, shapes));
        for (strand, &rank) in sorted.iter_mut().zip(&order.ranks) {
            strand.dissolve_rank = rank;
        }
        let scope = ErrorScopes::push(&self.gpu.device);
        self.strands.upload_sorted(&self.gpu, order, &sorted);
        self.chain_strand_spans = strand_spans(strands);
        let profiles: Vec<[f32; 4]> = shapes
            .profiles
            .iter()
            .map(|r| r.extend(0.0).to_array())
            .collect();
        if self.strand_profiles.write(
            &self.gpu.device,
            &self.gpu.queue,
            bytemuck::cast_slice(&profiles),
        ) {
            self.strands.bind_group = None;
        }
        scope.pop("uploading strands")
    }

    /// Uploads the static cluster data, replacing any earlier set.
    pub fn upload_clusters(&mut self, clusters: &ClusterSet<'_>) -> Result<()> {
        clusters.validate()?;
        let packed = pack_clusters(clusters);
        let scope = ErrorScopes::push(&self.gpu.device);
        self.clusters
            .upload(&self.gpu, clusters.cluster_chain, &packed);
        self.chain_ring_radii = chain_ring_radii(clusters);
        scope.pop("uploading clusters")
    }

    /// Uploads the static patch data, replacing any earlier set.
    pub fn upload_patches(&mut self, patches: &PatchSet<'_>) -> Result<()> {
        patches.validate()?;
        let packed = pack_patches(patches);
        let scope = ErrorScopes::push(&self.gpu.device);
        self.patches.upload(&self.gpu, patches.patch_chain, &packed);
        scope.pop("uploading patches")
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

    /// Renders one frame: uploads `frame`'s nodes and chain table, draws the head, strands,
    /// clusters and patches whose chains have nodes, and reads the image back (sRGB RGBA8,
    /// `settings.width`×`settings.height`).
    pub fn render(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
    ) -> Result<image::RgbaImage> {
        let started = std::time::Instant::now();
        settings.validate()?;
        let counts = self.upload_frame(frame, settings, 0)?;
        self.timings = RenderTimings {
            upload: started.elapsed().as_secs_f64(),
            ..RenderTimings::default()
        };
        let scope = ErrorScopes::push(&self.gpu.device);
        let result = self.draw(settings, counts, None);
        let checked = scope.pop("rendering a frame");
        let image = result?;
        checked?;
        image.ok_or_else(|| RenderError::Gpu("the frame was not read back".into()))
    }

    /// Renders one frame as [`Renderer::render`] does, but copies the image into `destination`
    /// on the GPU instead of reading it back (an interactive viewer's window): `destination`
    /// must be a `settings.width`×`settings.height` texture of
    /// [`crate::target::COLOR_FORMAT`] with `COPY_DST` usage. The commands are submitted, not
    /// waited for.
    pub fn render_to_texture(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
        destination: &wgpu::Texture,
    ) -> Result<()> {
        settings.validate()?;
        let size = (destination.width(), destination.height());
        if size != (settings.width, settings.height)
            || destination.format() != crate::target::COLOR_FORMAT
            || !destination.usage().contains(wgpu::TextureUsages::COPY_DST)
        {
            return Err(invalid(format!(
                "the destination texture is {}x{} {:?} with {:?}; the frame needs {}x{} {:?} \
                 with COPY_DST",
                size.0,
                size.1,
                destination.format(),
                destination.usage(),
                settings.width,
                settings.height,
                crate::target::COLOR_FORMAT
            )));
        }
        let started = std::time::Instant::now();
        let counts = self.upload_frame(frame, settings, 0)?;
        self.timings = RenderTimings {
            upload: started.elapsed().as_secs_f64(),
            ..RenderTimings::default()
        };
        let scope = ErrorScopes::push(&self.gpu.device);
        let result = self.draw(settings, counts, Some(destination));
        let checked = scope.pop("rendering a frame into a texture");
        result?;
        checked
    }

    /// Renders the frame shaded and colour-coded by level (Fig. 6) and puts the two side by side:
    /// shaded on the left, colour-coded on the right (`2·width`×`height` pixels).
    pub fn render_side_by_side(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
    ) -> Result<image::RgbaImage> {
        let shaded = self.render(
            frame,
            &FrameSettings {
                mode: ShadingMode::Shaded,
                ..*settings
            },
        )?;
        let coded = self.render(
            frame,
            &FrameSettings {
                mode: ShadingMode::LevelColors,
                ..*settings
            },
        )?;
        Ok(crate::output::side_by_side(&shaded, &coded))
    }

    /// Validates and uploads the per-frame data (nodes and the chain table with each chain's
    /// tessellation); returns the counts for the globals.
    pub(crate) fn upload_frame(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
        samples_per_strand: u32,
    ) -> Result<GeometryCounts> {
        frame.validate()?;
        let chains = frame.chain_count() as u32;
        for (what, items) in [
            ("strands", &self.strands),
            ("clusters", &self.clusters),
            ("patches", &self.patches),
        ] {
            let needed = items.order.chains_needed();
            if needed > chains {
                return Err(invalid(format!(
                    "the {what} follow chains up to {} but the frame has {chains} chains",
                    needed - 1
                )));
            }
        }
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
        let is_thin = |distance: f32| match settings.strand_style {
            StrandStyle::Lines => true,
            StrandStyle::Ribbons {
                width,
                min_width_pixels,
            } => (width * focal / distance.max(1e-6)).max(min_width_pixels) <= 1.0,
        };
        let samples = chain_table(
            frame,
            &settings.tessellation,
            settings.cluster_geometry,
            settings.camera.position,
            focal,
            &self.chain_ring_radii,
            is_thin,
            &mut self.chain_scratch,
            &mut self.chain_distances,
        );
        thin_chains(
            &mut self.chain_scratch,
            &self.chain_strand_spans,
            &self.chain_distances,
            focal,
            settings.strand_thinning,
        );
        let scope = ErrorScopes::push(&self.gpu.device);
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let mut replaced =
            self.nodes
                .write(device, queue, bytemuck::cast_slice(&self.node_scratch));
        replaced |= self
            .chains
            .write(device, queue, bytemuck::cast_slice(&self.chain_scratch));
        if replaced {
            self.scene_bind_group = None;
            self.light_scene_bind_group = None;
        }
        if self
            .chain_samples
            .reserve(device, u64::from(samples) * CHAIN_SAMPLE_BYTES)
        {
            self.strands.bind_group = None;
        }
        scope.pop("uploading skeleton nodes")?;
        Ok(GeometryCounts {
            strands: self.strands.order.item_count() as u32,
            chains,
            nodes: frame.node_count() as u32,
            samples_per_strand,
            samples_per_pixel: 0,
        })
    }

    pub(crate) fn scene_bind_group(&mut self) -> wgpu::BindGroup {
        if let Some(group) = &self.scene_bind_group {
            return group.clone();
        }
        let group = self.make_scene_bind_group(&self.globals);
        self.scene_bind_group = Some(group.clone());
        group
    }

    /// Group 0 of the light passes: the light globals with this frame's nodes and chains.
    fn light_scene_bind_group(&mut self) -> wgpu::BindGroup {
        if let Some(group) = &self.light_scene_bind_group {
            return group.clone();
        }
        let group = self.make_scene_bind_group(&self.shadow_maps.light_globals);
        self.light_scene_bind_group = Some(group.clone());
        group
    }

    fn make_scene_bind_group(&self, globals: &wgpu::Buffer) -> wgpu::BindGroup {
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render scene"),
                layout: &self.pipelines.scene_layout,
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

    /// The light's view of this frame's hair, when the frame is shaded with self-shadowing and
    /// has hair.
    fn shadow_frame(&self, settings: &FrameSettings) -> Option<ShadowFrame> {
        if !settings.shadows.enabled || settings.mode != ShadingMode::Shaded {
            return None;
        }
        let (centre, radius) = self.hair_bounds?;
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
        let strands = self.strand_count() as f32;
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
            strands_per_cluster: per(self.cluster_count()),
            strands_per_patch: per(self.patch_count()),
        })
    }

    pub(crate) fn item_bind_group(&mut self, kind: ItemKind) -> wgpu::BindGroup {
        let items = match kind {
            ItemKind::Strands => &mut self.strands,
            ItemKind::Clusters => &mut self.clusters,
            ItemKind::Patches => &mut self.patches,
        };
        if let Some(group) = &items.bind_group {
            return group.clone();
        }
        let items_entry = wgpu::BindGroupEntry {
            binding: 0,
            resource: items.buffer.buffer().as_entire_binding(),
        };
        let group = if kind == ItemKind::Strands {
            self.gpu
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("hair-render strand items"),
                    layout: &self.pipelines.strand_items_layout,
                    entries: &[
                        items_entry,
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: self.chain_samples.buffer().as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: self.strand_profiles.buffer().as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: self.drawn_strands.buffer().as_entire_binding(),
                        },
                    ],
                })
        } else {
            self.gpu
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("hair-render items"),
                    layout: &self.pipelines.items_layout,
                    entries: &[items_entry],
                })
        };
        items.bind_group = Some(group.clone());
        group
    }

    /// Draws the frame into the target, then reads it back (`destination` `None`) or copies it
    /// into `destination` (returning `None`).
    fn draw(
        &mut self,
        settings: &FrameSettings,
        counts: GeometryCounts,
        destination: Option<&wgpu::Texture>,
    ) -> Result<Option<image::RgbaImage>> {
        let started = std::time::Instant::now();
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
        // counts.w: chain-curve slots per chain (the most points a chain can have).
        let slots = settings.tessellation.max_segments + 1;
        let counts = GeometryCounts {
            samples_per_strand: slots,
            samples_per_pixel: self.sample_count,
            ..counts
        };
        let shadow = self.shadow_frame(settings);
        let globals = Globals::new(settings, counts, shadow.as_ref());
        self.gpu
            .queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        let maps_group = match &shadow {
            Some(frame) => {
                self.gpu.queue.write_buffer(
                    &self.shadow_maps.light_globals,
                    0,
                    bytemuck::bytes_of(&globals.for_light_passes()),
                );
                self.shadow_maps.prepare(
                    &self.gpu.device,
                    &self.pipelines.shadow_maps_layout,
                    frame.resolution,
                )
            }
            None => self.shadow_maps.unshadowed().clone(),
        };
        let light_scene_group = shadow.as_ref().map(|_| self.light_scene_bind_group());
        let scene_group = self.scene_bind_group();
        let curves_group = self
            .gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hair-render chain curves"),
                layout: &self.pipelines.chain_curves_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.chain_samples.buffer().as_entire_binding(),
                }],
            });
        // Strands in chain order over the list of the strands drawn (few draws, thinned and
        // dissolving chains included); clusters and patches nearest first, so that early depth
        // testing skips the hidden surfaces' shading.
        let mut batches: [Vec<Batch>; 3] = Default::default();
        self.strands.order.listed_batches(
            &self.chain_scratch,
            &mut self.drawn_scratch,
            &mut batches[0],
        );
        if self.drawn_strands.write(
            &self.gpu.device,
            &self.gpu.queue,
            bytemuck::cast_slice(&self.drawn_scratch),
        ) {
            self.strands.bind_group = None;
        }
        let item_groups = [
            self.item_bind_group(ItemKind::Strands),
            self.item_bind_group(ItemKind::Clusters),
            self.item_bind_group(ItemKind::Patches),
        ];
        for (items, out) in [&self.clusters, &self.patches]
            .into_iter()
            .zip(&mut batches[1..])
        {
            items.order.batches_front_to_back(
                &self.chain_scratch,
                &self.chain_distances,
                &mut self.order_scratch,
                out,
            );
        }
        let Some(target) = self.target.as_ref() else {
            return Err(RenderError::Gpu("render target missing".into()));
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
        if !batches[0].is_empty() {
            // One thread per (chain, point slot); threads past a chain's points return at once.
            let threads = u64::from(counts.chains) * u64::from(slots);
            let groups = threads.div_ceil(64);
            let max_groups = u64::from(
                self.gpu
                    .device
                    .limits()
                    .max_compute_workgroups_per_dimension,
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("hair-render chain curves"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipelines.chain_curves);
            pass.set_bind_group(0, &scene_group, &[]);
            pass.set_bind_group(1, &curves_group, &[]);
            pass.dispatch_workgroups(
                groups.min(max_groups) as u32,
                groups.div_ceil(max_groups) as u32,
                1,
            );
        }
        if let Some(light_scene) = &light_scene_group {
            self.shadow_maps.encode(
                &mut encoder,
                &self.pipelines.shadows.depth,
                &self.pipelines.shadows.opacity,
                light_scene,
                &item_groups,
                &batches,
                settings.shadows.along_stride,
            );
        }
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hair-render scene"),
                color_attachments: &[Some(target.color_attachment(background))],
                depth_stencil_attachment: Some(target.depth_attachment()),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &scene_group, &[]);
            pass.set_bind_group(2, &maps_group, &[]);
            if let Some(head) = &self.head {
                pass.set_pipeline(&self.pipelines.head);
                pass.set_vertex_buffer(0, head.vertices.slice(..));
                pass.set_index_buffer(head.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..head.index_count, 0, 0..1);
            }
            let [strand_batches, cluster_batches, patch_batches] = &batches;
            if !strand_batches.is_empty() {
                pass.set_bind_group(1, &item_groups[0], &[]);
                let mut current = None;
                for batch in strand_batches {
                    if current != Some(batch.thin) {
                        pass.set_pipeline(if batch.thin {
                            let [covered_per_fragment, covered_per_vertex] =
                                &self.pipelines.strand_lines_covered;
                            match (settings.line_shading, settings.line_coverage) {
                                (LineShading::PerVertex, LineCoverage::Pixel) => {
                                    &self.pipelines.strand_lines_shaded_per_vertex
                                }
                                (LineShading::PerFragment, LineCoverage::Pixel) => {
                                    &self.pipelines.strand_lines
                                }
                                (LineShading::PerVertex, LineCoverage::Width) => covered_per_vertex,
                                (LineShading::PerFragment, LineCoverage::Width) => {
                                    covered_per_fragment
                                }
                            }
                        } else {
                            &self.pipelines.strand_ribbons
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
            for (pipelines, group, batches, is_cluster) in [
                (
                    &self.pipelines.clusters,
                    &item_groups[1],
                    cluster_batches,
                    true,
                ),
                (
                    &self.pipelines.patches,
                    &item_groups[2],
                    patch_batches,
                    false,
                ),
            ] {
                if batches.is_empty() {
                    continue;
                }
                pass.set_bind_group(1, group, &[]);
                let mut current = None;
                for batch in batches {
                    if current != Some(batch.dissolving) {
                        pass.set_pipeline(pipelines.for_batch(batch.dissolving));
                        current = Some(batch.dissolving);
                    }
                    let bands = if is_cluster { batch.around_segments } else { 1 };
                    pass.draw(0..batch.surface_vertices(bands), batch.items.clone());
                }
            }
        }
        if let Some(destination) = destination {
            target.encode_copy_to(&mut encoder, destination);
            self.gpu.queue.submit([encoder.finish()]);
            self.timings.encode = started.elapsed().as_secs_f64();
            return Ok(None);
        }
        target.encode_readback(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        self.timings.encode = started.elapsed().as_secs_f64();
        let (image, gpu, readback) = target.read_image_timed(&self.gpu.device)?;
        self.timings.gpu = gpu;
        self.timings.readback = readback;
        Ok(Some(image))
    }
}
