//! The XPBD Newton step with the twist's long-range coupling, by conjugate gradients, for
//! [`LANES`](crate::dynamics::lanes::LANES) chains at once: the step's system `(M/h² + H)·Δx = b` with each bend's Jacobian given the turn of its
//! parent frame about its tangent, solved by a few iterations of conjugate gradients
//! preconditioned by the block-pentadiagonal band that the step already factorises.
//!
//! **Why.** The band's Gauss-Newton stiffness `H = Σ k_i·J_iᵀJ_i` has each bend's local blocks
//! (nodes `i`, `i − 1`, `i − 2`) but not the twist: moving a segment twists every later
//! transported frame, which turns every later rest direction `r_i` about its parent tangent
//! `t_{i−1}`. The residual `d_i − r_i` then has the Jacobian
//! `J̃_i = J_i + c_i·∇τ_{i−1}ᵀ`, `c_i = −t_{i−1} × r_i`, with the parent frame's twist
//! `τ_j = −Σ_{m ≤ j} hb_m·(δd_{m−1} + δd_m)` (`hb_m` the half curvature binormal of the
//! transport into segment `m`, as in the springs' twist pass; `δd_m = P_m·(δx_m − δx_{m−1})/l_m`
//! and `hb_m ⊥ d_{m−1}, d_m`, so the projections drop). On 32-node curly chains the band's step
//! is too long along the directions the twist stiffens, and the line search rejects it whole at
//! every Newton iteration (measured: 7.6 Newton iterations a substep; with the twisted matrix
//! solved exactly, 1.0).
//!
//! **How.** `Ã = A + Σ k_i·(J_iᵀc_i·gᵢᵀ + g_i·c_iᵀJ_i + |c_i|²·g_i·g_iᵀ)`, `g_i = ∇τ_{i−1}`, is
//! symmetric positive definite (a sum of `k·J̃ᵀJ̃`, the lengths' springs and the inertia). Its
//! product with a vector is `O(n)`: the band's blocks, a forward prefix sum for `τ(v)` and a
//! reverse suffix sum for `Σ w_i·g_i`, the same sums as the springs' twist pass. Preconditioned
//! conjugate gradients from `Δx = 0` start with the band's own step; every iterate minimises the
//! twisted quadratic model over a growing Krylov space, so it is a descent direction of the
//! objective (`bᵀΔx > ½·Δxᵀ·Ã·Δx > 0`) for the line search.

//!
//! **Lanes.** Conjugate gradients run lane-wise, preconditioned by the band that [`LaneSystem`]
//! factorised, over the unknowns `first..n` (node 0 follows the head where the roots are
//! attached). A lane whose iteration breaks down (a non-positive curvature `pᵀ·Ã·p` or a
//! non-finite value) keeps the iterate it had.

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::lane_blocks::LaneSystem;
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_springs::SpringScratch;
use crate::dynamics::lanes::{LaneVec3, Lanes};

/// Conjugate-gradient iterations of the twisted step (each one product with the twisted matrix
/// and one substitution with the band's factorisation).
pub(crate) const CG_ITERATIONS: usize = 4;

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

/// Sum over nodes `first..n` of `a_i·b_i`, per lane.
#[inline(always)]
fn dot<const N: usize>(a: &[LaneVec3; N], b: &[LaneVec3; N], first: usize, n: usize) -> Lanes {
    let mut sum = Lanes::splat(0.0);
    for i in first..n {
        sum = sum + a[i].dot(b[i]);
    }
    sum
}

/// The twisted step of every lane into `step` (which holds the band's step `A⁻¹·b` on entry),
/// from the factorised `system`, the right-hand side `rhs` (`b`, kept before the solve), the
/// joints of the assembly at the linearisation point (`springs`: directions, inverse lengths,
/// half binormals, rest directions) and the stiffnesses in `constants`, over the unknowns
/// `first..n` (with free roots the root bend has no spring in the assembly, and none here
/// either: only bends `i ≥ 2` carry the twist's stiffness terms). Returns 1.0 in the lanes
/// whose step is finite, 0.0 in the others (their `step` is not usable).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn twisted_step<const N: usize>(
    system: &LaneSystem<N>,
    springs: &SpringScratch<N>,
    constants: &[LaneNode],
    rhs: &[LaneVec3; N],
    scratch: &mut LaneTwistScratch<N>,
    first: usize,
    n: usize,
    step: &mut [LaneVec3; N],
) -> Lanes {
    let zero = Lanes::splat(0.0);
    let one = Lanes::splat(1.0);
    // x = 0, r = b, z = A⁻¹·r (the band's step, given), p = z, A·p = r.
    for i in first..n {
        scratch.residual[i] = rhs[i];
        scratch.preconditioned[i] = step[i];
        scratch.direction[i] = step[i];
        scratch.band_product[i] = rhs[i];
        step[i] = LaneVec3::default();
    }
    let mut rz = dot(&scratch.residual, &scratch.preconditioned, first, n);
    let mut going = one;
    for iteration in 0..CG_ITERATIONS {
        twist_product(springs, constants, scratch, first, n);
        for i in first..n {
            scratch.product[i] += scratch.band_product[i];
        }
        let pq = dot(&scratch.direction, &scratch.product, first, n);
        // Positive curvature and a finite r·z, else the lane keeps its iterate.
        let finite_rz = Lanes::zip(rz, rz, |a, _| f32::from(a.is_finite()));
        going = going * pq.greater(zero) * finite_rz;
        if !going.any() {
            break;
        }
        let alpha = Lanes::select(going, rz / pq, zero);
        for i in first..n {
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
        system.substitute(&mut scratch.preconditioned, first, n);
        let rz_next = dot(&scratch.residual, &scratch.preconditioned, first, n);
        let beta = rz_next / rz;
        rz = Lanes::select(going, rz_next, rz);
        // p = z + β·p, and A·p = r + β·A·p (A·z = r).
        for i in first..n {
            scratch.direction[i] = scratch.preconditioned[i] + scratch.direction[i].scale(beta);
            scratch.band_product[i] = scratch.residual[i] + scratch.band_product[i].scale(beta);
        }
    }
    let mut size = zero;
    for i in first..n {
        size = size + step[i].length_squared();
    }
    Lanes::zip(size, size, |a, _| f32::from(a.is_finite()))
}

/// `product = (Ã − A)·direction` lane-wise: the twist's terms of the twisted matrix (module
/// docs), by a forward prefix sum of the parent frames' twists `τ` and a reverse suffix sum of
/// the bends' weights.
#[inline(always)]
fn twist_product<const N: usize>(
    springs: &SpringScratch<N>,
    constants: &[LaneNode],
    scratch: &mut LaneTwistScratch<N>,
    first: usize,
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
    if first == 1 {
        product[0] = LaneVec3::default();
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::dynamics::forces::{rest_local_direction, walk_joints};
    use crate::dynamics::lane_springs::{LaneFrame, joint};
    use crate::dynamics::lanes::LANES;
    use crate::dynamics::tests::coiled_positions;
    use crate::frame::Frame;
    use crate::random::SplitMix64;

    const N: usize = 16;

    fn splat(v: Vec3) -> LaneVec3 {
        LaneVec3 {
            x: Lanes::splat(v.x),
            y: Lanes::splat(v.y),
            z: Lanes::splat(v.z),
        }
    }

    /// The bends' residuals `d_i − r_i` (nodes `1..n`) at `positions`, walked by the one-chain
    /// `walk_joints` (the springs' own definition of the transported frames).
    fn residuals(positions: &[Vec3], frame: &Frame, rest_local: &[Vec3]) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; positions.len()];
        walk_joints(positions, frame, rest_local, |joint| {
            out[joint.node] = joint.direction - joint.rest_direction;
        });
        out
    }

    /// `J̃_i·v` for every bend by central differences of the residuals along `v`.
    fn twisted_rates(
        positions: &[Vec3],
        frame: &Frame,
        rest_local: &[Vec3],
        v: &[Vec3],
    ) -> Vec<Vec3> {
        let epsilon = 1e-4;
        let moved = |sign: f32| -> Vec<Vec3> {
            let p: Vec<Vec3> = positions
                .iter()
                .zip(v)
                .map(|(p, v)| *p + *v * (sign * epsilon))
                .collect();
            residuals(&p, frame, rest_local)
        };
        let (plus, minus) = (moved(1.0), moved(-1.0));
        plus.iter()
            .zip(&minus)
            .map(|(a, b)| (*a - *b) / (2.0 * epsilon))
            .collect()
    }

    #[test]
    fn the_twist_product_is_the_twisted_model_less_the_band() {
        // J̃_i = J_i + c_i·∇τ_{i−1}ᵀ is the exact Jacobian of the residual d_i − r_i (the rest
        // direction turns with the parent frame's twist), so for any v, w:
        //   wᵀ·(Ã − A)·v = Σ_i k_i·((J̃_i·w)·(J̃_i·v) − (J_i·w)·(J_i·v)),
        // with J̃_i·v taken by central differences of the walked residuals (ε = 1e-4 m along
        // unit node moves: truncation ~ε²/l² = 1e-4 and f32 rounding ~6e-8/ε = 6e-4 of a rate
        // |v|/l = 100, so 1e-3 of the sum's scale) and J_i·v by the band's Jacobian
        // `Q·(v_i − v_{i−1}) + S·(v_{i−1} − v_{i−2})`. The chain: 16 nodes, 1 cm segments bent
        // by 0.8 rad, the bend plane turning by 0.9 rad a node, rest directions unlike its shape
        // and stiffnesses that differ per node, so the twist is a large part of the sum and a
        // wrong sign or index fails. Each lane gets its own random v, w (node 0 fixed).
        let n = N;
        let frame = Frame::from_tangent_and_normal(Vec3::new(0.3, -1.0, 0.1), Vec3::Z).unwrap();
        let lengths: Vec<f32> = (0..n).map(|i| if i == 0 { 0.0 } else { 0.01 }).collect();
        let positions = coiled_positions(&frame, &lengths, 0.8);
        let rest_local: Vec<Vec3> = (0..n)
            .map(|i| rest_local_direction(0.5, 0.4 * i as f32))
            .collect();
        let stiffness: Vec<f32> = (0..n).map(|i| 1.0 + 0.1 * i as f32).collect();
        let mut constants = vec![LaneNode::default(); n];
        let mut lane_positions = [LaneVec3::default(); N];
        for i in 0..n {
            constants[i].stiffness = Lanes::splat(stiffness[i]);
            constants[i].rest_local = splat(rest_local[i]);
            lane_positions[i] = splat(positions[i]);
        }
        // The joints at the linearisation point, as the assembly stores them.
        let mut springs = SpringScratch::<N>::new();
        let mut lane_frame = LaneFrame {
            normal: splat(frame.normal),
            binormal: splat(frame.binormal),
            tangent: splat(frame.tangent),
        };
        let mut energy = Lanes::splat(0.0);
        for i in 1..n {
            let terms = joint(
                &mut springs,
                &lane_positions,
                constants[i].rest_local,
                i,
                constants[i].stiffness,
                &mut lane_frame,
                &mut energy,
                None,
            );
            springs.rests[i] = terms.rest;
        }
        let mut rng = SplitMix64::new(11);
        let mut random_moves = || -> Vec<Vec<Vec3>> {
            (0..LANES)
                .map(|_| {
                    (0..n)
                        .map(|i| {
                            if i == 0 {
                                Vec3::ZERO
                            } else {
                                Vec3::new(
                                    rng.range(-1.0, 1.0),
                                    rng.range(-1.0, 1.0),
                                    rng.range(-1.0, 1.0),
                                )
                            }
                        })
                        .collect()
                })
                .collect()
        };
        let (v, w) = (random_moves(), random_moves());
        let mut scratch = LaneTwistScratch::<N>::new();
        for lane in 0..LANES {
            for i in 0..n {
                scratch.direction[i].set(lane, v[lane][i]);
            }
        }
        twist_product(&springs, &constants, &mut scratch, 1, n);
        for lane in 0..LANES {
            let (v, w) = (&v[lane], &w[lane]);
            let computed: f32 = (0..n).map(|i| scratch.product[i].get(lane).dot(w[i])).sum();
            let band_rate = |u: &[Vec3], i: usize| {
                let d = springs.directions[i].get(lane);
                let il = springs.inverse_lengths[i].0[lane];
                let step = u[i] - u[i - 1];
                let mut rate = (step - d * d.dot(step)) * il;
                if i >= 2 {
                    let dp = springs.directions[i - 1].get(lane);
                    let ilp = springs.inverse_lengths[i - 1].0[lane];
                    let r = springs.rests[i].get(lane);
                    rate += r.cross(dp.cross(u[i - 1] - u[i - 2])) * ilp;
                }
                rate
            };
            let (rates_v, rates_w) = (
                twisted_rates(&positions, &frame, &rest_local, v),
                twisted_rates(&positions, &frame, &rest_local, w),
            );
            let mut expected = 0.0f32;
            let mut scale = 0.0f32;
            let mut twist_part = 0.0f32;
            for i in 1..n {
                let band = band_rate(v, i).dot(band_rate(w, i));
                let twisted = rates_v[i].dot(rates_w[i]);
                expected += stiffness[i] * (twisted - band);
                twist_part += stiffness[i] * (twisted - band).abs();
                scale += stiffness[i] * rates_v[i].length() * rates_w[i].length();
            }
            assert!(
                twist_part > 0.05 * scale,
                "lane {lane}: the twist is {twist_part} of {scale}: the chain does not exercise it"
            );
            assert!(
                (computed - expected).abs() < 1e-3 * scale,
                "lane {lane}: wᵀ(Ã − A)v = {computed}, by differences {expected} (scale {scale})"
            );
        }
    }
}
