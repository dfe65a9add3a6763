//! Material parameters of the skeletons and settings of a simulation (integrator, step, failure
//! policy).

use serde::{Deserialize, Serialize};

use crate::dynamics::error::{DynamicsError, non_negative, positive};
use crate::style::{HairStyle, StyleKind};

pub use super::integrator_kind::IntegratorKind;

/// Material of the skeletons: mass, bending stiffness and damping (the same for every chain).
///
/// A skeleton stands for a section, cluster or strand group of many strands, so mass and stiffness
/// are those of the bundle; only their ratio `EI / λ` (and the damping rates) shape the motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DynamicsParams {
    /// Mass per unit length λ [kg/m]. Node `i` gets the lumped mass `λ·(l_i + l_{i+1})/2` [kg].
    pub linear_density: f32,
    /// Bending stiffness EI [N·m²]. The angular spring at the bend between segments `i − 1` and `i`
    /// has stiffness `k_i = EI / ((l_{i−1} + l_i)/2)` [N·m/rad] (the root bend uses `l_0 := l_1`).
    pub bending_stiffness: f32,
    /// Stiffness-proportional (Rayleigh) damping time β [s] of the angular springs: the damping
    /// force is `−β·H·v` with `H` the springs' (Gauss-Newton) stiffness matrix.
    pub bending_damping: f32,
    /// Air drag rate γ [1/s]: each node feels `m·γ·(w − v)` with `w` the wind velocity. It is also
    /// how wind acts on the hair.
    pub air_drag_rate: f32,
}

impl Default for DynamicsParams {
    /// The straight style's parameters.
    fn default() -> Self {
        DynamicsParams::for_style(&HairStyle::straight(0.02))
    }
}

/// Mass per unit length of a bundle of about 150 strands (6.5e-6 kg/m each) [kg/m].
pub const DEFAULT_LINEAR_DENSITY: f32 = 1.0e-3;

impl DynamicsParams {
    /// Bending stiffness per unit mass `EI/λ` [m³/s²] a style uses: curls hold their shape
    /// against gravity only if stiffer than straight hair (a single human hair has about 1.2e-3).
    pub fn stiffness_per_mass(kind: StyleKind) -> f32 {
        match kind {
            StyleKind::Straight => 2.0e-3,
            StyleKind::Wavy => 4.0e-3,
            StyleKind::Curly => 8.0e-3,
        }
    }

    /// Parameters suited to a style: `λ` = [`DEFAULT_LINEAR_DENSITY`], `EI = λ ·`
    /// [`DynamicsParams::stiffness_per_mass`], β = 1 ms, γ = 1.5/s.
    pub fn for_style(style: &HairStyle) -> Self {
        DynamicsParams {
            linear_density: DEFAULT_LINEAR_DENSITY,
            bending_stiffness: DEFAULT_LINEAR_DENSITY * Self::stiffness_per_mass(style.kind),
            bending_damping: 1.0e-3,
            air_drag_rate: 1.5,
        }
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<(), DynamicsError> {
        positive("linear_density (kg/m)", self.linear_density)?;
        non_negative("bending_stiffness (N·m²)", self.bending_stiffness)?;
        non_negative("bending_damping (s)", self.bending_damping)?;
        non_negative("air_drag_rate (1/s)", self.air_drag_rate)?;
        Ok(())
    }
}

/// The recommended XPBD settings' most substeps per 1/60 s step (their base is 8).
pub const XPBD_MAX_SUBSTEPS: u32 = 32;

/// The recommended XPBD settings' largest move of a node per substep relative to its root, as a
/// fraction of its segment's length (see [`AdaptiveSubsteps`]).
pub const XPBD_MAX_COURANT: f32 = 0.2;

/// What a step does when a chain becomes unstable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "policy")]
pub enum FailurePolicy {
    /// Return [`DynamicsError::Unstable`] and restore the state to its value before the step.
    Error,
    /// Redo the failing chain's step with the substep halved, up to `max_halvings` times, then
    /// return the error.
    HalveSubstep {
        /// How many times the substep may be halved (each halving doubles the chain's work).
        max_halvings: u32,
    },
}

/// Whether chain roots are carried by the head or move freely.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RootMode {
    /// Each root follows the head's rigid transform (its position and its frame).
    Attached,
    /// Roots are ordinary nodes with mass and the root bend has no spring (an unattached chain).
    Free,
}

/// How one simulation steps: integrator, step, substeps, roots and failure handling.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationSettings {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Time advanced by one call of `step` [s].
    pub time_step: f32,
    /// Substeps per step (the integrator's step is `time_step / substeps`).
    pub substeps: u32,
    /// Attached or free roots.
    pub roots: RootMode,
    /// What to do when a chain becomes unstable.
    pub on_failure: FailurePolicy,
    /// Speed scale of the energy blow-up test [m/s]: a chain whose kinetic energy per unit mass
    /// exceeds `½·max_speed²` has blown up (real hair moves at a few m/s).
    pub max_speed: f32,
    /// Dynamic follow-the-leader velocity correction `s_damping` of the position-based integrator,
    /// `0..=1` (Müller et al. 2012 use 0.9 to 1).
    pub follow_the_leader_damping: f32,
    /// More substeps in a step where the hair moves fast (`None`: always `substeps`).
    #[serde(default)]
    pub adaptive: Option<AdaptiveSubsteps>,
}

/// Substeps that follow the motion, chain by chain: a chain's step starts at
/// [`SimulationSettings::substeps`] and doubles them until none of its nodes would move more
/// than `max_courant` of its segment's rest length in one substep, measured relative to the
/// chain's root at the start of the step (so a head carried fast but rigidly costs nothing), up
/// to `max_substeps`.
///
/// The count is chosen from the chain's state alone, so a chain moves as it would alone, a run
/// resumed from a saved state steps as the original run did, and nothing depends on the thread
/// count.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveSubsteps {
    /// Most substeps one step may take (a power-of-two multiple of `substeps`).
    pub max_substeps: u32,
    /// Largest move per substep of a node relative to its root, as a fraction of its segment's
    /// rest length (a Courant number, > 0).
    pub max_courant: f32,
}

impl AdaptiveSubsteps {
    /// How many times a step of `time_step` [s] in `substeps` substeps doubles them for nodes
    /// that move at most `relative_speed` segment lengths per second [1/s] relative to their
    /// roots.
    pub fn doublings(&self, time_step: f32, substeps: u32, relative_speed: f32) -> u32 {
        let mut doublings = 0;
        let mut count = substeps;
        while count < self.max_substeps
            && relative_speed * time_step / count as f32 > self.max_courant
        {
            count *= 2;
            doublings += 1;
        }
        doublings
    }
}

impl Default for SimulationSettings {
    /// The recommended settings of the default integrator, [`IntegratorKind::DEFAULT`].
    fn default() -> Self {
        SimulationSettings::recommended(IntegratorKind::DEFAULT)
    }
}

impl SimulationSettings {
    /// Settings for `integrator` with a step of `time_step` [s] and `substeps` substeps; failures
    /// are errors, roots attached, `max_speed` 50 m/s, `s_damping` 0.9.
    pub fn new(integrator: IntegratorKind, time_step: f32, substeps: u32) -> Self {
        SimulationSettings {
            integrator,
            time_step,
            substeps,
            roots: RootMode::Attached,
            on_failure: FailurePolicy::Error,
            max_speed: 50.0,
            follow_the_leader_damping: 0.9,
            adaptive: None,
        }
    }

    /// The recommended settings of each integrator for a 60 Hz frame, from the stability map
    /// (`hairlod stability`): the substep each needs to stay stable and accurate on the styles'
    /// stiffness range with the default damping.
    ///
    /// XPBD starts at 8 substeps and doubles them, up to [`XPBD_MAX_SUBSTEPS`], where the hair
    /// moves fast ([`XPBD_MAX_COURANT`]); the others take a fixed count.
    pub fn recommended(integrator: IntegratorKind) -> Self {
        let substeps = match integrator {
            IntegratorKind::SemiImplicitEuler => 16,
            IntegratorKind::PositionBased => 4,
            IntegratorKind::LinearImplicit => 4,
            IntegratorKind::Xpbd => 8,
        };
        let mut settings = SimulationSettings::new(integrator, 1.0 / 60.0, substeps);
        if integrator == IntegratorKind::Xpbd {
            settings.adaptive = Some(AdaptiveSubsteps {
                max_substeps: XPBD_MAX_SUBSTEPS,
                max_courant: XPBD_MAX_COURANT,
            });
        }
        settings
    }

    /// The substeps of a chain's step whose fastest node moves `relative_speed` segment lengths
    /// per second [1/s] relative to its root: `substeps`, doubled as [`Self::adaptive`] asks.
    pub fn substeps_for(&self, relative_speed: f32) -> u32 {
        match &self.adaptive {
            None => self.substeps,
            Some(adaptive) => {
                self.substeps << adaptive.doublings(self.time_step, self.substeps, relative_speed)
            }
        }
    }

    /// `×8`, or `×8–32` where the substeps adapt to the motion (for tables and charts).
    pub fn substeps_label(&self) -> String {
        match self.max_substeps() {
            max if max > self.substeps => format!("×{}–{max}", self.substeps),
            _ => format!("×{}", self.substeps),
        }
    }

    /// The most substeps a step can take: `substeps`, or the adaptive limit when that is larger.
    pub fn max_substeps(&self) -> u32 {
        self.substeps_for(f32::INFINITY)
    }

    /// The integrator's step `time_step / substeps` [s].
    pub fn substep(&self) -> f32 {
        self.time_step / self.substeps as f32
    }

    /// Checks every setting, naming the first one out of range.
    pub fn validate(&self) -> Result<(), DynamicsError> {
        positive("time_step (s)", self.time_step)?;
        if self.substeps == 0 || self.substeps > 1 << 16 {
            return Err(DynamicsError::invalid(
                "substeps",
                self.substeps,
                "1..=65536",
            ));
        }
        if let FailurePolicy::HalveSubstep { max_halvings } = self.on_failure {
            if max_halvings > 16 {
                return Err(DynamicsError::invalid(
                    "max_halvings",
                    max_halvings,
                    "0..=16",
                ));
            }
        }
        if let Some(adaptive) = &self.adaptive {
            if adaptive.max_substeps == 0 || adaptive.max_substeps > 1 << 16 {
                return Err(DynamicsError::invalid(
                    "adaptive.max_substeps",
                    adaptive.max_substeps,
                    "1..=65536",
                ));
            }
            positive("adaptive.max_courant", adaptive.max_courant)?;
        }
        positive("max_speed (m/s)", self.max_speed)?;
        let s = self.follow_the_leader_damping;
        if !(0.0..=1.0).contains(&s) {
            return Err(DynamicsError::invalid(
                "follow_the_leader_damping",
                s,
                "0..=1",
            ));
        }
        Ok(())
    }
}
