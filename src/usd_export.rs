//! A run's strands as one USD file ([`HairUsd`], `hair.usda`): the strands of every frame as
//! time samples of one `BasisCurves` prim and, where the head deforms, the body beside them as a
//! `Mesh` prim at its own samples, both in the world [m, +Y up] on one time line, so that a USD
//! viewer plays the hair on its body.
//!
//! The time line is the body file's: frame 0 is the body's first sample (see
//! [`Shot::build_scene`](crate::Shot)), and frame `k` is at time code `(t₀ + k/fps)·T`, where
//! `t₀` [s] is the file time of the body's first sample and `T` the file's
//! `timeCodesPerSecond` (the scene's frame rate for a body timed in seconds: Alembic, the
//! procedural head's animation). Without a deforming body, frame `k` is at code `k` and `T` is
//! the frame rate.

use std::io;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use hair_core::dynamics::HeadMotion;
use hair_core::{Curves, MeshSequence, Scene, SequenceClock};
use hair_formats::{UsdCurvesWriter, UsdMeshTrack};

/// Collects a run's frames of strands and writes them, with the deforming body, as USD text.
#[derive(Debug, Clone)]
pub struct HairUsd {
    writer: Option<UsdCurvesWriter>,
    fps: f64,
    clock: SequenceClock,
    body: Option<(Arc<MeshSequence>, HeadMotion)>,
    frames: Option<Range<usize>>,
}

impl HairUsd {
    /// An export of a run of `scene` at `fps` frames per second (> 0) whose head moves by
    /// `head`: the body is written beside the strands where the scene's head deforms.
    pub fn new(scene: &Scene, head: &HeadMotion, fps: f32) -> Self {
        let fps = f64::from(fps);
        let clock = match &scene.body_motion {
            Some(motion) => motion.clock(),
            None => SequenceClock {
                time_codes_per_second: None,
                source_time_at_zero: -1.0 / fps,
            },
        };
        Self {
            writer: None,
            fps,
            clock,
            body: scene
                .body_motion
                .as_ref()
                .map(|motion| (motion.clone(), head.clone())),
            frames: None,
        }
    }

    /// The file's time codes per second: the body file's, else the frame rate.
    pub fn time_codes_per_second(&self) -> f64 {
        self.clock.time_codes_per_second.unwrap_or(self.fps)
    }

    /// The time code of frame `frame` (the state one step after frame `frame − 1`, at run time
    /// `(frame + 1)/fps`).
    pub fn time_code(&self, frame: usize) -> f64 {
        self.clock
            .time_code((frame as f64 + 1.0) / self.fps, self.fps)
    }

    /// Adds frame `frame`'s strands [m, world] (the same curves every frame; frames in
    /// increasing order). Errors (`InvalidInput`) name a frame out of order or curves that
    /// differ from the first frame's.
    pub fn push_frame(&mut self, frame: usize, curves: &Curves) -> io::Result<()> {
        let code = self.time_code(frame);
        match &mut self.writer {
            Some(writer) => writer.push_frame_at(code, &curves.points)?,
            None => {
                let mut writer = UsdCurvesWriter::new(
                    &curves.offsets,
                    curves.widths.as_deref(),
                    curves.colors.as_deref(),
                )?
                .with_time_codes_per_second(self.time_codes_per_second())?;
                writer.push_frame_at(code, &curves.points)?;
                self.writer = Some(writer);
            }
        }
        self.frames = Some(match &self.frames {
            Some(frames) => frames.start..frame + 1,
            None => frame..frame + 1,
        });
        Ok(())
    }

    /// Whether the body is written beside the strands (the head deforms).
    pub fn has_body(&self) -> bool {
        self.body.is_some()
    }

    /// Frames added so far.
    pub fn frame_count(&self) -> usize {
        self.writer.as_ref().map_or(0, UsdCurvesWriter::frame_count)
    }

    /// The body's samples written beside the strands: those inside the frames' time codes and
    /// the one on each side, placed in the world by the head's motion; `None` for a rigid head.
    pub fn body_track(&self) -> Option<UsdMeshTrack> {
        let (sequence, head) = self.body.as_ref()?;
        let frames = self.frames.clone()?;
        let (first, last) = (self.time_code(frames.start), self.time_code(frames.end - 1));
        let rate = self.fps;
        let codes: Vec<f64> = sequence
            .times()
            .iter()
            .map(|&time| self.clock.time_code(time, rate))
            .collect();
        let start = codes.iter().rposition(|&c| c <= first).unwrap_or(0);
        let end = codes
            .iter()
            .position(|&c| c >= last)
            .unwrap_or(codes.len() - 1);
        let samples = (start..=end)
            .map(|sample| {
                let pose = head.transform_at(sequence.times()[sample]);
                let points = sequence
                    .sample_positions(sample)
                    .iter()
                    .map(|&p| pose.transform_point(p))
                    .collect();
                (codes[sample], points)
            })
            .collect();
        Some(UsdMeshTrack {
            name: "body".to_owned(),
            triangles: sequence.triangles().to_vec(),
            samples,
        })
    }

    /// Writes the file at `path` whole, atomically, with the body beside the strands where the
    /// head deforms. No frame is an `InvalidInput` error naming the path.
    pub fn write(&mut self, path: &Path) -> io::Result<()> {
        let track = self.body_track();
        let Some(writer) = &mut self.writer else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("writing {}: no frame of strands to write", path.display()),
            ));
        };
        writer.set_mesh(track)?;
        writer.write(path)
    }
}
