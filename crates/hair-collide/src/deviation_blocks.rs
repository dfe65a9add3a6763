//! How far a deforming body strays from its fitted map, region by region (issue 53): the rest
//! vertices sorted into cubic blocks, each instant's largest deviation per block, and the
//! certified bound that reads only the deviations of the blocks around a point
//! ([`NearDeviations::bound`]).
//!
//! **Why.** The moving field's bound (`field_map.rs`) subtracts the deviation `δ` of the whole
//! mesh from the fitted map `F`: a talking head's jaw drops 12 mm while its scalp follows `F`
//! exactly, and the hair on the scalp, a few millimetres from it, then needs an exact search.
//!
//! **The bound.** Let `q = F⁻¹ p`, in block `c` of size `b`, and `L` the longest rest edge. A
//! triangle `T` with `d(q, T) < k b − L` has every vertex within `k b` of `q` (a point of a
//! triangle lies within its longest edge of each vertex), so in a block at most `k` blocks from
//! `c` along each axis; its deviation is at most `δ_k(c)`, the largest over those blocks. So,
//! with `σ` the map's least stretch, `r` the rest field's bound at `q` and `f_k = k b − L`,
//! splitting the triangles by their rest distance from `q`:
//!
//! `d(p, surface) ≥ min(σ r − δ_1(c), σ f_1 − δ_2(c), …, σ f_{K−1} − δ_K(c), σ f_K − δ)`,
//!
//! each triangle being at least `σ d(q, T) − δ_T` from `p` (`field_map.rs`). The same holds for
//! every surface of the straight morph from `F(rest)` to the current one, so where it is
//! positive `p` is on the rest field's side, as with the whole mesh's deviation. The larger of
//! this and the whole mesh's bound is taken.

use glam::Vec3;

/// How many widening rings of blocks the bound reads (`K` above).
const RINGS: usize = 2;

/// Blocks along the body's longest side, at most: the block grows on larger bodies.
const MAX_BLOCKS_ALONG: f32 = 48.0;

/// A block is at least this many longest edges wide, so that the first ring reaches beyond
/// the triangles it holds.
const EDGES_PER_BLOCK: f32 = 2.5;

/// Allowance \[m\] for the rounding of a point's block at a head's scale.
const ROUNDING: f32 = 1e-6;

/// The rest vertices sorted into cubic blocks: the grid, and each occupied block's vertices
/// (as ranges of the rest field's vertex order, which is sorted by block).
#[derive(Debug, Clone)]
pub(crate) struct Blocks {
    /// The grid's lowest corner \[m\] (rest body frame): one empty block below the vertices.
    origin: Vec3,
    /// A block's side \[m\].
    size: f32,
    /// Blocks along each axis.
    dims: [usize; 3],
    /// `f_k = k b − L − rounding` \[m\] for the rings `k = 1..=K`.
    reaches: [f32; RINGS],
    /// Per occupied block, its cell in the grid.
    cells: Vec<u32>,
    /// Per occupied block, its first vertex (in the sorted order); one more at the end.
    starts: Vec<u32>,
}

impl Blocks {
    /// The blocks of the mesh whose used vertices are `rest` \[m\] and whose longest edge is
    /// `longest_edge` \[m\]; returns them with the order that sorts `rest` by block (stable).
    pub(crate) fn of(rest: &[Vec3], longest_edge: f32) -> (Blocks, Vec<u32>) {
        let (low, high) = rest.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(low, high), &p| (low.min(p), high.max(p)),
        );
        let extent = if rest.is_empty() {
            0.0
        } else {
            (high - low).max_element()
        };
        let size = (EDGES_PER_BLOCK * longest_edge)
            .max(extent / MAX_BLOCKS_ALONG)
            .max(1e-4);
        let origin = if rest.is_empty() {
            Vec3::ZERO
        } else {
            low - Vec3::splat(size)
        };
        let span = if rest.is_empty() {
            Vec3::ZERO
        } else {
            high - origin
        };
        let dims = [0, 1, 2].map(|k| (span[k] / size).floor() as usize + 2);
        let reaches =
            std::array::from_fn(|k| (k + 1) as f32 * size - longest_edge - ROUNDING - size * 1e-6);
        let mut grid = Blocks {
            origin,
            size,
            dims,
            reaches,
            cells: Vec::new(),
            starts: Vec::new(),
        };
        let cell_of: Vec<u32> = rest
            .iter()
            .map(|&p| grid.cell(p).unwrap_or(0) as u32)
            .collect();
        let mut order: Vec<u32> = (0..rest.len() as u32).collect();
        order.sort_by_key(|&v| (cell_of[v as usize], v));
        for (position, &v) in order.iter().enumerate() {
            let cell = cell_of[v as usize];
            if grid.cells.last() != Some(&cell) {
                grid.cells.push(cell);
                grid.starts.push(position as u32);
            }
        }
        grid.starts.push(rest.len() as u32);
        (grid, order)
    }

    /// How many blocks hold vertices.
    pub(crate) fn occupied(&self) -> usize {
        self.cells.len()
    }

    /// The sorted vertices of occupied block `block` (a range of the rest field's order).
    pub(crate) fn vertices(&self, block: usize) -> std::ops::Range<usize> {
        self.starts[block] as usize..self.starts[block + 1] as usize
    }

    /// The grid cell holding `p` \[m\] (rest frame), `None` beyond the grid.
    #[inline]
    fn cell(&self, p: Vec3) -> Option<usize> {
        let t = (p - self.origin) / self.size;
        let mut index = 0;
        for k in (0..3).rev() {
            // Negative, NaN and too large all fail here.
            if !(t[k] >= 0.0 && t[k] < self.dims[k] as f32) {
                return None;
            }
            index = index * self.dims[k] + (t[k] as usize).min(self.dims[k] - 1);
        }
        Some(index)
    }
}

/// An instant's deviations around each block of the grid ([`Blocks`]): per cell, the largest
/// deviation of the first ring `δ_1` and the cap the wider rings put on the bound (see the
/// module documentation).
#[derive(Debug, Clone, Default)]
pub(crate) struct NearDeviations {
    /// Per grid cell, `(δ_1, min_k (σ f_k − δ_{k+1}))` \[m\] (with `δ_{K+1} = δ`).
    cells: Vec<[f32; 2]>,
    /// Scratch for the rings (one grid each) and a line of the grid.
    rings: Vec<f32>,
    line: Vec<f32>,
}

impl NearDeviations {
    /// Fills the deviations from `block_deviations` (per occupied block of `blocks`, \[m\]),
    /// the whole mesh's deviation `whole` \[m\] and the map's least stretch `shrink`.
    pub(crate) fn fill(
        &mut self,
        blocks: &Blocks,
        block_deviations: &[f32],
        whole: f32,
        shrink: f32,
    ) {
        let [nx, ny, nz] = blocks.dims;
        let count = nx * ny * nz;
        self.rings.clear();
        self.rings.resize(count, 0.0);
        for (&cell, &deviation) in blocks.cells.iter().zip(block_deviations) {
            self.rings[cell as usize] = deviation;
        }
        self.cells.clear();
        self.cells.resize(count, [0.0, f32::INFINITY]);
        for ring in 0..RINGS {
            // δ_{ring+1}: the last ring's grid widened by one block along each axis.
            for axis in 0..3 {
                widen(&mut self.rings, blocks.dims, axis, &mut self.line);
            }
            for (cell, &deviation) in self.cells.iter_mut().zip(&self.rings) {
                if ring == 0 {
                    cell[0] = deviation;
                } else {
                    cell[1] = cell[1].min(shrink * blocks.reaches[ring - 1] - deviation);
                }
            }
        }
        let last = shrink * blocks.reaches[RINGS - 1] - whole;
        for cell in &mut self.cells {
            cell[1] = cell[1].min(last);
        }
    }

    /// The certified distance \[m\] at the current point whose rest image `rest_point` (in
    /// the grid of `blocks`) has the rest field's bound `rest_bound` \[m\] (positive, with the
    /// side known), under a map of least stretch `shrink`; `None` beyond the grid, where only
    /// the whole mesh's deviation applies.
    #[inline]
    pub(crate) fn bound(
        &self,
        blocks: &Blocks,
        rest_point: Vec3,
        rest_bound: f32,
        shrink: f32,
    ) -> Option<f32> {
        let [near, cap] = *self.cells.get(blocks.cell(rest_point)?)?;
        Some((shrink * rest_bound - near).min(cap))
    }
}

/// Each value of `grid` (of `dims`) replaced by the largest of it and its two neighbours along
/// `axis`; `line` is scratch.
fn widen(grid: &mut [f32], dims: [usize; 3], axis: usize, line: &mut Vec<f32>) {
    let stride = [1, dims[0], dims[0] * dims[1]][axis];
    let n = dims[axis];
    // The lines along `axis` start at the cells whose coordinate along it is 0: `outer`
    // runs over the axes above it, `inner` over those below it.
    let (outer, inner) = (grid.len() / (n * stride), stride);
    for high in 0..outer {
        for low in 0..inner {
            let start = high * n * stride + low;
            line.clear();
            line.extend((0..n).map(|i| grid[start + i * stride]));
            for i in 0..n {
                let below = line[i.saturating_sub(1)];
                let above = line[(i + 1).min(n - 1)];
                grid[start + i * stride] = line[i].max(below).max(above);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against brute force: each cell's first ring is the largest deviation of the vertices
    /// in the 3 × 3 × 3 blocks around it, and its cap the smallest `σ f_k − δ_{k+1}` over the
    /// rings, found by scanning every block.
    #[test]
    fn the_rings_hold_the_largest_deviation_around_each_block() {
        let rest: Vec<Vec3> = (0..500)
            .map(|i| {
                let t = i as f32 * 0.37;
                Vec3::new(t.sin(), (1.3 * t).cos(), (0.7 * t).sin() * 0.5) * 0.1
            })
            .collect();
        let (blocks, order) = Blocks::of(&rest, 0.004);
        let deviations: Vec<f32> = (0..blocks.occupied())
            .map(|b| {
                blocks
                    .vertices(b)
                    .map(|i| {
                        let p = rest[order[i] as usize];
                        (p.x * 37.0).sin().abs() * 0.01
                    })
                    .fold(0.0, f32::max)
            })
            .collect();
        let (whole, shrink) = (0.011, 0.97);
        let mut near = NearDeviations::default();
        near.fill(&blocks, &deviations, whole, shrink);
        let [nx, ny, _] = blocks.dims;
        let at = |cell: usize| [cell % nx, (cell / nx) % ny, cell / (nx * ny)];
        for (cell, &[first, cap]) in near.cells.iter().enumerate() {
            let c = at(cell);
            let within = |ring: usize| {
                blocks
                    .cells
                    .iter()
                    .zip(&deviations)
                    .filter(|&(&other, _)| {
                        let o = at(other as usize);
                        (0..3).all(|k| c[k].abs_diff(o[k]) <= ring)
                    })
                    .map(|(_, &d)| d)
                    .fold(0.0, f32::max)
            };
            assert_eq!(first, within(1), "cell {c:?}");
            let mut expected = shrink * blocks.reaches[RINGS - 1] - whole;
            for ring in 1..RINGS {
                expected = expected.min(shrink * blocks.reaches[ring - 1] - within(ring + 1));
            }
            assert!(
                (cap - expected).abs() <= 1e-7,
                "cell {c:?}: {cap} {expected}"
            );
        }
        // Every vertex lies in its block's cell, and the blocks hold every vertex once.
        for b in 0..blocks.occupied() {
            for i in blocks.vertices(b) {
                assert_eq!(
                    blocks.cell(rest[order[i] as usize]),
                    Some(blocks.cells[b] as usize)
                );
            }
        }
        assert_eq!(*blocks.starts.last().unwrap() as usize, rest.len());
    }
}
