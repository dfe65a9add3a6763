//! 3×3 blocks with one matrix per lane ([`LANES`](crate::dynamics::lanes::LANES) chains at once)
//! and the block-pentadiagonal `L·D·Lᵀ` solve of
//! [`solve_block_pentadiagonal`](crate::dynamics::solve_block_pentadiagonal) on them: the linear
//! algebra of the lane-parallel XPBD step. Diagonal blocks are symmetric and stored by their six
//! entries ([`SymLanes`]); off-diagonal blocks are general ([`MatLanes`], by rows).

// Block loops index several per-node arrays by node on purpose: that is the form the vectoriser
// reads.
#![allow(clippy::needless_range_loop)]

use crate::dynamics::lanes::{LaneVec3, Lanes};

/// A symmetric 3×3 matrix per lane.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SymLanes {
    pub xx: Lanes,
    pub yy: Lanes,
    pub zz: Lanes,
    pub xy: Lanes,
    pub xz: Lanes,
    pub yz: Lanes,
}

/// A general 3×3 matrix per lane, by rows: `r[row][column]`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct MatLanes {
    pub r: [[Lanes; 3]; 3],
}

impl SymLanes {
    /// `a·I` per lane.
    #[inline(always)]
    pub fn scaled_identity(a: Lanes) -> SymLanes {
        let zero = Lanes::splat(0.0);
        SymLanes {
            xx: a,
            yy: a,
            zz: a,
            xy: zero,
            xz: zero,
            yz: zero,
        }
    }

    /// `self += a·I + b·u·uᵀ`.
    #[inline(always)]
    pub fn add_identity_and_outer(&mut self, a: Lanes, b: Lanes, u: LaneVec3) {
        let bx = b * u.x;
        let by = b * u.y;
        let bz = b * u.z;
        self.xx = self.xx + a + bx * u.x;
        self.yy = self.yy + a + by * u.y;
        self.zz = self.zz + a + bz * u.z;
        self.xy = self.xy + bx * u.y;
        self.xz = self.xz + bx * u.z;
        self.yz = self.yz + by * u.z;
    }

    /// `self += a·I`.
    #[inline(always)]
    pub fn add_to_diagonal(&mut self, a: Lanes) {
        self.xx = self.xx + a;
        self.yy = self.yy + a;
        self.zz = self.zz + a;
    }

    /// `self += s·(u·vᵀ + v·uᵀ)`.
    #[inline(always)]
    pub fn add_symmetric_outer(&mut self, s: Lanes, u: LaneVec3, v: LaneVec3) {
        let two = s + s;
        self.xx = self.xx + two * u.x * v.x;
        self.yy = self.yy + two * u.y * v.y;
        self.zz = self.zz + two * u.z * v.z;
        self.xy = self.xy + s * (u.x * v.y + v.x * u.y);
        self.xz = self.xz + s * (u.x * v.z + v.x * u.z);
        self.yz = self.yz + s * (u.y * v.z + v.y * u.z);
    }

    /// `self·v` per lane.
    #[inline(always)]
    pub fn mul_vec(&self, v: LaneVec3) -> LaneVec3 {
        LaneVec3 {
            x: self.xx * v.x + self.xy * v.y + self.xz * v.z,
            y: self.xy * v.x + self.yy * v.y + self.yz * v.z,
            z: self.xz * v.x + self.yz * v.y + self.zz * v.z,
        }
    }

    /// The largest diagonal entry per lane.
    #[inline(always)]
    pub fn largest_diagonal(&self) -> Lanes {
        self.xx.max(self.yy).max(self.zz)
    }

    /// The inverse per lane, and the determinant (the inverse is not finite where the
    /// determinant is 0).
    #[inline(always)]
    pub fn inverse(&self) -> (SymLanes, Lanes) {
        let cxx = self.yy * self.zz - self.yz * self.yz;
        let cxy = self.xz * self.yz - self.xy * self.zz;
        let cxz = self.xy * self.yz - self.xz * self.yy;
        let determinant = self.xx * cxx + self.xy * cxy + self.xz * cxz;
        let inverse = Lanes::splat(1.0) / determinant;
        (
            SymLanes {
                xx: cxx * inverse,
                xy: cxy * inverse,
                xz: cxz * inverse,
                yy: (self.xx * self.zz - self.xz * self.xz) * inverse,
                yz: (self.xy * self.xz - self.xx * self.yz) * inverse,
                zz: (self.xx * self.yy - self.xy * self.xy) * inverse,
            },
            determinant,
        )
    }

    /// The entry at `(row, column)`.
    #[inline(always)]
    fn at(&self, row: usize, column: usize) -> Lanes {
        match (row.min(column), row.max(column)) {
            (0, 0) => self.xx,
            (1, 1) => self.yy,
            (2, 2) => self.zz,
            (0, 1) => self.xy,
            (0, 2) => self.xz,
            _ => self.yz,
        }
    }
}

impl MatLanes {
    /// `self += s·u·vᵀ`.
    #[inline(always)]
    pub fn add_outer(&mut self, s: Lanes, u: LaneVec3, v: LaneVec3) {
        let su = [s * u.x, s * u.y, s * u.z];
        let v = [v.x, v.y, v.z];
        for row in 0..3 {
            for column in 0..3 {
                self.r[row][column] = self.r[row][column] + su[row] * v[column];
            }
        }
    }

    /// `self += a·I + b·u·uᵀ`.
    #[inline(always)]
    pub fn add_identity_and_outer(&mut self, a: Lanes, b: Lanes, u: LaneVec3) {
        self.add_outer(b, u, u);
        for d in 0..3 {
            self.r[d][d] = self.r[d][d] + a;
        }
    }

    /// `self·v` per lane.
    #[inline(always)]
    pub fn mul_vec(&self, v: LaneVec3) -> LaneVec3 {
        let row = |r: &[Lanes; 3]| r[0] * v.x + r[1] * v.y + r[2] * v.z;
        LaneVec3 {
            x: row(&self.r[0]),
            y: row(&self.r[1]),
            z: row(&self.r[2]),
        }
    }

    /// `selfᵀ·v` per lane.
    #[inline(always)]
    pub fn transpose_mul_vec(&self, v: LaneVec3) -> LaneVec3 {
        let column = |c: usize| self.r[0][c] * v.x + self.r[1][c] * v.y + self.r[2][c] * v.z;
        LaneVec3 {
            x: column(0),
            y: column(1),
            z: column(2),
        }
    }

    /// `self·B` for a symmetric `B`.
    #[inline(always)]
    fn mul_symmetric(&self, b: &SymLanes) -> MatLanes {
        let mut out = MatLanes::default();
        for row in 0..3 {
            for column in 0..3 {
                out.r[row][column] = self.r[row][0] * b.at(0, column)
                    + self.r[row][1] * b.at(1, column)
                    + self.r[row][2] * b.at(2, column);
            }
        }
        out
    }

    /// `self·Bᵀ`.
    #[inline(always)]
    fn mul_transpose(&self, b: &MatLanes) -> MatLanes {
        let mut out = MatLanes::default();
        for row in 0..3 {
            for column in 0..3 {
                out.r[row][column] = self.r[row][0] * b.r[column][0]
                    + self.r[row][1] * b.r[column][1]
                    + self.r[row][2] * b.r[column][2];
            }
        }
        out
    }

    /// The symmetric part of `self·Bᵀ` where it is known to be symmetric (only the upper
    /// triangle is computed).
    #[inline(always)]
    fn mul_transpose_symmetric(&self, b: &MatLanes) -> SymLanes {
        let entry = |row: usize, column: usize| {
            self.r[row][0] * b.r[column][0]
                + self.r[row][1] * b.r[column][1]
                + self.r[row][2] * b.r[column][2]
        };
        SymLanes {
            xx: entry(0, 0),
            yy: entry(1, 1),
            zz: entry(2, 2),
            xy: entry(0, 1),
            xz: entry(0, 2),
            yz: entry(1, 2),
        }
    }

    fn sub_assign(&mut self, b: &MatLanes) {
        for row in 0..3 {
            for column in 0..3 {
                self.r[row][column] = self.r[row][column] - b.r[row][column];
            }
        }
    }
}

impl SymLanes {
    #[inline(always)]
    fn sub_assign(&mut self, b: &SymLanes) {
        self.xx = self.xx - b.xx;
        self.yy = self.yy - b.yy;
        self.zz = self.zz - b.zz;
        self.xy = self.xy - b.xy;
        self.xz = self.xz - b.xz;
        self.yz = self.yz - b.yz;
    }
}

/// The block-pentadiagonal system of a batch, unknowns `first..n`: `diagonal[i] = A_ii`,
/// `first[i] = A_{i,i−1}`, `second[i] = A_{i,i−2}` (blocks reaching below `first` are ignored),
/// `rhs = b`.
pub(crate) struct LaneSystem<const N: usize> {
    pub diagonal: [SymLanes; N],
    pub first: [MatLanes; N],
    pub second: [MatLanes; N],
    pub rhs: [LaneVec3; N],
}

impl<const N: usize> LaneSystem<N> {
    pub(crate) fn new() -> Self {
        LaneSystem {
            diagonal: [SymLanes::default(); N],
            first: [MatLanes::default(); N],
            second: [MatLanes::default(); N],
            rhs: [LaneVec3::default(); N],
        }
    }

    /// Solves `A·x = b` for unknowns `start..n` of every lane in place (`rhs = x` on return;
    /// the blocks are overwritten by the factorisation): the algorithm of
    /// [`solve_block_pentadiagonal`](crate::dynamics::solve_block_pentadiagonal), lane-wise.
    /// Returns 1.0 in the lanes whose pivots were all positive definite and finite (their
    /// determinants positive), 0.0 in the others (their solution is not usable).
    #[inline(always)]
    pub(crate) fn solve(&mut self, start: usize, n: usize) -> Lanes {
        let good = self.factorise(start, n);
        substitute(
            &self.diagonal,
            &self.first,
            &self.second,
            &mut self.rhs,
            start,
            n,
        );
        good
    }

    /// Factorises the blocks of unknowns `start..n` in place (as
    /// [`factorise_block_pentadiagonal`](crate::dynamics::banded::factorise_block_pentadiagonal),
    /// lane-wise); returns 1.0 in the lanes whose pivots were all positive definite and finite.
    #[inline(always)]
    pub(crate) fn factorise(&mut self, start: usize, n: usize) -> Lanes {
        let zero = Lanes::splat(0.0);
        let mut good = Lanes::splat(1.0);
        for i in start..n {
            let mut d = self.diagonal[i];
            if i >= start + 2 {
                let w2 = self.second[i];
                let w2_dinv = w2.mul_symmetric(&self.diagonal[i - 2]);
                let correction = w2_dinv.mul_transpose(&self.first[i - 1]);
                self.first[i].sub_assign(&correction);
                d.sub_assign(&w2_dinv.mul_transpose_symmetric(&w2));
            }
            if i > start {
                let w1 = self.first[i];
                let w1_dinv = w1.mul_symmetric(&self.diagonal[i - 1]);
                d.sub_assign(&w1_dinv.mul_transpose_symmetric(&w1));
            }
            let (inverse, determinant) = d.inverse();
            // Positive and finite (NaN fails `>`; a finite positive determinant has a finite
            // reciprocal only when above ~1e-38, which `inverse` then shows as finite).
            let ok = determinant.greater(zero) * Lanes::splat(f32::MAX).greater(determinant);
            good = good * ok;
            self.diagonal[i] = inverse;
        }
        good
    }

    /// Replaces `v` (unknowns `start..n`) by `A⁻¹·v` with the factorisation
    /// [`LaneSystem::factorise`] left in the blocks (any number of times).
    #[inline(always)]
    pub(crate) fn substitute(&self, v: &mut [LaneVec3; N], start: usize, n: usize) {
        substitute(&self.diagonal, &self.first, &self.second, v, start, n);
    }
}

/// The forward and backward substitutions of [`LaneSystem::solve`] on `v`.
#[inline(always)]
fn substitute<const N: usize>(
    diagonal: &[SymLanes; N],
    first: &[MatLanes; N],
    second: &[MatLanes; N],
    v: &mut [LaneVec3; N],
    start: usize,
    n: usize,
) {
    // Forward: y_i = b_i − W_{i,i−1}·z_{i−1} − W_{i,i−2}·z_{i−2}, z_i = D_i⁻¹·y_i.
    for i in start..n {
        let mut y = v[i];
        if i > start {
            y -= first[i].mul_vec(v[i - 1]);
        }
        if i >= start + 2 {
            y -= second[i].mul_vec(v[i - 2]);
        }
        v[i] = diagonal[i].mul_vec(y);
    }
    // Backward: x_i = z_i − D_i⁻¹·(W_{i+1,i}ᵀ·x_{i+1} + W_{i+2,i}ᵀ·x_{i+2}).
    for i in (start..n).rev() {
        let mut sum = LaneVec3::default();
        if i + 1 < n {
            sum += first[i + 1].transpose_mul_vec(v[i + 1]);
        }
        if i + 2 < n {
            sum += second[i + 2].transpose_mul_vec(v[i + 2]);
        }
        v[i] -= diagonal[i].mul_vec(sum);
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat3, Vec3};

    use super::*;
    use crate::dynamics::lanes::LANES;
    use crate::dynamics::solve_block_pentadiagonal;
    use crate::random::SplitMix64;

    #[test]
    fn lane_solve_matches_the_one_chain_solve() {
        // Random SPD block-pentadiagonal systems (M + Σ JᵀJ over 3-node couplings), a different
        // one per lane, unknowns 1..n (node 0 fixed): each lane must agree with the banded solve
        // of the linear-implicit step (`solve_block_pentadiagonal`) to f32 rounding of a well-conditioned system (relative 1e-4).
        let n = 11;
        let mut rng = SplitMix64::new(7);
        let mut system = LaneSystem::<16>::new();
        let mut reference = Vec::new();
        for lane in 0..LANES {
            let mut diagonal = vec![Mat3::from_diagonal(Vec3::splat(2.0)); n];
            let mut first = vec![Mat3::ZERO; n];
            let mut second = vec![Mat3::ZERO; n];
            for joint in 3..n {
                let mut random =
                    || Mat3::from_cols_array(&std::array::from_fn(|_| rng.range(-1.0, 1.0)));
                let blocks = [random(), random(), random()];
                let nodes = [joint - 2, joint - 1, joint];
                for a in 0..3 {
                    for b in 0..3 {
                        let product = blocks[a].transpose() * blocks[b];
                        let (na, nb) = (nodes[a], nodes[b]);
                        if na == nb {
                            diagonal[na] += product;
                        } else if na == nb + 1 {
                            first[na] += product;
                        } else if na == nb + 2 {
                            second[na] += product;
                        }
                    }
                }
            }
            let b: Vec<Vec3> = (0..n)
                .map(|i| Vec3::new(i as f32, 1.0 + lane as f32, -0.5 * i as f32))
                .collect();
            for i in 1..n {
                let d = diagonal[i];
                system.diagonal[i].xx.0[lane] = d.x_axis.x;
                system.diagonal[i].yy.0[lane] = d.y_axis.y;
                system.diagonal[i].zz.0[lane] = d.z_axis.z;
                system.diagonal[i].xy.0[lane] = d.y_axis.x;
                system.diagonal[i].xz.0[lane] = d.z_axis.x;
                system.diagonal[i].yz.0[lane] = d.z_axis.y;
                for row in 0..3 {
                    for column in 0..3 {
                        system.first[i].r[row][column].0[lane] = first[i].col(column)[row];
                        system.second[i].r[row][column].0[lane] = second[i].col(column)[row];
                    }
                }
                system.rhs[i].set(lane, b[i]);
            }
            let mut x = b[1..].to_vec();
            let mut first_ref = first[1..].to_vec();
            first_ref[0] = Mat3::ZERO;
            let mut second_ref = second[1..].to_vec();
            second_ref[0] = Mat3::ZERO;
            if second_ref.len() > 1 {
                second_ref[1] = Mat3::ZERO;
            }
            assert!(solve_block_pentadiagonal(
                &mut diagonal[1..].to_vec(),
                &mut first_ref,
                &second_ref,
                &mut x
            ));
            reference.push(x);
        }
        let good = system.solve(1, n);
        for lane in 0..LANES {
            assert_eq!(good.0[lane], 1.0);
            for i in 1..n {
                let expected = reference[lane][i - 1];
                let got = system.rhs[i].get(lane);
                assert!(
                    (got - expected).length() <= 1e-4 * expected.length().max(1.0),
                    "lane {lane} node {i}: {got} vs {expected}"
                );
            }
        }
    }
}
