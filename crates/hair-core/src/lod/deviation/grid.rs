//! Nearest-point queries on a uniform grid: the distance from a query point to the closest of a
//! fixed set of points, searched ring by ring outwards from the query's cell.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::{IVec3, Vec3};

/// A multiplicative hash of the cell coordinates (the standard SipHash costs more than the
/// distance tests it guards).
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }
    fn write_i32(&mut self, value: i32) {
        self.write_u64(value as u32 as u64);
    }
    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

type Buckets = HashMap<IVec3, Vec<Vec3>, BuildHasherDefault<CellHasher>>;

/// A fixed set of points [m] bucketed in cubic cells of side `cell` [m].
#[derive(Debug, Clone)]
pub struct PointGrid {
    cell: f32,
    buckets: Buckets,
    /// The occupied cells' bounding box (inclusive), `min > max` when empty.
    min: IVec3,
    max: IVec3,
}

impl PointGrid {
    /// Buckets `points` (finite) into cells of side `cell` [m] (> 0).
    pub fn new(points: &[Vec3], cell: f32) -> PointGrid {
        let mut buckets = Buckets::default();
        let (mut min, mut max) = (IVec3::MAX, IVec3::MIN);
        for &point in points {
            let key = cell_of(point, cell);
            min = min.min(key);
            max = max.max(key);
            buckets.entry(key).or_default().push(point);
        }
        PointGrid {
            cell,
            buckets,
            min,
            max,
        }
    }

    /// Distance [m] from `query` to the nearest point, `None` when the grid is empty.
    ///
    /// Rings of cells at Chebyshev distance `k` from the query's cell are searched in turn; a
    /// point in ring `k` is at least `(k − 1)·cell` away, so the search stops once that bound
    /// passes the best distance found (exact, not approximate).
    pub fn nearest_distance(&self, query: Vec3) -> Option<f32> {
        if self.buckets.is_empty() {
            return None;
        }
        let centre = cell_of(query, self.cell);
        let mut best = f32::INFINITY;
        // Every occupied cell lies within this many rings of the query's cell.
        let far = (centre - self.min)
            .abs()
            .max((self.max - centre).abs())
            .max_element();
        for ring in 0..=far {
            if (ring - 1).max(0) as f32 * self.cell > best {
                break;
            }
            for_ring(centre, ring, |key| {
                if let Some(bucket) = self.buckets.get(&key) {
                    for point in bucket {
                        best = best.min(point.distance(query));
                    }
                }
            });
        }
        best.is_finite().then_some(best)
    }
}

/// The cell holding `point`.
fn cell_of(point: Vec3, cell: f32) -> IVec3 {
    (point / cell).floor().as_ivec3()
}

/// Calls `visit` for every cell at Chebyshev distance exactly `ring` from `centre`.
fn for_ring(centre: IVec3, ring: i32, mut visit: impl FnMut(IVec3)) {
    if ring == 0 {
        visit(centre);
        return;
    }
    for x in -ring..=ring {
        for y in -ring..=ring {
            let on_side = x.abs() == ring || y.abs() == ring;
            if on_side {
                for z in -ring..=ring {
                    visit(centre + IVec3::new(x, y, z));
                }
            } else {
                visit(centre + IVec3::new(x, y, -ring));
                visit(centre + IVec3::new(x, y, ring));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    #[test]
    fn agrees_with_brute_force_inside_and_outside_the_cloud() {
        let mut rng = SplitMix64::new(7);
        let points: Vec<Vec3> = (0..500)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.05)
            .collect();
        let grid = PointGrid::new(&points, 0.004);
        for _ in 0..300 {
            // Queries out to twice the cloud's size, so some start rings away from any point.
            let query = (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.25) * 0.1;
            let brute = points
                .iter()
                .map(|p| p.distance(query))
                .fold(f32::INFINITY, f32::min);
            assert_eq!(grid.nearest_distance(query), Some(brute));
        }
    }

    #[test]
    fn an_empty_grid_has_no_nearest_point() {
        assert_eq!(PointGrid::new(&[], 0.01).nearest_distance(Vec3::ZERO), None);
    }

    #[test]
    fn ring_visits_every_cell_of_its_shell_once() {
        let mut seen = Vec::new();
        for_ring(IVec3::ZERO, 2, |key| seen.push(key));
        // A shell of Chebyshev radius 2: 5³ − 3³ cells.
        assert_eq!(seen.len(), 125 - 27);
        seen.sort_by_key(|k| (k.x, k.y, k.z));
        seen.dedup();
        assert_eq!(seen.len(), 98);
    }
}
