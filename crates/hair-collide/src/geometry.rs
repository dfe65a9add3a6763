//! Exact closest-distance kernels between the core skeletons of swept-sphere volumes: points,
//! segments and planar convex polygons (rectangles, triangles).
//!
//! All functions return *squared* distances \[m²\] so that callers can compare against squared
//! radii or take one square root at the end. They are closed forms (clamped projections and the
//! classic segment–segment solution of Ericson, *Real-Time Collision Detection* §5.1.9), with no
//! iteration and no tolerance, so the same inputs always give the same bits: the BVH query and
//! the brute-force query agree exactly because both call these.

use glam::Vec3;

/// A filled planar convex polygon, seen through its edges and its plane.
pub trait ConvexPlanar {
    /// Number of edges.
    const EDGE_COUNT: usize;
    /// Edge `k` as `(start, end)` \[m\], `k < EDGE_COUNT`.
    fn edge(&self, k: usize) -> (Vec3, Vec3);
    /// A point of the plane \[m\] and the unit normal, or `None` for a degenerate polygon (then
    /// treated as the union of its edges).
    fn plane(&self) -> Option<(Vec3, Vec3)>;
    /// Whether `q`, assumed to lie in the plane, is inside or on the boundary.
    fn contains_coplanar_point(&self, q: Vec3) -> bool;
}

/// A triangle with its counter-clockwise unit normal (zero when degenerate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// Vertices \[m\], counter-clockwise seen from the tip of `normal`.
    pub vertices: [Vec3; 3],
    /// Unit normal, or zero for a degenerate triangle.
    pub normal: Vec3,
}

impl Triangle {
    /// The triangle `a, b, c` with its counter-clockwise unit normal (zero when degenerate).
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self {
            vertices: [a, b, c],
            normal: (b - a).cross(c - a).normalize_or_zero(),
        }
    }
}

impl ConvexPlanar for Triangle {
    const EDGE_COUNT: usize = 3;

    #[inline]
    fn edge(&self, k: usize) -> (Vec3, Vec3) {
        (self.vertices[k], self.vertices[(k + 1) % 3])
    }

    #[inline]
    fn plane(&self) -> Option<(Vec3, Vec3)> {
        (self.normal != Vec3::ZERO).then_some((self.vertices[0], self.normal))
    }

    #[inline]
    fn contains_coplanar_point(&self, q: Vec3) -> bool {
        (0..3).all(|k| {
            let (a, b) = self.edge(k);
            (b - a).cross(q - a).dot(self.normal) >= 0.0
        })
    }
}

/// A rectangle: centre, two orthonormal in-plane axes and half extents (either may be zero).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rectangle {
    /// Centre \[m\].
    pub center: Vec3,
    /// Unit in-plane axes `u`, `v`, orthogonal to each other.
    pub axes: [Vec3; 2],
    /// Half extents \[m\] along `u` and `v`, each `>= 0`.
    pub half_extents: [f32; 2],
}

impl Rectangle {
    /// The four corners \[m\], counter-clockwise about `u × v`.
    #[inline]
    pub fn corners(&self) -> [Vec3; 4] {
        let u = self.axes[0] * self.half_extents[0];
        let v = self.axes[1] * self.half_extents[1];
        [
            self.center - u - v,
            self.center + u - v,
            self.center + u + v,
            self.center - u + v,
        ]
    }
}

impl ConvexPlanar for Rectangle {
    const EDGE_COUNT: usize = 4;

    #[inline]
    fn edge(&self, k: usize) -> (Vec3, Vec3) {
        let corners = self.corners();
        (corners[k], corners[(k + 1) % 4])
    }

    #[inline]
    fn plane(&self) -> Option<(Vec3, Vec3)> {
        Some((self.center, self.axes[0].cross(self.axes[1])))
    }

    #[inline]
    fn contains_coplanar_point(&self, q: Vec3) -> bool {
        // Local coordinates: exact for zero extents, unlike edge half-plane tests.
        let local = q - self.center;
        local.dot(self.axes[0]).abs() <= self.half_extents[0]
            && local.dot(self.axes[1]).abs() <= self.half_extents[1]
    }
}

/// Squared distance \[m²\] between two points.
#[inline]
pub fn point_point_distance_squared(p: Vec3, q: Vec3) -> f32 {
    p.distance_squared(q)
}

/// Parameter `t ∈ [0, 1]` of the point of segment `a + t (b − a)` closest to `p`.
#[inline]
pub fn closest_parameter_on_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let length_squared = ab.length_squared();
    if length_squared <= 0.0 {
        return 0.0;
    }
    ((p - a).dot(ab) / length_squared).clamp(0.0, 1.0)
}

/// Squared distance \[m²\] from point `p` to segment `[a, b]` (a point when `a == b`).
#[inline]
pub fn point_segment_distance_squared(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let t = closest_parameter_on_segment(p, a, b);
    p.distance_squared(a + (b - a) * t)
}

/// Closest points `(on_first, on_second)` \[m\] between segments `[p1, q1]` and `[p2, q2]`.
///
/// Ericson's clamped solution; degenerate (zero-length) and parallel segments are handled.
pub fn segment_segment_closest_points(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (Vec3, Vec3) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.length_squared();
    let e = d2.length_squared();
    let f = d2.dot(r);
    if a <= 0.0 && e <= 0.0 {
        return (p1, p2);
    }
    let (s, t);
    if a <= 0.0 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= 0.0 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denominator = a * e - b * b;
            let s0 = if denominator > 0.0 {
                ((b * f - c * e) / denominator).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    (p1 + d1 * s, p2 + d2 * t)
}

/// Squared distance \[m²\] between segments `[p1, q1]` and `[p2, q2]`.
#[inline]
pub fn segment_segment_distance_squared(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> f32 {
    let (a, b) = segment_segment_closest_points(p1, q1, p2, q2);
    a.distance_squared(b)
}

/// Squared distance \[m²\] from point `p` to a planar convex polygon (its filled area).
pub fn point_polygon_distance_squared<P: ConvexPlanar>(p: Vec3, polygon: &P) -> f32 {
    if let Some((origin, normal)) = polygon.plane() {
        let height = (p - origin).dot(normal);
        let projected = p - normal * height;
        if polygon.contains_coplanar_point(projected) {
            return height * height;
        }
    }
    (0..P::EDGE_COUNT)
        .map(|k| {
            let (a, b) = polygon.edge(k);
            point_segment_distance_squared(p, a, b)
        })
        .fold(f32::INFINITY, f32::min)
}

/// Squared distance \[m²\] from segment `[p, q]` to a planar convex polygon (its filled area).
///
/// Zero when the segment crosses the polygon; otherwise the minimum lies at an endpoint against
/// the polygon or at the segment against a polygon edge (a segment parallel to the plane can
/// slide until it meets an edge or an endpoint without changing its distance).
pub fn segment_polygon_distance_squared<P: ConvexPlanar>(p: Vec3, q: Vec3, polygon: &P) -> f32 {
    if let Some((origin, normal)) = polygon.plane() {
        let height_p = (p - origin).dot(normal);
        let height_q = (q - origin).dot(normal);
        let crosses = (height_p <= 0.0 && height_q >= 0.0) || (height_p >= 0.0 && height_q <= 0.0);
        if crosses && height_p != height_q {
            let t = height_p / (height_p - height_q);
            let crossing = p + (q - p) * t;
            // Project onto the plane so that rounding in `t` cannot move it off.
            let crossing = crossing - normal * (crossing - origin).dot(normal);
            if polygon.contains_coplanar_point(crossing) {
                return 0.0;
            }
        }
    }
    let mut best =
        point_polygon_distance_squared(p, polygon).min(point_polygon_distance_squared(q, polygon));
    for k in 0..P::EDGE_COUNT {
        let (a, b) = polygon.edge(k);
        best = best.min(segment_segment_distance_squared(p, q, a, b));
    }
    best
}

/// Squared distance \[m²\] between two planar convex polygons (filled).
///
/// For closed convex polygons the minimum is reached with a point on an edge of one of them
/// (two interior closest points force parallel planes, and the pair can then slide to an edge);
/// and if they intersect, an edge of one touches the other. So the distance is the minimum of
/// every edge of each against the other's area.
pub fn polygon_polygon_distance_squared<P: ConvexPlanar, Q: ConvexPlanar>(
    first: &P,
    second: &Q,
) -> f32 {
    let mut best = f32::INFINITY;
    for k in 0..P::EDGE_COUNT {
        let (a, b) = first.edge(k);
        best = best.min(segment_polygon_distance_squared(a, b, second));
        if best == 0.0 {
            return 0.0;
        }
    }
    for k in 0..Q::EDGE_COUNT {
        let (a, b) = second.edge(k);
        best = best.min(segment_polygon_distance_squared(a, b, first));
        if best == 0.0 {
            return 0.0;
        }
    }
    best
}

/// Whether segment `[p, q]` comes within `radius` \[m\] of a filled planar convex polygon:
/// `segment_polygon_distance_squared(p, q, polygon).sqrt() <= radius`, exactly (the same
/// candidates; `sqrt` is monotone, so "the smallest is within" is "some candidate is within"),
/// returning at the first candidate within reach.
pub fn segment_polygon_within<P: ConvexPlanar>(p: Vec3, q: Vec3, polygon: &P, radius: f32) -> bool {
    if let Some((origin, normal)) = polygon.plane() {
        let height_p = (p - origin).dot(normal);
        let height_q = (q - origin).dot(normal);
        let crosses = (height_p <= 0.0 && height_q >= 0.0) || (height_p >= 0.0 && height_q <= 0.0);
        if crosses && height_p != height_q {
            let t = height_p / (height_p - height_q);
            let crossing = p + (q - p) * t;
            let crossing = crossing - normal * (crossing - origin).dot(normal);
            if polygon.contains_coplanar_point(crossing) {
                return 0.0 <= radius;
            }
        }
    }
    let within = |d: f32| d.sqrt() <= radius;
    if within(point_polygon_distance_squared(p, polygon))
        || within(point_polygon_distance_squared(q, polygon))
    {
        return true;
    }
    (0..P::EDGE_COUNT).any(|k| {
        let (a, b) = polygon.edge(k);
        within(segment_segment_distance_squared(p, q, a, b))
    })
}

/// Whether two filled planar convex polygons come within `radius` \[m\] of each other:
/// `polygon_polygon_distance_squared(first, second).sqrt() <= radius`, exactly, returning at the
/// first edge within reach.
pub fn polygon_polygon_within<P: ConvexPlanar, Q: ConvexPlanar>(
    first: &P,
    second: &Q,
    radius: f32,
) -> bool {
    (0..P::EDGE_COUNT).any(|k| {
        let (a, b) = first.edge(k);
        segment_polygon_within(a, b, second, radius)
    }) || (0..Q::EDGE_COUNT).any(|k| {
        let (a, b) = second.edge(k);
        segment_polygon_within(a, b, first, radius)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_segment_skew_lines_closed_form() {
        // The x axis segment and a segment parallel to z at (0.5, 2, ·): distance 2 along y.
        let d = segment_segment_distance_squared(
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.5, 2.0, -1.0),
            Vec3::new(0.5, 2.0, 1.0),
        );
        assert_eq!(d, 4.0);
    }

    #[test]
    fn parallel_and_degenerate_segments() {
        let d = segment_segment_distance_squared(
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
        );
        // Endpoint (1,0,0) to (2,1,0): sqrt(2).
        assert!((d - 2.0).abs() < 1e-6);
        let d = segment_segment_distance_squared(Vec3::Y, Vec3::Y, Vec3::ZERO, Vec3::X);
        assert_eq!(d, 1.0);
    }

    #[test]
    fn segment_through_triangle_is_zero() {
        let triangle = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let d = segment_polygon_distance_squared(
            Vec3::new(0.2, 0.2, -1.0),
            Vec3::new(0.2, 0.2, 1.0),
            &triangle,
        );
        assert_eq!(d, 0.0);
        let d = segment_polygon_distance_squared(
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
            &triangle,
        );
        // Closest triangle point to the line x = y = 1 is (0.5, 0.5, 0): distance sqrt(0.5).
        assert!((d - 0.5).abs() < 1e-6);
    }
}
