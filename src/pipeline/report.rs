//! What one frame of the pipeline did and what each stage cost.

use serde::{Deserialize, Serialize};

/// Wall-clock time of each stage of one frame [s].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StageTimes {
    /// Level selection and transitions.
    pub lod: f64,
    /// Dynamics (forces and integration), collision excluded.
    pub dynamics: f64,
    /// Collision detection and response.
    pub collision: f64,
    /// Rendering (filled by the caller that renders).
    pub rendering: f64,
}

impl StageTimes {
    /// The sum of all stages [s].
    pub fn total(&self) -> f64 {
        self.lod + self.dynamics + self.collision + self.rendering
    }

    /// Adds `other` stage by stage.
    pub fn add(&mut self, other: &StageTimes) {
        self.lod += other.lod;
        self.dynamics += other.dynamics;
        self.collision += other.collision;
        self.rendering += other.rendering;
    }
}

/// What one frame did.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct FrameReport {
    /// Frame number, from 0.
    pub frame: usize,
    /// Simulated time at the end of the frame [s].
    pub time: f64,
    /// Sections at each level: patches, clusters, strand groups.
    pub sections_at: [usize; 3],
    /// Sections drawn (in view and not occluded).
    pub visible_sections: usize,
    /// Sections that changed level this frame.
    pub level_changes: usize,
    /// Sections that came into view or left it this frame (they fade in or out over the blend).
    #[serde(default)]
    pub visibility_changes: usize,
    /// Sections still blending from their previous level.
    pub blending_sections: usize,
    /// Skeleton nodes simulated this frame.
    pub simulated_nodes: usize,
    /// Skeleton segments drawn: active skeleton segments of visible sections at strand level count
    /// once per strand.
    pub drawn_segments: usize,
    /// [`drawn_segments`](Self::drawn_segments) by level (patch, clusters, strand groups).
    #[serde(default)]
    pub drawn_at: [usize; 3],
    /// Screen area covered by the sections drawn at each level [pixels] (their bounding discs;
    /// 0 at fixed levels, which observe nothing).
    #[serde(default)]
    pub pixels_at: [f64; 3],
    /// Dynamics and collision time of each level's block [s] (patch, clusters, strand groups).
    #[serde(default)]
    pub level_seconds: [f64; 3],
    /// Skeleton nodes simulated in each level's block.
    #[serde(default)]
    pub level_nodes: [usize; 3],
    /// Dynamics time of each level's block [s] (patch, clusters, strand groups): the
    /// integrator's step.
    #[serde(default)]
    pub level_dynamics: [f64; 3],
    /// Collision time of each level's block [s]: contacts, response and friction before the
    /// step, the positional guarantee after it.
    #[serde(default)]
    pub level_collision: [f64; 3],
    /// Hair segments found touching the head.
    pub contacts: usize,
    /// The largest relative segment-length error the collision projection left this frame
    /// ([`hair_collide::ProjectionReport::max_stretch`]; 0 without collision). Above
    /// [`hair_collide::STRETCH_WARNING`] the step is too coarse for the hair's motion near the head.
    #[serde(default)]
    pub max_stretch: f32,
    /// The most substeps a simulated block's dynamics took this frame (0 when nothing was
    /// simulated): the settings' count, or more where their adaptive substeps met fast hair
    /// ([`hair_core::dynamics::SimulationSettings::adaptive`]).
    #[serde(default)]
    pub max_substeps: u32,
    /// Strands the renderer drew (the first view; 0 when not drawn): after strand thinning and
    /// dissolves, which [`drawn_segments`](Self::drawn_segments) does not see.
    #[serde(default)]
    pub rendered_strands: usize,
    /// Their segments, each strand tessellated as its chain is at its distance.
    #[serde(default)]
    pub rendered_strand_segments: usize,
    /// Time spent building deforming bodies' collision bodies at the frame's end [s] (their
    /// mesh, triangle tree, pseudonormals and vertex velocities); counted in
    /// [`StageTimes::collision`] too. 0 for rigid bodies.
    #[serde(default)]
    pub body_update: f64,
    /// Time per stage [s].
    pub times: StageTimes,
}

impl FrameReport {
    /// Calibrates a frame budget's cost model with this finished frame: each level block's
    /// dynamics and collision time per node, and the rendering time (when the frame was drawn)
    /// against the segments drawn and pixels covered at each level.
    pub fn calibrate(&self, model: &mut hair_core::lod::CostModel) {
        let render = (self.times.rendering > 0.0).then_some(hair_core::lod::RenderSample {
            seconds: self.times.rendering,
            drawn_segments: self.drawn_at,
            pixels: self.pixels_at,
        });
        model.observe(self.level_seconds, self.level_nodes, render);
    }

    /// Adds another character's report of the same frame: counts, work and stage times summed,
    /// the largest stretch kept (the frame and time stay this report's).
    pub fn add(&mut self, other: &FrameReport) {
        for level in 0..3 {
            self.sections_at[level] += other.sections_at[level];
            self.drawn_at[level] += other.drawn_at[level];
            self.pixels_at[level] += other.pixels_at[level];
            self.level_seconds[level] += other.level_seconds[level];
            self.level_nodes[level] += other.level_nodes[level];
            self.level_dynamics[level] += other.level_dynamics[level];
            self.level_collision[level] += other.level_collision[level];
        }
        self.visible_sections += other.visible_sections;
        self.level_changes += other.level_changes;
        self.visibility_changes += other.visibility_changes;
        self.blending_sections += other.blending_sections;
        self.simulated_nodes += other.simulated_nodes;
        self.drawn_segments += other.drawn_segments;
        self.contacts += other.contacts;
        self.max_stretch = self.max_stretch.max(other.max_stretch);
        self.max_substeps = self.max_substeps.max(other.max_substeps);
        self.body_update += other.body_update;
        self.times.add(&other.times);
    }
}

/// What the level-of-detail stage of a frame changed ([`crate::pipeline::Pipeline::begin_frame`], summed over a crowd's characters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct LodChanges {
    /// Sections that changed level.
    pub levels: usize,
    /// Sections that came into view or left it.
    pub visibility: usize,
}

impl LodChanges {
    /// Whether any section changed level or visibility.
    pub fn any(&self) -> bool {
        self.levels > 0 || self.visibility > 0
    }

    /// Adds another character's changes.
    pub fn add(&mut self, other: LodChanges) {
        self.levels += other.levels;
        self.visibility += other.visibility;
    }
}
