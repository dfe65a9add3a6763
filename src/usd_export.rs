//! A run's strands as one USD file ([`HairUsd`], `hair.usda`): the strands of every frame as
//! time samples of one `BasisCurves` prim and the body beside them as a `Mesh` prim, both in the
//! world [m, +Y up] on one time line, so that a USD viewer plays the hair on its body. A
//! deforming body is written at its own samples; a rigid head at each frame's pose (one sample
//! when it never moves).
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
use hair_core::{Curves, MeshSequence, Scene, SequenceClock, TriangleMesh};
use hair_formats::{UsdCurvesWriter, UsdMeshTrack};

/// The body written beside the strands (head space, placed in the world by the head's motion).
#[derive(Debug, Clone)]
enum ExportedBody {
    /// A deforming body: its own samples.
    Deforming(Arc<MeshSequence>),
    /// The rigid head's mesh, at each frame's pose.
    Rigid(Arc<TriangleMesh>),
    /// No body (a head without triangles).
    None,
}

/// Collects a run's frames of strands and writes them, with the body, as USD text.
#[derive(Debug, Clone)]
pub struct HairUsd {
    writer: Option<UsdCurvesWriter>,
    fps: f64,
    clock: SequenceClock,
    body: ExportedBody,
    head: HeadMotion,
    frames: Option<Range<usize>>,
}

impl HairUsd {
    /// An export of a run of `scene` at `fps` frames per second (> 0) whose head moves by
    /// `head`: the body is written beside the strands, deforming or rigid.
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
            body: match &scene.body_motion {
                Some(motion) => ExportedBody::Deforming(motion.clone()),
                None if scene.head.mesh.triangles.is_empty() => ExportedBody::None,
                None => ExportedBody::Rigid(Arc::new(scene.head.mesh.clone())),
            },
            head: head.clone(),
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

    /// Whether the body written beside the strands deforms (else it is the rigid head).
    pub fn body_deforms(&self) -> bool {
        matches!(self.body, ExportedBody::Deforming(_))
    }

    /// Frames added so far.
    pub fn frame_count(&self) -> usize {
        self.writer.as_ref().map_or(0, UsdCurvesWriter::frame_count)
    }

    /// The body's samples written beside the strands, placed in the world by the head's
    /// motion: a deforming body's own samples inside the frames' time codes and the one on each
    /// side; a rigid head's mesh at every frame's code and pose (the run time the frame shows,
    /// `(frame + 1)/fps`), or once at the first frame's code when it never moves. `None` before
    /// a frame is added.
    pub fn body_track(&self) -> Option<UsdMeshTrack> {
        let frames = self.frames.clone()?;
        let head = &self.head;
        let sequence = match &self.body {
            ExportedBody::None => return None,
            ExportedBody::Deforming(sequence) => sequence,
            ExportedBody::Rigid(mesh) => {
                let poses: Vec<(f64, hair_core::RigidTransform)> = frames
                    .map(|frame| {
                        let time = (frame as f64 + 1.0) / self.fps;
                        (self.time_code(frame), head.transform_at(time))
                    })
                    .collect();
                let still = poses.windows(2).all(|pair| pair[0].1 == pair[1].1);
                let kept = if still { &poses[..1] } else { &poses[..] };
                let samples = kept
                    .iter()
                    .map(|(code, pose)| {
                        let points = mesh.positions.iter();
                        (*code, points.map(|&p| pose.transform_point(p)).collect())
                    })
                    .collect();
                return Some(UsdMeshTrack {
                    name: "body".to_owned(),
                    triangles: mesh.triangles.clone(),
                    samples,
                });
            }
        };
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

    /// Writes the file at `path` whole, atomically, with the body beside the strands. No frame
    /// is an `InvalidInput` error naming the path.
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

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use hair_core::dynamics::HeadMotion;
    use hair_core::{Curves, RigidTransform, Scene};

    use super::HairUsd;

    /// Two short curves, the same every frame (the export checks only their layout).
    fn curves() -> Curves {
        Curves {
            points: vec![
                Vec3::ZERO,
                Vec3::Y * 0.01,
                Vec3::X,
                Vec3::X + Vec3::Y * 0.01,
            ],
            offsets: vec![0, 2, 4],
            widths: None,
            colors: None,
            skipped: Vec::new(),
        }
    }

    /// A rigid head is written beside the strands: its mesh at each frame's code `k`, placed by
    /// the head's pose at the time the frame shows, `(k + 1)/fps` (reference: the mesh posed by
    /// `HeadMotion::transform_at`, the same arithmetic: equal to rounding); a head that never
    /// moves once; and the file holds the `Mesh` prim `/body`.
    #[test]
    fn a_rigid_head_is_written_beside_the_strands_at_each_frames_pose() {
        let scene = Scene::preset("straight").unwrap();
        assert!(scene.body_motion.is_none());
        let mesh = &scene.head.mesh;
        let fps = 30.0;
        let nod = HeadMotion::nod(0.3, 2.0);
        let mut usd = HairUsd::new(&scene, &nod, fps);
        assert!(!usd.body_deforms());
        for frame in 0..4 {
            usd.push_frame(frame, &curves()).unwrap();
        }
        let track = usd.body_track().expect("the head");
        assert_eq!(track.triangles, mesh.triangles);
        assert_eq!(track.samples.len(), 4);
        for (frame, (code, points)) in track.samples.iter().enumerate() {
            assert_eq!(*code, frame as f64);
            let pose = nod.transform_at((frame as f64 + 1.0) / f64::from(fps));
            assert_eq!(points.len(), mesh.positions.len());
            for (point, &rest) in points.iter().zip(&mesh.positions) {
                assert!(point.distance(pose.transform_point(rest)) < 1e-6);
            }
        }
        // The nod moved the head between the frames: the samples differ.
        assert_ne!(track.samples[0].1, track.samples[3].1);
        let path = std::env::temp_dir().join(format!("hairlod-rigid-{}.usda", std::process::id()));
        usd.write(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert!(text.contains("def Mesh \"body\""), "no /body prim");
        // A head that never moves: one sample, at the first frame's code.
        let turned = RigidTransform::new(glam::Quat::from_rotation_y(0.4), Vec3::Y * 0.1);
        let mut still = HairUsd::new(&scene, &HeadMotion::Still(turned), fps);
        for frame in 2..5 {
            still.push_frame(frame, &curves()).unwrap();
        }
        let track = still.body_track().unwrap();
        assert_eq!(track.samples.len(), 1);
        assert_eq!(track.samples[0].0, 2.0);
        assert!(track.samples[0].1[0].distance(turned.transform_point(mesh.positions[0])) < 1e-6);
    }
}
