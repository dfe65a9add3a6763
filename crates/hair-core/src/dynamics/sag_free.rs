//! Sag-free initialisation: turn each angular spring's natural direction so that a skeleton's rest
//! shape is a static equilibrium under gravity, without changing its stiffness (in the spirit of
//! Hsu et al. 2023, "Sag-free initialization for strand-based hybrid hair simulation", for this
//! skeleton's angular springs).
//!
//! **The balance.** A chain with its root held and fixed segment lengths is statically determinate.
//! Cut it at node `i − 1`: the nodes `i..n` feel gravity, the length constraint of segment `i`
//! (a force through node `i − 1`, no moment about it) and the springs. The springs beyond joint `i`
//! act in pairs inside the cut piece, so its moment balance about node `i − 1` reads
//!
//! `τ_i + Σ_{j ≥ i} (x_j − x_{i−1}) × m_j·g = 0` (components across `d_i`),
//!
//! where `τ_i = k_i·α_i·(d_i × r_i)/|d_i × r_i|` is the torque of spring `i` on segment `i`
//! ([`add_spring_forces`](super::add_spring_forces)). Across `d_i` there are two equations per
//! joint for the two unknown angles of `r_i`; the component along `d_i` is the next joint's
//! balance. Without the twist that parallel transport carries along a bent chain, `τ_i` depends on
//! `r_i` alone and the balance gives `r_i` in closed form: `d_i` turned by the rotation vector
//! `ρ_i = −M_i⊥ / k_i`. The twist couples the joints at second order in the bend angles, so the
//! module iterates: measure the whole moment `M_i` of the exact forces (twist included), turn each
//! `r_i` by `−M_i⊥ / k_i` more, until every `|M_i⊥|` is below [`SAG_FREE_TOLERANCE`] of the
//! chain's gravity moment.
//!
//! **Limits.** The hair keeps its stiffness. A spring turned by `α` from its segment resists a
//! further bend with stiffness `k`, but a swing of the segment around its natural direction only
//! with `k·α·cot α`, which falls to zero at a quarter turn: past it the balance is unstable and
//! the hair rolls over. So a shape that needs a spring turned by more than [`MAX_NATURAL_TURN`]
//! (a long soft strand held out horizontally) is refused with the chain and node named
//! ([`TurnLimit::Refuse`]), or, for a shape that rests on a body, the spring turns that far and
//! the body carries the rest of the load ([`TurnLimit::Clamp`]; the shape then sinks onto the body
//! until it does, which `hairlod::hang_groom` lets happen before it takes the shape).
//!
//! **Contacts.** The constant contact forces a collision stage puts on a shape resting on a body
//! (friction, which opposes the weight's slide along the body) enter as loads; without them the
//! springs and the friction would both hold the weight, and push the hair up the body. The search
//! starts from the springs' current natural directions (the balance is unique where no spring is
//! clamped; where one is, the others keep what they had). The equilibrium is that of the forces,
//! so every integrator whose fixed point is `F(x) = 0` keeps it (semi-implicit, linear-implicit
//! and XPBD); the position-based integrator's constraint projection has its own fixed points.
//! Roots must be attached ([`RootMode::Attached`](super::RootMode)), and gravity and the head pose
//! are those given: a head turned away from that pose sags again, as real hair does.

use glam::{Quat, Vec3, Vec4};

use crate::dynamics::error::DynamicsError;
use crate::dynamics::forces::{add_spring_forces, rest_direction, transport};
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::params::DynamicsParams;
use crate::frame::Frame;
use crate::skeleton::SkeletonRest;
use crate::transform::RigidTransform;

/// Iterations stop when every joint's unbalanced moment is below this fraction of the largest
/// gravity moment of its chain.
pub const SAG_FREE_TOLERANCE: f32 = 1e-4;

/// Most iterations per chain (a chain of moderate bends converges in 3 to 6).
pub const SAG_FREE_MAX_ITERATIONS: usize = 60;

/// The largest turn [rad] of a spring's natural direction from its segment that sag-free
/// initialisation gives: beyond it the hair is too soft to hold the shape by itself.
pub const MAX_NATURAL_TURN: f32 = 1.5;

/// What [`make_sag_free`] does where a spring would have to turn by more than
/// [`MAX_NATURAL_TURN`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TurnLimit {
    /// Fail with [`DynamicsError::TooSoftToHold`]: for shapes in free air, which nothing else
    /// holds.
    Refuse,
    /// Turn it by [`MAX_NATURAL_TURN`] and leave the rest of the load to contact: for shapes that
    /// rest on the body, which carries what the springs cannot (counted in
    /// [`SagFreeReport::clamped_joints`]).
    Clamp,
}

/// What [`make_sag_free`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct SagFreeReport {
    /// Chains made sag-free.
    pub chains: usize,
    /// The largest turn of a natural direction from its segment [rad].
    pub max_turn: f32,
    /// The mean turn over all joints [rad].
    pub mean_turn: f32,
    /// The most iterations a chain needed.
    pub max_iterations: usize,
    /// The largest remaining unbalanced moment at a joint that is not clamped, as a fraction of
    /// its chain's gravity moment.
    pub max_residual: f32,
    /// Joints turned by [`MAX_NATURAL_TURN`] only ([`TurnLimit::Clamp`]), whose remaining load
    /// rests on contact.
    pub clamped_joints: usize,
}

/// Rewrites the natural angles of every chain of `rest` so that its rest shape, with the head at
/// `head`, is a static equilibrium of the springs of `params` under `gravity` [m/s²] and the
/// constant `contact_forces` [N] a body puts on the shape at rest (one per node, world frame;
/// empty for none), see the module docs. The search starts from the current natural angles. The
/// rest angles, lengths and roots are kept. Where a spring would have to turn by more than
/// [`MAX_NATURAL_TURN`], `limit` says whether to fail (changing nothing) or to clamp.
pub fn make_sag_free(
    rest: &mut SkeletonRest,
    params: &DynamicsParams,
    head: &RigidTransform,
    gravity: Vec3,
    contact_forces: &[Vec3],
    limit: TurnLimit,
) -> Result<SagFreeReport, DynamicsError> {
    if !contact_forces.is_empty() && contact_forces.len() != rest.node_count() {
        return Err(DynamicsError::StateMismatch {
            what: "contact forces",
            actual: contact_forces.len(),
            expected: rest.node_count(),
        });
    }
    if let Some(bad) = contact_forces.iter().position(|force| !force.is_finite()) {
        return Err(DynamicsError::invalid(
            "contact force",
            format!("{} at node {bad}", contact_forces[bad]),
            "finite forces [N]",
        ));
    }
    let model = DynamicsModel::new(rest.clone(), *params)?;
    let positions = rest.rest_positions(head);
    let mut natural_polar = rest.natural_polar_angles.clone();
    let mut natural_azimuth = rest.natural_azimuth_angles.clone();
    let mut report = SagFreeReport::default();
    let mut turn_sum = 0.0f64;
    let mut joints = 0usize;
    for chain in 0..rest.chain_count() {
        let nodes = rest.nodes(chain);
        let root_frame = rest.world_root_frame(chain, head);
        let balanced = balance_chain(
            ChainInputs {
                positions: &positions[nodes.clone()],
                root_frame: &root_frame,
                masses: &model.node_masses[nodes.clone()],
                stiffness: &model.joint_stiffness[nodes.clone()],
                loads: contact_forces.get(nodes.clone()).unwrap_or(&[]),
                natural_local: &model.rest_local_directions[nodes.clone()],
            },
            gravity,
            limit,
        )
        .map_err(|(node, turn)| DynamicsError::TooSoftToHold {
            chain,
            node,
            turn,
            max_turn: MAX_NATURAL_TURN,
        })?;
        for (i, local) in balanced.local_directions.iter().enumerate().skip(1) {
            // atan2 keeps small angles exact where acos of a cosine near 1 would not.
            let polar = local.truncate().length().atan2(local.z);
            let azimuth = if polar > 1e-7 {
                local.y.atan2(local.x)
            } else {
                0.0
            };
            natural_polar[nodes.start + i] = polar;
            natural_azimuth[nodes.start + i] = azimuth;
        }
        report.chains += 1;
        report.max_turn = report.max_turn.max(balanced.max_turn);
        report.max_iterations = report.max_iterations.max(balanced.iterations);
        report.max_residual = report.max_residual.max(balanced.residual);
        report.clamped_joints += balanced.clamped;
        turn_sum += balanced.turn_sum as f64;
        joints += nodes.len() - 1;
    }
    report.mean_turn = if joints > 0 {
        (turn_sum / joints as f64) as f32
    } else {
        0.0
    };
    rest.natural_polar_angles = natural_polar;
    rest.natural_azimuth_angles = natural_azimuth;
    Ok(report)
}

/// One chain's balance.
struct Balanced {
    /// Natural directions in the transported parent frames (normal, binormal, tangent), one per
    /// node (the root's unused).
    local_directions: Vec<Vec3>,
    iterations: usize,
    residual: f32,
    max_turn: f32,
    turn_sum: f32,
    clamped: usize,
}

/// One chain's data for [`balance_chain`], each slice one entry per node.
struct ChainInputs<'a> {
    /// Node positions [m], world, root first.
    positions: &'a [Vec3],
    /// The root frame, world.
    root_frame: &'a Frame,
    /// Node masses [kg].
    masses: &'a [f32],
    /// Joint stiffnesses [N·m/rad].
    stiffness: &'a [f32],
    /// Constant loads besides gravity [N] (or empty).
    loads: &'a [Vec3],
    /// The springs' current natural directions in their parent frames (local coordinates).
    natural_local: &'a [Vec3],
}

/// Finds the natural directions that balance one chain; on failure returns the node and the
/// turn it would need.
fn balance_chain(
    chain: ChainInputs<'_>,
    gravity: Vec3,
    limit: TurnLimit,
) -> Result<Balanced, (usize, f32)> {
    let ChainInputs {
        positions,
        root_frame,
        masses,
        stiffness,
        loads,
        natural_local,
    } = chain;
    let n = positions.len();
    // Segment directions and the parent frame of every joint, transported along the shape.
    let mut directions = vec![Vec3::ZERO; n];
    let mut parent_frames = vec![*root_frame; n];
    let mut frame = *root_frame;
    for i in 1..n {
        let direction = (positions[i] - positions[i - 1])
            .try_normalize()
            .unwrap_or(frame.tangent);
        directions[i] = direction;
        parent_frames[i] = frame;
        frame = transport(&frame, direction);
    }
    // Rotation vectors ρ_i (⊥ d_i) taking each segment to its spring's natural direction.
    let mut turns = vec![Vec3::ZERO; n];
    let mut clamped = vec![false; n];
    let mut local = vec![Vec3::Z; n];
    let to_local = |frame: &Frame, world: Vec3| {
        Vec3::new(
            frame.normal.dot(world),
            frame.binormal.dot(world),
            frame.tangent.dot(world),
        )
    };
    // Start from the springs' current natural directions.
    for i in 1..n {
        local[i] = natural_local[i];
        let natural = rest_direction(&parent_frames[i], natural_local[i]);
        let d = directions[i];
        let axis = d.cross(natural);
        let sin = axis.length();
        if sin > 1e-12 {
            turns[i] = axis / sin * sin.atan2(d.dot(natural));
        }
    }
    let zero = vec![Vec3::ZERO; n];
    let mut work = vec![Vec4::ZERO; n];
    let mut forces = vec![Vec3::ZERO; n];
    let mut moments = vec![Vec3::ZERO; n];
    // The loads' moments alone set the scale of the tolerance.
    let weights: Vec<Vec3> = masses
        .iter()
        .enumerate()
        .map(|(i, &m)| gravity * m + loads.get(i).copied().unwrap_or(Vec3::ZERO))
        .collect();
    cut_moments(positions, &weights, &mut moments);
    let scale = moments.iter().map(|m| m.length()).fold(0.0f32, f32::max);
    let tolerance = SAG_FREE_TOLERANCE * scale;
    let mut iterations = 0;
    let mut residual;
    loop {
        forces.fill(Vec3::ZERO);
        add_spring_forces(
            positions,
            &zero,
            root_frame,
            Vec3::ZERO,
            &local,
            stiffness,
            0.0,
            false,
            &mut work,
            &mut forces,
        );
        for (force, weight) in forces.iter_mut().zip(&weights) {
            *force += *weight;
        }
        cut_moments(positions, &forces, &mut moments);
        residual = 0.0f32;
        for i in 1..n {
            let d = directions[i];
            let across = moments[i] - d * d.dot(moments[i]);
            if !clamped[i] {
                residual = residual.max(across.length());
            }
            moments[i] = across;
        }
        if residual <= tolerance || iterations == SAG_FREE_MAX_ITERATIONS {
            break;
        }
        iterations += 1;
        for i in 1..n {
            if stiffness[i] <= 0.0 {
                continue;
            }
            let d = directions[i];
            let mut turn = turns[i] - moments[i] / stiffness[i];
            turn -= d * d.dot(turn);
            let mut angle = turn.length();
            if angle > MAX_NATURAL_TURN {
                match limit {
                    TurnLimit::Refuse => return Err((i, angle)),
                    TurnLimit::Clamp => {
                        turn *= MAX_NATURAL_TURN / angle;
                        angle = MAX_NATURAL_TURN;
                        clamped[i] = true;
                    }
                }
            } else {
                clamped[i] = false;
            }
            turns[i] = turn;
            let natural = if angle > 0.0 {
                Quat::from_axis_angle(turn / angle, angle) * d
            } else {
                d
            };
            local[i] = to_local(&parent_frames[i], natural.normalize());
        }
    }
    let max_turn = turns.iter().map(|t| t.length()).fold(0.0f32, f32::max);
    let turn_sum = turns.iter().map(|t| t.length()).sum();
    Ok(Balanced {
        local_directions: local,
        iterations,
        residual: if scale > 0.0 { residual / scale } else { 0.0 },
        max_turn,
        turn_sum,
        clamped: clamped.iter().filter(|&&c| c).count(),
    })
}

/// `moments[i] = Σ_{j ≥ i} (x_j − x_{i−1}) × f_j` for `i ≥ 1`: the moment about node `i − 1` of
/// the forces on the piece of chain beyond it (`moments[0]` is unused), by suffix sums.
fn cut_moments(positions: &[Vec3], forces: &[Vec3], moments: &mut [Vec3]) {
    let mut force_sum = Vec3::ZERO;
    let mut moment_sum = Vec3::ZERO;
    for i in (1..positions.len()).rev() {
        force_sum += forces[i];
        moment_sum += positions[i].cross(forces[i]);
        moments[i] = moment_sum - positions[i - 1].cross(force_sum);
    }
}
