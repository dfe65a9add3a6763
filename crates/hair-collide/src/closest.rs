//! Closest points, not only distances: between the core skeletons of two swept-sphere volumes
//! (for the hair–hair repulsion's direction) and from a point to a triangle with the feature it
//! lands on (for the signed distance to a body through pseudonormals).
//!
//! Same closed forms as [`crate::geometry`] (clamped projections, Ericson's segment–segment
//! solution and his point–triangle Voronoi-region walk, *Real-Time Collision Detection* §5.1.5),
//! so the distances agree with the distance kernels up to rounding.

use glam::Vec3;

use crate::geometry::{
    ConvexPlanar, Triangle, closest_parameter_on_segment, segment_segment_closest_points,
};

/// The part of a triangle a closest point lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TriangleFeature {
    /// Vertex `k` (0, 1 or 2).
    Vertex(u8),
    /// Edge `k`, from vertex `k` to vertex `(k + 1) % 3`.
    Edge(u8),
    /// The interior of the face.
    Face,
}

/// The point of the filled triangle closest to `p` \[m\], and the feature it lies on.
///
/// Ericson's walk over the Voronoi regions of the vertices, edges and face. A degenerate
/// (zero-area) triangle is handled as the union of its edges.
pub fn closest_point_on_triangle(p: Vec3, triangle: &Triangle) -> (Vec3, TriangleFeature) {
    let [a, b, c] = triangle.vertices;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, TriangleFeature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, TriangleFeature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, TriangleFeature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, TriangleFeature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, TriangleFeature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, TriangleFeature::Edge(1));
    }
    let sum = va + vb + vc;
    if sum > 0.0 && triangle.normal != Vec3::ZERO {
        let v = vb / sum;
        let w = vc / sum;
        return (a + ab * v + ac * w, TriangleFeature::Face);
    }
    // Degenerate triangle: the closest point of its edges.
    let mut best = (a, TriangleFeature::Vertex(0));
    let mut best_distance = f32::INFINITY;
    for k in 0..3u8 {
        let (s, e) = triangle.edge(k as usize);
        let q = s + (e - s) * closest_parameter_on_segment(p, s, e);
        let d = q.distance_squared(p);
        if d < best_distance {
            best_distance = d;
            best = (q, TriangleFeature::Edge(k));
        }
    }
    best
}

/// Squared distance \[m²\] and closest points `(on_point, on_polygon)` from `p` to a filled
/// planar convex polygon.
pub fn point_polygon_closest<P: ConvexPlanar>(p: Vec3, polygon: &P) -> (f32, Vec3, Vec3) {
    if let Some((origin, normal)) = polygon.plane() {
        let height = (p - origin).dot(normal);
        let projected = p - normal * height;
        if polygon.contains_coplanar_point(projected) {
            return (height * height, p, projected);
        }
    }
    let mut best = (f32::INFINITY, p, p);
    for k in 0..P::EDGE_COUNT {
        let (a, b) = polygon.edge(k);
        let q = a + (b - a) * closest_parameter_on_segment(p, a, b);
        let d = p.distance_squared(q);
        if d < best.0 {
            best = (d, p, q);
        }
    }
    best
}

/// Squared distance \[m²\] and closest points `(on_segment, on_polygon)` from segment `[p, q]`
/// to a filled planar convex polygon (same case analysis as
/// [`crate::geometry::segment_polygon_distance_squared`]).
pub fn segment_polygon_closest<P: ConvexPlanar>(
    p: Vec3,
    q: Vec3,
    polygon: &P,
) -> (f32, Vec3, Vec3) {
    if let Some((origin, normal)) = polygon.plane() {
        let height_p = (p - origin).dot(normal);
        let height_q = (q - origin).dot(normal);
        let crosses = (height_p <= 0.0 && height_q >= 0.0) || (height_p >= 0.0 && height_q <= 0.0);
        if crosses && height_p != height_q {
            let t = height_p / (height_p - height_q);
            let crossing = p + (q - p) * t;
            let crossing = crossing - normal * (crossing - origin).dot(normal);
            if polygon.contains_coplanar_point(crossing) {
                return (0.0, crossing, crossing);
            }
        }
    }
    let mut best = point_polygon_closest(p, polygon);
    let at_q = point_polygon_closest(q, polygon);
    if at_q.0 < best.0 {
        best = at_q;
    }
    for k in 0..P::EDGE_COUNT {
        let (a, b) = polygon.edge(k);
        let (on_segment, on_edge) = segment_segment_closest_points(p, q, a, b);
        let d = on_segment.distance_squared(on_edge);
        if d < best.0 {
            best = (d, on_segment, on_edge);
        }
    }
    best
}

/// Squared distance \[m²\] and closest points `(on_first, on_second)` between two filled planar
/// convex polygons: the best of every edge of each against the other's area.
pub fn polygon_polygon_closest<P: ConvexPlanar, Q: ConvexPlanar>(
    first: &P,
    second: &Q,
) -> (f32, Vec3, Vec3) {
    let mut best = (f32::INFINITY, Vec3::ZERO, Vec3::ZERO);
    for k in 0..P::EDGE_COUNT {
        let (a, b) = first.edge(k);
        let candidate = segment_polygon_closest(a, b, second);
        if candidate.0 < best.0 {
            best = candidate;
        }
    }
    for k in 0..Q::EDGE_COUNT {
        let (a, b) = second.edge(k);
        let (d, on_second, on_first) = segment_polygon_closest(a, b, first);
        if d < best.0 {
            best = (d, on_first, on_second);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Rectangle, point_polygon_distance_squared};

    #[test]
    fn point_triangle_regions() {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        // Barycentric interpolation rounds: within a few ulps of 0.2.
        let (q, f) = closest_point_on_triangle(Vec3::new(0.2, 0.2, 1.0), &t);
        assert!((q - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-7);
        assert_eq!(f, TriangleFeature::Face);
        let (q, f) = closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.5), &t);
        assert_eq!((q, f), (Vec3::ZERO, TriangleFeature::Vertex(0)));
        let (q, f) = closest_point_on_triangle(Vec3::new(0.5, -1.0, 0.0), &t);
        assert_eq!((q, f), (Vec3::new(0.5, 0.0, 0.0), TriangleFeature::Edge(0)));
        let (q, f) = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), &t);
        assert!((q - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-7);
        assert_eq!(f, TriangleFeature::Edge(1));
        let (q, f) = closest_point_on_triangle(Vec3::new(-0.5, 0.5, 0.0), &t);
        assert_eq!((q, f), (Vec3::new(0.0, 0.5, 0.0), TriangleFeature::Edge(2)));
    }

    #[test]
    fn closest_points_agree_with_distance_kernels() {
        let r = Rectangle {
            center: Vec3::new(0.1, 0.2, 0.3),
            axes: [Vec3::X, Vec3::Z],
            half_extents: [0.5, 0.25],
        };
        for p in [Vec3::new(2.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.4)] {
            let (d, on_p, on_r) = point_polygon_closest(p, &r);
            assert_eq!(on_p, p);
            assert!((d - point_polygon_distance_squared(p, &r)).abs() < 1e-6);
            assert!((on_r.distance_squared(p) - d).abs() < 1e-6);
        }
    }
}
