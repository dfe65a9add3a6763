//! [`Shot`]: a whole run resolved from a scene file (or built in code): the model to build (groom
//! and head parameters), the control inputs (head motion, wind, the camera path), the pipeline
//! settings, the frames and the outputs. Cheap to hold and clone; [`Shot::build_scene`] builds the
//! groom (or reads it and its body from files).

use std::f32::consts::TAU;

use glam::Vec3;
use hair_core::dynamics::{Environment, SimulationSettings};
use hair_core::fit::bind_profiles;
use hair_core::lod::{BudgetSettings, LodSettings};
use hair_core::{Camera, GroomParams, HairError, HeadParams, Scene};
use serde::Serialize;

use crate::loaded::{BodyFile, GroomFile, LoadedScene, load_scene};
use crate::pipeline::{Checkpoint, LodMode, Pipeline, PipelineSettings, Result};
use crate::rest_pose::{HangSettings, RestPose, hang_groom};

/// How the camera moves over a shot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum CameraMotion {
    /// Once around the target over the shot, at `distance`.
    Orbit,
    /// From `distance` to `end_distance`, geometrically (the paper's zoom-out).
    ZoomOut,
    /// Still at `distance`, `azimuth`, `elevation`.
    Fixed,
    /// Positions and targets at times, interpolated linearly (held before the first and after
    /// the last).
    Keyframes(Vec<CameraKeyframe>),
}

/// One camera keyframe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CameraKeyframe {
    /// Time [s] from the shot's start.
    pub time: f64,
    /// Camera position [m].
    pub position: Vec3,
    /// The point looked at [m].
    pub target: Vec3,
}

/// How a camera path is framed on the scene once it is built
/// ([`Shot::frame_scene`](crate::framing)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FrameAll {
    /// The zoom-out's last distance as the scene gives it [m]; `None`: 4 × the framed
    /// distance.
    pub end_distance: Option<f32>,
}

/// The camera path of a shot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CameraPath {
    /// How it moves.
    pub motion: CameraMotion,
    /// The point looked at [m] (world space).
    pub target: Vec3,
    /// Distance from the target [m] (zoom-out: at the first frame).
    pub distance: f32,
    /// Distance at the last frame of a zoom-out [m].
    pub end_distance: f32,
    /// Azimuth [rad] (0: in front of the face, +Z).
    pub azimuth: f32,
    /// Elevation above the horizontal [rad].
    pub elevation: f32,
    /// Vertical field of view [rad].
    pub fov: f32,
    /// Frame the scene once it is built ([`Shot::frame_scene`]): `target` and `distance` are
    /// then placeholders. Set where a scene reads a groom file and names no camera target,
    /// distance or keyframes.
    pub frame_all: Option<FrameAll>,
}

impl CameraPath {
    /// The camera at frame `frame` of `frames`, at time `time` [s] from the start.
    pub fn camera(&self, frame: usize, frames: usize, time: f64) -> Camera {
        let t = if frames > 1 {
            frame as f32 / (frames - 1) as f32
        } else {
            0.0
        };
        let orbit = |azimuth: f32, distance: f32| {
            Camera::orbit(self.target, distance, azimuth, self.elevation, self.fov)
        };
        match &self.motion {
            CameraMotion::Orbit => orbit(
                self.azimuth + TAU * frame as f32 / frames.max(1) as f32,
                self.distance,
            ),
            CameraMotion::ZoomOut => orbit(
                self.azimuth,
                self.distance * (self.end_distance / self.distance).powf(t),
            ),
            CameraMotion::Fixed => orbit(self.azimuth, self.distance),
            CameraMotion::Keyframes(keys) => {
                let (position, target) = interpolate_keys(keys, time);
                Camera::looking_at(position, target, self.fov)
            }
        }
    }
}

/// Position and target at `time` [s] between keyframes sorted by time (at least one).
fn interpolate_keys(keys: &[CameraKeyframe], time: f64) -> (Vec3, Vec3) {
    let first = keys[0];
    if time <= first.time || keys.len() == 1 {
        return (first.position, first.target);
    }
    for pair in keys.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if time <= b.time {
            let span = b.time - a.time;
            let s = if span > 0.0 {
                ((time - a.time) / span) as f32
            } else {
                1.0
            };
            return (a.position.lerp(b.position, s), a.target.lerp(b.target, s));
        }
    }
    let last = keys[keys.len() - 1];
    (last.position, last.target)
}

/// What a shot writes besides its report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Outputs {
    /// Shaded frames.
    pub shaded: bool,
    /// Frames colour-coded by level (strands yellow, clusters red, patches blue).
    pub color_coded: bool,
    /// Shaded | colour-coded pairs, twice as wide.
    pub side_by_side: bool,
    /// A contact sheet of every frame, scaled down.
    pub contact_sheet: bool,
    /// Every strand of every frame as a cyHair `.hair` file ([`Pipeline::strand_curves`]).
    pub hair: bool,
    /// Every strand of the run as one USD BasisCurves prim with a time sample per frame.
    pub usd: bool,
    /// Which strands the USD file holds: all, or the groom's guides.
    pub usd_strands: crate::usd_export::UsdStrands,
    /// The hair's reflectance model, with its default parameters
    /// ([`DrawStyle::hair_shading`](crate::pipeline::DrawStyle::hair_shading)).
    pub shading: hair_render::ShadingModel,
    /// How much of a pixel a strand line covers
    /// ([`DrawStyle::line_coverage`](crate::pipeline::DrawStyle::line_coverage)).
    pub line_coverage: hair_render::LineCoverage,
    /// How cluster tubes are drawn
    /// ([`DrawStyle::cluster_geometry`](crate::pipeline::DrawStyle::cluster_geometry)).
    pub cluster_geometry: hair_render::ClusterGeometry,
}

impl Outputs {
    /// The draw style the frames are written in: the shading, line coverage and cluster
    /// geometry asked for, lines shaded at their curve points.
    pub fn style(&self) -> crate::pipeline::DrawStyle {
        crate::pipeline::DrawStyle {
            hair_shading: self.shading.into(),
            line_coverage: self.line_coverage,
            cluster_geometry: self.cluster_geometry,
            ..crate::pipeline::DrawStyle::default()
        }
    }
}

/// One character of a crowd: its groom, where its head stands and how it moves, and the wind
/// around it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Character {
    /// A name for reports (`character 3` when none is given).
    pub name: String,
    /// Groom parameters (a preset with overrides).
    pub groom: GroomParams,
    /// Where the head stands: world from head space (the head's centre at its translation [m]).
    pub placement: hair_core::RigidTransform,
    /// The head's motion (already placed in the world, [`HeadMotion::placed`]), the wind and
    /// gravity.
    ///
    /// [`HeadMotion::placed`]: hair_core::dynamics::HeadMotion::placed
    #[serde(skip)]
    pub environment: Environment,
}

/// A whole run: what to build, how it is driven and seen, and what comes out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shot {
    /// Groom parameters (a preset with overrides).
    pub groom: GroomParams,
    /// The procedural head's parameters.
    pub head: HeadParams,
    /// A groom read from a file and fitted, in place of the generated one (`groom` then gives
    /// its material: the style's stiffness).
    pub groom_file: Option<GroomFile>,
    /// A body mesh read from a file, in place of the procedural head (only with `groom_file`).
    pub body_file: Option<BodyFile>,
    /// Head motion, wind and gravity.
    #[serde(skip)]
    pub environment: Environment,
    /// Level selection, integrator, time step and substeps, collision.
    #[serde(skip)]
    pub settings: PipelineSettings,
    /// Frame budget of the automatic levels (`None`: the pixel tolerance holds).
    #[serde(skip)]
    pub budget: Option<BudgetSettings>,
    /// The camera path.
    pub camera: CameraPath,
    /// Frames of the shot.
    pub frames: usize,
    /// Frame rate [Hz] (one pipeline step per frame).
    pub fps: f32,
    /// Image width [pixels].
    pub width: u32,
    /// Image height [pixels].
    pub height: u32,
    /// Seconds of settling at full detail under gravity before frame 0 [s].
    pub settle_seconds: f32,
    /// The shape the groom starts in ([`Shot::build_scene`] hangs it, or not).
    pub rest_pose: RestPose,
    /// What to write.
    pub outputs: Outputs,
    /// The paper's table (1 or 2) whose figures `bench` prints beside its own, if any.
    pub paper_table: Option<u8>,
    /// The characters of a crowd (empty: one character, [`Shot::groom`] on the head driven by
    /// [`Shot::environment`]); see [`Crowd`](crate::crowd::Crowd).
    pub characters: Vec<Character>,
    /// The procedural head's own deformation (`[body] animation`), sampled over the shot when
    /// the scene is built; `None`: the head is rigid.
    pub body_animation: Option<crate::body_animation::BodyAnimation>,
}

impl Shot {
    /// The camera of frame `frame`. A keyframed camera is read at the time the frame shows,
    /// `(frame + 1)/fps` [s]: the state after the frame's step, as the head's motion and a
    /// deforming body are (frame 0 shows one step after the start).
    pub fn camera(&self, frame: usize) -> Camera {
        let time = (frame as f64 + 1.0) / f64::from(self.fps);
        self.camera.camera(frame, self.frames, time)
    }

    /// The LOD settings of automatic mode matched to the image size (the defaults at a fixed
    /// level).
    pub fn lod_settings(&self) -> LodSettings {
        match self.settings.lod {
            LodMode::Auto(lod) => lod,
            LodMode::Fixed(_) => LodSettings {
                image_width: self.width,
                image_height: self.height,
                ..LodSettings::default()
            },
        }
    }

    /// Whether the shot is a crowd (it has characters).
    pub fn is_crowd(&self) -> bool {
        !self.characters.is_empty()
    }

    /// Builds the scene: the procedural head and the groom on it, or the groom and body read
    /// from [`Shot::groom_file`] and [`Shot::body_file`] ([`load_scene`]); then, as
    /// [`Shot::rest_pose`] says, hung on the body under this shot's gravity (with collision as
    /// the shot has it; [`RestPose::Hanging`]), or kept in the file's shape and made an
    /// equilibrium there ([`RestPose::Loaded`]), see [`hang_groom`]. The hair falls into place
    /// with this shot's integrator at that integrator's recommended step
    /// ([`SimulationSettings::recommended`]).
    pub fn build_scene(&self) -> Result<Scene> {
        Ok(self.build_loaded_scene()?.0)
    }

    /// [`Shot::build_scene`] with `groom` (a preset with overrides) on the procedural head
    /// instead of the shot's own groom: a crowd character's.
    pub fn build_scene_with(&self, groom: &GroomParams) -> Result<Scene> {
        let shot = Shot {
            groom: groom.clone(),
            groom_file: None,
            body_file: None,
            characters: Vec::new(),
            ..self.clone()
        };
        shot.build_scene()
    }

    /// [`Shot::build_scene`], with what loading the files measured (`None` for a generated
    /// groom).
    pub fn build_loaded_scene(&self) -> Result<(Scene, Option<LoadedScene>)> {
        let (mut scene, loaded) = match &self.groom_file {
            Some(groom) => {
                // The body's animation is read for the shot's frames only (frame k shows run
                // time (k + 1)/fps, the file's first sample at frame 0).
                let body = self.body_file.clone().map(|body| BodyFile {
                    seconds: Some(self.frames as f64 / f64::from(self.fps)),
                    ..body
                });
                let loaded = load_scene(groom, body.as_ref(), &self.groom)?;
                (loaded.scene.clone(), Some(loaded))
            }
            None => (Scene::new(&self.head, &self.groom)?, None),
        };
        if matches!(self.rest_pose, RestPose::Hanging | RestPose::Loaded) {
            hang_groom(
                &mut scene,
                &HangSettings {
                    collision: self.settings.collision,
                    gravity: self.environment.gravity,
                    fall: self.rest_pose == RestPose::Hanging,
                    // The scene's integrator, at its recommended step: the default one cannot
                    // hold curly skeletons much finer than the presets', so a scene that picks
                    // another for them must hang with it too (docs/dynamics.md, "Where the
                    // default fails").
                    dynamics: SimulationSettings::recommended(self.settings.dynamics.integrator),
                    ..HangSettings::default()
                },
            )?;
            // The strands keep their files' shapes on the new rest skeletons.
            if let Some(loaded) = &loaded {
                bind_profiles(&mut scene.groom, &loaded.fit, &loaded.curves)?;
            }
        }
        if let Some(animation) = &self.body_animation {
            let duration = self.frames as f64 / f64::from(self.fps);
            let sequence = animation.sample(&scene.head.mesh, duration)?;
            scene.set_body_motion(Some(std::sync::Arc::new(sequence)))?;
        }
        // The body's first sample is frame 0: frame k shows the state one step after the
        // frame before, at run time (k + 1)/fps, so the samples move to start there. The
        // sequence's clock keeps the file's time line (what `hair.usda` is written on).
        if let Some(motion) = scene.body_motion.take() {
            let sequence = std::sync::Arc::unwrap_or_clone(motion)
                .retimed(1.0 / f64::from(self.fps))
                .map_err(|error| HairError::invalid("body animation", error, "a valid sequence"))?;
            scene.set_body_motion(Some(std::sync::Arc::new(sequence)))?;
        }
        Ok((scene, loaded))
    }

    /// A pipeline on `scene` (built from this shot) with `settings`, settled for
    /// `settle_seconds`, or going on from `checkpoint`.
    pub fn pipeline(
        &self,
        scene: &Scene,
        settings: PipelineSettings,
        checkpoint: Option<Checkpoint>,
    ) -> Result<Pipeline> {
        match checkpoint {
            Some(checkpoint) => Pipeline::resume(
                scene.clone(),
                self.environment.clone(),
                settings,
                checkpoint,
            ),
            None => {
                let mut pipeline =
                    Pipeline::new(scene.clone(), self.environment.clone(), settings)?;
                pipeline.settle(self.settle_seconds)?;
                Ok(pipeline)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A keyframed camera's clipping planes follow its own look distance, not the orbit fields
    /// (`distance`) it does not use: a crowd's far heads stay in the picture.
    #[test]
    fn keyframed_cameras_see_as_far_as_they_look() {
        let key = |time: f64, z: f32| CameraKeyframe {
            time,
            position: Vec3::new(0.0, 0.5, z),
            target: Vec3::new(0.0, -9.1, -39.1),
        };
        let keys = vec![key(0.0, 0.9), key(0.4, 0.6)];
        let path = CameraPath {
            motion: CameraMotion::Keyframes(keys.clone()),
            target: Vec3::ZERO,
            distance: 0.6,
            end_distance: 0.6,
            azimuth: 0.0,
            elevation: 0.0,
            fov: 35f32.to_radians(),
            frame_all: None,
        };
        for (frame, time) in [(0, 0.0), (1, 0.2), (2, 0.4)] {
            let camera = path.camera(frame, 3, time);
            assert_eq!(
                (camera.position, camera.target),
                interpolate_keys(&keys, time)
            );
            // The farthest head of scenes/crowd.toml (40 m away), the widest (34 m away, 20°
            // to the side) and the nearest (1 m away).
            assert!(camera.sphere_in_frustum(Vec3::new(2.472, 0.0, -38.924), 0.15, 16.0 / 9.0));
            assert!(camera.sphere_in_frustum(Vec3::new(11.927, 0.0, -31.159), 0.15, 16.0 / 9.0));
            assert!(camera.sphere_in_frustum(Vec3::new(0.0, 0.0, 0.0), 0.15, 16.0 / 9.0));
        }
    }

    /// `section_count = 1`, documented as valid, builds (one section has no neighbour to take
    /// its width from), hangs and simulates a frame.
    #[test]
    fn a_single_section_groom_builds_and_runs_a_frame() {
        let shot = crate::SceneFile::parse(
            "[groom]\npreset = \"straight\"\nsection_count = 1\nstrands_per_group = 1\n",
        )
        .unwrap()
        .resolve()
        .unwrap();
        let scene = shot.build_scene().unwrap();
        assert_eq!(scene.groom.section_count(), 1);
        assert!(scene.groom.sections[0].width > 0.05);
        let mut pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
        let report = pipeline.advance(&shot.camera(0)).unwrap();
        assert_eq!(report.sections_at.iter().sum::<usize>(), 1);
    }
}
