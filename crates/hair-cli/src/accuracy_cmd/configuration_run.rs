//! One configuration's run in `hairlod accuracy`: its frame loop, stepped frame by frame beside
//! the others', and each frame compared with the reference's.

use hairlod::Level;
use hairlod::Pipeline;
use hairlod::Scene;
use hairlod::accuracy::{
    PhysicalError, geometric_error_of_visible, head_body, head_sight, image_error, pose_head_body,
    sample_skeletons, strand_skeletons, visible_samples,
};
use hairlod::collide::{CollisionBody, LineOfSight};
use hairlod::pipeline::{LodMode, PipelineError, PipelineRenderer, PipelineSettings};
use hairlod::run::{FrameLoop, RunOptions, View};
use hairlod::shot::Shot;

use super::Configuration;
use super::sweep::{FrameErrors, Group, Point};

/// Samples per strand-group skeleton for the geometric error.
const SAMPLES_PER_SKELETON: usize = 8;

/// What the reference leaves per frame for the others to be compared with.
pub(super) struct ReferenceFrame {
    image: image::RgbaImage,
    samples: Vec<glam::Vec3>,
    /// Which samples the viewer sees past the head.
    visible: Vec<bool>,
}

/// One configuration's run in the sweep: its frame loop (until the shot ends or its integrator
/// fails), the head body its physical errors are measured against and its frames' errors.
pub(super) struct ConfigurationRun<'s> {
    pub(super) label: String,
    group: Group,
    frame_loop: Option<FrameLoop<'s>>,
    body: CollisionBody,
    /// The reference's line of sight (the others are compared where the reference's samples
    /// are seen); `None` for the others.
    sight: Option<LineOfSight>,
    frames: Vec<FrameErrors>,
    failed: Option<String>,
}

impl<'s> ConfigurationRun<'s> {
    /// Builds the configuration's pipeline on `scene` (bound to `renderer`) and the head body
    /// (and, for the reference, the line of sight) once.
    pub(super) fn start(
        configuration: Configuration,
        shot: &'s Shot,
        scene: &Scene,
        renderer: &mut PipelineRenderer,
    ) -> Result<Self, PipelineError> {
        let probe = Pipeline::new(
            scene.clone(),
            shot.environment.clone(),
            PipelineSettings {
                lod: LodMode::Fixed(Level::Patch),
                ..configuration.settings
            },
        )?;
        let body = head_body(&probe)?;
        let sight = if configuration.group == Group::Reference {
            Some(head_sight(&probe)?)
        } else {
            None
        };
        drop(probe);
        let frame_loop = FrameLoop::start(
            shot,
            scene,
            RunOptions::whole(shot, configuration.settings),
            Some(renderer),
        )?;
        Ok(ConfigurationRun {
            label: configuration.label,
            group: configuration.group,
            frame_loop: Some(frame_loop),
            body,
            sight,
            frames: Vec::with_capacity(shot.frames),
            failed: None,
        })
    }

    /// Makes the run's next frame and compares it with the reference's (the reference's own
    /// frame fills `reference`). An unstable step ends a run other than the reference's, which
    /// is then reported as failed; any other error stops the sweep.
    pub(super) fn step(
        &mut self,
        renderer: &mut PipelineRenderer,
        reference: &mut Vec<ReferenceFrame>,
        (width, height): (u32, u32),
    ) -> Result<(), PipelineError> {
        let Some(frame_loop) = self.frame_loop.as_mut() else {
            return Ok(());
        };
        let output = match frame_loop.step(Some((renderer, &[View::Shaded]))) {
            Ok(Some(output)) => output,
            Ok(None) => return Ok(()),
            Err(error) if self.sight.is_none() && error.is_unstable() => {
                self.failed = Some(error.to_string());
                self.frame_loop = None;
                return Ok(());
            }
            Err(error) => return Err(error),
        };
        let (pipeline, camera, frame) = (output.pipeline, output.camera, output.report.frame);
        let image = &output.images[0];
        let cost = output.report.times.total();
        let samples = sample_skeletons(
            &pipeline.scene().groom,
            &strand_skeletons(pipeline)?,
            SAMPLES_PER_SKELETON,
        );
        pose_head_body(&mut self.body, pipeline)?;
        let physical = PhysicalError::of(pipeline, &self.body);
        if let Some(sight) = self.sight.as_mut() {
            // Against itself: SSIM 1, infinite PSNR, and the geometric error of its own samples.
            let head = pipeline.environment().head.transform_at(pipeline.time());
            sight.set_pose(head.rotation, head.translation)?;
            let visible = visible_samples(camera, sight, &samples);
            let geometric =
                geometric_error_of_visible(camera, width, height, &samples, &samples, &visible);
            self.frames.push(FrameErrors {
                cost,
                ssim: 1.0,
                psnr: f64::INFINITY,
                geometric,
                physical,
            });
            reference.push(ReferenceFrame {
                image: image.clone(),
                samples,
                visible,
            });
        } else {
            let reference = reference
                .get(frame)
                .ok_or_else(|| PipelineError::NoReferenceFrame { frame })?;
            let errors = image_error(&reference.image, image);
            self.frames.push(FrameErrors {
                cost,
                ssim: errors.ssim,
                psnr: errors.psnr,
                geometric: geometric_error_of_visible(
                    camera,
                    width,
                    height,
                    &reference.samples,
                    &samples,
                    &reference.visible,
                ),
                physical,
            });
        }
        Ok(())
    }

    /// The run's point: its frames summarised, or its failure.
    pub(super) fn point(self) -> Point {
        match self.failed {
            Some(reason) => Point::failed(self.label, self.group, reason),
            None => Point::new(self.label, self.group, self.frames),
        }
    }
}
