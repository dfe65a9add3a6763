//! A body's triangle tree with a few neighbouring triangles in each leaf (issue 53): the
//! triangles are split in halves across the widest extent of their centroids, again and again,
//! until [`GROUP_SIZE`] are left, and the parry3d tree is built over the groups' boxes. A query
//! visits a leaf and tests its triangles one by one.
//!
//! What it buys is the deforming body's refit, done every frame: a quarter of the leaves to move
//! and a quarter of the nodes to merge, where the queries lose little (a leaf's triangles are
//! neighbours, so its box is barely larger than theirs, and the tree is two levels shallower).

use glam::Vec3;
use parry3d::bounding_volume::{Aabb, BoundingVolume};
use parry3d::partitioning::{Bvh, BvhBuildStrategy};

use crate::geometry::Triangle;

/// Triangles per leaf of a body's tree (the last group may hold fewer).
pub(crate) const GROUP_SIZE: usize = 4;

/// A body's triangles in groups of neighbours, one group per leaf of its tree.
#[derive(Debug, Default)]
pub(crate) struct TriangleGroups {
    /// Group `g`'s triangles are `members[starts[g]..starts[g + 1]]`.
    starts: Vec<u32>,
    /// The triangle ids, group after group.
    members: Vec<u32>,
}

impl TriangleGroups {
    /// The triangle ids of group `group` (none for an id out of range).
    #[inline]
    pub(crate) fn members(&self, group: u32) -> &[u32] {
        let g = group as usize;
        match (self.starts.get(g), self.starts.get(g + 1)) {
            (Some(&start), Some(&end)) => &self.members[start as usize..end as usize],
            _ => &[],
        }
    }

    /// How many groups there are.
    pub(crate) fn count(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// The tight box of group `group`'s triangles over `positions` (the mesh's vertices, each
    /// triangle's corners `indices[t]`); `None` for an empty group.
    pub(crate) fn aabb_over(
        &self,
        group: u32,
        indices: &[[u32; 3]],
        positions: &[Vec3],
    ) -> Option<Aabb> {
        self.members(group)
            .iter()
            .map(|&t| corners_aabb(indices[t as usize].map(|i| positions[i as usize])))
            .reduce(|a, b| a.merged(&b))
    }
}

/// The groups of `triangles` and the tree over them (leaf data = group id, unpadded boxes).
/// Every triangle is in exactly one group.
pub(crate) fn grouped_tree(triangles: &[Triangle]) -> (TriangleGroups, Bvh) {
    let centroids: Vec<Vec3> = triangles
        .iter()
        .map(|t| (t.vertices[0] + t.vertices[1] + t.vertices[2]) / 3.0)
        .collect();
    let mut members: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut starts = Vec::with_capacity(members.len().div_ceil(GROUP_SIZE) + 1);
    split(&mut members, 0, &centroids, &mut starts);
    starts.push(members.len() as u32);
    let groups = TriangleGroups { starts, members };
    let boxes = (0..groups.count() as u32).map(|g| {
        let aabb = groups
            .members(g)
            .iter()
            .map(|&t| triangle_aabb(&triangles[t as usize]))
            .reduce(|a, b| a.merged(&b))
            .unwrap_or_else(Aabb::new_invalid);
        (g as usize, aabb)
    });
    let tree = Bvh::from_iter(BvhBuildStrategy::Binned, boxes);
    (groups, tree)
}

/// Cuts `ids` (which start at `offset` in the members) into groups of [`GROUP_SIZE`] (the last
/// may hold fewer): halves across the widest extent of their `centroids`, the first half a
/// whole number of groups, until a group is left; each group's start goes into `starts`.
fn split(ids: &mut [u32], offset: usize, centroids: &[Vec3], starts: &mut Vec<u32>) {
    if ids.len() <= GROUP_SIZE {
        if !ids.is_empty() {
            starts.push(offset as u32);
        }
        return;
    }
    let (low, high) = ids.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(low, high), &t| {
            let c = centroids[t as usize];
            (low.min(c), high.max(c))
        },
    );
    let extent = high - low;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let half = (ids.len().div_ceil(GROUP_SIZE) / 2).max(1) * GROUP_SIZE;
    // Ties broken by id: the same groups whatever the order the ids came in.
    ids.select_nth_unstable_by(half, |&a, &b| {
        centroids[a as usize][axis]
            .total_cmp(&centroids[b as usize][axis])
            .then(a.cmp(&b))
    });
    let (first, second) = ids.split_at_mut(half);
    split(first, offset, centroids, starts);
    split(second, offset + half, centroids, starts);
}

/// The tight box of a triangle.
pub(crate) fn triangle_aabb(triangle: &Triangle) -> Aabb {
    corners_aabb(triangle.vertices)
}

/// The tight box of a triangle's corners.
pub(crate) fn corners_aabb([a, b, c]: [Vec3; 3]) -> Aabb {
    Aabb::new(a.min(b).min(c), a.max(b).max(c))
}

/// Every leaf id of `bvh` (0 up to its leaf count), sorted by where its node lies in the tree's
/// memory: the tree keeps its nodes in one array, so a node's address orders it. A leaf the
/// tree would not show (none is expected) comes at the end, so none is left out.
pub(crate) fn leaf_order(bvh: &Bvh) -> Vec<u32> {
    let count = bvh.leaf_count();
    let mut placed: Vec<(usize, u32)> = (0..count)
        .map(|id| {
            let at = bvh
                .leaf_node(id)
                .map_or(usize::MAX, |node| std::ptr::from_ref(node) as usize);
            (at, id)
        })
        .collect();
    placed.sort_unstable();
    placed.into_iter().map(|(_, id)| id).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::{Head, HeadParams};

    /// Every triangle of the procedural head is in exactly one group, each group but the last
    /// holds [`GROUP_SIZE`], and a group's box holds its triangles and is small: neighbours,
    /// not triangles from across the head (its diagonal under a tenth of the head's).
    #[test]
    fn every_triangle_is_in_one_small_group() {
        let mesh = Head::procedural(&HeadParams::default()).unwrap().mesh;
        let body = crate::CollisionBody::from_mesh(&mesh).unwrap();
        let triangles = body.local_triangles();
        let (groups, tree) = grouped_tree(triangles);
        assert_eq!(groups.count(), triangles.len().div_ceil(GROUP_SIZE));
        assert_eq!(tree.leaf_count() as usize, groups.count());
        let mut seen = vec![0u32; triangles.len()];
        let head = tree.root_aabb();
        let head_diagonal = (head.maxs - head.mins).length();
        for g in 0..groups.count() as u32 {
            let members = groups.members(g);
            if (g as usize) + 1 < groups.count() {
                assert_eq!(members.len(), GROUP_SIZE);
            }
            let aabb = groups
                .aabb_over(g, &mesh.triangles, &mesh.positions)
                .unwrap();
            assert_eq!(tree.leaf_node(g).unwrap().aabb(), aabb);
            for &t in members {
                seen[t as usize] += 1;
                assert!(aabb.contains(&triangle_aabb(&triangles[t as usize])));
            }
            assert!((aabb.maxs - aabb.mins).length() < head_diagonal / 10.0);
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert!(groups.members(groups.count() as u32).is_empty());
    }
}
