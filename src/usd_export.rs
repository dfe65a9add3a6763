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

hair_core::named_enum! {
    /// Which strands `hair.usda` holds.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum UsdStrands {
        /// Every strand drawn, grown children included.
        #[default]
        All = "all",
        /// The guides only: a groom file's own strands, without the children grown around them
        /// ([`Groom::is_guide`](hair_core::Groom::is_guide)), for a DCC tool to grow its own (a
        /// groom of 900 guides with 13 children each writes 900 curves, not 12,600). A groom
        /// without children writes every strand.
        Guides = "guides",
    }
}

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
    /// The strands written (`None`: all), as indices of the run's curves.
    kept: Option<Vec<usize>>,
    /// The curves of the strands kept, reused frame to frame.
    selected: Curves,
    /// The groom's strands.
    groom_strands: usize,
}

impl HairUsd {
    /// An export of a run of `scene` at `fps` frames per second (> 0) whose head moves by
    /// `head`, of every strand: the body is written beside the strands, deforming or rigid.
    pub fn new(scene: &Scene, head: &HeadMotion, fps: f32) -> Self {
        HairUsd::of_strands(scene, head, fps, UsdStrands::All)
    }

    /// [`HairUsd::new`] writing `strands`: all, or the groom's guides.
    pub fn of_strands(scene: &Scene, head: &HeadMotion, fps: f32, strands: UsdStrands) -> Self {
        let groom = &scene.groom;
        let kept = (strands == UsdStrands::Guides && groom.children_per_guide > 0).then(|| {
            (0..groom.strands.strand_count())
                .filter(|&s| groom.is_guide(s))
                .collect()
        });
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
            kept,
            selected: Curves::default(),
            groom_strands: groom.strands.strand_count(),
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

    /// Strands written per frame: every strand of the groom, or its guides.
    pub fn strands_written(&self) -> usize {
        self.kept.as_ref().map_or(self.groom_strands, Vec::len)
    }

    /// Adds frame `frame`'s strands [m, world], every strand of the groom in its order (the
    /// same curves every frame; frames in increasing order); the guides are taken from them
    /// where only those are written. Errors (`InvalidInput`) name a frame out of order, curves
    /// that differ from the first frame's, or fewer curves than the groom's strands.
    pub fn push_frame(&mut self, frame: usize, curves: &Curves) -> io::Result<()> {
        let curves = match &self.kept {
            None => curves,
            Some(kept) => {
                select_curves(curves, kept, &mut self.selected)?;
                &self.selected
            }
        };
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

/// Writes into `out` the curves `kept` of `curves` (indices, increasing), with their widths and
/// colours. A kept index past the curves is an `InvalidInput` error.
fn select_curves(curves: &Curves, kept: &[usize], out: &mut Curves) -> io::Result<()> {
    if let Some(&last) = kept.last()
        && last >= curves.curve_count()
    {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "guide strand {last} of a run with {} curves: the curves are not the groom's",
                curves.curve_count()
            ),
        ));
    }
    out.points.clear();
    out.offsets.clear();
    out.offsets.push(0);
    let mut widths = curves.widths.as_ref().map(|_| Vec::new());
    let mut colors = curves.colors.as_ref().map(|_| Vec::new());
    for &curve in kept {
        let range = curves.range(curve);
        out.points.extend_from_slice(&curves.points[range.clone()]);
        out.offsets.push(out.points.len() as u32);
        if let (Some(out), Some(all)) = (&mut widths, &curves.widths) {
            out.extend_from_slice(&all[range.clone()]);
        }
        if let (Some(out), Some(all)) = (&mut colors, &curves.colors) {
            out.extend_from_slice(&all[range]);
        }
    }
    out.widths = widths;
    out.colors = colors;
    Ok(())
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

    /// Guides only: of a groom whose guides each have 3 children, strands 0, 4, 8, … are
    /// written, each with its own points (curve `k` read back from the file starts at x = 4k);
    /// all strands otherwise; curves that are not the groom's are refused.
    #[test]
    fn guides_only_writes_every_guide_and_no_child() {
        use super::UsdStrands;
        let mut scene = Scene::preset("straight").unwrap();
        scene.groom.children_per_guide = 3;
        let strands = scene.groom.strands.strand_count();
        let guides = strands.div_ceil(4);
        assert_eq!(scene.groom.guide_count(), guides);
        let curves = Curves {
            points: (0..strands)
                .flat_map(|s| [Vec3::X * s as f32, Vec3::new(s as f32, 0.01, 0.0)])
                .collect(),
            offsets: (0..=strands as u32).map(|s| 2 * s).collect(),
            widths: Some(vec![1e-4; 2 * strands]),
            colors: None,
            skipped: Vec::new(),
        };
        let head = HeadMotion::default();
        let mut usd = HairUsd::of_strands(&scene, &head, 24.0, UsdStrands::Guides);
        assert_eq!(usd.strands_written(), guides);
        usd.push_frame(0, &curves).unwrap();
        let path = std::env::temp_dir().join(format!("hairlod-guides-{}.usda", std::process::id()));
        usd.write(&path).unwrap();
        let read = hair_formats::read_usda_file_at(&path, 0.0, &Default::default()).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(read.curve_count(), guides);
        for k in 0..guides {
            assert_eq!(
                read.points[read.range(k).start].x,
                (4 * k) as f32,
                "guide {k}"
            );
        }
        let all = HairUsd::of_strands(&scene, &head, 24.0, UsdStrands::All);
        assert_eq!(all.strands_written(), strands);
        let mut short = HairUsd::of_strands(&scene, &head, 24.0, UsdStrands::Guides);
        let few = Curves {
            points: vec![Vec3::ZERO, Vec3::Y],
            offsets: vec![0, 2],
            ..curves
        };
        let error = short.push_frame(0, &few).unwrap_err().to_string();
        assert!(error.contains("not the groom's"), "{error}");
    }
}
