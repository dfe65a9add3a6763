//! From a [`SceneFile`] to a [`Shot`]: defaults filled in, every value checked against its range
//! (errors name the field path and the range).

use glam::{EulerRot, Quat};
use hair_core::dynamics::{
    AdaptiveSubsteps, Environment, HeadKeyframe, HeadMotion, IntegratorKind, SimulationSettings,
    WindField, XPBD_MAX_COURANT,
};
use hair_core::lod::{BudgetSettings, LodSettings};
use hair_core::{GroomParams, GroomPreset, HeadParams, RigidTransform};

use super::checks::{count, parse_size, positive, vector, within};
use super::choices::{CameraPathKind, MotionKind};
use super::{SCENE_FILE_VERSION, SceneFile, SceneFileError};
use crate::body_animation::{BodyAnimation, BodyAnimationKind};
use crate::pipeline::{LodMode, PipelineSettings};
use crate::rest_pose::RestPose;
use crate::shot::{CameraKeyframe, CameraMotion, CameraPath, FrameAll, Outputs, Shot};

type Result<T> = std::result::Result<T, SceneFileError>;

/// The preset whose material (stiffness) a groom file gets when `groom.preset` is not given.
pub const DEFAULT_FILE_MATERIAL: GroomPreset = GroomPreset::Straight;

impl SceneFile {
    /// The shot this file describes, defaults filled in; errors name the field path and the
    /// allowed range.
    pub fn resolve(&self) -> Result<Shot> {
        if let Some(version) = self.version
            && version != SCENE_FILE_VERSION
        {
            return Err(SceneFileError::new(format!(
                "version = {version}: this hairlod reads scene files of version \
                 {SCENE_FILE_VERSION}"
            )));
        }
        let groom_file = self.groom_file()?;
        let camera = self.camera_path(groom_file.is_some())?;
        let body_file = self.body_file(groom_file.is_some())?;
        let body_animation = self.body_animation(body_file.is_some())?;
        let groom = self.groom_params(groom_file.is_some())?;
        let frames = &self.frames;
        let frame_count = count("frames.count", frames.count.unwrap_or(12), 1, 1_000_000)?;
        let fps = within(
            "frames.fps",
            frames.fps.unwrap_or(60.0),
            1.0,
            10_000.0,
            "a rate in 1..=10000 Hz",
        )?;
        let (width, height) =
            parse_size("frames.size", frames.size.as_deref().unwrap_or("1280x720"))?;
        let environment = Environment {
            head: self.head_motion()?,
            wind: self.wind_field()?,
            ..Environment::default()
        };
        let settings = PipelineSettings {
            lod: self.lod_mode(width, height)?,
            drawn_as: self.lod.drawn_as.unwrap_or_default(),
            dynamics: self.dynamics_settings(fps)?,
            collision: self.dynamics.collision.unwrap_or(true),
            broad_phase: self.dynamics.collision_broad_phase.unwrap_or_default(),
        };
        let budget = match self.lod.budget_ms {
            None => None,
            Some(ms) => {
                if !(ms.is_finite() && ms > 0.0) {
                    return Err(SceneFileError::new(format!(
                        "lod.budget_ms = {ms}: expected a finite number of milliseconds > 0"
                    )));
                }
                // Hold a lowering of the tolerance for the blend time: its cost shows only
                // after it.
                let blend = match settings.lod {
                    LodMode::Auto(lod) => lod.blend_time,
                    LodMode::Fixed(_) => 0.0,
                };
                let method = self.lod.budget_method.unwrap_or_default();
                Some(BudgetSettings {
                    hold_frames: (blend * fps).round() as usize,
                    method,
                    ..BudgetSettings::new(ms / 1e3)
                })
            }
        };
        let rest_pose = self.rest_pose(groom_file.is_some())?;
        let settle_seconds = within(
            "dynamics.settle_seconds",
            self.dynamics.settle_seconds.unwrap_or(match rest_pose {
                RestPose::Hanging | RestPose::Loaded => 0.0,
                RestPose::Grown => 1.0,
            }),
            0.0,
            60.0,
            "seconds in 0..=60",
        )?;
        let output = &self.output;
        let color_coded = output.color_coded.unwrap_or(false);
        let side_by_side = output.side_by_side.unwrap_or(false);
        let outputs = Outputs {
            shaded: output.shaded.unwrap_or(!(color_coded || side_by_side)),
            color_coded,
            side_by_side,
            contact_sheet: output.contact_sheet.unwrap_or(false),
            hair: output.hair.unwrap_or(false),
            usd: output.usd.unwrap_or(false) || output.usd_strands.is_some(),
            usd_strands: output.usd_strands.unwrap_or_default(),
            shading: output.shading.unwrap_or_default(),
            line_coverage: output.line_coverage.unwrap_or_default(),
            cluster_geometry: output.clusters.unwrap_or_default(),
        };
        if let Some(json) = &output.json
            && json.trim().is_empty()
        {
            return Err(SceneFileError::new(
                "output.json = \"\": expected a file name",
            ));
        }
        if let Some(table) = self.bench.paper_table
            && !(1..=2).contains(&table)
        {
            return Err(SceneFileError::new(format!(
                "bench.paper_table = {table}: expected 1 or 2"
            )));
        }
        Ok(Shot {
            groom,
            head: HeadParams::default(),
            groom_file,
            body_file,
            environment,
            settings,
            budget,
            camera,
            frames: frame_count,
            fps,
            width,
            height,
            settle_seconds,
            rest_pose,
            outputs,
            paper_table: self.bench.paper_table,
            characters: self.characters()?,
            body_animation,
        })
    }

    /// The crowd's characters: each `[[character]]`'s own `groom`, `motion` and `wind` tables
    /// (the scene's when left out), placed at `position` turned by `yaw_degrees`; errors name
    /// `character[k]` and the field.
    fn characters(&self) -> Result<Vec<crate::shot::Character>> {
        let mut characters = Vec::with_capacity(self.character.len());
        for (k, table) in self.character.iter().enumerate() {
            let within_character = |error: SceneFileError| {
                SceneFileError::new(format!("character[{k}].{}", error.message))
            };
            let own = SceneFile {
                groom: table.groom.clone().unwrap_or_else(|| self.groom.clone()),
                motion: table.motion.clone().unwrap_or_else(|| self.motion.clone()),
                wind: table.wind.clone().unwrap_or_else(|| self.wind.clone()),
                character: Vec::new(),
                ..self.clone()
            };
            if own.groom.file.is_some() {
                return Err(within_character(SceneFileError::new(
                    "groom.file: crowd characters wear preset grooms for now (give the character \
                     its own groom table with a preset)",
                )));
            }
            let groom = own.groom_params(false).map_err(within_character)?;
            let position =
                super::bounds::head_point("position", table.position).map_err(within_character)?;
            let yaw = within(
                "yaw_degrees",
                table.yaw_degrees.unwrap_or(0.0),
                -360.0,
                360.0,
                "degrees in -360..=360",
            )
            .map_err(within_character)?;
            let placement = RigidTransform::new(Quat::from_rotation_y(yaw.to_radians()), position);
            let environment = Environment {
                head: own
                    .head_motion()
                    .map_err(within_character)?
                    .placed(&placement),
                wind: own.wind_field().map_err(within_character)?,
                ..Environment::default()
            };
            characters.push(crate::shot::Character {
                name: table
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("character {k}")),
                groom,
                placement,
                environment,
            });
        }
        Ok(characters)
    }

    /// `groom.rest_pose`: `hanging` by default, `loaded` by default for a groom file (and only
    /// for one).
    fn rest_pose(&self, groom_file: bool) -> Result<RestPose> {
        let default = if groom_file {
            RestPose::Loaded
        } else {
            RestPose::Hanging
        };
        let pose = self.groom.rest_pose.unwrap_or(default);
        if pose == RestPose::Loaded && !groom_file {
            return Err(SceneFileError::new(
                "groom.rest_pose = \"loaded\": needs groom.file (a generated groom's shape is \
                 grown, not a hairstyle; use hanging or grown)",
            ));
        }
        Ok(pose)
    }

    /// The groom's parameters: the preset with overrides (with a groom file, the preset gives
    /// the material; the default is then `straight`, the softest).
    fn groom_params(&self, groom_file: bool) -> Result<GroomParams> {
        let table = &self.groom;
        let default = if groom_file {
            DEFAULT_FILE_MATERIAL
        } else {
            GroomPreset::PaperCurly
        };
        let mut params = GroomParams::from(table.preset.unwrap_or(default));
        if let Some(v) = table.seed {
            params.seed = v;
        }
        if groom_file {
            // The fit counts sections and shapes the strands (checked in `groom_file`).
            return Ok(params);
        }
        if let Some(v) = table.section_count {
            params.section_count = count("groom.section_count", v, 1, 10_000)?;
        }
        if let Some(v) = table.strands_per_group {
            params.strands_per_group = count("groom.strands_per_group", v, 1, 10_000)?;
        }
        if let Some(v) = table.hair_length {
            params.hair_length = positive("groom.hair_length", v)?;
        }
        if let Some(v) = table.style_factor_degrees {
            params.style.factor_degrees = within(
                "groom.style_factor_degrees",
                v,
                0.0,
                90.0,
                "degrees in 0..=90",
            )?;
        }
        if let Some(v) = table.style_size {
            params.style.size = positive("groom.style_size", v)?;
        }
        if let Some(v) = table.smoothness {
            params.style.smoothness = positive("groom.smoothness", v)?;
        }
        if let Some(v) = table.seed {
            params.seed = v;
        }
        Ok(params)
    }

    fn head_motion(&self) -> Result<HeadMotion> {
        let table = &self.motion;
        let kind = table.kind.unwrap_or_default();
        let amplitude = within(
            "motion.amplitude_degrees",
            table.amplitude_degrees.unwrap_or(14.3),
            0.0,
            90.0,
            "degrees in 0..=90",
        )?
        .to_radians();
        let speed = positive("motion.peak_speed", table.peak_speed.unwrap_or(1.2))?;
        if kind != MotionKind::Keyframes && !table.keyframes.is_empty() {
            return Err(SceneFileError::new(format!(
                "motion.keyframes: given, but motion.kind = \"{kind}\"; set kind = \"keyframes\""
            )));
        }
        Ok(match kind {
            MotionKind::Shake => HeadMotion::shake(amplitude, speed),
            MotionKind::Nod => HeadMotion::nod(amplitude, speed),
            MotionKind::Keyframes => {
                if table.keyframes.is_empty() {
                    return Err(SceneFileError::new(
                        "motion.keyframes: motion.kind = \"keyframes\" needs at least one keyframe",
                    ));
                }
                let mut keys = Vec::with_capacity(table.keyframes.len());
                for (k, key) in table.keyframes.iter().enumerate() {
                    let field = format!("motion.keyframes[{k}]");
                    if !(key.time.is_finite() && key.time >= 0.0) {
                        return Err(SceneFileError::new(format!(
                            "{field}.time = {}: expected a finite time ≥ 0 s",
                            key.time
                        )));
                    }
                    if k > 0 && key.time <= table.keyframes[k - 1].time {
                        return Err(SceneFileError::new(format!(
                            "{field}.time = {}: keyframe times must increase",
                            key.time
                        )));
                    }
                    let [x, y, z] =
                        vector(&format!("{field}.rotation_degrees"), key.rotation_degrees)?
                            .to_array()
                            .map(f32::to_radians);
                    keys.push(HeadKeyframe {
                        time: key.time,
                        transform: RigidTransform {
                            rotation: Quat::from_euler(EulerRot::XYZ, x, y, z),
                            translation: super::bounds::head_point(
                                &format!("{field}.translation"),
                                key.translation,
                            )?,
                        },
                    });
                }
                HeadMotion::Keyframed(keys)
            }
            MotionKind::Still => HeadMotion::default(),
        })
    }

    fn wind_field(&self) -> Result<WindField> {
        let table = &self.wind;
        let speed = within(
            "wind.speed",
            table.speed.unwrap_or(0.0),
            0.0,
            100.0,
            "a speed in 0..=100 m/s",
        )?;
        let gusts = within(
            "wind.gusts",
            table.gusts.unwrap_or(0.0),
            0.0,
            100.0,
            "a speed in 0..=100 m/s",
        )?;
        let given = table.direction.unwrap_or([0.6, 0.0, -0.8]);
        let direction = super::bounds::direction("wind.direction", given)?;
        let period = positive("wind.gust_period", table.gust_period.unwrap_or(1.0))?;
        let length = positive("wind.gust_length", table.gust_length.unwrap_or(0.5))?;
        Ok(if gusts > 0.0 {
            WindField::gusting(
                direction * speed,
                gusts,
                period,
                length,
                table.seed.unwrap_or(7),
            )
        } else if speed > 0.0 {
            WindField::Constant(direction * speed)
        } else {
            WindField::Calm
        })
    }

    /// The camera path; with `from_files` (a groom file) and no target, distance or keyframes,
    /// framed on the scene once it is built ([`CameraPath::frame_all`]).
    /// `[body] animation`: the procedural head's only.
    fn body_animation(&self, body_file: bool) -> Result<Option<BodyAnimation>> {
        match self.body.animation.unwrap_or_default() {
            BodyAnimationKind::None => Ok(None),
            kind if body_file => Err(SceneFileError::new(format!(
                "body.animation = \"{kind}\": the procedural head's own deformation; a body \
                 file plays its own time samples (leave body.animation out)"
            ))),
            BodyAnimationKind::Talk => Ok(Some(BodyAnimation::talk())),
        }
    }

    fn camera_path(&self, from_files: bool) -> Result<CameraPath> {
        let table = &self.camera;
        let frame_all = (from_files
            && self.character.is_empty()
            && table.target.is_none()
            && table.distance.is_none()
            && table.keyframes.is_empty())
        .then_some(FrameAll {
            end_distance: table.end_distance,
        });
        let path = table.path.unwrap_or_default();
        let distance =
            super::bounds::camera_distance("camera.distance", table.distance.unwrap_or(0.8))?;
        let motion = match path {
            CameraPathKind::Orbit => CameraMotion::Orbit,
            CameraPathKind::ZoomOut => CameraMotion::ZoomOut,
            CameraPathKind::Fixed => CameraMotion::Fixed,
            CameraPathKind::Keyframes => {
                if table.keyframes.is_empty() {
                    return Err(SceneFileError::new(
                        "camera.keyframes: camera.path = \"keyframes\" needs at least one keyframe",
                    ));
                }
                let mut keys = Vec::new();
                for (k, key) in table.keyframes.iter().enumerate() {
                    let field = format!("camera.keyframes[{k}]");
                    if !(key.time.is_finite() && key.time >= 0.0)
                        || (k > 0 && key.time <= table.keyframes[k - 1].time)
                    {
                        return Err(SceneFileError::new(format!(
                            "{field}.time = {}: expected a finite time ≥ 0 s, increasing",
                            key.time
                        )));
                    }
                    let position =
                        super::bounds::camera_point(&format!("{field}.position"), key.position)?;
                    let target =
                        super::bounds::camera_point(&format!("{field}.target"), key.target)?;
                    super::bounds::camera_distance(
                        &format!("{field}: the distance from position to target"),
                        position.distance(target),
                    )?;
                    keys.push(CameraKeyframe {
                        time: key.time,
                        position,
                        target,
                    });
                }
                CameraMotion::Keyframes(keys)
            }
        };
        if path != CameraPathKind::Keyframes && !table.keyframes.is_empty() {
            return Err(SceneFileError::new(format!(
                "camera.keyframes: given, but camera.path = \"{path}\"; set path = \"keyframes\""
            )));
        }
        Ok(CameraPath {
            motion,
            target: super::bounds::camera_point("camera.target", table.target.unwrap_or([0.0; 3]))?,
            distance,
            end_distance: super::bounds::camera_distance(
                "camera.end_distance",
                table
                    .end_distance
                    .unwrap_or((4.0 * distance).min(super::MAX_CAMERA_DISTANCE)),
            )?,
            azimuth: within(
                "camera.azimuth_degrees",
                table.azimuth_degrees.unwrap_or(150.0),
                -3600.0,
                3600.0,
                "degrees in -3600..=3600",
            )?
            .to_radians(),
            elevation: within(
                "camera.elevation_degrees",
                table.elevation_degrees.unwrap_or(8.0),
                -89.0,
                89.0,
                "degrees in -89..=89",
            )?
            .to_radians(),
            fov: within(
                "camera.fov_degrees",
                table.fov_degrees.unwrap_or(35.0),
                1.0,
                170.0,
                "degrees in 1..=170",
            )?
            .to_radians(),
            frame_all,
        })
    }

    fn lod_mode(&self, width: u32, height: u32) -> Result<LodMode> {
        let table = &self.lod;
        let mode = table.mode.unwrap_or_default();
        let mut lod = LodSettings {
            image_width: width,
            image_height: height,
            ..LodSettings::default()
        };
        if let Some(v) = table.pixel_tolerance {
            lod.pixel_tolerance = within(
                "lod.pixel_tolerance",
                v,
                1e-3,
                1e4,
                "pixels in 0.001..=10000",
            )?;
        }
        if let Some(v) = table.blend_time {
            lod.blend_time = within("lod.blend_time", v, 0.0, 10.0, "seconds in 0..=10")?;
        }
        if let Some(v) = table.blend_lead {
            lod.blend_lead = within(
                "lod.blend_lead",
                v,
                0.0,
                1.0,
                "a fraction of the blend time in 0..=1",
            )?;
        }
        if let Some(v) = table.rules_min_pixels {
            lod.rules_min_pixels = within(
                "lod.rules_min_pixels",
                v,
                0.0,
                100_000.0,
                "pixels in 0..=100000",
            )?;
        }
        if let Some(v) = table.strands_per_pixel {
            lod.strands_per_pixel = within(
                "lod.strands_per_pixel",
                v,
                0.0,
                1000.0,
                "strands per pixel in 0..=1000",
            )?;
        }
        if let Some(raise) = table.raise_thinned_widths {
            lod.raise_thinned_widths = raise;
        }
        if let Some(model) = table.error_model {
            lod.error_model = model;
        }
        if let Some(test) = table.occlusion_test {
            lod.occlusion_test = test;
        }
        lod.validate()
            .map_err(|error| SceneFileError::new(format!("[lod]: {error}")))?;
        Ok(match mode.level() {
            None => LodMode::Auto(lod),
            Some(level) => LodMode::Fixed(level),
        })
    }

    fn dynamics_settings(&self, fps: f32) -> Result<SimulationSettings> {
        let table = &self.dynamics;
        let integrator = table.integrator.unwrap_or(IntegratorKind::DEFAULT);
        // The recommended substeps are per 1/60 s: keep the substep no longer at other rates.
        let recommended = SimulationSettings::recommended(integrator).substeps;
        let default = ((recommended as f32) * 60.0 / fps).ceil().max(1.0) as u32;
        let substeps = count(
            "dynamics.substeps",
            table.substeps.unwrap_or(default) as usize,
            1,
            10_000,
        )? as u32;
        let mut settings = SimulationSettings::new(integrator, 1.0 / fps, substeps);
        let recommended_max = SimulationSettings::recommended(integrator)
            .adaptive
            .map(|adaptive| ((adaptive.max_substeps as f32) * 60.0 / fps).ceil() as u32);
        let max_substeps = match table.max_substeps {
            Some(max) => Some(count("dynamics.max_substeps", max as usize, 1, 10_000)? as u32),
            None => recommended_max,
        };
        if let Some(max_substeps) = max_substeps.filter(|&max| max > substeps) {
            settings.adaptive = Some(AdaptiveSubsteps {
                max_substeps,
                max_courant: XPBD_MAX_COURANT,
            });
        }
        settings
            .validate()
            .map_err(|error| SceneFileError::new(format!("[dynamics]: {error}")))?;
        Ok(settings)
    }
}

#[cfg(test)]
mod tests;
