//! The renderer: static strands, clusters and patches uploaded once, skeleton nodes per frame,
//! images out. A frame runs as stages, each a unit with its own resources: the scene inputs
//! ([`crate::scene_inputs`]) and the items' batches ([`crate::items`]) are prepared first, then
//! the chain-curve pass ([`crate::chain_curves`]), the light passes ([`crate::shadow_pass`]) and
//! the main pass ([`crate::main_pass`]) are encoded from them, and the readback stage
//! ([`crate::readback`]) copies the image out.

use glam::Vec3;
use hair_core::TriangleMesh;

use crate::chain_curves::ChainCurvePass;
use crate::device::{AdapterReport, DeviceOptions, GpuContext, acquire_device};
use crate::drawn_counts::DrawnCounts;
use crate::error::{RenderError, Result, invalid};
use crate::evaluate;
use crate::head::{upload_mesh, validate_mesh};
use crate::inputs::{SkeletonFrame, StrandSet};
use crate::items::{HairItems, ItemKind};
use crate::main_pass::MainPass;
use crate::pipelines::Pipelines;
use crate::readback::{Destination, Readback};
use crate::scene_inputs::SceneInputs;
use crate::scopes::ErrorScopes;
use crate::settings::{FrameSettings, ShadingMode};
use crate::shadow_pass::{ShadowPass, shadow_frame};
use crate::strand_shapes::StrandShapes;
use crate::surfaces::{ClusterSet, PatchSet};
use crate::timings::RenderTimings;
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
    gpu: GpuContext,
    sample_count: u32,
    pipelines: Pipelines,
    /// Group 0: globals, nodes and the chain table.
    scene: SceneInputs,
    /// The static strands, clusters and patches, and each frame's batches over them.
    items: HairItems,
    /// Curve evaluation: the chain-curve compute pass and the samples it writes.
    curves: ChainCurvePass,
    /// Self-shadowing: the light passes and their maps.
    shadows: ShadowPass,
    /// The camera pass and the head.
    main_pass: MainPass,
    /// The render target and the copy of the image out.
    readback: Readback,
    /// Where the last frame's time went.
    timings: RenderTimings,
    /// What the last frame drew.
    drawn: DrawnCounts,
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
        // wgpu 30's GLSL writer assigns the WGSL `sample_mask` output (a u32) to
        // `gl_SampleMask[0]` (an int) without a cast, which Mesa refuses to compile; on GL the
        // covered lines keep or drop whole fragments instead.
        let sample_mask_output = gpu.adapter.get_info().backend != wgpu::Backend::Gl;
        let pipelines = Pipelines::new(device, sample_count, sample_mask_output);
        let scene = SceneInputs::new(device);
        let items = HairItems::new(device);
        let curves = ChainCurvePass::new(device);
        let shadows = ShadowPass::new(device, &pipelines);
        scope.pop("building the render pipelines")?;
        Ok(Renderer {
            gpu,
            sample_count,
            pipelines,
            scene,
            items,
            curves,
            shadows,
            main_pass: MainPass::new(),
            readback: Readback::new(sample_count),
            timings: RenderTimings::default(),
            drawn: DrawnCounts::default(),
        })
    }

    /// Where the time of the last [`Renderer::render`] (or [`Renderer::render_to_texture`],
    /// without the wait and the readback) went.
    pub fn last_timings(&self) -> RenderTimings {
        self.timings
    }

    /// The strands and strand segments the last frame drew in its camera pass, after thinning
    /// and dissolves (the light passes draw the same strands).
    pub fn last_drawn(&self) -> DrawnCounts {
        self.drawn
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
        self.items.count(ItemKind::Strands)
    }

    /// Number of uploaded clusters.
    pub fn cluster_count(&self) -> usize {
        self.items.count(ItemKind::Clusters)
    }

    /// Number of uploaded patches.
    pub fn patch_count(&self) -> usize {
        self.items.count(ItemKind::Patches)
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
        self.items.upload_strands(&self.gpu, strands, shapes)
    }

    /// Moves each uploaded strand by `shifts[s]` [m, world] in the frames drawn from now on,
    /// `shifts` in upload order (one per strand; empty: no shifts, the default after every
    /// upload). The whole strand moves, its shape kept: a body that stretches carries each
    /// strand's root on its own triangle, which the skeleton's rest offsets do not follow, so
    /// the frame loop shifts each strand from where its skeleton draws its root
    /// ([`hair_core::representation::drawn::drawn_strand_root`]) to where the body carries it.
    /// The evaluation pass ([`Renderer::evaluate_strands`]) reads the B-splines unshifted.
    ///
    /// Errors: a count that is neither 0 nor the strand count, a shift that is not finite (the
    /// shifts set before stay).
    pub fn set_strand_root_shifts(&mut self, shifts: &[Vec3]) -> Result<()> {
        self.items.set_strand_root_shifts(&self.gpu, shifts)
    }

    /// Whether the strands are drawn shifted ([`Renderer::set_strand_root_shifts`]).
    pub fn strands_shifted(&self) -> bool {
        self.items.strands_shifted()
    }

    /// Uploads the static cluster data, replacing any earlier set.
    pub fn upload_clusters(&mut self, clusters: &ClusterSet<'_>) -> Result<()> {
        self.items.upload_clusters(&self.gpu, clusters)
    }

    /// Uploads the static patch data, replacing any earlier set.
    pub fn upload_patches(&mut self, patches: &PatchSet<'_>) -> Result<()> {
        self.items.upload_patches(&self.gpu, patches)
    }

    /// Sets the head mesh drawn with the hair (`None` removes it).
    pub fn set_head_mesh(&mut self, mesh: Option<&TriangleMesh>) -> Result<()> {
        let head = match mesh {
            None => None,
            Some(mesh) => {
                validate_mesh(mesh)?;
                let scope = ErrorScopes::push(&self.gpu.device);
                let head = upload_mesh(&self.gpu.device, mesh);
                scope.pop("uploading the head mesh")?;
                head
            }
        };
        self.main_pass.set_head(head);
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
        let result = self.draw(settings, counts, Destination::Image);
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
        let result = self.draw(settings, counts, Destination::Texture(destination));
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

    /// Evaluates every strand's B-spline on the GPU (the same WGSL code the vertex shader uses) at
    /// `samples_per_strand` evenly spaced parameters, `u = i / (samples − 1)`; strand-major points
    /// [m], strands in upload order. Strands without nodes give `NaN` points. Meant for checks
    /// against [`crate::bspline`].
    pub fn evaluate_strands(
        &mut self,
        frame: &SkeletonFrame<'_>,
        samples_per_strand: u32,
    ) -> Result<Vec<Vec3>> {
        let total = evaluate::check_request(
            self.strand_count() as u64,
            samples_per_strand,
            self.gpu.device.limits().max_storage_buffer_binding_size,
        )?;
        // Camera and colours do not matter for evaluation; only the counts do.
        let settings = FrameSettings::new(1, 1, crate::camera::Camera::default());
        let counts = self.upload_frame(frame, &settings, samples_per_strand)?;
        if total == 0 {
            return Ok(Vec::new());
        }
        let scope = ErrorScopes::push(&self.gpu.device);
        let globals = Globals::new(&settings, counts, None);
        self.scene.write_globals(&self.gpu.queue, &globals);
        let (device, pipelines) = (&self.gpu.device, &self.pipelines);
        let scene_group = self.scene.bind_group(device, pipelines);
        let strand_group =
            self.items
                .bind_group(ItemKind::Strands, device, pipelines, self.curves.samples());
        let result = evaluate::dispatch(&self.gpu, pipelines, &scene_group, &strand_group, total);
        let checked = scope.pop("evaluating strands");
        let sorted = result?;
        checked?;
        // Back from chain-sorted order to upload order.
        Ok(evaluate::to_upload_order(
            &sorted,
            self.items.strand_order(),
            samples_per_strand,
        ))
    }

    /// Validates and uploads the per-frame data (nodes and the chain table with each chain's
    /// tessellation); returns the counts for the globals.
    fn upload_frame(
        &mut self,
        frame: &SkeletonFrame<'_>,
        settings: &FrameSettings,
        samples_per_strand: u32,
    ) -> Result<GeometryCounts> {
        frame.validate()?;
        let chains = frame.chain_count() as u32;
        self.items.check_chains(chains)?;
        let samples = self.scene.pack(frame, settings, &self.items);
        let scope = ErrorScopes::push(&self.gpu.device);
        if self.scene.upload(&self.gpu) {
            self.shadows.scene_replaced();
        }
        if self.curves.reserve(&self.gpu.device, samples) {
            self.items.chain_samples_replaced();
        }
        scope.pop("uploading skeleton nodes")?;
        Ok(GeometryCounts {
            strands: self.strand_count() as u32,
            chains,
            nodes: frame.node_count() as u32,
            samples_per_strand,
            samples_per_pixel: 0,
        })
    }

    /// Draws the frame into the target, then reads it back (returning the image) or copies it
    /// into a texture (returning `None`): prepares every pass's resources, encodes the
    /// chain-curve, light and main passes from them, and copies the image out.
    fn draw(
        &mut self,
        settings: &FrameSettings,
        counts: GeometryCounts,
        destination: Destination<'_>,
    ) -> Result<Option<image::RgbaImage>> {
        let started = std::time::Instant::now();
        let (gpu, pipelines) = (&self.gpu, &self.pipelines);
        self.readback
            .prepare(&gpu.device, settings.width, settings.height)?;
        // Chain-curve slots per chain (the most points a chain can have).
        let slots = settings.tessellation.max_segments + 1;
        let counts = GeometryCounts {
            samples_per_strand: slots,
            samples_per_pixel: self.sample_count,
            ..counts
        };
        let shadow = shadow_frame(
            settings,
            self.scene.hair_bounds(),
            self.items.count(ItemKind::Strands),
            self.items.count(ItemKind::Clusters),
            self.items.count(ItemKind::Patches),
        );
        let globals = Globals::new(settings, counts, shadow.as_ref());
        self.scene.write_globals(&gpu.queue, &globals);
        let maps_group = self.shadows.prepare(
            gpu,
            pipelines,
            &self.scene,
            shadow.as_ref(),
            &globals,
            settings.shadows.along_stride,
        );
        let scene_group = self.scene.bind_group(&gpu.device, pipelines);
        let items = self.items.prepare(
            gpu,
            pipelines,
            self.curves.samples(),
            self.scene.chain_table(),
            self.scene.chain_distances(),
        );
        self.drawn = DrawnCounts::of_strand_batches(&items.batches[0]);
        let draws_strands = !items.batches[0].is_empty();
        self.curves
            .prepare(&gpu.device, pipelines, counts.chains, slots, draws_strands);
        self.main_pass.prepare(settings);
        let target = self.readback.target()?;

        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("hair-render frame"),
            });
        self.curves.encode(&mut encoder, pipelines, &scene_group);
        self.shadows.encode(&mut encoder, pipelines, &items);
        self.main_pass.encode(
            &mut encoder,
            pipelines,
            target,
            &scene_group,
            &maps_group,
            &items,
        );
        self.readback.encode(&mut encoder, destination)?;
        gpu.queue.submit([encoder.finish()]);
        self.timings.encode = started.elapsed().as_secs_f64();
        if let Destination::Texture(_) = destination {
            return Ok(None);
        }
        let (image, waited, copied) = self.readback.read(&gpu.device)?;
        self.timings.gpu = waited;
        self.timings.readback = copied;
        Ok(Some(image))
    }
}
