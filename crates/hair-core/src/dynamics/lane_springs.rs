//! The angular spring forces of [`LANES`](crate::dynamics::lanes::LANES) chains at once: the
//! exact gradient of the bending energy (twist terms included) that
//! [`add_spring_forces`](crate::dynamics::add_spring_forces) computes for one chain, without
//! damping, written for the lane-parallel position-based step.
//!
//! The same arithmetic in a cheaper order: one reciprocal of `1 + t·d` serves the twist binormal
//! and the frame transport, `r × g` is the bend axis already at hand, the bend angle and
//! `α/sin α` share one division ([`Lanes::bend_angle_and_factor`]), the forces of a joint are
//! carried in registers until their node is complete, and the transported normal is not
//! re-orthonormalised (the transport is a rotation: it keeps the normal's f32 rounding error at the
//! size it had, ~1e-7 per node, instead of letting it grow). Where a segment is turned back on its
//! parent (`1 + t·d < 1e-4`) the two reflections are undefined, and that lane's frame is carried by
//! [`Frame::transported_to`] instead (the quaternion code chooses an axis), as
//! [`transport`](crate::dynamics::transport) does for one chain.

use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::frame::Frame;

/// `1 + t·d` below which a segment counts as turned back on its parent: the frame is then
/// transported by the quaternion code (as [`transport`](crate::dynamics::transport)).
const REVERSED: f32 = 1e-4;

/// Frames of every lane.
#[derive(Clone, Copy)]
pub(crate) struct LaneFrame {
    pub normal: LaneVec3,
    pub binormal: LaneVec3,
    pub tangent: LaneVec3,
}

/// One segment of every lane seen from its parent frame: what the lane steps' walks along a
/// chain (the springs, the XPBD objective and damping sweep) share.
#[derive(Clone, Copy)]
pub(crate) struct LaneSegment {
    /// The current length [m] (before clamping at 1e-12 for its inverse).
    pub length: Lanes,
    /// `1/max(l, 1e-12)` [1/m].
    pub inverse_length: Lanes,
    /// The unit direction `d`, or the parent tangent where the segment has no length.
    pub direction: LaneVec3,
    /// The rest direction `r` in the parent frame.
    pub rest: LaneVec3,
    /// `1 + t·d`: below [`REVERSED`] the segment is turned back on its parent and the fast
    /// transport undefined.
    pub one_plus_cos: Lanes,
    /// `1/max(1 + t·d, 1e-6)`, shared by the twist binormal and the transport.
    pub inverse_one_plus_cos: Lanes,
}

impl LaneFrame {
    /// The segment from `start` to `end` [m] of every lane, its rest direction `rest_local` in
    /// this (parent) frame.
    #[inline(always)]
    pub(crate) fn segment(
        &self,
        start: LaneVec3,
        end: LaneVec3,
        rest_local: LaneVec3,
    ) -> LaneSegment {
        let one = Lanes::splat(1.0);
        let tiny = Lanes::splat(1e-12);
        let segment = end - start;
        let length = segment.length_squared().sqrt();
        let valid = length.greater(tiny);
        let inverse_length = one / length.max(tiny);
        let tangent = self.tangent;
        let direction = LaneVec3::select(valid, segment.scale(inverse_length), tangent);
        let rest = self.normal.scale(rest_local.x)
            + self.binormal.scale(rest_local.y)
            + tangent.scale(rest_local.z);
        let one_plus_cos = one + tangent.dot(direction);
        let inverse_one_plus_cos = one / one_plus_cos.max(Lanes::splat(1e-6));
        LaneSegment {
            length,
            inverse_length,
            direction,
            rest,
            one_plus_cos,
            inverse_one_plus_cos,
        }
    }

    /// [`transported`](Self::transported) without the check for a segment turned back on its
    /// parent: that lane's frame is then not usable, and the caller, which collects
    /// [`LaneSegment::reversed`], redoes the walk with the checked transport.
    #[inline(always)]
    pub(crate) fn transported_unchecked(&self, segment: &LaneSegment) -> LaneFrame {
        let direction = segment.direction;
        let sum = self.tangent + direction;
        let normal = self.normal - sum.scale(sum.dot(self.normal) * segment.inverse_one_plus_cos);
        LaneFrame {
            binormal: direction.cross(normal),
            normal,
            tangent: direction,
        }
    }

    /// This frame transported to `segment`'s direction: the rotation taking `t` to `d`, as two
    /// reflections (see `forces::transport`; the term `2(t·n)·d` is 0 for an orthonormal frame),
    /// the normal not re-orthonormalised; in the lanes where the segment is turned back on its
    /// parent, by [`Frame::transported_to`].
    #[inline(always)]
    pub(crate) fn transported(&self, segment: &LaneSegment) -> LaneFrame {
        let mut frame = self.transported_unchecked(segment);
        let reversed = segment.reversed();
        if reversed.any() {
            self.transport_reversed(&mut frame, reversed, segment.direction);
        }
        frame
    }

    /// The lanes of `reversed` (1.0 / 0.0) of `frame`: this frame carried to `direction` by the
    /// quaternion code, one lane at a time (a segment turned back on its parent is rare).
    #[cold]
    #[inline(never)]
    fn transport_reversed(&self, frame: &mut LaneFrame, reversed: Lanes, direction: LaneVec3) {
        for lane in 0..LANES {
            if reversed.0[lane] > 0.0 {
                let parent = Frame {
                    normal: self.normal.get(lane),
                    binormal: self.binormal.get(lane),
                    tangent: self.tangent.get(lane),
                };
                let carried = parent.transported_to(direction.get(lane));
                frame.normal.set(lane, carried.normal);
                frame.binormal.set(lane, carried.binormal);
                frame.tangent.set(lane, carried.tangent);
            }
        }
    }
}

impl LaneSegment {
    /// 1.0 in the lanes where the segment is turned back on its parent (`1 + t·d` below
    /// [`REVERSED`]), 0.0 elsewhere.
    #[inline(always)]
    pub(crate) fn reversed(&self) -> Lanes {
        Lanes::splat(REVERSED).greater(self.one_plus_cos)
    }
}

/// Per-node scratch of the spring pass for `N` ≥ the node count.
pub(crate) struct SpringScratch<const N: usize> {
    /// Spring forces [N], then (in the position-based step) the shape target's displacements [m].
    pub forces: [LaneVec3; N],
    /// Unit directions of the segments.
    pub directions: [LaneVec3; N],
    /// Half curvature binormals `t_{i−1} × d_i / (1 + t_{i−1}·d_i)` of the transports.
    pub half_binormals: [LaneVec3; N],
    /// `1/l` of every segment's current length [1/m].
    pub inverse_lengths: [Lanes; N],
    /// Twist torque of every spring on its parent frame [N·m].
    pub twist: [Lanes; N],
    /// Rest directions `r_i` in the transported parent frames (the XPBD step's assembly writes
    /// them, for its twisted step).
    pub rests: [LaneVec3; N],
}

impl<const N: usize> SpringScratch<N> {
    pub(crate) fn new() -> Self {
        let v = [LaneVec3::default(); N];
        let s = [Lanes::default(); N];
        SpringScratch {
            forces: v,
            directions: v,
            half_binormals: v,
            inverse_lengths: s,
            twist: s,
            rests: v,
        }
    }
}

/// What one joint contributes: `Q·g` (on its node, with the opposite on the node before) and
/// the bend torque `k·(α/sin α)·(d × r)`; and its rest direction `r` in the transported parent
/// frame (for the XPBD step's blocks).
pub(crate) struct JointTerms {
    pub qg: LaneVec3,
    pub torque: LaneVec3,
    pub rest: LaneVec3,
    /// The segment's current length [m] (before clamping at 1e-12 for its inverse).
    pub length: Lanes,
}

/// The joint ending at node `i` (≥ 1) with stiffness `k`: stores the segment's direction, inverse
/// length, half binormal and twist torque, adds its energy, and carries `frame` (the parent frame,
/// on return segment `i`'s) along: with the checked transport where `reversed` is `None`, else
/// with the unchecked one, the lanes it leaves unusable added to `reversed`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn joint<const N: usize>(
    s: &mut SpringScratch<N>,
    positions: &[LaneVec3; N],
    rest_local: LaneVec3,
    i: usize,
    k: Lanes,
    frame: &mut LaneFrame,
    energy: &mut Lanes,
    reversed: Option<&mut Lanes>,
) -> JointTerms {
    let seg = frame.segment(positions[i - 1], positions[i], rest_local);
    let (direction, rest, inverse_length) = (seg.direction, seg.rest, seg.inverse_length);
    let tangent = frame.tangent;
    // 1/(1 + t·d), shared by the twist binormal and the transport (clamped at 1e-6, as
    // `add_spring_forces` clamps it, where the segment is turned back on its parent).
    let half_binormal = tangent.cross(direction).scale(seg.inverse_one_plus_cos);
    // Bend angle α = ∠(d, r) and α/sin α.
    let axis = direction.cross(rest);
    let sin = axis.length_squared().sqrt();
    let cos = direction.dot(rest);
    let (angle, factor) = Lanes::bend_angle_and_factor(sin, cos);
    *energy = *energy + Lanes::splat(0.5) * k * angle * angle;
    let scaled = factor * k;
    let torque = axis.scale(scaled);
    s.twist[i] = tangent.dot(torque);
    s.half_binormals[i] = half_binormal;
    s.directions[i] = direction;
    s.inverse_lengths[i] = inverse_length;
    // g = k·(α/sin α)·(d − r); Q·g = (g − d(d·g))/l.
    let g = (direction - rest).scale(scaled);
    let qg = (g - direction.scale(direction.dot(g))).scale(inverse_length);
    // Transport the frame to d.
    *frame = match reversed {
        None => frame.transported(&seg),
        Some(reversed) => {
            *reversed = reversed.max(seg.reversed());
            frame.transported_unchecked(&seg)
        }
    };
    JointTerms {
        qg,
        torque,
        rest,
        length: seg.length,
    }
}

/// Writes the spring forces [N] of nodes `0..n` (`2 ≤ n ≤ N`) into `s.forces` and returns the
/// bending energies [J] and `Σ w_i·|F_i|²` over nodes `first..n` [N²/kg]. `rest_local(i)`,
/// `stiffness(i)` and `weight(i)` are node `i`'s rest direction (local), spring stiffness
/// [N·m/rad] and inverse mass [1/kg].
///
/// The walk transports the frames unchecked (the position-based step's hot loop); where some
/// lane has a segment turned back on its parent, it is walked again with the checked transport.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn spring_forces<const N: usize>(
    s: &mut SpringScratch<N>,
    positions: &[LaneVec3; N],
    n: usize,
    first: usize,
    rest_local: impl Fn(usize) -> LaneVec3,
    stiffness: impl Fn(usize) -> Lanes,
    weight: impl Fn(usize) -> Lanes,
    root_frame: LaneFrame,
) -> (Lanes, Lanes) {
    let mut walk = |reversed: Option<&mut Lanes>| {
        spring_walk(
            s,
            positions,
            n,
            first,
            &rest_local,
            &stiffness,
            &weight,
            root_frame,
            reversed,
        )
    };
    let mut reversed = Lanes::splat(0.0);
    let fast = walk(Some(&mut reversed));
    if reversed.any() { walk(None) } else { fast }
}

/// [`spring_forces`]' walk, its transport checked where `reversed` is `None`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn spring_walk<const N: usize>(
    s: &mut SpringScratch<N>,
    positions: &[LaneVec3; N],
    n: usize,
    first: usize,
    rest_local: &impl Fn(usize) -> LaneVec3,
    stiffness: &impl Fn(usize) -> Lanes,
    weight: &impl Fn(usize) -> Lanes,
    root_frame: LaneFrame,
    mut reversed: Option<&mut Lanes>,
) -> (Lanes, Lanes) {
    let n = n.clamp(2, N);
    let mut energy = Lanes::splat(0.0);
    let mut frame = root_frame;
    // Forces of nodes i − 2 and i − 1 collected so far (joint i adds +Sᵀg, Q·g − Sᵀg, −Q·g to
    // nodes i − 2, i − 1, i; node i − 2 is then complete).
    let root_joint = joint(
        s,
        positions,
        rest_local(1),
        1,
        stiffness(1),
        &mut frame,
        &mut energy,
        reversed.as_deref_mut(),
    );
    let mut before = root_joint.qg;
    let mut last = -root_joint.qg;
    for i in 2..n {
        let parent_direction = s.directions[i - 1];
        let parent_inverse_length = s.inverse_lengths[i - 1];
        let terms = joint(
            s,
            positions,
            rest_local(i),
            i,
            stiffness(i),
            &mut frame,
            &mut energy,
            reversed.as_deref_mut(),
        );
        // Sᵀ·g = d_{i−1} × (r × g)/l_{i−1} = −m with m = d_{i−1} × torque/l_{i−1} (r × g =
        // −torque).
        let m = parent_direction
            .cross(terms.torque)
            .scale(parent_inverse_length);
        s.forces[i - 2] = before - m;
        before = last + terms.qg + m;
        last = -terms.qg;
    }
    s.forces[n - 2] = before;
    s.forces[n - 1] = last;
    // Twist pass, tip to root (see `add_spring_forces`): A_j = Σ_{i > j} W_i, and
    // −∂E/∂d_j = A_j·κb_j/2 + A_{j+1}·κb_{j+1}/2 acts on nodes j and j − 1 through
    // Q_j = (I − d_j d_jᵀ)/l_j. Both binormals are perpendicular to d_j (κb_j ∝ t_{j−1} × d_j,
    // κb_{j+1} ∝ d_j × d_{j+1}), so Q_j is just 1/l_j here. Node j is complete once it has its
    // force, so the weighted sum of squares is taken on the way.
    let mut suffix = Lanes::splat(0.0);
    let mut next_twist = Lanes::splat(0.0);
    let mut next_half_binormal = LaneVec3::default();
    let mut pending = LaneVec3::default();
    let mut weighted = Lanes::splat(0.0);
    for j in (1..n).rev() {
        let a_next = suffix;
        let a_here = suffix + next_twist;
        let half_binormal = s.half_binormals[j];
        let pull = half_binormal.scale(a_here) + next_half_binormal.scale(a_next);
        let force = pull.scale(s.inverse_lengths[j]);
        let total = s.forces[j] + force - pending;
        s.forces[j] = total;
        if j >= first {
            weighted = weighted + total.length_squared() * weight(j);
        }
        pending = force;
        suffix = a_here;
        next_twist = s.twist[j];
        next_half_binormal = half_binormal;
    }
    let root = s.forces[0] - pending;
    s.forces[0] = root;
    if first == 0 {
        weighted = weighted + root.length_squared() * weight(0);
    }
    (energy, weighted)
}
