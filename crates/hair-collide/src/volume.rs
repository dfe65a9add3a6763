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

use crate::geometry::{
    Rectangle, Triangle, point_point_distance_squared, point_polygon_distance_squared,
    point_segment_distance_squared, polygon_polygon_distance_squared,
    segment_polygon_distance_squared, segment_segment_distance_squared,
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
    /// brute-force paths so that they agree bit for bit.
    pub fn intersects_triangle(&self, triangle: &Triangle) -> bool {
        core_triangle_distance_squared(self.core(), triangle).sqrt() <= self.radius()
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
