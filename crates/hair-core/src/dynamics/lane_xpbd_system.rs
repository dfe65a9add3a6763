//! The Newton system of the XPBD step ([`xpbd`](crate::dynamics::xpbd)):
//! one walk of [`LANES`](crate::dynamics::lanes::LANES) chains that computes the bending forces
//! (exact gradient, twist included), the stiff length springs, the inertia, the objective `Φ`
//! and the Gauss-Newton blocks of `M/h² + H` together, over the unknowns `first..n` (node 0 fixed
//! where the roots are attached; with free roots node 0 is an unknown and the root bend has no
//! spring); and the walk that evaluates `Φ` alone for the line search.
//!
//! The blocks of one bend (`J = [−S, S − Q, Q]` on nodes `i − 2, i − 1, i`, see
//! [`forces`](crate::dynamics::forces)) are written from their structure instead of 3×3
//! products: with `P = I − d·dᵀ`, `Q = P/l`, `c_r = r·d_p`,
//! `S = (d_p·rᵀ − c_r·I)/l_p`, `Q² = P/l²`,
//! `SᵀS = (r·rᵀ − c_r·(r·d_pᵀ + d_p·rᵀ) + c_r²·I)/l_p²` and
//! `Q·S = (a·rᵀ − c_r·P)/(l·l_p)` with `a = P·d_p`; the stiff length spring adds `κ·d·dᵀ`.
//! (`d`, `l`: the segment's direction and length; `d_p`, `l_p`: its parent's; `r`: the rest
//! direction in the transported parent frame.)

// Node loops index several per-node arrays by node on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::lane_blocks::{LaneSystem, MatLanes, SymLanes};
use crate::dynamics::lane_model::LaneNode;
use crate::dynamics::lane_springs::{LaneFrame, SpringScratch, joint};
use crate::dynamics::lanes::{LaneVec3, Lanes};

/// What the walks need of a batch besides the positions.
pub(crate) struct LaneChainTerms<'a, const N: usize> {
    /// Node constants (`n` of them).
    pub constants: &'a [LaneNode],
    /// The first unknown: 1 with attached roots, 0 with free ones.
    pub first: usize,
    /// The lengths' stiffness κ [N/m] per segment (index of its end node).
    pub kappa: &'a [Lanes; N],
    /// `m·(1 + h·γ)/h²` per node [kg/s²]: the inertia of the objective.
    pub inertia: &'a [Lanes; N],
    /// The prediction's displacements `δ̃` [m].
    pub predicted: &'a [LaneVec3; N],
    /// The head-carried root frame at the substep's end.
    pub root_frame: LaneFrame,
}

impl<const N: usize> LaneChainTerms<'_, N> {
    /// The stiffness of bend `i` [N·m/rad] in the step: none at the root bend of a free root.
    #[inline(always)]
    fn stiffness(&self, i: usize) -> Lanes {
        if i == 1 && self.first == 0 {
            Lanes::splat(0.0)
        } else {
            self.constants[i].stiffness
        }
    }

    /// The inertia term of node `i`: `½·m(1+hγ)/h²·|δ − δ̃|²` [J] and `δ̃ − δ` [m].
    #[inline(always)]
    fn lag(&self, delta: &[LaneVec3; N], i: usize) -> (Lanes, LaneVec3) {
        let lag = self.predicted[i] - delta[i];
        (
            Lanes::splat(0.5) * self.inertia[i] * lag.length_squared(),
            lag,
        )
    }
}

/// Assembles `(M/h² + H)·Δx = −∇Φ` at `x_n + δ` (`here`, with an attached root at its end
/// position) into `system` (unknowns `first..n`; the bending scratch in `springs`) and returns
/// the objective `Φ = E_bend + E_length + ½·Σ m(1+hγ)/h²·|δ − δ̃|²` [J] per lane.
#[inline(always)]
pub(crate) fn assemble<const N: usize>(
    terms: &LaneChainTerms<'_, N>,
    springs: &mut SpringScratch<N>,
    system: &mut LaneSystem<N>,
    here: &[LaneVec3; N],
    delta: &[LaneVec3; N],
    n: usize,
) -> Lanes {
    let zero = Lanes::splat(0.0);
    let half = Lanes::splat(0.5);
    let mut bend = zero;
    let mut stretch_energy = zero;
    let mut inertia_energy = zero;
    let mut frame = terms.root_frame;
    system.rhs[0] = LaneVec3::default();
    // Node i ≥ 2 + first reaches node i − 2 among the unknowns.
    let reach = 2 + terms.first;
    if terms.first == 0 {
        let (energy, lag) = terms.lag(delta, 0);
        inertia_energy = energy;
        system.rhs[0] = lag.scale(terms.inertia[0]);
        system.diagonal[0] = SymLanes::scaled_identity(terms.inertia[0]);
        system.first[0] = MatLanes::default();
        system.second[0] = MatLanes::default();
    }
    for i in 1..n {
        let c = &terms.constants[i];
        let k = terms.stiffness(i);
        // Inertia: rhs = m·(1+hγ)/h²·(δ̃ − δ), its diagonal block and energy.
        let inertia = terms.inertia[i];
        let (energy, lag) = terms.lag(delta, i);
        inertia_energy = inertia_energy + energy;
        system.rhs[i] = lag.scale(inertia);
        system.diagonal[i] = SymLanes::scaled_identity(inertia);
        system.first[i] = MatLanes::default();
        system.second[i] = MatLanes::default();
        let parent = (i >= 2).then(|| (springs.directions[i - 1], springs.inverse_lengths[i - 1]));
        let joint_terms = joint(
            springs,
            here,
            c.rest_local,
            i,
            k,
            &mut frame,
            &mut bend,
            None,
        );
        springs.rests[i] = joint_terms.rest;
        let d = springs.directions[i];
        let il = springs.inverse_lengths[i];
        // Bending forces: −Q·g on node i, Q·g − Sᵀg on i − 1, Sᵀg on i − 2, with
        // Sᵀg = −d_p × torque / l_p (see `lane_springs`).
        system.rhs[i] -= joint_terms.qg;
        system.rhs[i - 1] += joint_terms.qg;
        // Length spring: ½·κ·(l − l₀)², force κ·(l − l₀)·d pulling node i back.
        let kappa = terms.kappa[i];
        let stretch = joint_terms.length - c.rest_length;
        stretch_energy = stretch_energy + half * kappa * stretch * stretch;
        let pull = d.scale(kappa * stretch);
        system.rhs[i] -= pull;
        system.rhs[i - 1] += pull;
        // Diagonal block of node i: k·Q² + κ·d·dᵀ = (k/l²)·I + (κ − k/l²)·d·dᵀ.
        let q2 = k * il * il;
        system.diagonal[i].add_identity_and_outer(q2, kappa - q2, d);
        let Some((dp, ilp)) = parent else {
            if terms.first == 0 {
                // A free root: the length spring's κ·d·dᵀ on (0, 0) and −κ·d·dᵀ on (1, 0) (the
                // root bend has no spring).
                system.diagonal[0].add_identity_and_outer(zero, kappa, d);
                system.first[1].add_identity_and_outer(zero, -kappa, d);
            }
            continue;
        };
        let m = dp.cross(joint_terms.torque).scale(ilp);
        system.rhs[i - 1] += m;
        if i >= reach {
            system.rhs[i - 2] -= m;
        }
        let r = joint_terms.rest;
        let cr = r.dot(dp);
        let a = dp - d.scale(d.dot(dp));
        let kp2 = k * ilp * ilp;
        let kq = k * il * ilp;
        // The length spring's coupling of nodes i − 1 and i: κ·d·dᵀ on (i−1, i−1), −κ·d·dᵀ on
        // (i, i−1).
        // (i−1, i−1) += k·(SᵀS − Q·S − (Q·S)ᵀ + Q²) + κ·d·dᵀ
        //   = k·(c_r/l_p + 1/l)²·I − k·(2·c_r/(l·l_p) + 1/l²)·d·dᵀ + (k/l_p²)·r·rᵀ
        //     + sym(r, −(k/l_p²)·c_r·d_p − k/(l·l_p)·a) + κ·d·dᵀ.
        let sum = cr * ilp + il;
        let two_cross = (cr + cr) * kq;
        system.diagonal[i - 1].add_identity_and_outer(k * sum * sum, kappa - two_cross - q2, d);
        system.diagonal[i - 1].add_identity_and_outer(zero, kp2, r);
        system.diagonal[i - 1].add_symmetric_outer(
            Lanes::splat(-1.0),
            r,
            dp.scale(kp2 * cr) + a.scale(kq),
        );
        // (i, i−1) += k·(Q·S − Q²) − κ·d·dᵀ
        //   = (k/(l·l_p))·a·rᵀ − e·I + (e − κ)·d·dᵀ, e = k·(c_r/(l·l_p) + 1/l²).
        let e = cr * kq + q2;
        system.first[i].add_outer(kq, a, r);
        system.first[i].add_identity_and_outer(-e, e - kappa, d);
        if i >= reach {
            // (i−2, i−2) += k·SᵀS.
            system.diagonal[i - 2].add_identity_and_outer(kp2 * cr * cr, kp2, r);
            system.diagonal[i - 2].add_symmetric_outer(-(kp2 * cr), r, dp);
            // (i, i−2) += −k·Q·S = −(k/(l·l_p))·(a·rᵀ − c_r·I + c_r·d·dᵀ).
            let f = kq * cr;
            system.second[i].add_outer(-kq, a, r);
            system.second[i].add_identity_and_outer(f, -f, d);
            // (i−1, i−2) += −k·(SᵀS − Q·S)
            //   = r·((k/l_p²)·(c_r·d_p − r))ᵀ + ((k/l_p²)·c_r·d_p + (k/(l·l_p))·a)·rᵀ
            //     − (k/l_p)·c_r·(c_r/l_p + 1/l)·I + (k/(l·l_p))·c_r·d·dᵀ.
            system.first[i - 1].add_outer(kp2, r, dp.scale(cr) - r);
            system.first[i - 1].add_outer(Lanes::splat(1.0), dp.scale(kp2 * cr) + a.scale(kq), r);
            system.first[i - 1].add_identity_and_outer(-(k * ilp * cr * sum), f, d);
        }
    }
    // Twist, tip to root (see `lane_springs::spring_forces`): −∂E/∂d_j = A_j·κb_j/2 +
    // A_{j+1}·κb_{j+1}/2 on nodes j and j − 1 (both binormals ⟂ d_j, so Q_j is 1/l_j).
    let mut suffix = zero;
    let mut next_twist = zero;
    let mut next_half_binormal = LaneVec3::default();
    for j in (1..n).rev() {
        let a_next = suffix;
        let a_here = suffix + next_twist;
        let half_binormal = springs.half_binormals[j];
        let pull = half_binormal.scale(a_here) + next_half_binormal.scale(a_next);
        let force = pull.scale(springs.inverse_lengths[j]);
        system.rhs[j] += force;
        system.rhs[j - 1] -= force;
        suffix = a_here;
        next_twist = springs.twist[j];
        next_half_binormal = half_binormal;
    }
    bend + stretch_energy + inertia_energy
}

/// The objective `Φ` [J] per lane at `x_n + δ` (`here`): the same sums, in the same order and
/// with the same arithmetic, as [`assemble`] returns (so that the line search compares like
/// with like), without forces or blocks.
#[inline(always)]
pub(crate) fn objective<const N: usize>(
    terms: &LaneChainTerms<'_, N>,
    here: &[LaneVec3; N],
    delta: &[LaneVec3; N],
    n: usize,
) -> Lanes {
    let zero = Lanes::splat(0.0);
    let half = Lanes::splat(0.5);
    let mut bend = zero;
    let mut stretch_energy = zero;
    let mut inertia_energy = zero;
    let mut frame = terms.root_frame;
    if terms.first == 0 {
        inertia_energy = terms.lag(delta, 0).0;
    }
    for i in 1..n {
        let c = &terms.constants[i];
        inertia_energy = inertia_energy + terms.lag(delta, i).0;
        // As `lane_springs::joint`.
        let segment = frame.segment(here[i - 1], here[i], c.rest_local);
        let (direction, rest) = (segment.direction, segment.rest);
        let axis = direction.cross(rest);
        let sin = axis.length_squared().sqrt();
        let cos = direction.dot(rest);
        let (angle, _) = Lanes::bend_angle_and_factor(sin, cos);
        bend = bend + half * terms.stiffness(i) * angle * angle;
        frame = frame.transported(&segment);
        let stretch = segment.length - c.rest_length;
        stretch_energy = stretch_energy + half * terms.kappa[i] * stretch * stretch;
    }
    bend + stretch_energy + inertia_energy
}
