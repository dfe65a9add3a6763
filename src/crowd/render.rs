//! [`CrowdRenderer`]: every character's groom and head drawn in one pass. The grooms' static
//! data are uploaded once, one after the other (each character's chains numbered after the
//! characters before it); each frame gathers every character's skeletons in that order and
//! draws the heads at their simulated poses, deforming ones deformed, as one mesh
//! ([`CrowdHeads`]).

use std::time::Instant;

use hair_core::{Camera, NO_PROFILE, PROFILE_SAMPLES, RigidTransform, TriangleMesh};
use hair_render::{
    ActiveSkeletons, GroomGeometry, Renderer, RendererOptions, ShadingMode, StrandThinning,
};

use super::frame::Crowd;
use super::heads::CrowdHeads;
use super::model::CrowdModel;
use crate::pipeline::{DrawStyle, DrawnSource, Result};
use crate::run::{FrameRenderer, Runnable, View, render_view_of};

/// A renderer bound to a crowd's grooms and heads.
pub struct CrowdRenderer {
    renderer: Renderer,
    active: ActiveSkeletons,
    /// The characters' heads and what was last uploaded of them.
    heads: CrowdHeads,
    /// Line shading, hair shading, line coverage.
    style: DrawStyle,
    /// This frame's strand root shifts (scratch).
    shifts: Vec<glam::Vec3>,
}

impl CrowdRenderer {
    /// A renderer from `options` with every character of `model` uploaded.
    pub fn new(options: &RendererOptions, model: &CrowdModel) -> Result<Self> {
        let renderer = Renderer::new(options)?;
        let mut crowd_renderer = CrowdRenderer {
            renderer,
            active: ActiveSkeletons::new(),
            heads: CrowdHeads::default(),
            style: DrawStyle::default(),
            shifts: Vec::new(),
        };
        crowd_renderer.bind(model)?;
        Ok(crowd_renderer)
    }

    /// Draws the frames that follow in `style`.
    pub fn set_style(&mut self, style: DrawStyle) {
        self.style = style;
    }

    /// Uploads the grooms of `model`'s characters, one after the other, and keeps their heads.
    pub fn bind(&mut self, model: &CrowdModel) -> Result<()> {
        let geometry = concatenated_geometry(model);
        self.renderer
            .upload_strands_with_shapes(&geometry.strands(), &geometry.strand_shapes())?;
        self.renderer.upload_clusters(&geometry.clusters())?;
        self.renderer.upload_patches(&geometry.patches())?;
        self.heads = CrowdHeads::new(model);
        Ok(())
    }

    /// The wgpu renderer (adapter report, settings).
    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    /// Gathers every character's skeletons, shifts the strands of deforming heads onto the
    /// roots their bodies carry, and poses the heads where the simulation has them,
    /// a rigid one tessellated as coarsely as
    /// [`HEAD_PIXEL_TOLERANCE`](crate::head_levels::HEAD_PIXEL_TOLERANCE) allows from `camera`
    /// in an image `height` pixels tall, a deforming one as its body at the time drawn.
    fn prepare(
        &mut self,
        crowd: &mut impl DrawnSource,
        camera: &Camera,
        height: u32,
    ) -> Result<()> {
        crowd.gather_drawn(&mut self.active)?;
        crowd.strand_root_shifts(&self.active, &mut self.shifts);
        self.renderer.set_strand_root_shifts(&self.shifts)?;
        let poses = crowd.head_poses();
        let deformed = crowd.deformed_bodies();
        if let Some(mesh) = self.heads.mesh_to_draw(&poses, &deformed, camera, height) {
            self.renderer.set_head_mesh(Some(&mesh))?;
        }
        Ok(())
    }

    /// Renders the crowd through `camera` into a `width`×`height` image (shaded or colour-coded
    /// by level); returns the image and the time it took [s].
    pub fn render(
        &mut self,
        crowd: &mut impl DrawnSource,
        camera: &Camera,
        (width, height): (u32, u32),
        mode: ShadingMode,
    ) -> Result<(image::RgbaImage, f64)> {
        let started = Instant::now();
        self.prepare(crowd, camera, height)?;
        let mut settings = self.style.frame_settings(width, height, camera, mode);
        settings.strand_thinning = crowd.strand_thinning();
        let image = self.renderer.render(&self.active.frame(), &settings)?;
        Ok((image, started.elapsed().as_secs_f64()))
    }

    /// Renders shaded and colour-coded side by side (`2·width`×`height`); returns the image and
    /// the time it took [s].
    pub fn render_side_by_side(
        &mut self,
        crowd: &mut impl DrawnSource,
        camera: &Camera,
        (width, height): (u32, u32),
    ) -> Result<(image::RgbaImage, f64)> {
        let started = Instant::now();
        self.prepare(crowd, camera, height)?;
        let mut settings = self
            .style
            .frame_settings(width, height, camera, ShadingMode::Shaded);
        settings.strand_thinning = crowd.strand_thinning();
        let image = self
            .renderer
            .render_side_by_side(&self.active.frame(), &settings)?;
        Ok((image, started.elapsed().as_secs_f64()))
    }
}

impl FrameRenderer for CrowdRenderer {
    fn render_source(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &Camera,
        size: (u32, u32),
        mode: ShadingMode,
    ) -> Result<(image::RgbaImage, f64)> {
        self.render(source, camera, size, mode)
    }

    fn render_source_side_by_side(
        &mut self,
        source: &mut impl DrawnSource,
        camera: &Camera,
        size: (u32, u32),
    ) -> Result<(image::RgbaImage, f64)> {
        self.render_side_by_side(source, camera, size)
    }

    fn last_drawn(&self) -> hair_render::DrawnCounts {
        self.renderer().last_drawn()
    }
}

impl DrawnSource for Crowd {
    fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        active.clear();
        self.append_drawn(active)
    }

    fn head_poses(&self) -> Vec<RigidTransform> {
        self.world()
            .characters()
            .iter()
            .map(|c| c.head_pose())
            .collect()
    }

    fn strand_thinning(&self) -> StrandThinning {
        self.settings().strand_thinning()
    }

    fn strand_root_shifts(&self, active: &ActiveSkeletons, shifts: &mut Vec<glam::Vec3>) {
        Crowd::strand_root_shifts(self, active, shifts);
    }

    fn deformed_bodies(&self) -> Vec<Option<TriangleMesh>> {
        crate::pipeline::body_meshes(self.world().characters().iter().map(|character| {
            (
                character.model().scene.body_motion.as_ref(),
                character.time(),
            )
        }))
    }
}

impl Runnable for Crowd {
    type Renderer = CrowdRenderer;

    fn pixel_tolerance(&self) -> Option<f32> {
        Crowd::pixel_tolerance(self)
    }

    fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        Crowd::set_pixel_tolerance(self, pixel_tolerance)
    }

    fn set_frame_budget(&mut self, budget: Option<(f64, hair_core::lod::CostModel)>) -> Result<()> {
        Crowd::set_frame_budget(self, budget)
    }

    fn advance(&mut self, camera: &Camera) -> Result<crate::pipeline::FrameReport> {
        Crowd::advance(self, camera)
    }

    fn observe_frame(&mut self, report: &crate::pipeline::FrameReport) {
        Crowd::observe_frame(self, report);
    }

    fn render_view(
        &mut self,
        renderer: &mut CrowdRenderer,
        camera: &Camera,
        size: (u32, u32),
        view: View,
    ) -> Result<(image::RgbaImage, f64)> {
        render_view_of(renderer, self, camera, size, view)
    }

    fn drawn_by(renderer: &CrowdRenderer) -> hair_render::DrawnCounts {
        renderer.last_drawn()
    }

    fn run_mode(&self) -> crate::pipeline::RunMode {
        self.settings().lod.run_mode()
    }
}

/// Every character's strands, clusters and patches, one groom after the other, with chain
/// numbers offset by the chains of the grooms before.
pub fn concatenated_geometry(model: &CrowdModel) -> GroomGeometry {
    let mut all = GroomGeometry::default();
    let mut chains = 0u32;
    for member in &model.members {
        let groom = &member.scene.groom;
        let one = GroomGeometry::new(groom);
        let shift = |c: &u32| c + chains;
        let strands = one.strand_chain.len();
        all.strand_chain.extend(one.strand_chain.iter().map(shift));
        all.strand_root_offsets.extend(&one.strand_root_offsets);
        all.strand_shades.extend(&one.strand_shades);
        // Lengths and tip scales are all-or-nothing per upload: fill the defaults (1) where a
        // groom has none.
        let pad = |values: &mut Vec<f32>, own: &[f32], before: usize| {
            if own.is_empty() && values.is_empty() {
                return;
            }
            values.resize(before, 1.0);
            if own.is_empty() {
                values.resize(before + strands, 1.0);
            } else {
                values.extend_from_slice(own);
            }
        };
        let before = all.strand_chain.len() - strands;
        pad(&mut all.strand_lengths, &one.strand_lengths, before);
        pad(&mut all.strand_tip_scales, &one.strand_tip_scales, before);
        // Profiles likewise (none where a groom has none), their indices past the ones before.
        if !(one.strand_profiles.is_empty() && all.strand_profiles.is_empty()) {
            let base = (all.profiles.len() / PROFILE_SAMPLES) as u32;
            all.strand_profiles.resize(before, NO_PROFILE);
            if one.strand_profiles.is_empty() {
                all.strand_profiles.resize(before + strands, NO_PROFILE);
            } else {
                all.strand_profiles.extend(
                    one.strand_profiles
                        .iter()
                        .map(|&p| if p == NO_PROFILE { p } else { p + base }),
                );
            }
        }
        all.profiles.extend(&one.profiles);
        all.cluster_chain
            .extend(one.cluster_chain.iter().map(shift));
        all.cluster_root_radii.extend(&one.cluster_root_radii);
        all.cluster_tip_radii.extend(&one.cluster_tip_radii);
        all.patch_chain.extend(one.patch_chain.iter().map(shift));
        all.patch_widths.extend(&one.patch_widths);
        chains += groom.skeletons.chain_count() as u32;
    }
    let strands = all.strand_chain.len();
    for values in [&mut all.strand_lengths, &mut all.strand_tip_scales] {
        if !values.is_empty() {
            values.resize(strands, 1.0);
        }
    }
    all
}
