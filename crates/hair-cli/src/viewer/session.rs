//! The viewer's front end on the frame pipeline, without a window: the [`Pipeline`] of a scene,
//! the controls' state (paused, colour coding, level, tolerance, budget, wind, head motion), the
//! camera, and one frame at a time through [`Pipeline::advance`], the same frame loop `render`
//! drives. The window ([`super::app`]) draws what this holds.

use std::collections::VecDeque;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::Vec3;
use hairlod::Level;
use hairlod::core::Camera;
use hairlod::core::dynamics::{Environment, HeadMotion, WindField};
use hairlod::core::lod::{BudgetController, BudgetSettings, LodSettings};
use hairlod::pipeline::{FrameReport, LodMode, Pipeline};
use hairlod::render::ShadingMode;
use hairlod::shot::Shot;

use super::controls::{Action, LevelChoice};
use super::orbit::Orbit;

/// The wind that `w` turns on in a calm scene: the paper's Table 2 wind (2.5 m/s from the front
/// left, 1.5 m/s gusts over 1 s and 0.5 m/s, seed 7).
fn default_wind() -> WindField {
    WindField::gusting(Vec3::new(0.6, 0.0, -0.8) * 2.5, 1.5, 1.0, 0.5, 7)
}

/// The frame budget that `b` turns on when the scene has none [s].
const DEFAULT_BUDGET_SECONDS: f64 = 0.1;

/// The head motions `m` cycles through.
const MOTIONS: [&str; 4] = ["scene", "still", "shake", "nod"];

/// Frames over which the HUD's frames per second are measured.
const FPS_WINDOW: usize = 30;

/// The viewer's simulation and controls.
pub struct Session {
    shot: Shot,
    pipeline: Pipeline,
    /// The automatic-level settings to return to from a forced level (tolerance aside).
    auto_lod: LodSettings,
    /// The scene's own environment (wind and head motion as the file has them).
    scene_environment: Environment,
    /// The fingerprint of the run as the scene defines it (checkpoints resume only with it).
    scene_fingerprint: String,
    paused: bool,
    step_requested: bool,
    color_coded: bool,
    hud_visible: bool,
    level: LevelChoice,
    /// Pixel tolerance of the automatic levels [pixels].
    tolerance: f32,
    /// Frame budget [s] and whether it steers the tolerance.
    budget_seconds: f64,
    budget: Option<BudgetController>,
    wind_on: bool,
    /// Index into [`MOTIONS`].
    motion: usize,
    /// `None`: follow the scene's camera path.
    orbit: Option<Orbit>,
    last_report: Option<FrameReport>,
    /// Wall-clock instants of the last simulated frames.
    frame_instants: VecDeque<Instant>,
    quit: bool,
}

impl Session {
    /// A session on `pipeline` (built from `shot`, at its first frame or a checkpoint's).
    pub fn new(shot: Shot, pipeline: Pipeline) -> Result<Session> {
        let auto_lod = match pipeline.settings().lod {
            LodMode::Auto(lod) => lod,
            LodMode::Fixed(_) => shot.lod_settings(),
        };
        let level = match pipeline.settings().lod {
            LodMode::Auto(_) => LevelChoice::Auto,
            LodMode::Fixed(Level::StrandGroup) => LevelChoice::Strands,
            LodMode::Fixed(Level::Cluster) => LevelChoice::Clusters,
            LodMode::Fixed(Level::Patch) => LevelChoice::Patches,
        };
        let tolerance = pipeline
            .selector()
            .map_or(auto_lod.pixel_tolerance, |s| s.settings().pixel_tolerance);
        let budget = match (shot.budget, level) {
            (Some(settings), LevelChoice::Auto) => {
                Some(BudgetController::new(settings, tolerance)?)
            }
            _ => None,
        };
        Ok(Session {
            budget_seconds: shot.budget.map_or(DEFAULT_BUDGET_SECONDS, |b| b.budget),
            budget,
            scene_environment: pipeline.environment().clone(),
            scene_fingerprint: pipeline.fingerprint(),
            wind_on: pipeline.environment().wind != WindField::Calm,
            auto_lod,
            level,
            tolerance,
            paused: false,
            step_requested: false,
            color_coded: shot.outputs.color_coded && !shot.outputs.shaded,
            hud_visible: true,
            motion: 0,
            orbit: None,
            last_report: None,
            frame_instants: VecDeque::with_capacity(FPS_WINDOW + 1),
            quit: false,
            shot,
            pipeline,
        })
    }

    /// The camera of the next frame: the user's orbit, or the scene's path at the pipeline's
    /// frame (held at its last frame past the shot's end).
    pub fn camera(&self) -> Camera {
        match &self.orbit {
            Some(orbit) => orbit.camera(),
            None => self.shot.camera(
                self.pipeline
                    .frame()
                    .min(self.shot.frames.saturating_sub(1)),
            ),
        }
    }

    /// Applies a control; `height` is the window's height [pixels] (for panning).
    pub fn apply(&mut self, action: Action, height: u32) -> Result<()> {
        match action {
            Action::Orbit { dx, dy } => self.orbit_mut().orbit(dx, dy),
            Action::Pan { dx, dy } => self.orbit_mut().pan(dx, dy, height),
            Action::Zoom(notches) => self.orbit_mut().zoom(notches),
            Action::ResetView => self.orbit = None,
            Action::TogglePause => self.paused = !self.paused,
            Action::Step => {
                self.paused = true;
                self.step_requested = true;
            }
            Action::ToggleColorCode => self.color_coded = !self.color_coded,
            Action::CycleLevel => self.set_level(self.level.next())?,
            Action::SetLevel(choice) => self.set_level(choice)?,
            Action::ScaleTolerance(factor) => {
                self.set_tolerance((self.tolerance * factor).clamp(0.001, 10000.0))?;
            }
            Action::ToggleBudget => {
                self.budget = match self.budget {
                    Some(_) => None,
                    None => Some(self.budget_controller()?),
                };
            }
            Action::ScaleBudget(factor) => {
                self.budget_seconds = (self.budget_seconds * factor).clamp(1e-3, 10.0);
                if self.budget.is_some() {
                    self.budget = Some(self.budget_controller()?);
                }
            }
            Action::ToggleWind => {
                self.wind_on = !self.wind_on;
                self.update_environment()?;
            }
            Action::CycleMotion => {
                self.motion = (self.motion + 1) % MOTIONS.len();
                self.update_environment()?;
            }
            Action::Screenshot | Action::Quit => {
                // The window handles these (it has the image).
                if action == Action::Quit {
                    self.quit = true;
                }
            }
            Action::ToggleHud => self.hud_visible = !self.hud_visible,
        }
        Ok(())
    }

    /// The orbit camera, taken over from the scene's camera at the first mouse move.
    fn orbit_mut(&mut self) -> &mut Orbit {
        let camera = self.camera();
        self.orbit
            .get_or_insert_with(|| Orbit::from_camera(&camera))
    }

    fn budget_controller(&self) -> Result<BudgetController> {
        BudgetController::new(BudgetSettings::new(self.budget_seconds), self.tolerance)
            .context("the frame budget")
    }

    fn set_tolerance(&mut self, tolerance: f32) -> Result<()> {
        self.tolerance = tolerance;
        self.pipeline.set_pixel_tolerance(tolerance)?;
        if self.budget.is_some() {
            // The budget steers on from the tolerance the user set.
            self.budget = Some(self.budget_controller()?);
        }
        Ok(())
    }

    fn set_level(&mut self, choice: LevelChoice) -> Result<()> {
        let mode = match choice {
            LevelChoice::Auto => LodMode::Auto(LodSettings {
                pixel_tolerance: self.tolerance,
                ..self.auto_lod
            }),
            LevelChoice::Strands => LodMode::Fixed(Level::StrandGroup),
            LevelChoice::Clusters => LodMode::Fixed(Level::Cluster),
            LevelChoice::Patches => LodMode::Fixed(Level::Patch),
        };
        self.pipeline.set_lod_mode(mode)?;
        self.level = choice;
        Ok(())
    }

    /// Hands the pipeline the environment the wind and motion switches ask for.
    fn update_environment(&mut self) -> Result<()> {
        let scene = &self.scene_environment;
        let head = match MOTIONS[self.motion] {
            "still" => HeadMotion::Still(self.pipeline.head_pose()),
            "shake" => HeadMotion::shake(14.3f32.to_radians(), 1.2),
            "nod" => HeadMotion::nod(14.3f32.to_radians(), 1.2),
            _ => scene.head.clone(),
        };
        let wind = match (self.wind_on, &scene.wind) {
            (false, _) => WindField::Calm,
            (true, WindField::Calm) => default_wind(),
            (true, wind) => wind.clone(),
        };
        self.pipeline.set_environment(Environment {
            head,
            wind,
            gravity: scene.gravity,
        })?;
        Ok(())
    }

    /// Whether the next drawn frame steps the simulation (playing, or a single step asked for).
    pub fn wants_step(&mut self) -> bool {
        !self.paused || std::mem::take(&mut self.step_requested)
    }

    /// Advances the pipeline one frame through `camera` (levels, dynamics with collision), with
    /// the tolerance the frame budget steers to; the caller renders and then calls
    /// [`Session::frame_drawn`].
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        if let Some(controller) = &self.budget
            && self.level == LevelChoice::Auto
        {
            self.tolerance = controller.tolerance();
            self.pipeline.set_pixel_tolerance(self.tolerance)?;
        }
        Ok(self.pipeline.advance(camera)?)
    }

    /// Records a stepped frame once drawn: its rendering time [s], the budget's update, the
    /// frame rate.
    pub fn frame_drawn(&mut self, mut report: FrameReport, rendering: f64) -> Result<()> {
        report.times.rendering = rendering;
        if let Some(controller) = &mut self.budget
            && self.level == LevelChoice::Auto
        {
            controller.update(report.times.total())?;
        }
        self.last_report = Some(report);
        self.frame_instants.push_back(Instant::now());
        if self.frame_instants.len() > FPS_WINDOW {
            self.frame_instants.pop_front();
        }
        Ok(())
    }

    /// Simulated frames per second over the last frames stepped (`None` before two); frozen
    /// while paused.
    pub fn fps(&self) -> Option<f64> {
        let (first, last) = (self.frame_instants.front()?, self.frame_instants.back()?);
        let seconds = last.duration_since(*first).as_secs_f64();
        (self.frame_instants.len() > 1 && seconds > 0.0)
            .then(|| (self.frame_instants.len() - 1) as f64 / seconds)
    }

    /// The pipeline (to render and checkpoint).
    pub fn pipeline_mut(&mut self) -> &mut Pipeline {
        &mut self.pipeline
    }

    /// The pipeline.
    pub fn pipeline(&self) -> &Pipeline {
        &self.pipeline
    }

    /// The style frames are drawn in (the scene's `output.shading` and `output.line_coverage`).
    pub fn draw_style(&self) -> hairlod::pipeline::DrawStyle {
        self.shot.outputs.style()
    }

    /// Whether the run's model differs from the scene's now (wind, head motion or level mode
    /// changed), so a checkpoint of it resumes only with the same changes.
    pub fn differs_from_scene(&self) -> bool {
        self.pipeline.fingerprint() != self.scene_fingerprint
    }

    /// Shaded or colour-coded.
    pub fn shading(&self) -> ShadingMode {
        if self.color_coded {
            ShadingMode::LevelColors
        } else {
            ShadingMode::Shaded
        }
    }

    /// What the HUD shows.
    pub fn status(&self) -> Status {
        Status {
            report: self.last_report,
            fps: self.fps(),
            paused: self.paused,
            color_coded: self.color_coded,
            level: self.level,
            tolerance: self.tolerance,
            budget: self.budget.as_ref().map(|_| self.budget_seconds),
            wind_on: self.wind_on,
            motion: MOTIONS[self.motion],
            following_path: self.orbit.is_none(),
        }
    }

    /// Whether the HUD is shown.
    pub fn hud_visible(&self) -> bool {
        self.hud_visible
    }

    /// Whether the user asked to quit.
    pub fn quit_requested(&self) -> bool {
        self.quit
    }
}

/// The state the HUD shows.
#[derive(Debug, Clone, Copy)]
pub struct Status {
    /// The last stepped frame's report (stage times with rendering, counts).
    pub report: Option<FrameReport>,
    /// Simulated frames per second.
    pub fps: Option<f64>,
    /// Paused.
    pub paused: bool,
    /// Colour-coded by level.
    pub color_coded: bool,
    /// The level choice.
    pub level: LevelChoice,
    /// The pixel tolerance [pixels].
    pub tolerance: f32,
    /// The frame budget [s], when it steers the tolerance.
    pub budget: Option<f64>,
    /// Wind on.
    pub wind_on: bool,
    /// The head motion's name.
    pub motion: &'static str,
    /// The camera follows the scene's path.
    pub following_path: bool,
}
