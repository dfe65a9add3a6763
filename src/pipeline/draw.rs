//! Drawing a pipeline's frame: the skeletons to draw gathered on the groom's chain numbering and
//! handed to the wgpu renderer, which evaluates the NURBS on the GPU; the head mesh drawn at its
//! simulated pose, tessellated as coarsely as its size on screen allows
//! ([`crate::head_levels`]).

use std::time::Instant;

use glam::Vec3;
use hair_core::{Camera, RigidTransform, Scene, TriangleMesh};
use hair_render::{
    ActiveSkeletons, FrameSettings, Renderer, RendererOptions, ShadingMode, StrandThinning,
};

use super::error::Result;
use super::pipeline::Pipeline;
use super::style::DrawStyle;
use crate::head_levels::{HEAD_PIXEL_TOLERANCE, HeadLevels};

/// What a frame is drawn from: a run in memory ([`Pipeline`], a
/// [`Crowd`](crate::crowd::Crowd)) or a frame read back from a simulation cache
/// ([`crate::cache`]). The renderers draw whatever gives them these.
pub trait DrawnSource {
    /// Fills `active` (cleared first) with the skeletons to draw, on the grooms' chain numbering.
    fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()>;

    /// Each character's head pose, in the shot's order (one for a lone character).
    fn head_poses(&self) -> Vec<RigidTransform>;

    /// How the renderer thins the strand groups small on screen.
    fn strand_thinning(&self) -> StrandThinning;

    /// Each character's body mesh at the time drawn [m, head space], in the shot's order:
    /// `Some` where its head deforms ([`Scene::body_motion`]), `None` where the rigid head mesh
    /// is drawn. Empty (the default): every head rigid.
    fn deformed_bodies(&self) -> Vec<Option<TriangleMesh>> {
        Vec::new()
    }

    /// Fills `shifts` (cleared first) with each strand's shift [m, world] onto where its
    /// character's deforming body carries its root, for the skeletons `active` gathered, in the
    /// order the grooms' strands are uploaded
    /// ([`Renderer::set_strand_root_shifts`]); left empty where no head deforms (the default).
    fn strand_root_shifts(&self, _active: &ActiveSkeletons, shifts: &mut Vec<Vec3>) {
        shifts.clear();
    }
}

impl DrawnSource for Pipeline {
    fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        Pipeline::gather_drawn(self, active)
    }

    fn head_poses(&self) -> Vec<RigidTransform> {
        vec![self.head_pose()]
    }

    fn strand_thinning(&self) -> StrandThinning {
        self.settings().strand_thinning()
    }

    fn deformed_bodies(&self) -> Vec<Option<TriangleMesh>> {
        vec![self.character().body_mesh()]
    }

    fn strand_root_shifts(&self, active: &ActiveSkeletons, shifts: &mut Vec<Vec3>) {
        Pipeline::strand_root_shifts(self, active, shifts);
    }
}

/// A renderer bound to one pipeline's groom and head (uploaded once), with its per-frame buffer.
/// The head mesh is drawn where the simulation has it: it is uploaded again, posed, whenever the
/// head has moved or its tessellation changed since the last frame drawn.
pub struct PipelineRenderer {
    renderer: Renderer,
    active: ActiveSkeletons,
    /// The head's tessellations.
    head_levels: HeadLevels,
    /// The pose and tessellation the uploaded head mesh has.
    head_pose: (RigidTransform, usize),
    /// Line shading, hair shading, line coverage.
    style: DrawStyle,
    /// This frame's strand root shifts (scratch).
    shifts: Vec<Vec3>,
}

impl PipelineRenderer {
    /// A renderer from `options` (adapter and backend), with `scene`'s groom and head uploaded.
    pub fn new(options: &RendererOptions, scene: &Scene) -> Result<Self> {
        PipelineRenderer::with_renderer(Renderer::new(options)?, scene)
    }

    /// A pipeline renderer on an already built `renderer` (for example one on a window's
    /// device, [`hair_render::acquire_device_for_surface`]), with `scene`'s groom and head
    /// uploaded.
    pub fn with_renderer(mut renderer: Renderer, scene: &Scene) -> Result<Self> {
        renderer.upload_groom(&scene.groom)?;
        renderer.set_head_mesh(Some(&scene.head.mesh))?;
        Ok(PipelineRenderer {
            renderer,
            active: ActiveSkeletons::new(),
            head_levels: HeadLevels::new(&scene.head),
            head_pose: (RigidTransform::IDENTITY, 0),
            style: DrawStyle::default(),
            shifts: Vec::new(),
        })
    }

    /// Draws `scene`'s groom (the one bound) once at every level and throws the frames away
    /// ([`Renderer::warm_up`]), and once more in this renderer's style when it is not the
    /// default (so set the style first), so that the first frame a benchmark times costs what
    /// the later ones do (a software rasterizer compiles each pipeline at its first draw).
    /// Returns the frames drawn.
    pub fn warm_up(&mut self, scene: &Scene) -> Result<usize> {
        let mut frames = self.renderer.warm_up(&scene.groom)?;
        if self.style != DrawStyle::default() {
            // The style's own pipelines (covered lines, Marschner's shading) at the strand level.
            let mut active = ActiveSkeletons::new();
            active.gather_rest_pose(&scene.groom, hair_core::Level::StrandGroup)?;
            let settings =
                self.style
                    .frame_settings(160, 90, &Camera::default(), ShadingMode::Shaded);
            self.renderer.render(&active.frame(), &settings)?;
            frames += 1;
        }
        Ok(frames)
    }

    /// Draws the frames that follow in `style`.
    pub fn set_style(&mut self, style: DrawStyle) {
        self.style = style;
    }

    /// The style frames are drawn in.
    pub fn style(&self) -> DrawStyle {
        self.style
    }

    /// Uploads the groom and head of another pipeline's scene.
    pub fn bind(&mut self, pipeline: &Pipeline) -> Result<()> {
        self.renderer.upload_groom(&pipeline.scene().groom)?;
        self.renderer
            .set_head_mesh(Some(&pipeline.scene().head.mesh))?;
        self.head_levels = HeadLevels::new(&pipeline.scene().head);
        self.head_pose = (RigidTransform::IDENTITY, 0);
        Ok(())
    }

    /// Gathers the source's skeletons to draw, shifts its strands onto the roots a deforming
    /// body carries, and poses the head mesh where the simulation has it, for a frame drawn
    /// with `settings`.
    fn prepare(&mut self, source: &mut impl DrawnSource, settings: &FrameSettings) -> Result<()> {
        source.gather_drawn(&mut self.active)?;
        source.strand_root_shifts(&self.active, &mut self.shifts);
        self.renderer.set_strand_root_shifts(&self.shifts)?;
        let pose = source.head_poses().first().copied().unwrap_or_default();
        match source.deformed_bodies().into_iter().next().flatten() {
            Some(mesh) => {
                // Deforming: its mesh at this time, uploaded every frame (no tessellations).
                self.renderer.set_head_mesh(Some(&mesh.posed(&pose)))?;
                self.head_pose = (pose, usize::MAX);
                Ok(())
            }
            None => self.pose_head(pose, settings),
        }
    }

    /// Poses the head mesh at `pose`, tessellated as coarsely as [`HEAD_PIXEL_TOLERANCE`]
    /// allows through `settings`' camera (uploaded again only when either changed).
    fn pose_head(&mut self, pose: RigidTransform, settings: &FrameSettings) -> Result<()> {
        let level = self.head_levels.select(
            &settings.camera,
            settings.height,
            &pose,
            HEAD_PIXEL_TOLERANCE,
        );
        if (pose, level) != self.head_pose {
            let mesh = self.head_levels.levels()[level].mesh.posed(&pose);
            self.renderer.set_head_mesh(Some(&mesh))?;
            self.head_pose = (pose, level);
        }
        Ok(())
    }

    /// The wgpu renderer (adapter report, settings).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// Renders the pipeline's current skeletons through `camera` into a `width`×`height` image
    /// (shaded, or colour-coded by level); returns the image and the time it took [s].
    pub fn render(
        &mut self,
        pipeline: &mut impl DrawnSource,
        camera: &Camera,
        width: u32,
        height: u32,
        mode: ShadingMode,
    ) -> Result<(image::RgbaImage, f64)> {
        let settings = self.style.frame_settings(width, height, camera, mode);
        self.render_with_settings(pipeline, &settings)
    }

    /// Renders the pipeline's current skeletons with `settings` as given, not this renderer's
    /// style (a benchmark's variants of one frame: without shadows, other textures, other map
    /// sizes), its strand thinning the pipeline's
    /// ([`PipelineSettings::strand_thinning`](super::PipelineSettings::strand_thinning));
    /// returns the image and the time it took [s].
    pub fn render_with_settings(
        &mut self,
        pipeline: &mut impl DrawnSource,
        settings: &FrameSettings,
    ) -> Result<(image::RgbaImage, f64)> {
        let started = Instant::now();
        self.prepare(pipeline, settings)?;
        let settings = FrameSettings {
            strand_thinning: pipeline.strand_thinning(),
            ..*settings
        };
        let image = self.renderer.render(&self.active.frame(), &settings)?;
        Ok((image, started.elapsed().as_secs_f64()))
    }

    /// Renders the pipeline's frame with `settings` but without its hair: the head at its pose,
    /// the target's clears, resolve and readback, which every frame pays whatever it draws.
    /// Returns the image and the time it took [s].
    pub fn render_without_hair(
        &mut self,
        pipeline: &Pipeline,
        settings: &FrameSettings,
    ) -> Result<(image::RgbaImage, f64)> {
        let started = Instant::now();
        self.pose_head(pipeline.head_pose(), settings)?;
        self.active.clear();
        for _ in 0..pipeline.scene().groom.skeletons.chain_count() {
            self.active.push_inactive_chain();
        }
        let image = self.renderer.render(&self.active.frame(), settings)?;
        Ok((image, started.elapsed().as_secs_f64()))
    }

    /// Renders the pipeline's current skeletons through `camera` into `destination` (a window's
    /// texture, see [`Renderer::render_to_texture`]) instead of an image; returns the time it
    /// took to record and submit [s] (the GPU's work is not waited for).
    pub fn render_to_texture(
        &mut self,
        pipeline: &mut impl DrawnSource,
        camera: &Camera,
        mode: ShadingMode,
        destination: &hair_render::wgpu::Texture,
    ) -> Result<f64> {
        let started = Instant::now();
        let mut settings =
            self.style
                .frame_settings(destination.width(), destination.height(), camera, mode);
        settings.strand_thinning = pipeline.strand_thinning();
        self.prepare(pipeline, &settings)?;
        self.renderer
            .render_to_texture(&self.active.frame(), &settings, destination)?;
        Ok(started.elapsed().as_secs_f64())
    }

    /// Renders shaded and colour-coded side by side (`2·width`×`height`); returns the image and
    /// the time it took [s].
    pub fn render_side_by_side(
        &mut self,
        pipeline: &mut impl DrawnSource,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<(image::RgbaImage, f64)> {
        let started = Instant::now();
        let mut settings = self
            .style
            .frame_settings(width, height, camera, ShadingMode::Shaded);
        settings.strand_thinning = pipeline.strand_thinning();
        self.prepare(pipeline, &settings)?;
        let image = self
            .renderer
            .render_side_by_side(&self.active.frame(), &settings)?;
        Ok((image, started.elapsed().as_secs_f64()))
    }
}
