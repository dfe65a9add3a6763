//! The collision stage's settings ([`CollisionSettings`]), what each of its halves reports
//! ([`ContactReport`], [`ProjectionReport`], [`CollisionStepReport`]) and the state it carries
//! from step to step ([`VelocityMemory`]).

use glam::Vec3;
use hair_core::dynamics::StepReport;

use crate::broad_phase::BroadPhase;
use crate::error::{CollideError, Result};
use crate::hair_hair::HairHairSettings;

/// The positional guarantee \[m\]: after [`CollisionSolver::after_step`](crate::CollisionSolver::after_step) no simulated node (other
/// than an attached root, which the head carries) is deeper than this inside a closed body.
/// Projection puts nodes [`CollisionSettings::skin`] outside; this allows for f32 rounding
/// at head scale (~10⁻⁸ m) and for creases where the projection of one face lands near another.
pub const PENETRATION_TOLERANCE: f32 = 1.0e-4;

/// How the collision stage responds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionSettings {
    /// Response forces of §5.4 (cancel each touching node's approach over the step).
    pub response: bool,
    /// Friction coefficient μ in `[0, 1]` (§5.4: `−μ ×` the tangential part of the node's
    /// other forces); 0 turns friction off.
    pub friction: f32,
    /// The positional guarantee: project nodes that end a step inside a body back out.
    pub project_positions: bool,
    /// Distance \[m\] outside the surface where projected nodes are placed, in
    /// `[0, PENETRATION_TOLERANCE]`.
    pub skin: f32,
    /// Hair–hair repulsion between sections (beyond the paper); `None` (the default) is off.
    pub hair_hair: Option<HairHairSettings>,
    /// How the hair near a body is found (the same contacts either way).
    pub broad_phase: BroadPhase,
}

impl Default for CollisionSettings {
    /// Response on, μ = 0.3, projection on with a 10 µm skin, hair–hair off, the paper's
    /// hierarchies as the broad phase.
    fn default() -> Self {
        CollisionSettings {
            response: true,
            friction: 0.3,
            project_positions: true,
            skin: 1.0e-5,
            hair_hair: None,
            broad_phase: BroadPhase::default(),
        }
    }
}

impl CollisionSettings {
    /// Checks every setting, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        if !(0.0..=1.0).contains(&self.friction) {
            return Err(CollideError::InvalidParameter {
                name: "friction",
                value: self.friction.to_string(),
                allowed: "0..=1 (a larger coefficient would reverse the pull)",
            });
        }
        if !(0.0..=PENETRATION_TOLERANCE).contains(&self.skin) {
            return Err(CollideError::InvalidParameter {
                name: "skin",
                value: self.skin.to_string(),
                allowed: "0..=1e-4 m",
            });
        }
        if let Some(hair_hair) = &self.hair_hair {
            hair_hair.validate()?;
        }
        Ok(())
    }
}

/// What [`CollisionSolver::before_step`](crate::CollisionSolver::before_step) found.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactReport {
    /// Segments touching a body (summed over bodies).
    pub contact_segments: usize,
    /// `(segment, triangle)` pairs touching (summed over bodies; 0 for contacts from the
    /// distance field, which visits no triangle).
    pub contact_pairs: usize,
    /// Segments that the distance field could not decide and the exact triangle tests did
    /// ([`BroadPhase::FieldContacts`] only).
    pub exact_fallbacks: usize,
    /// Segments a certified clearance remembered from an earlier step cleared without a field
    /// sample ([`FieldContacts::remembered`](crate::FieldContacts::remembered)).
    pub remembered: usize,
    /// Nodes that received a response or friction force.
    pub contact_nodes: usize,
    /// Overlapping segment pairs of different sections (0 when hair–hair is off).
    pub hair_hair_pairs: usize,
    /// Whether the hierarchy was rebuilt (layout changed) rather than refitted.
    pub rebuilt: bool,
}

/// What [`CollisionSolver::after_step`](crate::CollisionSolver::after_step) did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProjectionReport {
    /// Nodes found inside a body and projected out.
    pub projected_nodes: usize,
    /// The deepest penetration found \[m\] (0 when none).
    pub max_depth: f32,
    /// The largest relative length error `|ℓ − ℓ₀| / ℓ₀` of a segment whose lower end was
    /// projected, after the projection (0 when none). A projected segment is turned about its
    /// parent to keep its length; only where no direction at that length is outside (its parent
    /// itself inside: a root set in the scalp) does the position win and the segment stretch,
    /// which a large value reports (see [`STRETCH_WARNING`]).
    pub max_stretch: f32,
}

/// A segment stretched beyond this fraction by the projection (5 %) means the step was too
/// coarse for the hair's motion near the head: front ends warn about it.
pub const STRETCH_WARNING: f32 = 0.05;

/// Both reports of one [`CollisionSolver::step`](crate::CollisionSolver::step), and the dynamics'.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CollisionStepReport {
    /// Contacts and forces before the step.
    pub contacts: ContactReport,
    /// The dynamics step.
    pub dynamics: StepReport,
    /// Projection after the step.
    pub projection: ProjectionReport,
}

/// What the collision response remembers between steps: the node positions [m] at the last
/// [`CollisionSolver::before_step`](crate::CollisionSolver::before_step) and its time [s] (`None` before the first), from which it
/// takes node velocities by finite differences.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VelocityMemory {
    /// Node positions [m] at the last step, one per model node.
    pub positions: Vec<Vec3>,
    /// Time of the last step [s].
    pub time: Option<f64>,
}
