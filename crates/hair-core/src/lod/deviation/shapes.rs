//! Distances from a point to the drawn shapes of the coarse levels: a cluster's tube taken as a
//! solid (its axis with a radius per axis sample) and a patch's ruled strip (rows of segments
//! across the hair, joined by triangles).

use glam::Vec3;

/// The point of segment `a`–`b` closest to `p`: its parameter `t ∈ [0, 1]` and distance [m].
pub(super) fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> (f32, f32) {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (t, p.distance(a + ab * t))
}

/// Distance [m] from `p` to the filled triangle `(a, b, c)`: the distance to its plane when `p`
/// projects inside it, else to the nearest edge (a degenerate triangle is its edges).
pub(super) fn triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let normal = (b - a).cross(c - a);
    let area2 = normal.length_squared();
    if area2 > f32::MIN_POSITIVE {
        // Barycentric coordinates of the projection from the sub-triangle areas.
        let (pa, pb, pc) = (a - p, b - p, c - p);
        let u = pb.cross(pc).dot(normal);
        let v = pc.cross(pa).dot(normal);
        let w = pa.cross(pb).dot(normal);
        if u >= 0.0 && v >= 0.0 && w >= 0.0 {
            return (p - a).dot(normal).abs() / area2.sqrt();
        }
    }
    [(a, b), (b, c), (c, a)]
        .into_iter()
        .map(|(from, to)| closest_on_segment(p, from, to).1)
        .fold(f32::INFINITY, f32::min)
}

/// A shape cut into pieces along the hair, each with a bounding sphere, so that a distance query
/// skips the pieces that cannot beat the best distance found so far.
pub(super) trait Pieces {
    /// Number of pieces.
    fn piece_count(&self) -> usize;
    /// Bounding sphere (centre [m], radius [m]) of piece `k`.
    fn bound(&self, k: usize) -> (Vec3, f32);
    /// Distance [m] from `p` to piece `k`.
    fn piece_distance(&self, p: Vec3, k: usize) -> f32;

    /// Distance [m] from `p` to the whole shape, starting the search at piece `hint` (the piece
    /// expected nearest) and going outwards both ways; exact whatever the hint.
    fn distance(&self, p: Vec3, hint: usize) -> f32 {
        let count = self.piece_count();
        let mut best = f32::INFINITY;
        let start = hint.min(count.saturating_sub(1));
        // start, start + 1, start − 1, start + 2, … until both sides are past the ends.
        for step in 0..2 * count {
            let offset = step.div_ceil(2);
            let k = if step % 2 == 1 {
                start + offset
            } else {
                match start.checked_sub(offset) {
                    Some(k) => k,
                    None => continue,
                }
            };
            if k >= count {
                continue;
            }
            let (centre, radius) = self.bound(k);
            if p.distance(centre) - radius >= best {
                continue;
            }
            best = best.min(self.piece_distance(p, k));
        }
        best
    }
}

/// The solid tube around the polyline `axis` whose radius at axis point `k` is `radii[k]`
/// (linear between them). Its distance from a point is `max(0, |p − q| − r(q))` at the nearest
/// axis point `q` of a segment, minimised over segments; 0 inside.
pub(super) struct Tube {
    axis: Vec<Vec3>,
    radii: Vec<f32>,
    bounds: Vec<(Vec3, f32)>,
}

impl Tube {
    /// A tube from its axis samples [m] and radii [m] (equal lengths, at least 2).
    pub(super) fn new(axis: Vec<Vec3>, radii: Vec<f32>) -> Tube {
        let bounds = axis
            .windows(2)
            .enumerate()
            .map(|(k, ends)| {
                let centre = 0.5 * (ends[0] + ends[1]);
                (
                    centre,
                    0.5 * ends[0].distance(ends[1]) + radii[k].max(radii[k + 1]),
                )
            })
            .collect();
        Tube {
            axis,
            radii,
            bounds,
        }
    }
}

impl Pieces for Tube {
    fn piece_count(&self) -> usize {
        self.bounds.len()
    }
    fn bound(&self, k: usize) -> (Vec3, f32) {
        self.bounds[k]
    }
    fn piece_distance(&self, p: Vec3, k: usize) -> f32 {
        let (t, distance) = closest_on_segment(p, self.axis[k], self.axis[k + 1]);
        let radius = self.radii[k] + (self.radii[k + 1] - self.radii[k]) * t;
        (distance - radius).max(0.0)
    }
}

/// The ruled strip through the rows `left[k]`–`right[k]` [m], each quad between rows split into
/// two triangles.
pub(super) struct Strip {
    left: Vec<Vec3>,
    right: Vec<Vec3>,
    bounds: Vec<(Vec3, f32)>,
}

impl Strip {
    /// A strip from its two edges [m] (equal lengths, at least 2).
    pub(super) fn new(left: Vec<Vec3>, right: Vec<Vec3>) -> Strip {
        let bounds = (0..left.len() - 1)
            .map(|k| {
                let corners = [left[k], right[k], left[k + 1], right[k + 1]];
                let centre = 0.25 * corners.iter().copied().sum::<Vec3>();
                let radius = corners
                    .iter()
                    .map(|c| c.distance(centre))
                    .fold(0.0f32, f32::max);
                (centre, radius)
            })
            .collect();
        Strip {
            left,
            right,
            bounds,
        }
    }
}

impl Pieces for Strip {
    fn piece_count(&self) -> usize {
        self.bounds.len()
    }
    fn bound(&self, k: usize) -> (Vec3, f32) {
        self.bounds[k]
    }
    fn piece_distance(&self, p: Vec3, k: usize) -> f32 {
        let (a0, b0) = (self.left[k], self.right[k]);
        let (a1, b1) = (self.left[k + 1], self.right[k + 1]);
        triangle_distance(p, a0, b0, a1).min(triangle_distance(p, b0, b1, a1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_distance_over_the_face_edges_and_corners() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        // Above the face: the height.
        assert!((triangle_distance(Vec3::new(0.2, 0.2, 0.5), a, b, c) - 0.5).abs() < 1e-6);
        // Beyond the hypotenuse x + y = 1, in the plane: (1.5 − 1)/√2 from (1, 0.5).
        let d = triangle_distance(Vec3::new(1.0, 0.5, 0.0), a, b, c);
        assert!((d - 0.5 / 2f32.sqrt()).abs() < 1e-6);
        // Past a corner: the distance to the corner.
        let d = triangle_distance(Vec3::new(-0.3, -0.4, 0.0), a, b, c);
        assert!((d - 0.5).abs() < 1e-6);
    }

    #[test]
    fn tube_distance_is_zero_inside_and_radial_outside() {
        let tube = Tube::new(vec![Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0)], vec![0.2, 0.1]);
        assert_eq!(tube.distance(Vec3::new(0.05, -0.5, 0.0), 0), 0.0);
        // At mid-length the radius is 0.15: 0.4 − 0.15.
        let d = tube.distance(Vec3::new(0.0, -0.5, 0.4), 0);
        assert!((d - 0.25).abs() < 1e-6);
    }

    #[test]
    fn strip_distance_is_the_height_over_a_flat_strip() {
        let left = vec![Vec3::new(-1.0, 0.0, 0.0), Vec3::new(-1.0, -1.0, 0.0)];
        let right = vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, -1.0, 0.0)];
        let strip = Strip::new(left, right);
        assert!((strip.distance(Vec3::new(0.3, -0.7, 0.25), 0) - 0.25).abs() < 1e-6);
        // Off the side: to the edge x = 1.
        assert!((strip.distance(Vec3::new(1.5, -0.5, 0.0), 0) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_pruned_search_is_exact_whatever_the_hint() {
        // A helix as axis: pieces far along it come back close in space.
        let axis: Vec<Vec3> = (0..60)
            .map(|k| {
                let a = k as f32 * 0.4;
                Vec3::new(0.02 * a.cos(), -0.003 * k as f32, 0.02 * a.sin())
            })
            .collect();
        let radii: Vec<f32> = (0..60).map(|k| 0.004 + 0.0001 * k as f32).collect();
        let tube = Tube::new(axis, radii);
        for q in 0..50 {
            let p = Vec3::new(
                0.03 * (q as f32).sin(),
                -0.004 * q as f32,
                0.025 * (q as f32).cos(),
            );
            let brute = (0..tube.piece_count())
                .map(|k| tube.piece_distance(p, k))
                .fold(f32::INFINITY, f32::min);
            for hint in [0, 17, 58, 1000] {
                assert_eq!(tube.distance(p, hint), brute);
            }
        }
    }
}
