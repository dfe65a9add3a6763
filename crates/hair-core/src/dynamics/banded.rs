//! A symmetric positive definite block-pentadiagonal solve (3×3 blocks, two sub-diagonals): the
//! per-chain linear system of the implicit integrator, by block `L·D·Lᵀ` factorisation in place.

use glam::{Mat3, Vec3};

/// The outer product `a·bᵀ`.
#[inline]
pub fn outer(a: Vec3, b: Vec3) -> Mat3 {
    Mat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The cross-product matrix `[a]ₓ` (`[a]ₓ·v = a × v`).
#[inline]
pub fn cross_matrix(a: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, a.z, -a.y),
        Vec3::new(-a.z, 0.0, a.x),
        Vec3::new(a.y, -a.x, 0.0),
    )
}

/// Solves `A·x = b` for a symmetric positive definite matrix `A` of `n × n` blocks of 3×3 with
/// blocks only on the diagonal and the first two sub-diagonals (and their transposes above):
/// [`factorise_block_pentadiagonal`], then [`substitute_block_pentadiagonal`].
///
/// On entry `diagonal[i] = A_ii`, `first[i] = A_{i,i−1}` (`first[0]` unused), `second[i] =
/// A_{i,i−2}` (`second[0..2]` unused), `rhs = b`. On exit `rhs = x` and the matrices hold the
/// factorisation. Returns `false` when a pivot block is singular or not finite.
pub fn solve_block_pentadiagonal(
    diagonal: &mut [Mat3],
    first: &mut [Mat3],
    second: &[Mat3],
    rhs: &mut [Vec3],
) -> bool {
    if !factorise_block_pentadiagonal(diagonal, first, second) {
        return false;
    }
    substitute_block_pentadiagonal(diagonal, first, second, rhs);
    true
}

/// Factorises in place the block-pentadiagonal SPD matrix of [`solve_block_pentadiagonal`]
/// (`diagonal[i] = D_i⁻¹`, `first[i] = L_{i,i−1}·D_{i−1}` on exit). Uses `A = L·D·Lᵀ` with
/// `W_ij = L_ij·D_j`: `W_{i,i−2} = A_{i,i−2}`,
/// `W_{i,i−1} = A_{i,i−1} − W_{i,i−2}·D_{i−2}⁻¹·W_{i−1,i−2}ᵀ`,
/// `D_i = A_ii − Σ_j W_ij·D_j⁻¹·W_ijᵀ`. Returns `false` when a pivot block is singular or not
/// finite.
pub fn factorise_block_pentadiagonal(
    diagonal: &mut [Mat3],
    first: &mut [Mat3],
    second: &[Mat3],
) -> bool {
    let n = diagonal.len();
    for i in 0..n {
        let mut d = diagonal[i];
        if i >= 2 {
            let w2 = second[i];
            let w2_dinv = w2 * diagonal[i - 2];
            first[i] -= w2_dinv * first[i - 1].transpose();
            d -= w2_dinv * w2.transpose();
        }
        if i >= 1 {
            let w1 = first[i];
            d -= w1 * diagonal[i - 1] * w1.transpose();
        }
        let determinant = d.determinant();
        if !(determinant.is_finite() && determinant > 0.0) {
            return false;
        }
        diagonal[i] = d.inverse();
    }
    true
}

/// Replaces `rhs` by `A⁻¹·rhs`, `A` factorised by [`factorise_block_pentadiagonal`] (which can
/// be followed by any number of substitutions).
pub fn substitute_block_pentadiagonal(
    diagonal: &[Mat3],
    first: &[Mat3],
    second: &[Mat3],
    rhs: &mut [Vec3],
) {
    let n = diagonal.len();
    // Forward: y_i = b_i − W_{i,i−1}·z_{i−1} − W_{i,i−2}·z_{i−2}, z_i = D_i⁻¹·y_i (stored in rhs).
    for i in 0..n {
        let mut y = rhs[i];
        if i >= 1 {
            y -= first[i] * rhs[i - 1];
        }
        if i >= 2 {
            y -= second[i] * rhs[i - 2];
        }
        rhs[i] = diagonal[i] * y;
    }
    // Backward: x_i = z_i − D_i⁻¹·(W_{i+1,i}ᵀ·x_{i+1} + W_{i+2,i}ᵀ·x_{i+2}).
    for i in (0..n).rev() {
        let mut sum = Vec3::ZERO;
        if i + 1 < n {
            sum += first[i + 1].transpose() * rhs[i + 1];
        }
        if i + 2 < n {
            sum += second[i + 2].transpose() * rhs[i + 2];
        }
        rhs[i] -= diagonal[i] * sum;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    #[test]
    fn matches_a_dense_solve() {
        // A = M + Σ JᵀJ with random 3-node couplings (SPD, pentadiagonal); compare A·x with b.
        let n = 9;
        let mut rng = SplitMix64::new(3);
        let mut dense = vec![[0.0f64; 27]; 27];
        let random_mat = |rng: &mut SplitMix64| {
            Mat3::from_cols_array(&std::array::from_fn(|_| rng.range(-1.0, 1.0)))
        };
        for (i, row) in dense.iter_mut().enumerate() {
            row[i] = 2.0;
        }
        for joint in 2..n {
            let blocks = [
                random_mat(&mut rng),
                random_mat(&mut rng),
                random_mat(&mut rng),
            ];
            let nodes = [joint - 2, joint - 1, joint];
            for (a, &na) in nodes.iter().enumerate() {
                for (b, &nb) in nodes.iter().enumerate() {
                    let product = blocks[a].transpose() * blocks[b];
                    for r in 0..3 {
                        for c in 0..3 {
                            dense[3 * na + r][3 * nb + c] += product.col(c)[r] as f64;
                        }
                    }
                }
            }
        }
        let block = |i: usize, j: usize| {
            Mat3::from_cols_array(&std::array::from_fn(|k| {
                dense[3 * i + k % 3][3 * j + k / 3] as f32
            }))
        };
        let mut diagonal: Vec<Mat3> = (0..n).map(|i| block(i, i)).collect();
        let mut first: Vec<Mat3> = (0..n)
            .map(|i| if i >= 1 { block(i, i - 1) } else { Mat3::ZERO })
            .collect();
        let second: Vec<Mat3> = (0..n)
            .map(|i| if i >= 2 { block(i, i - 2) } else { Mat3::ZERO })
            .collect();
        let b: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f32, 1.0, -0.5 * i as f32))
            .collect();
        let mut x = b.clone();
        assert!(solve_block_pentadiagonal(
            &mut diagonal,
            &mut first,
            &second,
            &mut x
        ));
        for r in 0..3 * n {
            let ax: f64 = (0..3 * n)
                .map(|c| dense[r][c] * x[c / 3][c % 3] as f64)
                .sum();
            assert!((ax - b[r / 3][r % 3] as f64).abs() < 1e-4, "row {r}: {ax}");
        }
        // A second substitution with the same factorisation solves again, bit for bit.
        let mut again = b.clone();
        substitute_block_pentadiagonal(&diagonal, &first, &second, &mut again);
        assert_eq!(again, x);
    }
}
