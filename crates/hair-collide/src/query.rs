//! Hair against a body: for each colliding segment, the body triangles its volume touches.
//! A BVH version (simultaneous descent of both trees) and a brute-force version (every segment
//! against every triangle) with identical, deterministically sorted output.

use parry3d::bounding_volume::{Aabb, BoundingVolume};
use parry3d::partitioning::BvhNode;
use rayon::prelude::*;

use crate::body::CollisionBody;
use crate::bvh::{HairBvh, aabb_padding};
use crate::triangle_groups::triangle_aabb;
use crate::volume::{Pss, SweptSphere};

/// Contacts of hair segments with body triangles, flat.
///
/// Segment `segments[k]` touches triangles `triangles[triangle_offsets[k]..triangle_offsets[k + 1]]`.
/// `segments` is ascending, each triangle list is ascending, so two equal contact sets compare
/// equal whatever the traversal order.
#[derive(Debug, Clone, Default)]
pub struct SegmentContacts {
    /// Ids of the segments that touch at least one triangle, ascending.
    pub segments: Vec<u32>,
    /// `segments.len() + 1` offsets into `triangles` (`[0]` when there is no contact).
    pub triangle_offsets: Vec<u32>,
    /// Touched triangle ids, grouped per segment, ascending within each group.
    pub triangles: Vec<u32>,
    /// Scratch `(segment, triangle)` pairs, kept to avoid allocating each step.
    pairs: Vec<(u32, u32)>,
    /// Scratch pairs of each chunk of [`CHUNK`] volumes, found side by side.
    chunk_pairs: Vec<Vec<(u32, u32)>>,
}

/// Segment volumes per parallel task of a query: fixed, so the chunks (and, after the sort,
/// the contacts) are the same whatever the thread count.
pub(crate) const CHUNK: usize = 256;

impl PartialEq for SegmentContacts {
    fn eq(&self, other: &Self) -> bool {
        self.segments == other.segments
            && self.triangle_offsets == other.triangle_offsets
            && self.triangles == other.triangles
    }
}

impl Eq for SegmentContacts {}

impl SegmentContacts {
    /// An empty contact set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of colliding segments.
    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    /// Number of `(segment, triangle)` pairs.
    pub fn pair_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether no segment touches the body.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// `(segment id, touched triangle ids)` for each colliding segment, ascending.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &[u32])> + '_ {
        self.segments.iter().enumerate().map(|(k, &segment)| {
            let range = self.triangle_offsets[k] as usize..self.triangle_offsets[k + 1] as usize;
            (segment, &self.triangles[range])
        })
    }

    /// Rebuilds the flat arrays from the scratch pairs (sorted first unless `sorted`).
    fn finish(&mut self, sorted: bool) {
        if !sorted {
            self.pairs.sort_unstable();
        }
        debug_assert!(self.pairs.is_sorted());
        self.segments.clear();
        self.triangles.clear();
        self.triangle_offsets.clear();
        self.triangle_offsets.push(0);
        for &(segment, triangle) in &self.pairs {
            if self.segments.last() != Some(&segment) {
                if !self.segments.is_empty() {
                    self.triangle_offsets.push(self.triangles.len() as u32);
                }
                self.segments.push(segment);
            }
            self.triangles.push(triangle);
        }
        if !self.segments.is_empty() {
            self.triangle_offsets.push(self.triangles.len() as u32);
        }
    }
}

/// Rounding allowance \[m\] of the cull by a body's ball: a few ulps at the ball's scale.
pub(crate) fn ball_padding(bound: &Pss) -> f32 {
    64.0 * f32::EPSILON * (1.0 + bound.center.abs().max_element() + bound.radius)
}

/// Whether an AABB touches a ball grown by a rounding padding (conservative).
pub(crate) fn aabb_touches_ball(aabb: &Aabb, ball: &Pss, padding: f32) -> bool {
    let closest = ball.center.clamp(aabb.mins, aabb.maxs);
    let reach = ball.radius + padding;
    closest.distance_squared(ball.center) <= reach * reach
}

/// Hair against body through both hierarchies; writes into `contacts` (reusing its memory).
///
/// `hair` is in the body's own frame (the collision solver builds its hierarchy in head space,
/// where its bodies are given): the body's pose is not read, and the triangle ids returned index
/// [`CollisionBody::local_triangles`].
///
/// The hair tree is culled by the body's top-level PSS, then both trees descend together on AABB
/// overlap, and every surviving `(segment, triangle)` leaf pair gets the exact swept-sphere test
/// [`crate::SweptSphere::intersects_triangle`]. The output equals
/// [`query_body_brute_force`]'s exactly (leaf AABBs are padded, see [`crate::aabb_padding`]).
pub fn query_body(hair: &HairBvh, body: &CollisionBody, contacts: &mut SegmentContacts) {
    if !hair.tree_is_current() {
        // Volumes updated without the tree: each against the body's tree, same exact tests.
        return query_volumes(hair.volumes(), body, contacts, false);
    }
    contacts.pairs.clear();
    if hair.segment_count() > 0 && body.triangle_count() > 0 {
        let bound = body.local_bounding_volume();
        let bound_padding = ball_padding(&bound);
        let check = |hair_node: &BvhNode, body_node: &BvhNode| {
            hair_node.intersects(body_node)
                && aabb_touches_ball(&hair_node.aabb(), &bound, bound_padding)
        };
        let volumes = hair.volumes();
        let triangles = body.local_triangles();
        for (segment, leaf) in hair.bvh().leaf_pairs(body.bvh(), check) {
            let volume = &volumes[segment as usize];
            for &triangle in body.leaf_triangles(leaf) {
                if volume.intersects_triangle(&triangles[triangle as usize]) {
                    contacts.pairs.push((segment, triangle));
                }
            }
        }
    }
    contacts.finish(false);
}

/// Hair against body through the body's distance field: every segment volume that the field
/// clears ([`DistanceField::clears`](crate::DistanceField::clears)) is skipped, and each of the
/// others gets the exact swept-sphere test against the triangles its padded AABB overlaps in the
/// body's tree. `volumes` are in the body's own frame, as for [`query_body`], and indexed as the
/// hierarchy's segments.
///
/// The field only ever clears volumes that touch no triangle, so the output equals
/// [`query_body`]'s and [`query_body_brute_force`]'s exactly; its cost follows the segments
/// (a few field lookups each) and the segments near the surface, not the pairs of tree nodes.
pub fn query_body_near(
    volumes: &[SweptSphere],
    body: &CollisionBody,
    contacts: &mut SegmentContacts,
) {
    query_volumes(volumes, body, contacts, true);
}

/// Hair against body through the body's hierarchy alone: each segment volume (culled by the
/// body's ball) against the triangles its padded AABB overlaps in the body's tree, with the exact
/// test, in chunks side by side on rayon's threads. `volumes` are in the body's own frame, as for
/// [`query_body`], and indexed as the hierarchy's segments.
///
/// The output equals [`query_body`]'s and [`query_body_brute_force`]'s exactly, whatever the
/// thread count; it needs no hair hierarchy, and spreads over the cores where the simultaneous
/// descent of two trees does not (measured 1.9× faster than [`query_body`] on the paper-curly
/// groom on 2 cores, `docs/collision.md`). The collision solver queries bodies this way.
pub fn query_body_volumes(
    volumes: &[SweptSphere],
    body: &CollisionBody,
    contacts: &mut SegmentContacts,
) {
    query_volumes(volumes, body, contacts, false);
}

/// Each volume (culled by the body's ball and, with `use_field`, its distance field) against
/// the triangles its padded AABB overlaps in the body's tree, with the exact test. Chunks of
/// [`CHUNK`] volumes run side by side; their pairs are concatenated in chunk order and sorted,
/// so the contacts do not depend on the thread count.
fn query_volumes(
    volumes: &[SweptSphere],
    body: &CollisionBody,
    contacts: &mut SegmentContacts,
    use_field: bool,
) {
    contacts.pairs.clear();
    if body.triangle_count() > 0 {
        let bound = body.local_bounding_volume();
        let bound_padding = ball_padding(&bound);
        // A deforming instant's own field would be built again at the next instant.
        let field = (use_field && !body.is_deforming()).then(|| body.distance_field());
        let chunks = volumes.len().div_ceil(CHUNK);
        contacts.chunk_pairs.resize_with(chunks, Vec::new);
        contacts.chunk_pairs[..chunks]
            .par_iter_mut()
            .enumerate()
            .for_each(|(chunk, pairs)| {
                pairs.clear();
                let first = chunk * CHUNK;
                let end = (first + CHUNK).min(volumes.len());
                for (segment, volume) in (first..end).zip(&volumes[first..end]) {
                    let padding = aabb_padding(volume);
                    let aabb = volume.aabb(padding);
                    if !aabb_touches_ball(&aabb, &bound, bound_padding)
                        || field.is_some_and(|field| field.clears(volume, padding))
                    {
                        continue;
                    }
                    for_each_touched(volume, body, |triangle| {
                        pairs.push((segment as u32, triangle))
                    });
                }
                // Chunks hold ascending segment ranges: sorted chunks concatenate sorted.
                pairs.sort_unstable();
            });
        for pairs in &contacts.chunk_pairs[..chunks] {
            contacts.pairs.extend_from_slice(pairs);
        }
    }
    contacts.finish(true);
}

/// Calls `touched` with each triangle (ascending within the tree's order, not sorted) that
/// `volume` (body frame) touches: the body's tree descended with the volume's padded AABB (and,
/// for a rectangle, its slab, [`SweptSphere::may_touch_box`]), then the exact test.
pub(crate) fn for_each_touched(
    volume: &SweptSphere,
    body: &CollisionBody,
    mut touched: impl FnMut(u32),
) {
    let padding = aabb_padding(volume);
    let query = BvhNode::leaf(volume.aabb(padding), 0);
    let reaches =
        |node: &BvhNode| node.intersects(&query) && volume.may_touch_box(&node.aabb(), padding);
    let triangles = body.local_triangles();
    let reach = volume.aabb(padding);
    for leaf in body.bvh().leaves(reaches) {
        for &triangle in body.leaf_triangles(leaf) {
            let triangle_box = triangle_aabb(&triangles[triangle as usize]);
            if reach.intersects(&triangle_box)
                && volume.intersects_triangle(&triangles[triangle as usize])
            {
                touched(triangle);
            }
        }
    }
}

/// Hair against body by testing every segment volume against every triangle with the exact test
/// (no culling at all): the reference for tests and the baseline for benchmarks. `hair` is in
/// the body's own frame, as for [`query_body`].
pub fn query_body_brute_force(
    hair: &HairBvh,
    body: &CollisionBody,
    contacts: &mut SegmentContacts,
) {
    contacts.pairs.clear();
    for (segment, volume) in hair.volumes().iter().enumerate() {
        for (triangle, body_triangle) in body.local_triangles().iter().enumerate() {
            if volume.intersects_triangle(body_triangle) {
                contacts.pairs.push((segment as u32, triangle as u32));
            }
        }
    }
    contacts.finish(false);
}
