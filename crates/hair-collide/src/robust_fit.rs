//! The affine map fitted to the bulk of a deformation, not to all of it (issue 53): a talking
//! head's skull squashes and stretches (an affine deformation) while its jaw drops, and the
//! least-squares fit of the whole mesh spreads the jaw's drop over the skull (4–8 mm there).
//! Fitted with the jaw weighed down, the skull follows the map to rounding, and the bounds per
//! region (`deviation_blocks.rs`) clear the hair on it.
//!
//! **How.** Concentration steps of least trimmed squares over blocks of vertices: from the
//! whole mesh's fit, keep the blocks whose root-mean-square residual is at most the median of
//! those (by vertex count, so at least half the vertices), fit them alone, and repeat until
//! the blocks kept no longer change (each step lowers the kept blocks' sum of squares). A
//! block's residual under any affine map `W = [G t]` (displacements `d ≈ G X̃ + t` of the
//! centred rest vertices `X̃`) follows from its moments,
//! `Σ |d − W h|² = Σ|d|² − 2 W : Σ d hᵀ + (Wᵀ W) : Σ h hᵀ` with `h = (X̃, 1)`, so a step
//! costs a few operations per block and none per vertex. `Σ h hᵀ` is the rest's, found once.
//! The map only has to fit well: what bounds the distances is each block's deviation from it,
//! measured afterwards over every vertex.

use glam::{DMat4, DVec4};

/// Concentration steps at most: the blocks kept settle within three or four on a jaw and a
/// squash.
const ITERATIONS: usize = 4;

/// The smallest threshold \[m\]: residuals below it count as fitting.
const SCALE_FLOOR: f64 = 1e-5;

/// One block's moments at an instant: `Σ d hᵀ` (its fourth row zero) and `Σ |d|²` \[m²\].
#[derive(Debug, Clone, Copy)]
pub(crate) struct BlockMoments {
    pub(crate) cross: DMat4,
    pub(crate) square: f64,
}

/// The map `W = [G t]` (as a 4 × 4 matrix with a zero fourth row) that fits the displacements
/// of the blocks with moments `moments` (each block's rest `Σ h hᵀ` in `rest`), starting from
/// `start`, with the blocks that do not fit the bulk left out; the last fit where the blocks
/// kept are too flat to fit. `errors`, `ranks` and `kept` are scratch.
pub(crate) fn bulk_fit(
    rest: &[DMat4],
    moments: &[BlockMoments],
    start: DMat4,
    errors: &mut Vec<f64>,
    ranks: &mut Vec<(f64, f64)>,
    kept: &mut Vec<bool>,
) -> DMat4 {
    let mut fit = start;
    // Every block kept: the start is the whole mesh's fit.
    kept.clear();
    kept.resize(rest.len(), true);
    for _ in 0..ITERATIONS {
        // `(W H) : W = (Wᵀ W) : H`, with `Wᵀ W` found once for all blocks.
        let gram = fit.transpose() * fit;
        errors.clear();
        errors.extend(rest.iter().zip(moments).map(|(spread, m)| {
            let count = spread.w_axis.w.max(1.0);
            let squares = m.square - 2.0 * frobenius(&fit, &m.cross) + frobenius(&gram, spread);
            (squares.max(0.0) / count).sqrt()
        }));
        ranks.clear();
        ranks.extend(
            errors
                .iter()
                .zip(rest)
                .map(|(&e, spread)| (e, spread.w_axis.w)),
        );
        let scale = weighted_median(ranks).max(SCALE_FLOOR);
        // The blocks kept: where they are the last iteration's, so is the fit.
        let mut changed = false;
        for (keep, &error) in kept.iter_mut().zip(errors.iter()) {
            changed |= *keep != (error <= scale);
            *keep = error <= scale;
        }
        if !changed {
            break;
        }
        let (mut spread, mut cross) = (DMat4::ZERO, DMat4::ZERO);
        for ((rest, m), _) in rest
            .iter()
            .zip(moments)
            .zip(kept.iter())
            .filter(|(_, k)| **k)
        {
            spread += *rest;
            cross += m.cross;
        }
        // Positive semi-definite: its determinant is at most its diagonal's product
        // (Hadamard), and far below it where the weighted vertices are nearly flat.
        let diagonal = spread.x_axis.x * spread.y_axis.y * spread.z_axis.z * spread.w_axis.w;
        let determinant = spread.determinant();
        if determinant.is_nan() || determinant <= 1e-9 * diagonal {
            break;
        }
        let next = cross * spread.inverse();
        if !next.is_finite() {
            break;
        }
        fit = next;
    }
    fit
}

/// `Σᵢⱼ aᵢⱼ bᵢⱼ`.
fn frobenius(a: &DMat4, b: &DMat4) -> f64 {
    let dot = |x: DVec4, y: DVec4| x.dot(y);
    dot(a.x_axis, b.x_axis)
        + dot(a.y_axis, b.y_axis)
        + dot(a.z_axis, b.z_axis)
        + dot(a.w_axis, b.w_axis)
}

/// The median of the errors in `ranks` (`(error, vertex count)` per block), each counted as
/// many times as its block has vertices; sorts `ranks`.
fn weighted_median(ranks: &mut [(f64, f64)]) -> f64 {
    let total: f64 = ranks.iter().map(|r| r.1).sum();
    ranks.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut seen = 0.0;
    for &(error, count) in ranks.iter() {
        seen += count;
        if seen * 2.0 >= total {
            return error;
        }
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat3, DVec3};

    /// Blocks of points, 60 % of them moved by one affine map and the rest by it plus a drop
    /// (a jaw): the bulk fit recovers the map to rounding, where the whole least-squares fit
    /// spreads the drop.
    #[test]
    fn the_bulk_fit_leaves_a_dropped_part_out() {
        let g = DMat3::from_cols(
            DVec3::new(-0.04, 0.01, 0.0),
            DVec3::new(0.02, 0.08, -0.01),
            DVec3::new(0.0, 0.03, -0.03),
        );
        let t = DVec3::new(0.01, -0.02, 0.005);
        let (mut rest, mut moments) = (Vec::new(), Vec::new());
        for block in 0..50 {
            let mut spread = DMat4::ZERO;
            let mut m = BlockMoments {
                cross: DMat4::ZERO,
                square: 0.0,
            };
            for i in 0..20 {
                let s = (block * 20 + i) as f64;
                let x = DVec3::new((0.37 * s).sin(), (0.71 * s).cos(), (0.13 * s).sin()) * 0.1;
                let drop = if block % 5 < 2 {
                    DVec3::Y * -0.012
                } else {
                    DVec3::ZERO
                };
                let d = g * x + t + drop;
                let h = x.extend(1.0);
                spread += DMat4::from_cols(h * h.x, h * h.y, h * h.z, h);
                m.cross += DMat4::from_cols(
                    d.extend(0.0) * h.x,
                    d.extend(0.0) * h.y,
                    d.extend(0.0) * h.z,
                    d.extend(0.0),
                );
                m.square += d.length_squared();
            }
            rest.push(spread);
            moments.push(m);
        }
        let total = rest.iter().fold(DMat4::ZERO, |a, b| a + *b);
        let cross = moments.iter().fold(DMat4::ZERO, |a, m| a + m.cross);
        let whole = cross * total.inverse();
        let expected = DMat4::from_cols(
            g.x_axis.extend(0.0),
            g.y_axis.extend(0.0),
            g.z_axis.extend(0.0),
            t.extend(0.0),
        );
        let off = |fit: DMat4| {
            (fit - expected)
                .to_cols_array()
                .iter()
                .map(|x| x.abs())
                .fold(0.0, f64::max)
        };
        assert!(
            off(whole) > 1e-3,
            "the whole fit spreads the drop: {}",
            off(whole)
        );
        let (mut errors, mut ranks, mut kept) = (Vec::new(), Vec::new(), Vec::new());
        let bulk = bulk_fit(&rest, &moments, whole, &mut errors, &mut ranks, &mut kept);
        assert!(off(bulk) < 1e-9, "the bulk fit is off by {}", off(bulk));
        assert_eq!(kept.iter().filter(|k| **k).count(), 30);
    }
}
