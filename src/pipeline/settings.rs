//! What the frame pipeline runs: automatic levels or one fixed level, how the levels are drawn,
//! the dynamics settings, collision on or off and how it finds the hair near the head.

use hair_collide::BroadPhase;
use hair_core::Level;
use hair_core::dynamics::{IntegratorKind, SimulationSettings};
use hair_core::lod::LodSettings;
use serde::{Deserialize, Serialize};

/// How sections get their level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LodMode {
    /// Chosen every frame by the selector (§7).
    Auto(LodSettings),
    /// Every section at this level, visible or not (the paper's Strands, Clusters and Patches
    /// columns).
    Fixed(Level),
}

hair_core::named_enum! {
    /// What a run's levels were, by the paper's column names (reports, tables and charts):
    /// [`ModeRun::mode`](crate::run::ModeRun::mode).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub enum RunMode {
        /// Automatic levels.
        Lods = "LODs",
        /// Every section as strand groups.
        Strands = "Strands",
        /// Every section as clusters.
        Clusters = "Clusters",
        /// Every section as a patch.
        Patches = "Patches",
        /// Automatic levels switched at once, without blends (the paper's popping study).
        LodsInstantSwitching = "LODs, instant switching",
        /// Automatic levels within a frame budget.
        LodsFrameBudget = "LODs, frame budget",
    }
}

impl LodMode {
    /// The run's mode: `LODs`, `Strands`, `Clusters` or `Patches` (the paper's columns).
    pub fn run_mode(&self) -> RunMode {
        match self {
            LodMode::Auto(_) => RunMode::Lods,
            LodMode::Fixed(Level::StrandGroup) => RunMode::Strands,
            LodMode::Fixed(Level::Cluster) => RunMode::Clusters,
            LodMode::Fixed(Level::Patch) => RunMode::Patches,
        }
    }

    /// The name used in reports: `LODs`, `Strands`, `Clusters` or `Patches` (the paper's columns).
    pub fn column_name(&self) -> &'static str {
        self.run_mode().name()
    }
}

hair_core::named_enum! {
    /// How a section is drawn, whatever level it is simulated at.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub enum DrawnAs {
        /// Each level as itself (the paper): strand groups as their strands, clusters as
        /// textured tubes, a patch as a textured strip.
        #[default]
        Level = "level",
        /// Every level as strands: a section simulated as clusters or as a patch has its five
        /// strand-group skeletons rebuilt each frame from its simulated skeletons, each node
        /// kept at its rest offset from the source nodes beside it
        /// ([`StrandFollow`](hair_core::lod::StrandFollow)), and its strands drawn on them. The
        /// simulation's cost stays the level's; the drawing costs what the strands cost (thin
        /// them with [`strands_per_pixel`](hair_core::lod::LodSettings::strands_per_pixel) and
        /// widen those kept with
        /// [`raise_thinned_widths`](hair_core::lod::LodSettings::raise_thinned_widths)).
        Strands = "strands",
    }
}

/// Settings of a [`Pipeline`](super::Pipeline).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipelineSettings {
    /// Level selection.
    pub lod: LodMode,
    /// How the levels are drawn: each as itself (the default) or all as strands.
    pub drawn_as: DrawnAs,
    /// Integrator, frame time step (one step per frame) and substeps.
    pub dynamics: SimulationSettings,
    /// Hair-head collision (response, friction and the positional guarantee) on.
    pub collision: bool,
    /// How the collision stage finds the hair near the head: contacts from the head's distance
    /// field (the default), or the exact triangle tests through the paper's hierarchies or
    /// culled by the field (see [`BroadPhase`]).
    pub broad_phase: BroadPhase,
}

impl PipelineSettings {
    /// How many of each strand group's strands are drawn: thinned to the LOD settings'
    /// [`strands_per_pixel`](hair_core::lod::LodSettings::strands_per_pixel) in automatic mode
    /// (when above 0), all of them at a fixed level.
    pub fn strand_thinning(&self) -> hair_render::StrandThinning {
        match self.lod {
            LodMode::Auto(lod) if lod.strands_per_pixel > 0.0 => {
                hair_render::StrandThinning::ByScreenWidth {
                    strands_per_pixel: lod.strands_per_pixel,
                    raise_widths: lod.raise_thinned_widths,
                }
            }
            _ => hair_render::StrandThinning::Off,
        }
    }
}

impl Default for PipelineSettings {
    /// Automatic levels with default settings, each drawn as itself, the default integrator
    /// ([`IntegratorKind::DEFAULT`], XPBD) at its recommended 60 Hz settings (8 substeps, up to
    /// 32 where the hair moves fast), collision on
    /// with contacts from the head's distance field.
    fn default() -> Self {
        PipelineSettings {
            lod: LodMode::Auto(LodSettings::default()),
            drawn_as: DrawnAs::default(),
            dynamics: SimulationSettings::recommended(IntegratorKind::DEFAULT),
            collision: true,
            broad_phase: BroadPhase::default(),
        }
    }
}
