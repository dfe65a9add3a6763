//! The frame pipeline (DESIGN "One frame"): control → level selection and transitions → dynamics
//! with collision → skeletons for the renderer, with the wall-clock time of each stage.

use std::time::Instant;

use glam::Vec3;
use hair_collide::{
    CollisionBody, CollisionChain, CollisionSettings, CollisionSolver, groom_chain,
};
use hair_core::dynamics::{DynamicsParams, Environment};
use hair_core::lod::{
    LodSelector, SectionChoice, SectionObservation, head_point_acceleration_from_poses,
    motion_measure,
};
use hair_core::skeleton::node_frames;
use hair_core::{Camera, Frame, Level, RigidTransform, Scene};
use hair_render::ActiveSkeletons;

use super::block::LevelBlock;
use super::error::Result;
use super::report::{FrameReport, LodChanges, StageTimes};
use super::settings::{LodMode, PipelineSettings};
use super::transitions::{SectionLevels, rebuild_blocks};

/// A hair simulation with levels of detail: owns the scene, the per-level skeleton states and
/// solvers, the level selector and the collision solvers, and advances one frame at a time.
///
/// ```
/// use hairlod::pipeline::{Pipeline, PipelineSettings};
/// use hairlod::core::dynamics::Environment;
/// use hairlod::{Camera, Scene};
///
/// let scene = Scene::preset("curly")?;
/// let mut pipeline = Pipeline::new(scene, Environment::default(), PipelineSettings::default())?;
/// let camera = Camera::default();
/// let report = pipeline.advance(&camera)?;
/// assert_eq!(report.sections_at.iter().sum::<usize>(), pipeline.scene().groom.section_count());
/// # Ok::<(), hairlod::pipeline::PipelineError>(())
/// ```
pub struct Pipeline {
    scene: Scene,
    environment: Environment,
    settings: PipelineSettings,
    params: DynamicsParams,
    selector: Option<LodSelector>,
    blocks: [LevelBlock; 3],
    solvers: [Option<CollisionSolver>; 3],
    levels: SectionLevels,
    choices: Vec<SectionChoice>,
    observations: Vec<SectionObservation>,
    frame: usize,
    time: f64,
    frames_scratch: Vec<Frame>,
    collision_chains: Vec<CollisionChain>,
    /// A frame whose levels are chosen but whose dynamics step has not run
    /// ([`Pipeline::begin_frame`]).
    pending: Option<PendingFrame>,
}

/// What [`Pipeline::begin_frame`] leaves for [`Pipeline::finish_frame`].
#[derive(Debug, Clone, Copy, Default)]
struct PendingFrame {
    changes: LodChanges,
    times: StageTimes,
}

impl Pipeline {
    /// A pipeline for `scene` driven by `environment` (head motion, wind, gravity), every section
    /// at rest at the finest level, strand groups (automatic mode: [`settle`](Self::settle) lets
    /// the hair fall into place at full detail, and the first frame hands each section down to
    /// the level it is given), or at the fixed level.
    pub fn new(scene: Scene, environment: Environment, settings: PipelineSettings) -> Result<Self> {
        settings.dynamics.validate()?;
        let groom = &scene.groom;
        let sections = groom.section_count();
        let params = DynamicsParams::for_style(&groom.params.style);
        let (selector, start_level) = match settings.lod {
            LodMode::Auto(lod) => (
                Some(LodSelector::new(groom, &scene.head.occluder_boxes(), lod)?),
                Level::StrandGroup,
            ),
            LodMode::Fixed(level) => (None, level),
        };
        let solvers = if settings.collision {
            let make = || -> Result<CollisionSolver> {
                let body = CollisionBody::from_mesh(&scene.head.mesh)?;
                Ok(CollisionSolver::new(
                    vec![body],
                    CollisionSettings::default(),
                )?)
            };
            [Some(make()?), Some(make()?), Some(make()?)]
        } else {
            [None, None, None]
        };
        let visible_choice = SectionChoice {
            level: start_level,
            visible: true,
            reason: hair_core::lod::Reason::Fixed,
        };
        let mut pipeline = Pipeline {
            environment,
            settings,
            params,
            selector,
            blocks: Level::ALL.map(LevelBlock::empty),
            solvers,
            levels: SectionLevels::new(sections, start_level),
            choices: vec![visible_choice; sections],
            observations: vec![SectionObservation::default(); sections],
            frame: 0,
            time: 0.0,
            frames_scratch: Vec::new(),
            collision_chains: Vec::new(),
            pending: None,
            scene,
        };
        pipeline.start_at_rest()?;
        Ok(pipeline)
    }

    /// Builds the blocks of the starting levels and puts every skeleton in its rest shape.
    fn start_at_rest(&mut self) -> Result<()> {
        let head = self.environment.head.transform_at(self.time);
        let groom = &self.scene.groom;
        for level in Level::ALL {
            let sections = self.levels.members(level);
            let mut block = LevelBlock::build(
                groom,
                level,
                sections,
                self.params,
                self.settings.dynamics,
                self.time,
            )?;
            if let Some(simulation) = &block.simulation {
                let rest = simulation.model().rest.rest_positions(&head);
                block.state.node_positions = rest;
            }
            self.blocks[level as usize] = block;
        }
        self.refresh_collision_chains()?;
        Ok(())
    }

    /// Lets the hair settle from its rest shape under gravity (and the environment at time 0)
    /// for `seconds` [s] at the current levels, without choosing levels or advancing the clock:
    /// a groom's rest shape is not an equilibrium under gravity, and a run should not start with
    /// hair falling into place (which the motion criterion would rightly read as motion).
    pub fn settle(&mut self, seconds: f32) -> Result<()> {
        let step = self.settings.dynamics.time_step;
        let steps = (seconds / step).ceil().max(0.0) as usize;
        let still = Environment {
            head: hair_core::dynamics::HeadMotion::Still(
                self.environment.head.transform_at(self.time),
            ),
            ..self.environment.clone()
        };
        for _ in 0..steps {
            for (block, solver) in self.blocks.iter_mut().zip(self.solvers.iter_mut()) {
                let Some(simulation) = block.simulation.as_mut() else {
                    continue;
                };
                block.state.time = 0.0;
                match solver {
                    Some(solver) => {
                        solver.step(simulation, &mut block.state, &still)?;
                    }
                    None => {
                        simulation.step(&mut block.state, &still)?;
                    }
                }
            }
        }
        for block in &mut self.blocks {
            block.state.time = self.time;
            block
                .previous_velocities
                .copy_from_slice(&block.state.node_velocities);
        }
        Ok(())
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The settings.
    pub fn settings(&self) -> &PipelineSettings {
        &self.settings
    }

    /// The environment (head motion, wind, gravity).
    pub fn environment(&self) -> &Environment {
        &self.environment
    }

    /// Replaces the environment from the next frame on.
    pub fn set_environment(&mut self, environment: Environment) {
        self.environment = environment;
    }

    /// The level selector (`None` with a fixed level).
    pub fn selector_mut(&mut self) -> Option<&mut LodSelector> {
        self.selector.as_mut()
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Frames advanced so far.
    pub fn frame(&self) -> usize {
        self.frame
    }

    /// The current level of every section.
    pub fn section_levels(&self) -> &[Level] {
        self.levels.current()
    }

    /// The last choice of every section (level, visibility, reason).
    pub fn choices(&self) -> &[SectionChoice] {
        &self.choices
    }

    /// The block of `level`: the sections simulated at it and their state.
    pub fn block(&self, level: Level) -> &LevelBlock {
        &self.blocks[level as usize]
    }

    /// Advances one frame of `settings.dynamics.time_step` seconds seen by `camera`: chooses
    /// levels, hands state over where a section changed level, steps every block with collision.
    /// The same as [`Pipeline::begin_frame`] then [`Pipeline::finish_frame`].
    pub fn advance(&mut self, camera: &Camera) -> Result<FrameReport> {
        self.begin_frame(camera)?;
        self.finish_frame()
    }

    /// The level-of-detail stage of a frame seen by `camera`: chooses levels, starts and ends
    /// blends and hands state over where a section changed level, without stepping the dynamics;
    /// returns how many sections changed level or visibility. Drawing now ([`Pipeline::gather_drawn`]) shows the
    /// frame's levels and blend coverages on the skeletons of the frame before, so the image change
    /// that the level decisions alone make can be measured (the popping measure). A frame already
    /// begun is not begun again (its changes are returned).
    pub fn begin_frame(&mut self, camera: &Camera) -> Result<LodChanges> {
        if let Some(pending) = self.pending {
            return Ok(pending.changes);
        }
        camera.validate()?;
        let mut times = StageTimes::default();
        let started = Instant::now();
        let head = self.environment.head.transform_at(self.time);
        let (levels, visibility) = self.select_levels(camera, &head)?;
        let changes = LodChanges { levels, visibility };
        let blends_ended = self.levels.blends_finished(self.time);
        if levels > 0 || blends_ended {
            rebuild_blocks(
                &self.scene.groom,
                &mut self.blocks,
                &mut self.levels,
                self.params,
                self.settings.dynamics,
                self.time,
                &head,
            )?;
            self.refresh_collision_chains()?;
        }
        times.lod = started.elapsed().as_secs_f64();
        self.pending = Some(PendingFrame { changes, times });
        Ok(changes)
    }

    /// The rest of a frame begun with [`Pipeline::begin_frame`]: one dynamics step with collision
    /// per block, the clock advanced by `settings.dynamics.time_step`. Without a begun frame it
    /// steps with the levels as they are (no selection).
    pub fn finish_frame(&mut self) -> Result<FrameReport> {
        let PendingFrame { changes, mut times } = self.pending.take().unwrap_or_default();
        let mut contacts = 0;
        let mut max_stretch = 0.0f32;
        for (block, solver) in self.blocks.iter_mut().zip(self.solvers.iter_mut()) {
            let Some(simulation) = block.simulation.as_mut() else {
                continue;
            };
            block
                .previous_velocities
                .copy_from_slice(&block.state.node_velocities);
            block.state.time = self.time;
            match solver {
                Some(solver) => {
                    let started = Instant::now();
                    let report =
                        solver.before_step(simulation, &mut block.state, &self.environment)?;
                    contacts += report.contact_segments;
                    times.collision += started.elapsed().as_secs_f64();
                    let started = Instant::now();
                    simulation.step(&mut block.state, &self.environment)?;
                    times.dynamics += started.elapsed().as_secs_f64();
                    let started = Instant::now();
                    let projection =
                        solver.after_step(simulation, &mut block.state, &self.environment)?;
                    max_stretch = max_stretch.max(projection.max_stretch);
                    times.collision += started.elapsed().as_secs_f64();
                }
                None => {
                    let started = Instant::now();
                    simulation.step(&mut block.state, &self.environment)?;
                    times.dynamics += started.elapsed().as_secs_f64();
                }
            }
        }
        self.time += f64::from(self.settings.dynamics.time_step);
        let report = FrameReport {
            frame: self.frame,
            time: self.time,
            sections_at: Level::ALL.map(|level| {
                self.levels
                    .current()
                    .iter()
                    .filter(|&&l| l == level)
                    .count()
            }),
            visible_sections: self.choices.iter().filter(|c| c.visible).count(),
            level_changes: changes.levels,
            visibility_changes: changes.visibility,
            blending_sections: self.levels.blending_count(),
            simulated_nodes: self.blocks.iter().map(LevelBlock::node_count).sum(),
            drawn_segments: self.drawn_segments(),
            contacts,
            max_stretch,
            times,
        };
        self.frame += 1;
        Ok(report)
    }

    /// Observes every section on its current level and chooses levels; returns how many sections
    /// changed level and how many came into view or left it (their transitions and fades are
    /// started in `self.levels`).
    fn select_levels(&mut self, camera: &Camera, head: &RigidTransform) -> Result<(usize, usize)> {
        let groom = &self.scene.groom;
        let Some(selector) = self.selector.as_mut() else {
            return Ok((0, 0));
        };
        let frame_time = self.settings.dynamics.time_step;
        // The head's poses a frame before, now and a frame after, once for every node.
        let head_poses = [-1.0, 0.0, 1.0].map(|k| {
            self.environment
                .head
                .transform_at(self.time + k * f64::from(frame_time))
        });
        let wind = &self.environment.wind;
        let time = self.time;
        for (section, observation) in self.observations.iter_mut().enumerate() {
            let level = self.levels.current()[section];
            let block = &self.blocks[level as usize];
            let slot = block
                .slot(section)
                .expect("a section is simulated at its level");
            let nodes = block.nodes(slot);
            let positions = &block.state.node_positions[nodes.clone()];
            let velocities = &block.state.node_velocities[nodes.clone()];
            let motion = motion_measure(
                positions,
                velocities,
                self.params.air_drag_rate,
                |x| wind.velocity_at(x, time),
                |x| head_point_acceleration_from_poses(&head_poses, frame_time, x),
            );
            *observation = SectionObservation::of_section(groom, section, level, positions, motion);
        }
        let choices = selector.select(&self.observations, camera, head)?;
        self.choices.copy_from_slice(choices);
        // The first frame picks the starting levels outright: there is nothing on screen to
        // blend from.
        let blend = if self.frame == 0 {
            0.0
        } else {
            selector.settings().blend_time
        };
        let mut changes = 0;
        let mut visibility_changes = 0;
        for (section, choice) in self.choices.iter().enumerate() {
            if self.levels.current()[section] != choice.level {
                self.levels.switch(section, choice.level, time, blend);
                changes += 1;
            }
            // Coming into view or leaving it fades over the blend too: a section drawn at once
            // where the conservative occlusion test or the frustum let it through would pop.
            if self
                .levels
                .set_visible(section, choice.visible, time, blend)
            {
                visibility_changes += 1;
            }
        }
        Ok((changes, visibility_changes))
    }

    /// Points every collision solver at its block's chains (rebuilds hierarchies on change).
    fn refresh_collision_chains(&mut self) -> Result<()> {
        let groom = &self.scene.groom;
        for (block, solver) in self.blocks.iter().zip(self.solvers.iter_mut()) {
            let (Some(solver), Some(simulation)) = (solver.as_mut(), block.simulation.as_ref())
            else {
                continue;
            };
            self.collision_chains.clear();
            for (model_chain, &chain) in block.chains.iter().enumerate() {
                if let Some(mut collision) = groom_chain(groom, chain) {
                    collision.chain = model_chain as u32;
                    self.collision_chains.push(collision);
                }
            }
            solver.set_chains(simulation, &self.collision_chains)?;
        }
        Ok(())
    }

    /// The time [s] the drawn skeletons are shown at: the end of the frame, also when a frame is
    /// begun and not yet stepped (the clock has not advanced yet).
    fn display_time(&self) -> f64 {
        match self.pending {
            Some(_) => self.time + f64::from(self.settings.dynamics.time_step),
            None => self.time,
        }
    }

    /// Skeleton segments drawn this frame (strand groups count each of their strands).
    fn drawn_segments(&self) -> usize {
        let groom = &self.scene.groom;
        let display_time = self.display_time();
        let mut segments = 0;
        for section in 0..groom.section_count() {
            if self.levels.shown_weight(section, display_time) <= 0.0 {
                continue;
            }
            for level in self.levels.drawn(section) {
                for chain in groom.section_chains(section, level) {
                    let per_chain = groom.skeletons.chain_node_count(chain).saturating_sub(1);
                    let copies = if level == Level::StrandGroup {
                        let group = chain - groom.level_chains(Level::StrandGroup).start;
                        groom.strands.strands(group).len()
                    } else {
                        1
                    };
                    segments += per_chain * copies;
                }
            }
        }
        segments
    }

    /// Fills `active` with the skeletons to draw, on the groom's chain numbering: the chains of
    /// every visible section at its level (and, while it blends, at its previous level too: the new
    /// level's coverage rises from 0 to 1 over the first half of the blend, then the old one's falls
    /// from 1 to 0 over the second half, a dissolve; a section coming into view or leaving it
    /// dissolves in or out over the blend as a whole), with node frames computed from the simulated
    /// positions; everything else inactive.
    pub fn gather_drawn(&mut self, active: &mut ActiveSkeletons) -> Result<()> {
        let head = self.environment.head.transform_at(self.time);
        let display_time = self.display_time();
        let groom = &self.scene.groom;
        active.clear();
        for chain in 0..groom.skeletons.chain_count() {
            let (section, level, _) = groom.chain_owner(chain);
            let shown = self.levels.shown_weight(section, display_time);
            let drawn = shown > 0.0 && self.levels.drawn(section).any(|drawn| drawn == level);
            let block = &self.blocks[level as usize];
            let located = block.slot(section).filter(|_| drawn);
            let Some(slot) = located else {
                active.push_inactive_chain();
                continue;
            };
            // The chain's nodes inside the section's node range of the block.
            let section_chains = groom.section_chains(section, level);
            let before: usize = (section_chains.start..chain)
                .map(|c| groom.skeletons.chain_node_count(c))
                .sum();
            let count = groom.skeletons.chain_node_count(chain);
            let start = block.nodes(slot).start + before;
            let positions = &block.state.node_positions[start..start + count];
            self.frames_scratch.clear();
            self.frames_scratch.resize(count, Frame::default());
            let root_frame = groom.skeletons.world_root_frame(chain, &head);
            node_frames(&root_frame, positions, &mut self.frames_scratch);
            // While blending, the new level dissolves in over the first half of the blend on top
            // of the whole old level, which then dissolves out over the second half: no frame
            // shows less hair than either level, and the switch frame itself changes little. A
            // section coming into view or leaving it dissolves in or out as a whole.
            let weight = self.levels.blend_weight(section, display_time);
            let coverage = if level == self.levels.current()[section] {
                (2.0 * weight).min(1.0)
            } else {
                (2.0 * (1.0 - weight)).min(1.0)
            };
            let coverage = coverage * shown;
            active.push_chain_with_coverage(positions, &self.frames_scratch, coverage)?;
        }
        Ok(())
    }

    /// The largest distance of any simulated node from the head's centre [m] (a sanity measure).
    pub fn max_node_distance(&self, centre: Vec3) -> f32 {
        self.blocks
            .iter()
            .flat_map(|block| block.state.node_positions.iter())
            .map(|p| p.distance(centre))
            .fold(0.0, f32::max)
    }
}
