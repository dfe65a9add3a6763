//! The exact cells of a distance field, stored apart in bricks for
//! [`DistanceField::sample`](crate::DistanceField::sample): only bricks holding a cell whose eight
//! corners are exact are kept, each with its corners (one layer of vertices more than its cells,
//! so every cell's corners lie in its own brick) and a bit per cell. A sample then reads one
//! brick of 500 bytes, its corners two or three cache lines apart, where the whole grid's rows
//! and planes lie kilobytes and megabytes apart; and the bricks, a shell around the surface, are
//! a few per cent of the grid. This is what the collision stage pays for after a frame was drawn
//! and the caches hold the renderer's data instead.

/// Cells along each side of a brick (64 cells, one `u64` of flags).
const CELLS: usize = 4;

/// Vertices along each side of a brick.
const SIDE: usize = CELLS + 1;

/// Values per brick.
const VALUES: usize = SIDE * SIDE * SIDE;

/// No brick stored here.
const EMPTY: u32 = u32::MAX;

/// The exact cells of a grid, in bricks of 4³ cells.
#[derive(Debug, Clone, Default)]
pub(crate) struct ExactBricks {
    /// Bricks along x, y, z (covering the grid's cells).
    bricks: [usize; 3],
    /// Per brick (x fastest): its place among the stored ones, or [`EMPTY`].
    index: Vec<u32>,
    /// Per stored brick: its 5³ corner values, x fastest.
    values: Vec<f32>,
    /// Per stored brick: bit `i + 4j + 16k` set where cell `(i, j, k)` of the brick has eight
    /// exact corners.
    exact: Vec<u64>,
    /// Per stored brick: its 5³ corners' closest triangles (as `values`; [`EMPTY`] where none
    /// was recorded).
    triangles: Vec<u32>,
}

impl ExactBricks {
    /// The bricks of a grid of `dims` vertices (x fastest) holding `values`, of which those
    /// flagged in `exact` are exact, and each vertex's closest triangle in `triangles` (the
    /// same layout; empty when none were recorded).
    pub fn new(values: &[f32], triangles: &[u32], exact: &[bool], dims: [usize; 3]) -> Self {
        let cells = dims.map(|d| d.saturating_sub(1));
        let bricks = cells.map(|c| c.div_ceil(CELLS));
        let vertex = |i: usize, j: usize, k: usize| i + dims[0] * (j + dims[1] * k);
        let mut stored = ExactBricks {
            bricks,
            index: vec![EMPTY; bricks.iter().product()],
            ..ExactBricks::default()
        };
        for bz in 0..bricks[2] {
            for by in 0..bricks[1] {
                for bx in 0..bricks[0] {
                    let mut mask = 0u64;
                    for (bit, (ci, cj, ck)) in cell_offsets().enumerate() {
                        let [i, j, k] = [bx * CELLS + ci, by * CELLS + cj, bz * CELLS + ck];
                        if i >= cells[0] || j >= cells[1] || k >= cells[2] {
                            continue;
                        }
                        let corners_exact = (0..8).all(|corner| {
                            exact[vertex(
                                i + (corner & 1),
                                j + ((corner >> 1) & 1),
                                k + (corner >> 2),
                            )]
                        });
                        if corners_exact {
                            mask |= 1 << bit;
                        }
                    }
                    if mask == 0 {
                        continue;
                    }
                    stored.index[bx + bricks[0] * (by + bricks[1] * bz)] =
                        stored.exact.len() as u32;
                    stored.exact.push(mask);
                    for vk in 0..SIDE {
                        for vj in 0..SIDE {
                            for vi in 0..SIDE {
                                let [i, j, k] = [bx * CELLS + vi, by * CELLS + vj, bz * CELLS + vk];
                                // Corners past the grid belong to no exact cell.
                                let inside = i < dims[0] && j < dims[1] && k < dims[2];
                                stored.values.push(if inside {
                                    values[vertex(i, j, k)]
                                } else {
                                    0.0
                                });
                                stored.triangles.push(if inside {
                                    triangles.get(vertex(i, j, k)).copied().unwrap_or(EMPTY)
                                } else {
                                    EMPTY
                                });
                            }
                        }
                    }
                }
            }
        }
        stored
    }

    /// The eight corner values of cell `(i, j, k)` (which must be a cell of the grid) as
    /// `c[y·2 + x][z]`, where all eight are exact; `None` elsewhere.
    #[inline]
    pub fn corners(&self, i: usize, j: usize, k: usize) -> Option<[[f32; 2]; 4]> {
        let at = self.exact_cell(i, j, k)?;
        let v = &self.values[at..at + SIDE * SIDE + SIDE + 2];
        let (y, z) = (SIDE, SIDE * SIDE);
        Some([
            [v[0], v[z]],
            [v[1], v[z + 1]],
            [v[y], v[z + y]],
            [v[y + 1], v[z + y + 1]],
        ])
    }

    /// The closest triangle recorded at the corner of exact cell `(i, j, k)` nearest the
    /// point at fractions `f` (each in `[0, 1]`) across the cell; `None` where the cell is not
    /// exact or no triangle was recorded there.
    #[inline]
    pub fn nearest_triangle(&self, [i, j, k]: [usize; 3], f: [f32; 3]) -> Option<u32> {
        let [ri, rj, rk] = f.map(|f| usize::from(f >= 0.5));
        let at = self.exact_cell(i, j, k)? + ri + SIDE * rj + SIDE * SIDE * rk;
        self.triangles.get(at).copied().filter(|&t| t != EMPTY)
    }

    /// Where the lowest corner of cell `(i, j, k)` (a cell of the grid) is stored, where the
    /// cell is exact; `None` elsewhere.
    #[inline]
    fn exact_cell(&self, i: usize, j: usize, k: usize) -> Option<usize> {
        let [bx, by, bz] = [i / CELLS, j / CELLS, k / CELLS];
        let brick = self.index[bx + self.bricks[0] * (by + self.bricks[1] * bz)];
        if brick == EMPTY {
            return None;
        }
        let brick = brick as usize;
        let [ci, cj, ck] = [i % CELLS, j % CELLS, k % CELLS];
        if self.exact[brick] & (1 << (ci + CELLS * cj + CELLS * CELLS * ck)) == 0 {
            return None;
        }
        Some(brick * VALUES + ci + SIDE * cj + SIDE * SIDE * ck)
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.index.len() * std::mem::size_of::<u32>()
            + self.triangles.len() * std::mem::size_of::<u32>()
            + self.values.len() * std::mem::size_of::<f32>()
            + self.exact.len() * std::mem::size_of::<u64>()
    }
}

/// The cells of a brick, in bit order: `(i, j, k)` for bit `i + 4j + 16k`.
fn cell_offsets() -> impl Iterator<Item = (usize, usize, usize)> {
    (0..CELLS * CELLS * CELLS)
        .map(|bit| (bit % CELLS, (bit / CELLS) % CELLS, bit / (CELLS * CELLS)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every cell of a grid whose sides are not multiples of the brick answers as the dense grid
    /// does: its eight corners where all are exact, `None` where one is not (a random
    /// exactness, so that bricks hold some exact cells and not others).
    #[test]
    fn bricks_answer_every_cell_as_the_dense_grid() {
        let dims = [11, 7, 9];
        let count = dims.iter().product::<usize>();
        let values: Vec<f32> = (0..count).map(|v| v as f32 * 0.5 - 3.0).collect();
        let mut state = 12345u64;
        let exact: Vec<bool> = (0..count)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 33) % 5 != 0
            })
            .collect();
        let triangles: Vec<u32> = (0..count as u32).map(|v| v * 7).collect();
        let bricks = ExactBricks::new(&values, &triangles, &exact, dims);
        let vertex = |i: usize, j: usize, k: usize| i + dims[0] * (j + dims[1] * k);
        let (mut some, mut none) = (0, 0);
        for k in 0..dims[2] - 1 {
            for j in 0..dims[1] - 1 {
                for i in 0..dims[0] - 1 {
                    let corner = |x: usize, y: usize, z: usize| vertex(i + x, j + y, k + z);
                    let all = (0..8).all(|c| exact[corner(c & 1, (c >> 1) & 1, c >> 2)]);
                    let expected = all.then(|| {
                        [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .map(|(x, y)| [values[corner(x, y, 0)], values[corner(x, y, 1)]])
                    });
                    assert_eq!(bricks.corners(i, j, k), expected, "cell {i} {j} {k}");
                    // The nearest corner's triangle: the far corner at fractions ≥ ½.
                    let nearest = bricks.nearest_triangle([i, j, k], [0.7, 0.2, 0.5]);
                    assert_eq!(nearest, all.then(|| triangles[corner(1, 0, 1)]));
                    if all {
                        some += 1;
                    } else {
                        none += 1;
                    }
                }
            }
        }
        assert!(some > 0 && none > 0, "{some} exact cells, {none} others");
    }
}
