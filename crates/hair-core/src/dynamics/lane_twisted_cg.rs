//! The twisted XPBD step ([`twisted_cg`](crate::dynamics::twisted_cg), whose module docs give
//! the method) for [`LANES`](crate::dynamics::lanes::LANES) chains at once, with attached roots
//! (unknowns `1..n`): conjugate gradients on the system with the twist's long-range coupling,
//! preconditioned by the band that [`LaneSystem`] factorised, lane-wise and in the same order of
//! operations as the one-chain step. A lane whose iteration breaks down (a non-positive
//! curvature `pᵀ·Ã·p` or a non-finite value) keeps the iterate it had, as the one-chain step
//! stops there.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::lane_blocks::LaneSystem;
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_springs::SpringScratch;
use crate::dynamics::lanes::{LaneVec3, Lanes};
use crate::dynamics::twisted_cg::CG_ITERATIONS;

/// The conjugate-gradient vectors of a batch (on the stack, `N` ≥ the node count).
pub(crate) struct LaneTwistScratch<const N: usize> {
    residual: [LaneVec3; N],
    preconditioned: [LaneVec3; N],
    direction: [LaneVec3; N],
    /// `A·p` for the band `A`, by recurrence.
    band_product: [LaneVec3; N],
    product: [LaneVec3; N],
    weights: [Lanes; N],
}

impl<const N: usize> LaneTwistScratch<N> {
    pub(crate) fn new() -> Self {
        let v = [LaneVec3::default(); N];
        LaneTwistScratch {
            residual: v,
            preconditioned: v,
            direction: v,
            band_product: v,
            product: v,
            weights: [Lanes::splat(0.0); N],
        }
    }
}

/// Sum over nodes `1..n` of `a_i·b_i`, per lane.
#[inline(always)]
fn dot<const N: usize>(a: &[LaneVec3; N], b: &[LaneVec3; N], n: usize) -> Lanes {
    let mut sum = Lanes::splat(0.0);
    for i in 1..n {
        sum = sum + a[i].dot(b[i]);
    }
    sum
}

/// The twisted step of every lane into `step` (which holds the band's step `A⁻¹·b` on entry),
/// from the factorised `system`, the right-hand side `rhs` (`b`, kept before the solve), the
/// joints of the assembly at the linearisation point (`springs`: directions, inverse lengths,
/// half binormals, rest directions) and the stiffnesses in `constants`. Returns 1.0 in the lanes
/// whose step is finite, 0.0 in the others (their `step` is not usable).
#[inline(always)]
pub(crate) fn twisted_step<const N: usize>(
    system: &LaneSystem<N>,
    springs: &SpringScratch<N>,
    constants: &[LaneNode],
    rhs: &[LaneVec3; N],
    scratch: &mut LaneTwistScratch<N>,
    n: usize,
    step: &mut [LaneVec3; N],
) -> Lanes {
    let zero = Lanes::splat(0.0);
    let one = Lanes::splat(1.0);
    // x = 0, r = b, z = A⁻¹·r (the band's step, given), p = z, A·p = r.
    for i in 1..n {
        scratch.residual[i] = rhs[i];
        scratch.preconditioned[i] = step[i];
        scratch.direction[i] = step[i];
        scratch.band_product[i] = rhs[i];
        step[i] = LaneVec3::default();
    }
    let mut rz = dot(&scratch.residual, &scratch.preconditioned, n);
    let mut going = one;
    for iteration in 0..CG_ITERATIONS {
        twist_product(springs, constants, scratch, n);
        for i in 1..n {
            scratch.product[i] += scratch.band_product[i];
        }
        let pq = dot(&scratch.direction, &scratch.product, n);
        // Positive curvature and a finite r·z, else the lane keeps its iterate (the one-chain
        // step's `break`).
        let finite_rz = Lanes::zip(rz, rz, |a, _| f32::from(a.is_finite()));
        going = going * pq.greater(zero) * finite_rz;
        if !going.any() {
            break;
        }
        let alpha = Lanes::select(going, rz / pq, zero);
        for i in 1..n {
            step[i] = LaneVec3::select(going, step[i] + scratch.direction[i].scale(alpha), step[i]);
            scratch.residual[i] = LaneVec3::select(
                going,
                scratch.residual[i] - scratch.product[i].scale(alpha),
                scratch.residual[i],
            );
        }
        if iteration + 1 == CG_ITERATIONS {
            break;
        }
        scratch.preconditioned = scratch.residual;
        system.substitute(&mut scratch.preconditioned, 1, n);
        let rz_next = dot(&scratch.residual, &scratch.preconditioned, n);
        let beta = rz_next / rz;
        rz = Lanes::select(going, rz_next, rz);
        // p = z + β·p, and A·p = r + β·A·p (A·z = r).
        for i in 1..n {
            scratch.direction[i] = scratch.preconditioned[i] + scratch.direction[i].scale(beta);
            scratch.band_product[i] = scratch.residual[i] + scratch.band_product[i].scale(beta);
        }
    }
    let mut size = zero;
    for i in 1..n {
        size = size + step[i].length_squared();
    }
    Lanes::zip(size, size, |a, _| f32::from(a.is_finite()))
}

/// `product = (Ã − A)·direction` lane-wise: the twist's terms of the twisted matrix, as the
/// one-chain `TwistScratch::twist_product` computes them (forward prefix sum of the parent
/// frames' twists, reverse suffix sum of the bends' weights).
#[inline(always)]
fn twist_product<const N: usize>(
    springs: &SpringScratch<N>,
    constants: &[LaneNode],
    scratch: &mut LaneTwistScratch<N>,
    n: usize,
) {
    let zero = Lanes::splat(0.0);
    let v = &scratch.direction;
    let product = &mut scratch.product;
    for i in 0..n {
        product[i] = LaneVec3::default();
    }
    let mut twist = zero; // τ_{i−1}
    for i in 1..n {
        let d = springs.directions[i];
        let il = springs.inverse_lengths[i];
        let half_binormal = springs.half_binormals[i];
        let u = v[i] - v[i - 1];
        let mut turn_rate = half_binormal.dot(u) * il;
        scratch.weights[i] = zero;
        if i >= 2 {
            let dp = springs.directions[i - 1];
            let ilp = springs.inverse_lengths[i - 1];
            let r = springs.rests[i];
            let k = constants[i].stiffness;
            let turn = -dp.cross(r);
            let w = v[i - 1] - v[i - 2];
            let rate = (u - d.scale(d.dot(u))).scale(il) + r.cross(dp.cross(w)).scale(ilp);
            // J_iᵀ·(k·c_i·τ_{i−1}).
            let g = turn.scale(k * twist);
            let qg = (g - d.scale(d.dot(g))).scale(il);
            let stg = dp.cross(r.cross(g)).scale(ilp);
            product[i] += qg;
            product[i - 1] -= qg;
            product[i - 1] += stg;
            product[i - 2] -= stg;
            scratch.weights[i] = k * (turn.dot(rate) + turn.length_squared() * twist);
            turn_rate = turn_rate + half_binormal.dot(w) * ilp;
        }
        // τ_i = τ_{i−1} − hb_i·(δd_{i−1} + δd_i).
        twist = twist - turn_rate;
    }
    // Σ_i w_i·∇τ_{i−1} = −Σ_m A_m·∇(hb_m·(δd_{m−1} + δd_m)), A_m = Σ_{i > m} w_i.
    let mut suffix = zero;
    for m in (1..n).rev() {
        let pull = springs.half_binormals[m].scale(suffix);
        let here = pull.scale(springs.inverse_lengths[m]);
        product[m] -= here;
        product[m - 1] += here;
        if m >= 2 {
            let before = pull.scale(springs.inverse_lengths[m - 1]);
            product[m - 1] -= before;
            product[m - 2] += before;
        }
        suffix = suffix + scratch.weights[m];
    }
    product[0] = LaneVec3::default();
}
