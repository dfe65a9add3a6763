//! One substep of one chain for the two force-based integrators, semi-implicit Euler and
//! linear-implicit (the position-based and XPBD steps are lane kernels: `position_based.rs`,
//! `xpbd.rs`), and the lengths' stiffness the implicit steps share.
//!
//! Both evaluate forces at the start of the substep (time `t`, head pose at `t`), carry
//! attached roots to the head pose at `t + h` and end with every segment at its rest length.

use glam::{Mat3, Vec3, Vec4};

use crate::dynamics::banded::{cross_matrix, outer, solve_block_pentadiagonal};
use crate::dynamics::constraints::{follow_the_leader, project_lengths};
use crate::dynamics::forces::{Joint, add_external_forces, add_spring_forces, walk_joints};
use crate::dynamics::params::{DynamicsParams, RootMode};
use crate::frame::Frame;
use crate::transform::RigidTransform;

/// The constants of one chain (slices of the model's per-node arrays).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ChainConstants<'a> {
    pub masses: &'a [f32],
    pub rest_lengths: &'a [f32],
    pub stiffness: &'a [f32],
    pub rest_local: &'a [Vec3],
    /// Root position in head space [m].
    pub root_position: Vec3,
    /// Root frame in head space.
    pub root_frame: Frame,
}

/// The implicit integrator's per-node scratch of one chain.
pub(crate) struct ImplicitArrays<'a> {
    pub diagonal: &'a mut [Mat3],
    pub first: &'a mut [Mat3],
    pub second: &'a mut [Mat3],
    pub rhs: &'a mut [Vec3],
}

/// The state and scratch of one chain.
pub(crate) struct ChainArrays<'a> {
    pub positions: &'a mut [Vec3],
    pub velocities: &'a mut [Vec3],
    pub collision: &'a [Vec3],
    /// Wind velocities [m/s] at the nodes, sampled at the start of the step and held over its
    /// substeps (like the collision forces).
    pub wind: &'a mut [Vec3],
    /// Forces [N]; the position-based integrator reuses it for the positions at the substep start.
    pub forces: &'a mut [Vec3],
    /// Follow-the-leader corrections [m] (position-based integrator).
    pub corrections: &'a mut [Vec3],
    /// Scratch of the springs' twist pass.
    pub work: &'a mut [Vec4],
    pub implicit: Option<ImplicitArrays<'a>>,
}

/// What one substep needs besides the chain.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Substep<'a> {
    /// Length [s].
    pub h: f32,
    pub head_start: RigidTransform,
    pub head_end: RigidTransform,
    /// The head's angular velocity over the substep [rad/s].
    pub head_spin: Vec3,
    pub gravity: Vec3,
    pub params: &'a DynamicsParams,
    pub roots: RootMode,
}

impl Substep<'_> {
    pub(crate) fn attached(&self) -> bool {
        self.roots == RootMode::Attached
    }

    /// First integrated node: 1 with attached roots, 0 with free ones.
    pub(crate) fn first_free_node(&self) -> usize {
        usize::from(self.attached())
    }
}

/// Root position [m] at the end of the substep and root velocity [m/s] over it.
pub(crate) fn root_motion(chain: &ChainConstants, step: &Substep) -> (Vec3, Vec3) {
    let start = step.head_start.transform_point(chain.root_position);
    let end = step.head_end.transform_point(chain.root_position);
    (end, (end - start) / step.h)
}

/// External forces at the substep start: gravity, drag towards the wind, collision.
fn external_forces(chain: &ChainConstants, arrays: &mut ChainArrays, step: &Substep, drag: f32) {
    arrays.forces.fill(Vec3::ZERO);
    let wind = &*arrays.wind;
    add_external_forces(
        chain.masses,
        arrays.velocities,
        |i| wind[i],
        arrays.collision,
        step.gravity,
        drag,
        arrays.forces,
    );
}

/// Semi-implicit Euler: `v ← v + h·F/m`, `x ← x + h·v`, then follow-the-leader lengths and the
/// stretching velocity removed (the paper's model).
pub(crate) fn semi_implicit_euler(
    chain: &ChainConstants,
    arrays: &mut ChainArrays,
    step: &Substep,
) {
    let h = step.h;
    external_forces(chain, arrays, step, step.params.air_drag_rate);
    let root_frame = step.head_start.transform_frame(&chain.root_frame);
    add_spring_forces(
        arrays.positions,
        arrays.velocities,
        &root_frame,
        step.head_spin,
        chain.rest_local,
        chain.stiffness,
        step.params.bending_damping,
        !step.attached(),
        arrays.work,
        arrays.forces,
    );
    // `forces` then holds the predicted positions.
    for i in step.first_free_node()..arrays.positions.len() {
        arrays.velocities[i] += arrays.forces[i] * (h / chain.masses[i]);
        arrays.positions[i] += arrays.velocities[i] * h;
        arrays.forces[i] = arrays.positions[i];
    }
    finish_with_projection(chain, arrays, step);
}

/// Newton iterations of the mass-weighted length projection.
const PROJECTION_ITERATIONS: usize = 3;

/// Carries an attached root, projects onto the segment lengths (mass-weighted fast projection,
/// then follow-the-leader for the last rounding) and adds the projection's displacement to the
/// velocities, `v ← v + (x' − x_pred)/h`, where `arrays.forces` holds the predicted positions
/// `x_pred = x + h·v` of the free nodes: the velocity of the projected motion `(x' − x)/h`,
/// written so that a projection below the positions' rounding leaves the velocities alone (taking
/// `(x' − x)/h` from stored f32 positions quantises velocities to `ulp(x)/h`, a noise that never
/// settles). (Keeping the integrated velocities with only their stretching part removed instead
/// lets the projection feed energy into a swinging chain: measured, it blows up even without
/// springs.)
fn finish_with_projection(chain: &ChainConstants, arrays: &mut ChainArrays, step: &Substep) {
    if step.attached() {
        let (root, root_velocity) = root_motion(chain, step);
        arrays.positions[0] = root;
        arrays.velocities[0] = root_velocity;
    }
    let attached = step.attached();
    project_lengths(
        arrays.positions,
        |i| {
            if i == 0 && attached {
                0.0
            } else {
                1.0 / chain.masses[i]
            }
        },
        chain.rest_lengths,
        arrays.corrections,
        arrays.work,
        PROJECTION_ITERATIONS,
    );
    follow_the_leader(arrays.positions, chain.rest_lengths);
    let inverse_h = 1.0 / step.h;
    for i in step.first_free_node()..arrays.positions.len() {
        arrays.velocities[i] += (arrays.positions[i] - arrays.forces[i]) * inverse_h;
    }
}

/// Adds one spring's Gauss-Newton stiffness `c·J_iᵀJ_i` (`J_i = ∂(d_i − r_i)/∂x`, the local
/// blocks `Q`, `S − Q`, `−S` of [`Joint`]) to the block-pentadiagonal system of its chain:
/// `diagonal[i] = A_ii`, `first[i] = A_{i,i−1}`, `second[i] = A_{i,i−2}`.
pub(crate) fn add_spring_blocks(joint: &Joint, c: f32, implicit: &mut ImplicitArrays) {
    let i = joint.node;
    let q = (Mat3::IDENTITY - outer(joint.direction, joint.direction)) * (1.0 / joint.length);
    implicit.diagonal[i] += q * q * c;
    if let Some((parent_direction, parent_length)) = joint.parent {
        let s = cross_matrix(joint.rest_direction)
            * cross_matrix(parent_direction)
            * (1.0 / parent_length);
        let middle = s - q;
        implicit.diagonal[i - 1] += middle.transpose() * middle * c;
        implicit.diagonal[i - 2] += s.transpose() * s * c;
        implicit.first[i] += q * middle * c;
        implicit.second[i] -= q * s * c;
        implicit.first[i - 1] -= middle.transpose() * s * c;
    } else {
        implicit.diagonal[i - 1] += q * q * c;
        implicit.first[i] -= q * q * c;
    }
}

/// The lengths' stiffness in an implicit step, relative to the larger of the inertia `m/h²` and
/// the bending stiffness `k/l²` at the segment.
pub(crate) const LENGTH_STIFFNESS: f32 = 100.0;

/// The lengths' stiffness κ_j [N/m] in an implicit step:
/// `κ_j = LENGTH_STIFFNESS·max(m_j/h², k_j/l_j², k_{j+1}/l_j²)`.
#[inline]
pub(crate) fn length_stiffness(chain: &ChainConstants, j: usize, inverse_h_squared: f32) -> f32 {
    let rest = chain.rest_lengths[j];
    let next = chain.stiffness.get(j + 1).copied().unwrap_or(0.0);
    let bending = chain.stiffness[j].max(next) / (rest * rest);
    LENGTH_STIFFNESS * (chain.masses[j] * inverse_h_squared).max(bending)
}

/// Adds the segment lengths as stiff springs `½·κ_j·(|x_j − x_{j−1}| − l_j)²`
/// ([`length_stiffness`]) to an implicit step: their forces to `forces` (when given) and their
/// Gauss-Newton blocks `κ·u·uᵀ` (on `(j, j)`, `(j−1, j−1)`, and `−κ·u·uᵀ` on `(j, j−1)`), times
/// `block_weight`, to the block-pentadiagonal system's `diagonal` and `first`. Returns their
/// energy [J].
pub(crate) fn add_length_springs(
    chain: &ChainConstants,
    positions: &[Vec3],
    inverse_h_squared: f32,
    block_weight: f32,
    mut forces: Option<&mut [Vec3]>,
    diagonal: &mut [Mat3],
    first: &mut [Mat3],
) -> f32 {
    let mut energy = 0.0;
    for j in 1..positions.len() {
        let segment = positions[j] - positions[j - 1];
        let length = segment.length();
        if length <= 1e-12 {
            continue;
        }
        let u = segment / length;
        let kappa = length_stiffness(chain, j, inverse_h_squared);
        let stretch = length - chain.rest_lengths[j];
        energy += 0.5 * kappa * stretch * stretch;
        if let Some(forces) = forces.as_deref_mut() {
            let force = u * (kappa * stretch);
            forces[j] -= force;
            forces[j - 1] += force;
        }
        let block = outer(u, u) * (kappa * block_weight);
        diagonal[j] += block;
        diagonal[j - 1] += block;
        first[j] -= block;
    }
    energy
}

/// Adds to `forces` the segment tensions that would hold the chain's nodes `1..n` in balance if it
/// were at rest: cutting segment `i`, `T_i = d_i·Σ_{j ≥ i} F_j`, which pulls node `i` by
/// `−T_i·d_i` and node `i − 1` by `+T_i·d_i`. Forces along the segments are what the length
/// constraints absorb, so for exact constraints this changes nothing; for a step that meets the
/// lengths only through stiff springs and a projection afterwards, it takes the quasi-static load
/// off them, and a chain at a static equilibrium of its springs and gravity stays there. For
/// chains held at the root.
pub(crate) fn add_static_tensions(positions: &[Vec3], forces: &mut [Vec3]) {
    let n = positions.len();
    let mut beyond = Vec3::ZERO;
    // Walk tip to root; `beyond` is Σ_{j ≥ i} F_j before segment i's tension is added.
    for i in (1..n).rev() {
        beyond += forces[i];
        let Some(direction) = (positions[i] - positions[i - 1]).try_normalize() else {
            continue;
        };
        let pull = direction * direction.dot(beyond);
        forces[i] -= pull;
        forces[i - 1] += pull;
        // The piece beyond segment i now balances along it.
        beyond -= pull;
    }
}

/// Linearised backward Euler of springs, spring damping and drag, then the length projection.
///
/// For chains held at the root, the step also carries the segment tensions of the chain at rest
/// ([`add_static_tensions`]) and the lengths' stiffness: the step then moves the chain across its
/// segments, not along them, so the projection after it has little to undo. Without them the
/// projection takes back only the part of the step that the mass metric calls stretching, and a
/// chain under tension (hanging hair) comes to rest away from the static equilibrium of its
/// forces, by an amount that grows with `(h·ω)²` (measured on sag-free curls: 2 cm after 2 s;
/// with the stiffness alone 2.2 mm; with both 0.04 mm). It also keeps the step stable on the
/// stiff chains where it used to fail. A free chain (which falls as a whole, with no tension of a
/// chain at rest) keeps the plain step: the lengths' stiffness would amplify the rounding of its
/// rigid motion a hundredfold.
///
/// `(M(1 + hγ) + (hβ + h²)·H + h²·K_len)·v' = M·v + h·(F_spring + F_len + M·g + M·γ·w + F_col)` with
/// `H = Σ k_i J_iᵀJ_i` (block-pentadiagonal along the chain) and the lengths as stiff springs
/// ([`add_length_springs`]), a kinematic root moved to the right-hand side; then
/// `x ← x + h·v'` and the projection of [`semi_implicit_euler`]. Returns `false` when the system
/// could not be factorised (a non-finite entry).
pub(crate) fn linear_implicit(
    chain: &ChainConstants,
    arrays: &mut ChainArrays,
    step: &Substep,
) -> bool {
    let h = step.h;
    let params = step.params;
    let gamma = params.air_drag_rate;
    // External forces without the drag on v (drag is implicit): m·g + m·γ·w + F_col.
    external_forces(chain, arrays, step, 0.0);
    let n = arrays.positions.len();
    let Some(implicit) = arrays.implicit.as_mut() else {
        return false;
    };
    for i in 0..n {
        let m = chain.masses[i];
        arrays.forces[i] += arrays.wind[i] * (m * gamma);
        implicit.diagonal[i] = Mat3::from_diagonal(Vec3::splat(m * (1.0 + h * gamma)));
        implicit.first[i] = Mat3::ZERO;
        implicit.second[i] = Mat3::ZERO;
    }
    let root_frame = step.head_start.transform_frame(&chain.root_frame);
    let skip_root = !step.attached();
    // Spring forces (exact gradient, no damping: damping is implicit below).
    add_spring_forces(
        arrays.positions,
        arrays.velocities,
        &root_frame,
        Vec3::ZERO,
        chain.rest_local,
        chain.stiffness,
        0.0,
        skip_root,
        arrays.work,
        arrays.forces,
    );
    let weight = h * params.bending_damping + h * h;
    let forces = &mut *arrays.forces;
    walk_joints(arrays.positions, &root_frame, chain.rest_local, |joint| {
        let i = joint.node;
        let k = chain.stiffness[i];
        if k == 0.0 || (i == 1 && skip_root) {
            return;
        }
        if i == 1 {
            // The root frame's spin moves r_1: explicit damping term +β·k·J₁ᵀ(ω × r₁).
            let g = step.head_spin.cross(joint.rest_direction) * (params.bending_damping * k);
            let qg = joint.q(g);
            forces[1] += qg;
            forces[0] -= qg;
        }
        add_spring_blocks(joint, weight * k, implicit);
    });
    if step.attached() {
        add_static_tensions(arrays.positions, forces);
        // The lengths as stiff springs in the same solve (h²·κ·u·uᵀ), only their stiffness: the
        // lengths are exact after the last projection, and a force from the rounding of a length
        // (κ·1e-8 m) would be noise of a few percent of the weight at short substeps.
        add_length_springs(
            chain,
            arrays.positions,
            1.0 / (h * h),
            h * h,
            None,
            implicit.diagonal,
            implicit.first,
        );
    }
    for (((rhs, velocity), mass), force) in implicit
        .rhs
        .iter_mut()
        .zip(&*arrays.velocities)
        .zip(chain.masses)
        .zip(&*forces)
    {
        *rhs = *velocity * *mass + *force * h;
    }
    let (root_end, root_velocity) = root_motion(chain, step);
    if step.attached() {
        implicit.rhs[1] -= implicit.first[1] * root_velocity;
        if n > 2 {
            implicit.rhs[2] -= implicit.second[2] * root_velocity;
            implicit.second[2] = Mat3::ZERO;
        }
        implicit.first[1] = Mat3::ZERO;
        implicit.diagonal[0] = Mat3::IDENTITY;
        implicit.rhs[0] = root_velocity;
    }
    if !solve_block_pentadiagonal(
        implicit.diagonal,
        implicit.first,
        implicit.second,
        implicit.rhs,
    ) {
        return false;
    }
    for i in 0..n {
        arrays.velocities[i] = implicit.rhs[i];
        arrays.positions[i] += implicit.rhs[i] * h;
        arrays.forces[i] = arrays.positions[i];
    }
    if step.attached() {
        arrays.positions[0] = root_end;
    }
    finish_with_projection(chain, arrays, step);
    true
}
