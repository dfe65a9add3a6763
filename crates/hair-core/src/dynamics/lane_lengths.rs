//! The segment lengths of [`LANES`](crate::dynamics::lanes::LANES) chains at once: the
//! mass-weighted fast projection and follow-the-leader of the XPBD step, each lane as the
//! one-chain [`constraints`](crate::dynamics::constraints) (which the other integrators use)
//! would.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::constraints::LENGTH_TOLERANCE;
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lanes::{LaneVec3, Lanes};

/// Newton iterations of the length projection (it converges quadratically and stops when within
/// [`LENGTH_TOLERANCE`](crate::dynamics::constraints::LENGTH_TOLERANCE)).
pub(crate) const LENGTH_ITERATIONS: usize = 3;

/// The mass-weighted fast projection onto the segment lengths
/// ([`project_lengths`](crate::dynamics::constraints::project_lengths)) of every lane, node 0 of
/// inverse mass `root_weight` [1/kg] (0: fixed): [`LENGTH_ITERATIONS`] Newton steps of the tridiagonal system, a lane stopping once all
/// its segments are within [`LENGTH_TOLERANCE`] (or a pivot vanishes).
#[inline(always)]
pub(crate) fn project_lengths<const N: usize>(
    positions: &mut [LaneVec3; N],
    constants: &[LaneNode],
    root_weight: Lanes,
    n: usize,
) {
    let zero = Lanes::splat(0.0);
    let one = Lanes::splat(1.0);
    let tiny = Lanes::splat(1e-12);
    let free_root = root_weight.greater(zero).any();
    let tolerance = Lanes::splat(LENGTH_TOLERANCE);
    let mut directions = [LaneVec3::default(); N];
    let mut violations = [zero; N];
    let mut sweep = [zero; N];
    let mut todo = one;
    let weight = |i: usize| {
        if i == 0 {
            root_weight
        } else {
            constants[i].inverse_mass
        }
    };
    for _ in 0..LENGTH_ITERATIONS {
        let mut outside = zero;
        for i in 1..n {
            let segment = positions[i] - positions[i - 1];
            let length = segment.length_squared().sqrt();
            directions[i] = LaneVec3::select(
                length.greater(tiny),
                segment.scale(one / length.max(tiny)),
                LaneVec3::default(),
            );
            let violation = length - constants[i].rest_length;
            violations[i] = violation;
            outside = outside.max(
                violation
                    .abs()
                    .greater(tolerance * constants[i].rest_length),
            );
        }
        todo = todo * outside;
        if !todo.any() {
            return;
        }
        // Thomas algorithm: c'_i in `sweep`, d'_i in `violations`.
        let mut previous_c = zero;
        let mut previous_d = zero;
        let mut previous_off = zero;
        for i in 1..n {
            let diagonal = weight(i - 1) + weight(i);
            let off = if i + 1 < n {
                -(weight(i) * directions[i].dot(directions[i + 1]))
            } else {
                zero
            };
            let pivot = diagonal - previous_off * previous_c;
            // A NaN or vanishing pivot stops the lane (as the one-chain projection returns there).
            todo = todo * pivot.abs().greater(Lanes::splat(1e-30));
            let inverse = one / pivot;
            let c = off * inverse;
            let d = (violations[i] - previous_off * previous_d) * inverse;
            sweep[i] = c;
            violations[i] = d;
            previous_c = c;
            previous_d = d;
            previous_off = off;
        }
        // Back substitution: λ_i in `violations`.
        let mut next_lambda = zero;
        for i in (1..n).rev() {
            let lambda = violations[i] - sweep[i] * next_lambda;
            violations[i] = lambda;
            next_lambda = lambda;
        }
        if free_root {
            let moved = positions[0] + directions[1].scale(violations[1] * root_weight);
            positions[0] = LaneVec3::select(todo, moved, positions[0]);
        }
        for i in 1..n {
            let mut delta = directions[i].scale(violations[i]);
            if i + 1 < n {
                delta -= directions[i + 1].scale(violations[i + 1]);
            }
            let moved = positions[i] - delta.scale(weight(i));
            positions[i] = LaneVec3::select(todo, moved, positions[i]);
        }
    }
}

/// Follow-the-leader ([`follow_the_leader`](crate::dynamics::follow_the_leader)) of every lane:
/// segments further than [`LENGTH_TOLERANCE`] from their rest length are set to it.
#[inline(always)]
pub(crate) fn follow_the_leader<const N: usize>(
    positions: &mut [LaneVec3; N],
    constants: &[LaneNode],
    n: usize,
) {
    let tiny = Lanes::splat(1e-12);
    let one = Lanes::splat(1.0);
    let tolerance = Lanes::splat(LENGTH_TOLERANCE);
    let mut previous_direction = LaneVec3::default();
    for i in 1..n {
        let rest = constants[i].rest_length;
        let segment = positions[i] - positions[i - 1];
        let length = segment.length_squared().sqrt();
        let direction = LaneVec3::select(
            length.greater(tiny),
            segment.scale(one / length.max(tiny)),
            previous_direction,
        );
        let off = (length - rest).abs().greater(tolerance * rest);
        positions[i] =
            LaneVec3::select(off, positions[i - 1] + direction.scale(rest), positions[i]);
        previous_direction = direction;
    }
}
