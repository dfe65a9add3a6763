//! Occluder boxes inside a body mesh from a file, for the paper's conservative occlusion test
//! (§7.1: hair whose rays from the camera cross a box inside the body is hidden by it), as the
//! procedural head has its inscribed boxes ([`Head::occluder_boxes`](hair_core::Head::occluder_boxes)).
//!
//! The body's bounding box (and two cells around it) is cut into cubic cells. A cell is *solid*
//! when it is certainly inside the body: it does not touch the surface (its centre is farther
//! from the surface than its half diagonal, so the surface cannot cross it) and it cannot be
//! reached from outside the bounding box through cells that do not touch the surface (a flood
//! fill). Neither test reads the sign of the distance, so a mesh that is not closed still gets
//! sound boxes: a hole larger than a cell lets the flood in, and fewer cells are solid. Boxes
//! are then grown from the deepest solid cells near the hair, face by face while the grown
//! face is all solid cells; every point of every box is inside the body.

use std::collections::VecDeque;

use glam::{IVec3, UVec3, Vec3};
use hair_collide::CollisionBody;
use hair_core::TriangleMesh;

/// How [`occluder_boxes`] cuts the body and how many boxes it keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OccluderSettings {
    /// Cells along the longest side of the body's bounding box, 8..=256.
    pub cells_along_longest: u32,
    /// Boxes kept at most.
    pub max_boxes: usize,
    /// How far around the hair's bounding box [m] a box's seed cell may lie (boxes far from the
    /// hair hide none of it).
    pub margin: f32,
}

impl Default for OccluderSettings {
    /// 96 cells along the longest side, at most 6 boxes, seeds within 10 cm of the hair.
    fn default() -> Self {
        OccluderSettings {
            cells_along_longest: 96,
            max_boxes: 6,
            margin: 0.1,
        }
    }
}

/// Boxes `(min, max)` [m] inside the body `collision` (made from `mesh`, at its identity pose),
/// grown from solid cells within `settings.margin` of `region` (the hair's bounds, `(min, max)`),
/// deepest first, each from a cell no earlier box covers; see the module docs. Empty when no
/// cell is certainly inside (an open mesh, or a body thinner than two cells).
pub fn occluder_boxes(
    collision: &CollisionBody,
    mesh: &TriangleMesh,
    region: (Vec3, Vec3),
    settings: &OccluderSettings,
) -> Vec<(Vec3, Vec3)> {
    let Some((low, high)) = mesh.bounds() else {
        return Vec::new();
    };
    let longest = (high - low).max_element();
    if !(longest.is_finite() && longest > 0.0) {
        return Vec::new();
    }
    let cells_along = settings.cells_along_longest.clamp(8, 256);
    let cell = longest / cells_along as f32;
    // Two cells of outside all around: the outer layer's centres lie 1.5 cells from the body's
    // bounds, clear of its surface, so the flood starts everywhere around it.
    let origin = low - Vec3::splat(2.0 * cell);
    let dims = ((high - low) / cell).ceil().as_uvec3() + UVec3::splat(5);
    let grid = Grid { origin, cell, dims };
    let half_diagonal = 0.5 * 3f32.sqrt() * cell;
    let depth: Vec<f32> = (0..grid.len())
        .map(|index| {
            collision
                .signed_distance(grid.centre(grid.cell_of(index)))
                .map_or(0.0, f32::abs)
        })
        .collect();
    let clear: Vec<bool> = depth.iter().map(|&d| d > half_diagonal).collect();
    let outside = flood_from_boundary(&grid, &clear);
    let solid: Vec<bool> = (0..grid.len())
        .map(|index| clear[index] && !outside[index])
        .collect();

    let near = (
        region.0 - Vec3::splat(settings.margin),
        region.1 + Vec3::splat(settings.margin),
    );
    let mut seeds: Vec<usize> = (0..grid.len())
        .filter(|&index| {
            let centre = grid.centre(grid.cell_of(index));
            solid[index] && centre.cmpge(near.0).all() && centre.cmple(near.1).all()
        })
        .collect();
    seeds.sort_by(|&a, &b| depth[b].total_cmp(&depth[a]).then(a.cmp(&b)));
    let mut covered = vec![false; grid.len()];
    let mut boxes = Vec::new();
    for seed in seeds {
        if boxes.len() >= settings.max_boxes {
            break;
        }
        if covered[seed] {
            continue;
        }
        let (min, max) = grow_box(&grid, &solid, grid.cell_of(seed));
        for z in min.z..=max.z {
            for y in min.y..=max.y {
                for x in min.x..=max.x {
                    covered[grid.index(IVec3::new(x, y, z))] = true;
                }
            }
        }
        boxes.push((grid.corner(min), grid.corner(max + IVec3::ONE)));
    }
    boxes
}

/// A regular grid of cubic cells.
struct Grid {
    /// The low corner of cell (0, 0, 0) [m].
    origin: Vec3,
    /// Cell side [m].
    cell: f32,
    /// Cells along x, y, z.
    dims: UVec3,
}

impl Grid {
    fn len(&self) -> usize {
        (self.dims.x * self.dims.y * self.dims.z) as usize
    }

    fn index(&self, c: IVec3) -> usize {
        let c = c.as_uvec3();
        ((c.z * self.dims.y + c.y) * self.dims.x + c.x) as usize
    }

    fn cell_of(&self, index: usize) -> IVec3 {
        let index = index as u32;
        let x = index % self.dims.x;
        let y = (index / self.dims.x) % self.dims.y;
        let z = index / (self.dims.x * self.dims.y);
        UVec3::new(x, y, z).as_ivec3()
    }

    fn contains(&self, c: IVec3) -> bool {
        c.cmpge(IVec3::ZERO).all() && c.as_uvec3().cmplt(self.dims).all()
    }

    /// The low corner of cell `c` (or the high corner of cell `c − 1`) [m].
    fn corner(&self, c: IVec3) -> Vec3 {
        self.origin + c.as_vec3() * self.cell
    }

    fn centre(&self, c: IVec3) -> Vec3 {
        self.corner(c) + Vec3::splat(0.5 * self.cell)
    }
}

/// The six face neighbours' offsets.
const NEIGHBOURS: [IVec3; 6] = [
    IVec3::X,
    IVec3::NEG_X,
    IVec3::Y,
    IVec3::NEG_Y,
    IVec3::Z,
    IVec3::NEG_Z,
];

/// Cells reachable from the grid's boundary through `clear` cells (face neighbours).
fn flood_from_boundary(grid: &Grid, clear: &[bool]) -> Vec<bool> {
    let mut reached = vec![false; grid.len()];
    let mut queue = VecDeque::new();
    for index in 0..grid.len() {
        let c = grid.cell_of(index);
        let on_boundary =
            c.cmpeq(IVec3::ZERO).any() || (c + IVec3::ONE).as_uvec3().cmpeq(grid.dims).any();
        if on_boundary && clear[index] {
            reached[index] = true;
            queue.push_back(c);
        }
    }
    while let Some(c) = queue.pop_front() {
        for step in NEIGHBOURS {
            let next = c + step;
            if grid.contains(next) {
                let index = grid.index(next);
                if clear[index] && !reached[index] {
                    reached[index] = true;
                    queue.push_back(next);
                }
            }
        }
    }
    reached
}

/// The box of cells `(min, max)` (inclusive) grown from `seed` one face at a time, in turn, while
/// the layer added is all `solid`.
fn grow_box(grid: &Grid, solid: &[bool], seed: IVec3) -> (IVec3, IVec3) {
    let (mut min, mut max) = (seed, seed);
    let mut growing = [true; 6];
    while growing.iter().any(|&g| g) {
        for (face, step) in NEIGHBOURS.into_iter().enumerate() {
            if !growing[face] {
                continue;
            }
            let (mut lo, mut hi) = (min, max);
            // The layer just outside this face.
            for axis in 0..3 {
                if step[axis] > 0 {
                    lo[axis] = max[axis] + 1;
                    hi[axis] = max[axis] + 1;
                } else if step[axis] < 0 {
                    lo[axis] = min[axis] - 1;
                    hi[axis] = min[axis] - 1;
                }
            }
            let all_solid = grid.contains(lo)
                && grid.contains(hi)
                && (lo.z..=hi.z).all(|z| {
                    (lo.y..=hi.y)
                        .all(|y| (lo.x..=hi.x).all(|x| solid[grid.index(IVec3::new(x, y, z))]))
                });
            if all_solid {
                min = min.min(lo);
                max = max.max(hi);
            } else {
                growing[face] = false;
            }
        }
    }
    (min, max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed axis-aligned box mesh from `min` to `max`, counter-clockwise from outside.
    fn cube(min: Vec3, max: Vec3) -> TriangleMesh {
        let p = |x: bool, y: bool, z: bool| {
            Vec3::new(
                if x { max.x } else { min.x },
                if y { max.y } else { min.y },
                if z { max.z } else { min.z },
            )
        };
        let positions = vec![
            p(false, false, false),
            p(true, false, false),
            p(true, true, false),
            p(false, true, false),
            p(false, false, true),
            p(true, false, true),
            p(true, true, true),
            p(false, true, true),
        ];
        let triangles = vec![
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [3, 7, 6],
            [3, 6, 2],
            [0, 4, 7],
            [0, 7, 3],
            [1, 2, 6],
            [1, 6, 5],
        ];
        let mut mesh = TriangleMesh {
            positions,
            triangles,
            ..TriangleMesh::default()
        };
        mesh.compute_vertex_normals();
        mesh
    }

    /// In a closed cube the boxes lie inside it, within two cells of its faces (the cells that
    /// touch the surface are left out, and no more), and an open mesh (one face missing, a hole
    /// far larger than a cell) gets none.
    #[test]
    fn boxes_lie_inside_a_cube_and_fill_it_and_an_open_box_gets_none() {
        let (min, max) = (Vec3::new(-0.1, 0.0, -0.05), Vec3::new(0.1, 0.3, 0.05));
        let mesh = cube(min, max);
        let body = CollisionBody::from_mesh(&mesh).unwrap();
        let settings = OccluderSettings {
            cells_along_longest: 30,
            ..OccluderSettings::default()
        };
        let boxes = occluder_boxes(&body, &mesh, (min, max), &settings);
        assert!(!boxes.is_empty());
        let cell = 0.3 / 30.0;
        let (lo, hi) = boxes[0];
        for (b_lo, b_hi) in &boxes {
            assert!(
                b_lo.cmpge(min).all() && b_hi.cmple(max).all(),
                "{b_lo} {b_hi}"
            );
        }
        // A convex body's deepest cell grows to fill it but for the surface cells (a cell whose
        // centre lies within its half diagonal of a face, and the cell of grid rounding).
        assert!((lo - min).max_element() <= 2.0 * cell + 1e-5, "{lo}");
        assert!((max - hi).max_element() <= 2.0 * cell + 1e-5, "{hi}");

        let mut open = mesh.clone();
        open.triangles.truncate(10);
        let body = CollisionBody::from_mesh(&open).unwrap();
        assert!(occluder_boxes(&body, &open, (min, max), &settings).is_empty());
    }
}
