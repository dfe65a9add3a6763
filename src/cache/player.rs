//! [`CachedRun`]: a run played back from a simulation cache through the one frame loop: each
//! frame's "advance" reads its record instead of simulating, and the renderer draws the record.

use std::marker::PhantomData;
use std::time::Instant;

use hair_core::lod::CostModel;
use hair_core::{Camera, RigidTransform};
use hair_render::{ActiveSkeletons, StrandThinning};

use super::bodies::CachedBodies;
use super::{FrameRecord, SimulationCache};
use crate::pipeline::{
    CharacterModel, DrawnSource, FrameReport, PipelineError, PipelineSettings, Result, RunMode,
};
use crate::run::{FrameRenderer, Runnable, View, render_view_of};

/// A run read back from a [`SimulationCache`], frame after frame from `first_frame`, drawn by a
/// renderer of kind `R` ([`PipelineRenderer`](crate::pipeline::PipelineRenderer) for a lone
/// character, [`CrowdRenderer`](crate::crowd::CrowdRenderer) for a crowd) bound to the same
/// scene the cache was simulated from. It chooses nothing: the levels, blends and poses are the
/// simulation's, so a pixel tolerance or frame budget has nothing to steer. A deforming head is
/// drawn deformed at each record's time, its strands on the roots its body carries.
pub struct CachedRun<R> {
    cache: SimulationCache,
    settings: PipelineSettings,
    bodies: CachedBodies,
    next_frame: usize,
    record: Option<FrameRecord>,
    read_seconds: f64,
    renderer: PhantomData<fn(&mut R)>,
}

impl<R> CachedRun<R> {
    /// A run of `cache`'s records from `first_frame` on, drawn with `settings`' strand thinning
    /// (the settings the cache was simulated with: its fingerprint holds them), for
    /// `characters`, the models it was simulated from in the shot's order (their deforming
    /// bodies are sampled at each record's time). Errors: a deforming body whose roots cannot
    /// be attached to its rest mesh.
    pub fn new(
        cache: SimulationCache,
        characters: &[CharacterModel],
        settings: PipelineSettings,
        first_frame: usize,
    ) -> Result<Self> {
        Ok(CachedRun {
            cache,
            settings,
            bodies: CachedBodies::of(characters)?,
            next_frame: first_frame,
            record: None,
            read_seconds: 0.0,
            renderer: PhantomData,
        })
    }

    /// The cache's directory.
    pub fn cache_dir(&self) -> &std::path::Path {
        self.cache.dir()
    }

    /// The record of the frame last advanced to.
    pub fn record(&self) -> Option<&FrameRecord> {
        self.record.as_ref()
    }

    /// Time spent reading and checking records so far [s].
    pub fn read_seconds(&self) -> f64 {
        self.read_seconds
    }

    fn current(&self) -> Result<&FrameRecord> {
        self.record.as_ref().ok_or_else(|| PipelineError::Cache {
            path: self.cache.dir().to_path_buf(),
            frame: None,
            why: "no frame read yet: advance before drawing".into(),
        })
    }
}

impl<R> DrawnSource for CachedRun<R> {
    fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        active.clone_from(&self.current()?.drawn);
        Ok(())
    }

    fn head_poses(&self) -> Vec<RigidTransform> {
        self.record
            .as_ref()
            .map(|r| r.head_poses.clone())
            .unwrap_or_default()
    }

    fn strand_thinning(&self) -> StrandThinning {
        self.settings.strand_thinning()
    }

    fn deformed_bodies(&self) -> Vec<Option<hair_core::TriangleMesh>> {
        self.record
            .as_ref()
            .map(|r| self.bodies.meshes(r.report.time))
            .unwrap_or_default()
    }

    fn strand_root_shifts(&self, active: &ActiveSkeletons, shifts: &mut Vec<glam::Vec3>) {
        match &self.record {
            Some(r) => self
                .bodies
                .strand_root_shifts(&r.head_poses, r.report.time, active, shifts),
            None => shifts.clear(),
        }
    }
}

impl<R: FrameRenderer> Runnable for CachedRun<R> {
    type Renderer = R;

    fn pixel_tolerance(&self) -> Option<f32> {
        None
    }

    fn set_pixel_tolerance(&mut self, _pixel_tolerance: f32) -> Result<()> {
        Ok(())
    }

    fn set_frame_budget(&mut self, _budget: Option<(f64, CostModel)>) -> Result<()> {
        Ok(())
    }

    /// Reads the next frame's record (the camera played no part: the simulation chose the
    /// levels); returns the simulation's report of it.
    fn advance(&mut self, _camera: &Camera) -> Result<FrameReport> {
        let started = Instant::now();
        let record = self.cache.read(self.next_frame)?;
        self.read_seconds += started.elapsed().as_secs_f64();
        self.next_frame += 1;
        let report = record.report;
        self.record = Some(record);
        Ok(report)
    }

    fn observe_frame(&mut self, _report: &FrameReport) {}

    fn render_view(
        &mut self,
        renderer: &mut R,
        camera: &Camera,
        size: (u32, u32),
        view: View,
    ) -> Result<(image::RgbaImage, f64)> {
        render_view_of(renderer, self, camera, size, view)
    }

    fn drawn_by(renderer: &R) -> hair_render::DrawnCounts {
        renderer.last_drawn()
    }

    fn run_mode(&self) -> RunMode {
        self.settings.lod.run_mode()
    }
}
