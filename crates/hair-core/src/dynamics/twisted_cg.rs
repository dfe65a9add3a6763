//! The XPBD Newton step with the twist's long-range coupling, by conjugate gradients on one
//! chain: the step's system `(M/h² + H)·Δx = b` with each bend's Jacobian given the turn of its
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

use std::cell::RefCell;

use glam::{Mat3, Vec3};

use crate::dynamics::banded::substitute_block_pentadiagonal;
use crate::dynamics::forces::{Joint, walk_joints};
use crate::frame::Frame;

/// Conjugate-gradient iterations of the twisted step (each one product with the twisted matrix
/// and one substitution with the band's factorisation).
pub(crate) const CG_ITERATIONS: usize = 4;

/// What the twisted product needs of one joint (node `i ≥ 1`).
#[derive(Debug, Clone, Copy, Default)]
struct TwistJoint {
    /// Unit direction `d_i` and length `l_i` [m] of segment `i`.
    direction: Vec3,
    length: f32,
    /// Unit direction and length [m] of the parent segment (length 0 for node 1).
    parent_direction: Vec3,
    parent_length: f32,
    /// The rest direction `r_i` in the transported parent frame.
    rest: Vec3,
    /// `c_i = −t_{i−1} × r_i`: the residual's change per radian of the parent frame's twist.
    turn: Vec3,
    /// `hb_i`, half the curvature binormal of the transport into segment `i`.
    half_binormal: Vec3,
    /// The spring's stiffness `k_i` [N·m/rad] where its bend is in the step's matrix, else 0.
    stiffness: f32,
}

impl TwistJoint {
    /// `J_i·v` (`Q·(v_i − v_{i−1}) + S·(v_{i−1} − v_{i−2})`, as in [`Joint`]).
    #[inline]
    fn jacobian(&self, v: &[Vec3], i: usize) -> Vec3 {
        let u = v[i] - v[i - 1];
        let mut rate = (u - self.direction * self.direction.dot(u)) / self.length;
        if self.parent_length > 0.0 {
            let w = v[i - 1] - v[i - 2];
            rate += self.rest.cross(self.parent_direction.cross(w)) / self.parent_length;
        }
        rate
    }

    /// Adds `J_iᵀ·g` to `out` (nodes `i`, `i − 1`, `i − 2`).
    #[inline]
    fn add_jacobian_transpose(&self, g: Vec3, out: &mut [Vec3], i: usize) {
        let qg = (g - self.direction * self.direction.dot(g)) / self.length;
        out[i] += qg;
        out[i - 1] -= qg;
        if self.parent_length > 0.0 {
            let stg = self.parent_direction.cross(self.rest.cross(g)) / self.parent_length;
            out[i - 1] += stg;
            out[i - 2] -= stg;
        }
    }
}

/// Per-thread scratch of the twisted step: the right-hand side, the joints and the conjugate-gradient vectors (grown to the longest chain,
/// then reused: nothing is allocated per step).
#[derive(Debug, Default)]
pub(crate) struct TwistScratch {
    rhs: Vec<Vec3>,
    joints: Vec<TwistJoint>,
    residual: Vec<Vec3>,
    preconditioned: Vec<Vec3>,
    direction: Vec<Vec3>,
    /// `A·p` for the band `A` and the search direction `p` (by recurrence, no product).
    band_product: Vec<Vec3>,
    product: Vec<Vec3>,
    twist_weights: Vec<f32>,
}

thread_local! {
    static SCRATCH: RefCell<TwistScratch> = RefCell::new(TwistScratch::default());
}

/// Runs `work` with this thread's twisted-step scratch.
pub(crate) fn with_scratch<R>(work: impl FnOnce(&mut TwistScratch) -> R) -> R {
    SCRATCH.with(|scratch| work(&mut scratch.borrow_mut()))
}

impl TwistScratch {
    /// Keeps a copy of the step's right-hand side `b` (before the band's solve replaces it).
    pub(crate) fn keep_rhs(&mut self, rhs: &[Vec3]) {
        let n = rhs.len();
        for buffer in [
            &mut self.rhs,
            &mut self.residual,
            &mut self.preconditioned,
            &mut self.direction,
            &mut self.band_product,
            &mut self.product,
        ] {
            buffer.resize(n, Vec3::ZERO);
        }
        self.joints.resize(n, TwistJoint::default());
        self.twist_weights.resize(n, 0.0);
        self.rhs.copy_from_slice(rhs);
    }

    /// The twisted step (module docs) into `step`, from the band's factorisation (`diagonal`,
    /// `first`, `second` as [`factorise_block_pentadiagonal`](crate::dynamics::banded::factorise_block_pentadiagonal)
    /// left them) and the right-hand side [`TwistScratch::keep_rhs`] kept, at `positions` (the step's
    /// linearisation point). `step` holds the band's step on entry. `active(i)` says whether
    /// bend `i` is in the matrix with stiffness `stiffness[i]`; with `attached`, node 0 is not an
    /// unknown. Returns `false` where a value is not finite (`step` then holds the band's step
    /// again).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn twisted_step(
        &mut self,
        factorised: (&[Mat3], &[Mat3], &[Mat3]),
        positions: &[Vec3],
        root_frame: &Frame,
        rest_local: &[Vec3],
        stiffness: &[f32],
        attached: bool,
        step: &mut [Vec3],
    ) -> bool {
        self.linearise(positions, root_frame, rest_local, stiffness, attached);
        let (d, f, s) = factorised;
        // x = 0, r = b, z = A⁻¹·r (the band's step, given), p = z, A·p = r.
        self.residual.copy_from_slice(&self.rhs);
        self.preconditioned.copy_from_slice(step);
        self.direction.copy_from_slice(step);
        self.band_product.copy_from_slice(&self.rhs);
        step.fill(Vec3::ZERO);
        let dot = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum::<f32>();
        let mut rz = dot(&self.residual, &self.preconditioned);
        for iteration in 0..CG_ITERATIONS {
            // q = Ã·p = A·p + (Ã − A)·p.
            self.twist_product(attached);
            for (q, band) in self.product.iter_mut().zip(&self.band_product) {
                *q += *band;
            }
            let pq = dot(&self.direction, &self.product);
            if !(pq > 0.0 && rz.is_finite()) {
                break;
            }
            let alpha = rz / pq;
            for ((x, r), (p, q)) in step
                .iter_mut()
                .zip(self.residual.iter_mut())
                .zip(self.direction.iter().zip(&self.product))
            {
                *x += *p * alpha;
                *r -= *q * alpha;
            }
            if iteration + 1 == CG_ITERATIONS {
                break;
            }
            self.preconditioned.copy_from_slice(&self.residual);
            substitute_block_pentadiagonal(d, f, s, &mut self.preconditioned);
            let rz_next = dot(&self.residual, &self.preconditioned);
            let beta = rz_next / rz;
            rz = rz_next;
            // p = z + β·p, and A·p = r + β·A·p (A·z = r): the band's product by recurrence.
            for ((p, band), (z, r)) in self
                .direction
                .iter_mut()
                .zip(self.band_product.iter_mut())
                .zip(self.preconditioned.iter().zip(&self.residual))
            {
                *p = *z + *p * beta;
                *band = *r + *band * beta;
            }
        }
        if step.iter().all(|v| v.is_finite()) {
            return true;
        }
        step.copy_from_slice(&self.rhs);
        substitute_block_pentadiagonal(d, f, s, step);
        false
    }

    /// The joints of the twisted matrix at `positions` (the step's linearisation point).
    fn linearise(
        &mut self,
        positions: &[Vec3],
        root_frame: &Frame,
        rest_local: &[Vec3],
        stiffness: &[f32],
        attached: bool,
    ) {
        let root_tangent = root_frame.tangent;
        walk_joints(positions, root_frame, rest_local, |joint: &Joint| {
            let i = joint.node;
            let (parent_direction, parent_length) = joint.parent.unwrap_or((root_tangent, 0.0));
            let k = stiffness[i];
            self.joints[i] = TwistJoint {
                direction: joint.direction,
                length: joint.length,
                parent_direction,
                parent_length,
                rest: joint.rest_direction,
                turn: -parent_direction.cross(joint.rest_direction),
                half_binormal: parent_direction.cross(joint.direction)
                    / (1.0 + parent_direction.dot(joint.direction)).max(1e-6),
                stiffness: if k > 0.0 && (i >= 2 || attached) {
                    k
                } else {
                    0.0
                },
            };
        });
    }

    /// `product = (Ã − A)·direction`: the twist's terms of the twisted matrix (module docs).
    fn twist_product(&mut self, attached: bool) {
        let n = self.direction.len();
        let v = &self.direction;
        self.product.fill(Vec3::ZERO);
        // Forward: the parent frame's twist τ_{i−1}(v) at each bend; the bends' twist terms
        // k·(J_iᵀ·c_i·τ + g_i·(c_i·J_i·v + |c_i|²·τ)), the g_i part as weights w_i.
        let mut twist = 0.0f32; // τ_{i−1}
        for i in 1..n {
            let joint = self.joints[i];
            self.twist_weights[i] = 0.0;
            if joint.stiffness > 0.0 && i >= 2 {
                let k = joint.stiffness;
                let rate = joint.jacobian(v, i);
                joint.add_jacobian_transpose(joint.turn * (k * twist), &mut self.product, i);
                self.twist_weights[i] =
                    k * (joint.turn.dot(rate) + joint.turn.length_squared() * twist);
            }
            // τ_i = τ_{i−1} − hb_i·(δd_{i−1} + δd_i).
            let mut turn = joint.half_binormal.dot(v[i] - v[i - 1]) / joint.length;
            if joint.parent_length > 0.0 {
                turn += joint.half_binormal.dot(v[i - 1] - v[i - 2]) / joint.parent_length;
            }
            twist -= turn;
        }
        // Reverse: Σ_i w_i·∇τ_{i−1} = −Σ_m A_m·∇(hb_m·(δd_{m−1} + δd_m)), A_m = Σ_{i > m} w_i.
        let mut suffix = 0.0f32;
        for m in (1..n).rev() {
            let joint = self.joints[m];
            let pull = joint.half_binormal * suffix;
            let here = pull / joint.length;
            self.product[m] -= here;
            self.product[m - 1] += here;
            if joint.parent_length > 0.0 {
                let before = pull / joint.parent_length;
                self.product[m - 1] -= before;
                self.product[m - 2] += before;
            }
            suffix += self.twist_weights[m];
        }
        if attached {
            self.product[0] = Vec3::ZERO;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::forces::rest_local_direction;
    use crate::dynamics::tests::coiled_positions;
    use crate::random::SplitMix64;

    /// A curly chain of 16 nodes (1 cm segments bent by 0.8 rad, the bend plane turning by
    /// 0.9 rad a node) whose rest directions differ from its shape (every spring loaded), with
    /// stiffnesses that differ per node.
    fn curly_chain() -> (Vec<Vec3>, Frame, Vec<Vec3>, Vec<f32>) {
        let n = 16;
        let frame = Frame::from_tangent_and_normal(Vec3::new(0.3, -1.0, 0.1), Vec3::Z).unwrap();
        let lengths: Vec<f32> = (0..n).map(|i| if i == 0 { 0.0 } else { 0.01 }).collect();
        let positions = coiled_positions(&frame, &lengths, 0.8);
        let rest_local = (0..n)
            .map(|i| rest_local_direction(0.5, 0.4 * i as f32))
            .collect();
        let stiffness = (0..n).map(|i| 1.0 + 0.1 * i as f32).collect();
        (positions, frame, rest_local, stiffness)
    }

    /// The bends' residuals `d_i − r_i` (nodes `1..n`) at `positions`.
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
        // |v|/l = 100, so 1e-3 of the sum's scale) and J_i·v by the band's Jacobian. The twist
        // terms are a large part of the sum on this chain, so a wrong sign or index fails.
        let (positions, frame, rest_local, stiffness) = curly_chain();
        let n = positions.len();
        let mut rng = SplitMix64::new(11);
        let mut random_moves = || -> Vec<Vec3> {
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
        };
        let mut scratch = TwistScratch::default();
        scratch.keep_rhs(&vec![Vec3::ZERO; n]);
        scratch.linearise(&positions, &frame, &rest_local, &stiffness, true);
        for _ in 0..4 {
            let (v, w) = (random_moves(), random_moves());
            scratch.direction.copy_from_slice(&v);
            scratch.twist_product(true);
            let computed: f32 = scratch.product.iter().zip(&w).map(|(p, w)| p.dot(*w)).sum();
            let (rates_v, rates_w) = (
                twisted_rates(&positions, &frame, &rest_local, &v),
                twisted_rates(&positions, &frame, &rest_local, &w),
            );
            let mut expected = 0.0f32;
            let mut scale = 0.0f32;
            let mut twist_part = 0.0f32;
            for i in 1..n {
                let joint = scratch.joints[i];
                let band = joint.jacobian(&v, i).dot(joint.jacobian(&w, i));
                let twisted = rates_v[i].dot(rates_w[i]);
                expected += stiffness[i] * (twisted - band);
                twist_part += stiffness[i] * (twisted - band).abs();
                scale += stiffness[i] * rates_v[i].length() * rates_w[i].length();
            }
            assert!(
                twist_part > 0.05 * scale,
                "the twist is {twist_part} of {scale}: the test chain does not exercise it"
            );
            assert!(
                (computed - expected).abs() < 1e-3 * scale,
                "wᵀ(Ã − A)v = {computed}, by differences {expected} (scale {scale})"
            );
        }
    }
}
