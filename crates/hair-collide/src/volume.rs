//! Swept-sphere volumes (§5.2): a core skeleton (point, segment or rectangle) grown by a radius,
//! with exact pairwise distance and intersection, triangle tests, AABBs and parry3d shapes.
//!
//! `B = C ⊕ S`: every query runs on the core skeletons and subtracts the radii, exactly as the
//! paper describes. The kernels are closed forms (see [`crate::geometry`]), so results do not
//! depend on iteration tolerances; [`SweptSphere::to_parry`] gives the same volume as a parry
//! shape (`Ball`, `Capsule`, `RoundCuboid`) for use with parry's own queries.

use glam::{Mat3, Quat, Vec3};
use parry3d::bounding_volume::Aabb;
use parry3d::math::Pose;
use parry3d::shape::{Ball, Capsule, Cuboid, RoundCuboid, SharedShape};

use crate::closest::{point_polygon_closest, polygon_polygon_closest, segment_polygon_closest};
use crate::geometry::{
    Rectangle, Triangle, closest_parameter_on_segment, point_point_distance_squared,
    point_polygon_distance_squared, point_segment_distance_squared,
    polygon_polygon_distance_squared, polygon_polygon_within, segment_polygon_distance_squared,
    segment_polygon_within, segment_segment_closest_points, segment_segment_distance_squared,
};

/// Point-swept sphere (PSS): a ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pss {
    /// Centre \[m\].
    pub center: Vec3,
    /// Radius \[m\], `>= 0`.
    pub radius: f32,
}

/// Line-swept sphere (LSS): a capsule around the segment `[start, end]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lss {
    /// First end of the core segment \[m\].
    pub start: Vec3,
    /// Second end of the core segment \[m\].
    pub end: Vec3,
    /// Radius \[m\], `>= 0` (0 for a lone strand: the volume is the segment itself).
    pub radius: f32,
}

/// Rectangle-swept sphere (RSS): a zero-thickness rectangle with a border radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rss {
    /// The core rectangle (centre \[m\], orthonormal axes, half extents \[m\]).
    pub rectangle: Rectangle,
    /// Radius \[m\], `>= 0`.
    pub radius: f32,
}

/// One swept-sphere volume of any of the three kinds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SweptSphere {
    /// Point-swept sphere.
    Point(Pss),
    /// Line-swept sphere.
    Line(Lss),
    /// Rectangle-swept sphere.
    Rectangle(Rss),
}

impl From<Pss> for SweptSphere {
    fn from(value: Pss) -> Self {
        SweptSphere::Point(value)
    }
}
impl From<Lss> for SweptSphere {
    fn from(value: Lss) -> Self {
        SweptSphere::Line(value)
    }
}
impl From<Rss> for SweptSphere {
    fn from(value: Rss) -> Self {
        SweptSphere::Rectangle(value)
    }
}

/// The core skeleton of a volume, borrowed for dispatch.
#[derive(Debug, Clone, Copy)]
enum Core {
    Point(Vec3),
    Segment(Vec3, Vec3),
    Rectangle(Rectangle),
}

/// Squared distance \[m²\] between two core skeletons.
fn core_distance_squared(first: Core, second: Core) -> f32 {
    use Core::*;
    match (first, second) {
        (Point(p), Point(q)) => point_point_distance_squared(p, q),
        (Point(p), Segment(a, b)) | (Segment(a, b), Point(p)) => {
            point_segment_distance_squared(p, a, b)
        }
        (Point(p), Rectangle(r)) | (Rectangle(r), Point(p)) => {
            point_polygon_distance_squared(p, &r)
        }
        (Segment(a, b), Segment(c, d)) => segment_segment_distance_squared(a, b, c, d),
        (Segment(a, b), Rectangle(r)) | (Rectangle(r), Segment(a, b)) => {
            segment_polygon_distance_squared(a, b, &r)
        }
        (Rectangle(r), Rectangle(s)) => polygon_polygon_distance_squared(&r, &s),
    }
}

/// Squared distance \[m²\] from a core skeleton to a triangle.
fn core_triangle_distance_squared(core: Core, triangle: &Triangle) -> f32 {
    match core {
        Core::Point(p) => point_polygon_distance_squared(p, triangle),
        Core::Segment(a, b) => segment_polygon_distance_squared(a, b, triangle),
        Core::Rectangle(r) => polygon_polygon_distance_squared(&r, triangle),
    }
}

/// Squared distance \[m²\] and closest points `(on_first, on_second)` between two core skeletons.
fn core_closest(first: Core, second: Core) -> (f32, Vec3, Vec3) {
    use Core::*;
    let swap = |(d, a, b): (f32, Vec3, Vec3)| (d, b, a);
    match (first, second) {
        (Point(p), Point(q)) => (p.distance_squared(q), p, q),
        (Point(p), Segment(a, b)) => {
            let q = a + (b - a) * closest_parameter_on_segment(p, a, b);
            (p.distance_squared(q), p, q)
        }
        (Segment(a, b), Point(p)) => {
            let q = a + (b - a) * closest_parameter_on_segment(p, a, b);
            (p.distance_squared(q), q, p)
        }
        (Point(p), Rectangle(r)) => point_polygon_closest(p, &r),
        (Rectangle(r), Point(p)) => swap(point_polygon_closest(p, &r)),
        (Segment(a, b), Segment(c, d)) => {
            let (x, y) = segment_segment_closest_points(a, b, c, d);
            (x.distance_squared(y), x, y)
        }
        (Segment(a, b), Rectangle(r)) => segment_polygon_closest(a, b, &r),
        (Rectangle(r), Segment(a, b)) => swap(segment_polygon_closest(a, b, &r)),
        (Rectangle(r), Rectangle(s)) => polygon_polygon_closest(&r, &s),
    }
}

impl SweptSphere {
    fn core(&self) -> Core {
        match self {
            SweptSphere::Point(v) => Core::Point(v.center),
            SweptSphere::Line(v) => Core::Segment(v.start, v.end),
            SweptSphere::Rectangle(v) => Core::Rectangle(v.rectangle),
        }
    }

    /// Radius \[m\] of the swept sphere.
    pub fn radius(&self) -> f32 {
        match self {
            SweptSphere::Point(v) => v.radius,
            SweptSphere::Line(v) => v.radius,
            SweptSphere::Rectangle(v) => v.radius,
        }
    }

    /// Distance \[m\] between the core skeletons, radii not subtracted.
    pub fn core_distance(&self, other: &SweptSphere) -> f32 {
        core_distance_squared(self.core(), other.core()).sqrt()
    }

    /// Closest points `(on_self, on_other)` \[m\] of the two core skeletons and their distance
    /// \[m\] (radii not subtracted). Where the cores cross, both points are the crossing point.
    pub fn core_closest_points(&self, other: &SweptSphere) -> (Vec3, Vec3, f32) {
        let (d, a, b) = core_closest(self.core(), other.core());
        (a, b, d.sqrt())
    }

    /// Signed separation \[m\]: core distance minus both radii. Positive: the gap between the
    /// surfaces (exact); zero or negative: the volumes intersect (then `-distance` is how much
    /// the radii overlap, a lower bound on penetration when the cores themselves intersect).
    pub fn distance(&self, other: &SweptSphere) -> f32 {
        self.core_distance(other) - (self.radius() + other.radius())
    }

    /// Whether the two closed volumes share a point (touching counts).
    pub fn intersects(&self, other: &SweptSphere) -> bool {
        self.core_distance(other) <= self.radius() + other.radius()
    }

    /// Signed separation \[m\] from the volume to a (filled) triangle: core distance minus radius.
    pub fn triangle_distance(&self, triangle: &Triangle) -> f32 {
        core_triangle_distance_squared(self.core(), triangle).sqrt() - self.radius()
    }

    /// Whether the closed volume touches the (filled) triangle.
    ///
    /// This is the exact leaf test of every hair–body query, shared by the BVH and the
    /// brute-force paths so that they agree bit for bit. It equals
    /// `triangle_distance(triangle) <= 0` but stops at the first candidate within reach.
    pub fn intersects_triangle(&self, triangle: &Triangle) -> bool {
        if self.beyond_triangle_plane(triangle) {
            return false;
        }
        let radius = self.radius();
        match self.core() {
            Core::Point(p) => point_polygon_distance_squared(p, triangle).sqrt() <= radius,
            Core::Segment(a, b) => segment_polygon_within(a, b, triangle, radius),
            Core::Rectangle(r) => polygon_polygon_within(&r, triangle, radius),
        }
    }

    /// Quick exact reject for [`SweptSphere::intersects_triangle`]: a separating slab. The
    /// volume lies within `radius` of its core, so it cannot touch the triangle when (a) the
    /// core lies farther than the radius from the triangle's plane, on one side; or (b) for a
    /// segment, the triangle lies wholly before its start or past its end along its axis, by
    /// more than the radius; or (c) for a rectangle, the triangle lies wholly beyond the
    /// rectangle's plane or one of its edges, by more than the radius; or (d) the core lies
    /// wholly beyond one of the triangle's edges, along the edge's normal within the triangle's
    /// plane, by more than the radius (hair lying on the scalp beside a triangle); or (e) for a
    /// segment, on an axis across the segment and one of the triangle's edges (where the segment
    /// is a point), the triangle lies wholly to one side of it by more than the radius. Each
    /// side is widened by a rounding margin (see [`crate::aabb_padding`]) so that only pairs the
    /// full test rejects are rejected. Most candidate pairs of a query end here, after a few dot
    /// products.
    fn beyond_triangle_plane(&self, triangle: &Triangle) -> bool {
        let origin = triangle.vertices[0];
        let reach = self.radius()
            + 64.0 * f32::EPSILON * (1.0 + self.magnitude() + origin.abs().max_element());
        let outside = |low: f32, high: f32, values: &[f32]| {
            values.iter().all(|&h| h > high) || values.iter().all(|&h| h < low)
        };
        let normal = triangle.normal;
        if normal != Vec3::ZERO {
            let height = |p: Vec3| (p - origin).dot(normal);
            let separated = match self {
                SweptSphere::Point(v) => outside(-reach, reach, &[height(v.center)]),
                SweptSphere::Line(v) => outside(-reach, reach, &[height(v.start), height(v.end)]),
                SweptSphere::Rectangle(v) => {
                    outside(-reach, reach, &v.rectangle.corners().map(height))
                }
            };
            if separated {
                return true;
            }
        }
        let along = |origin: Vec3, axis: Vec3| triangle.vertices.map(|p| (p - origin).dot(axis));
        if normal != Vec3::ZERO && self.beyond_triangle_edges(triangle, reach) {
            return true;
        }
        match self {
            SweptSphere::Point(_) => false,
            SweptSphere::Line(v) => {
                let axis = v.end - v.start;
                let length = axis.length();
                if length > 0.0 && outside(-reach, length + reach, &along(v.start, axis / length)) {
                    return true;
                }
                // (e): the axes across the segment and each edge.
                let [a, b, c] = triangle.vertices;
                [b - a, c - b, a - c].into_iter().any(|edge| {
                    let across = axis.cross(edge);
                    let scale = across.length();
                    scale > 0.0 && outside(-reach, reach, &along(v.start, across / scale))
                })
            }
            SweptSphere::Rectangle(v) => {
                let r = &v.rectangle;
                let n = r.axes[0].cross(r.axes[1]);
                outside(-reach, reach, &along(r.center, n))
                    || (0..2).any(|k| {
                        let half = r.half_extents[k] + reach;
                        outside(-half, half, &along(r.center, r.axes[k]))
                    })
            }
        }
    }

    /// Part (d) of [`beyond_triangle_plane`](Self::beyond_triangle_plane): whether the core lies
    /// wholly beyond one of the (non-degenerate) triangle's edges, along the edge's outward
    /// normal within the triangle's plane, by more than `reach` \[m\].
    fn beyond_triangle_edges(&self, triangle: &Triangle, reach: f32) -> bool {
        let [a, b, c] = triangle.vertices;
        let core_points: &[Vec3] = match self {
            SweptSphere::Point(v) => &[v.center],
            SweptSphere::Line(v) => &[v.start, v.end],
            SweptSphere::Rectangle(_) => &[],
        };
        let corners;
        let points = match self {
            SweptSphere::Rectangle(v) => {
                corners = v.rectangle.corners();
                &corners[..]
            }
            _ => core_points,
        };
        [(a, b, c), (b, c, a), (c, a, b)]
            .into_iter()
            .any(|(from, to, third)| {
                // The edge's normal within the plane, turned away from the third vertex.
                let mut outward = (to - from).cross(triangle.normal);
                if (third - from).dot(outward) > 0.0 {
                    outward = -outward;
                }
                let scale = outward.length();
                scale > 0.0
                    && points
                        .iter()
                        .all(|&p| (p - from).dot(outward) > reach * scale)
            })
    }

    /// Axis-aligned bounds \[m\] of the volume, enlarged by `padding` \[m\] on every side.
    pub fn aabb(&self, padding: f32) -> Aabb {
        let (lo, hi) = match self {
            SweptSphere::Point(v) => (v.center, v.center),
            SweptSphere::Line(v) => (v.start.min(v.end), v.start.max(v.end)),
            SweptSphere::Rectangle(v) => {
                let c = v.rectangle.corners();
                (
                    c[0].min(c[1]).min(c[2]).min(c[3]),
                    c[0].max(c[1]).max(c[2]).max(c[3]),
                )
            }
        };
        let grow = Vec3::splat(self.radius() + padding);
        Aabb::new(lo - grow, hi + grow)
    }

    /// Whether the volume may touch a point of the box `aabb` beyond what [`aabb`](Self::aabb)
    /// overlap tells, conservatively: `false` only where a separating axis shows the box farther
    /// from the core than the radius plus `padding` \[m\] (the rounding allowance of
    /// [`crate::aabb_padding`]). For a rectangle the axes are its normal and its two axes, so
    /// that a tree descent skips the triangles a tilted patch's own AABB overlaps but the patch
    /// cannot reach (the patch queries 7 % faster); for points and segments their AABB is
    /// already as tight (the axes across a segment and the box's axes measured no faster), and
    /// this is `true`.
    pub fn may_touch_box(&self, aabb: &Aabb, padding: f32) -> bool {
        let center = (aabb.mins + aabb.maxs) * 0.5;
        let half = (aabb.maxs - aabb.mins) * 0.5;
        let reach = self.radius() + padding;
        // On `axis`, the core's interval `[low, high]` (about the box's centre) against the box's.
        let apart = |axis: Vec3, low: f32, high: f32| {
            let extent = half.dot(axis.abs());
            let grown = reach * axis.length();
            low > extent + grown || high < -(extent + grown)
        };
        match self {
            SweptSphere::Point(_) | SweptSphere::Line(_) => true,
            SweptSphere::Rectangle(v) => {
                let r = &v.rectangle;
                let offset = r.center - center;
                let normal = r.axes[0].cross(r.axes[1]);
                let at = offset.dot(normal);
                !apart(normal, at, at)
                    && (0..2).all(|k| {
                        let at = offset.dot(r.axes[k]);
                        let e = r.half_extents[k] * r.axes[k].length();
                        !apart(r.axes[k], at - e, at + e)
                    })
            }
        }
    }

    /// Largest absolute coordinate \[m\] of the core skeleton: the scale of its rounding errors.
    pub fn magnitude(&self) -> f32 {
        match self {
            SweptSphere::Point(v) => v.center.abs().max_element(),
            SweptSphere::Line(v) => v.start.abs().max(v.end.abs()).max_element(),
            SweptSphere::Rectangle(v) => v
                .rectangle
                .corners()
                .iter()
                .fold(0.0f32, |m, c| m.max(c.abs().max_element())),
        }
    }

    /// Whether every coordinate and the radius are finite.
    pub fn is_finite(&self) -> bool {
        match self {
            SweptSphere::Point(v) => v.center.is_finite() && v.radius.is_finite(),
            SweptSphere::Line(v) => {
                v.start.is_finite() && v.end.is_finite() && v.radius.is_finite()
            }
            SweptSphere::Rectangle(v) => {
                let r = &v.rectangle;
                r.center.is_finite()
                    && r.axes[0].is_finite()
                    && r.axes[1].is_finite()
                    && r.half_extents.iter().all(|h| h.is_finite())
                    && v.radius.is_finite()
            }
        }
    }

    /// The same volume as a parry3d shape and its pose: `Ball` for a PSS, `Capsule` for an LSS,
    /// `RoundCuboid` (a cuboid of half extents `(h_u, h_v, 0)` with border radius `r`) for an RSS.
    pub fn to_parry(&self) -> (Pose, SharedShape) {
        match self {
            SweptSphere::Point(v) => (
                Pose::from_translation(v.center),
                SharedShape::new(Ball::new(v.radius)),
            ),
            SweptSphere::Line(v) => (
                Pose::IDENTITY,
                SharedShape::new(Capsule::new(v.start, v.end, v.radius)),
            ),
            SweptSphere::Rectangle(v) => {
                let r = &v.rectangle;
                let rotation = Quat::from_mat3(&Mat3::from_cols(
                    r.axes[0],
                    r.axes[1],
                    r.axes[0].cross(r.axes[1]),
                ));
                let shape = RoundCuboid {
                    inner_shape: Cuboid::new(Vec3::new(r.half_extents[0], r.half_extents[1], 0.0)),
                    border_radius: v.radius,
                };
                (
                    Pose::from_parts(r.center, rotation),
                    SharedShape::new(shape),
                )
            }
        }
    }
}

impl Rss {
    /// The RSS of `rectangle` grown by `radius` \[m\].
    pub fn new(rectangle: Rectangle, radius: f32) -> Self {
        Self { rectangle, radius }
    }
}
