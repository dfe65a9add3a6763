//! The analytic head-and-neck surface: a star-shaped radius function of direction, with its gradient.
//!
//! The surface is the set of points `radius(d) · d` for unit directions `d` from the head's centre
//! (the origin). `radius` is a smooth union (log-sum-exp of radii, blend width
//! [`UNION_BLEND_WIDTH`]) of the radii along `d` of convex pieces that all contain the origin, so the
//! union is star-shaped about the origin and `radius(d)` is exact and smooth:
//!
//! | piece | shape | centre [m] | semi-axes [m] |
//! |---|---|---|---|
//! | cranium | ellipsoid | (0, 0.012, -0.008) | (0.074, 0.095, 0.098) |
//! | jaw and chin | ellipsoid, narrower, below the front | (0, -0.035, 0.022) | (0.056, 0.078, 0.070) |
//! | nose | ellipsoid, a gentle bump on the face | (0, -0.008, 0.05) | (0.020, 0.032, 0.058) |
//! | neck | vertical cylinder, radius 0.055, axis (x, z) = (0, -0.012), y from -0.25 to 0.03, closed ends rounded over [`NECK_EDGE_BLEND_WIDTH`] | | |
//!
//! The radius of a convex piece along `d` is `1 / g(d)`, where `g` is the piece's gauge function
//! (positively homogeneous of degree 1, with a closed form for ellipsoids, cylinders and
//! half-spaces). Gradients are carried analytically through every blend, so normals are exact.

use glam::DVec3;

/// Width [m] of the log-sum-exp blend that unites cranium, jaw, nose and neck (a fillet of a few mm).
pub const UNION_BLEND_WIDTH: f64 = 0.006;
/// Width [m] of the log-sum-exp blend that rounds the neck's closed ends.
pub const NECK_EDGE_BLEND_WIDTH: f64 = 0.008;
/// The cranium ellipsoid's centre [m].
pub const CRANIUM_CENTRE: DVec3 = DVec3::new(0.0, 0.012, -0.008);
/// The cranium ellipsoid's semi-axes (half-width x, half-height y, half-depth z) [m].
pub const CRANIUM_SEMI_AXES: DVec3 = DVec3::new(0.074, 0.095, 0.098);
const JAW_CENTRE: DVec3 = DVec3::new(0.0, -0.035, 0.022);
const JAW_SEMI_AXES: DVec3 = DVec3::new(0.056, 0.078, 0.070);
const NOSE_CENTRE: DVec3 = DVec3::new(0.0, -0.008, 0.05);
const NOSE_SEMI_AXES: DVec3 = DVec3::new(0.02, 0.032, 0.058);
/// The neck cylinder's radius [m].
pub const NECK_RADIUS: f64 = 0.055;
/// The z coordinate of the neck's (vertical) axis [m]; its x is 0.
pub const NECK_AXIS_Z: f64 = -0.012;
/// Height [m] of the neck's closed bottom (the lowest point of the body).
pub const NECK_BOTTOM_Y: f64 = -0.25;
/// Height [m] of the neck's top end, hidden inside the cranium.
const NECK_TOP_Y: f64 = 0.03;

/// A radius [m] along a unit direction, with the gradient of its degree-0 homogeneous extension
/// `r(p) = r(p / |p|)` evaluated at that unit direction (tangent to the unit sphere) [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusSample {
    /// Distance [m] from the origin to the surface along the direction.
    pub radius: f64,
    /// Gradient of the radius with respect to the direction [m per unit of direction].
    pub gradient: DVec3,
}

/// A gauge function value [1/m] (positively homogeneous of degree 1) and its gradient [1/m].
#[derive(Debug, Clone, Copy)]
struct Gauge {
    value: f64,
    gradient: DVec3,
}

impl Gauge {
    /// The radius along unit `direction`: `r = 1/g`, `∇r = r d - r² ∇g`; `None` when the ray never
    /// leaves the piece (`g = 0`, an infinite radius).
    fn radius(self, direction: DVec3) -> Option<RadiusSample> {
        if self.value <= 1e-12 {
            return None;
        }
        let radius = 1.0 / self.value;
        Some(RadiusSample {
            radius,
            gradient: direction * radius - self.gradient * (radius * radius),
        })
    }
}

/// The gauge of the ellipsoid `|(p - centre) * inverse_semi_axes| ≤ 1`, which must contain the
/// origin. A zero component of `inverse_semi_axes` makes an infinite cylinder along that axis.
///
/// With `u = d ⊙ a⁻¹`, `w = c ⊙ a⁻¹`, `m = 1 - |w|²`: the ray `t·d` leaves the piece where
/// `|t u - w|² = 1`, so `g = 1/t = (s - u·w)/m` with `s = √((u·w)² + |u|² m)`.
fn ellipsoid_gauge(direction: DVec3, centre: DVec3, inverse_semi_axes: DVec3) -> Gauge {
    let u = direction * inverse_semi_axes;
    let w = centre * inverse_semi_axes;
    let m = 1.0 - w.length_squared();
    let uw = u.dot(w);
    let s = (uw * uw + u.length_squared() * m).sqrt();
    if s <= 1e-300 {
        return Gauge {
            value: 0.0,
            gradient: DVec3::ZERO,
        };
    }
    let gradient_u = (-w + (w * uw + u * m) / s) / m;
    Gauge {
        value: (s - uw) / m,
        gradient: gradient_u * inverse_semi_axes,
    }
}

/// The gauge of the half-space `normal · p ≤ offset` (`offset > 0`, so it contains the origin).
fn half_space_gauge(direction: DVec3, normal: DVec3, offset: f64) -> Gauge {
    let value = normal.dot(direction) / offset;
    if value > 0.0 {
        Gauge {
            value,
            gradient: normal / offset,
        }
    } else {
        Gauge {
            value: 0.0,
            gradient: DVec3::ZERO,
        }
    }
}

/// Log-sum-exp blend of radii: a smooth maximum (`sign = 1`, union) or minimum (`sign = -1`,
/// intersection) with blend `width` [m]. It never lies below the maximum (above the minimum).
fn blend(samples: &[RadiusSample], width: f64, sign: f64) -> RadiusSample {
    let extreme = samples
        .iter()
        .map(|sample| sign * sample.radius)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut total = 0.0;
    let mut gradient = DVec3::ZERO;
    for sample in samples {
        let weight = ((sign * sample.radius - extreme) / width).exp();
        total += weight;
        gradient += sample.gradient * weight;
    }
    RadiusSample {
        radius: sign * (extreme + width * total.ln()),
        gradient: gradient / total,
    }
}

/// The neck: a vertical cylinder cut by its bottom and top planes, edges rounded.
fn neck_radius(direction: DVec3) -> RadiusSample {
    let pieces = [
        ellipsoid_gauge(
            direction,
            DVec3::new(0.0, 0.0, NECK_AXIS_Z),
            DVec3::new(1.0 / NECK_RADIUS, 0.0, 1.0 / NECK_RADIUS),
        ),
        half_space_gauge(direction, DVec3::NEG_Y, -NECK_BOTTOM_Y),
        half_space_gauge(direction, DVec3::Y, NECK_TOP_Y),
    ];
    let mut samples = [RadiusSample {
        radius: 0.0,
        gradient: DVec3::ZERO,
    }; 3];
    let mut count = 0;
    for piece in pieces {
        if let Some(sample) = piece.radius(direction) {
            samples[count] = sample;
            count += 1;
        }
    }
    // Every direction leaves the bounded neck through the side or an end, so `count >= 1`.
    blend(&samples[..count], NECK_EDGE_BLEND_WIDTH, -1.0)
}

/// The head's radius along unit `direction` [m], with its gradient.
pub fn radius_sample(direction: DVec3) -> RadiusSample {
    let ellipsoid = |centre: DVec3, semi_axes: DVec3| {
        ellipsoid_gauge(direction, centre, DVec3::ONE / semi_axes)
            .radius(direction)
            .expect("a bounded ellipsoid has a finite radius in every direction")
    };
    let samples = [
        ellipsoid(CRANIUM_CENTRE, CRANIUM_SEMI_AXES),
        ellipsoid(JAW_CENTRE, JAW_SEMI_AXES),
        ellipsoid(NOSE_CENTRE, NOSE_SEMI_AXES),
        neck_radius(direction),
    ];
    blend(&samples, UNION_BLEND_WIDTH, 1.0)
}

/// The surface point [m] and unit outward normal along `direction` (any non-zero finite vector).
///
/// The surface is the zero set of `F(p) = |p| - r(p)`; at `p = r d` its gradient is
/// `d - ∇r(d) / r`, which always has a positive component along `d` (so `n · p > 0`).
pub fn surface_point(direction: DVec3) -> (DVec3, DVec3) {
    let direction = direction.try_normalize().unwrap_or(DVec3::Y);
    let sample = radius_sample(direction);
    let normal = (direction - sample.gradient / sample.radius)
        .try_normalize()
        .unwrap_or(direction);
    (direction * sample.radius, normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directions(count: usize) -> impl Iterator<Item = DVec3> {
        // A Fibonacci sphere: `count` well-spread unit directions.
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        (0..count).map(move |i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let ring = (1.0 - y * y).sqrt();
            let angle = golden * i as f64;
            DVec3::new(ring * angle.sin(), y, ring * angle.cos())
        })
    }

    #[test]
    fn gradient_matches_central_differences() {
        // Reference: (r(d + h e) - r(d - h e)) / 2h, an O(h²) estimate of ∂r/∂e.
        let h = 1e-6;
        for direction in directions(500) {
            let sample = radius_sample(direction);
            for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                let plus = radius_sample((direction + axis * h).normalize()).radius;
                let minus = radius_sample((direction - axis * h).normalize()).radius;
                // The degree-0 extension r(p/|p|) is what the gradient describes.
                let numeric = (plus - minus) / (2.0 * h);
                let analytic = sample.gradient.dot(axis);
                assert!(
                    (numeric - analytic).abs() < 1e-6,
                    "{direction:?} {axis:?}: {numeric} vs {analytic}"
                );
            }
            assert!(sample.gradient.dot(direction).abs() < 1e-9);
        }
    }

    #[test]
    fn surface_contains_the_pieces_and_is_bounded() {
        for direction in directions(2000) {
            let radius = radius_sample(direction).radius;
            let cranium =
                ellipsoid_gauge(direction, CRANIUM_CENTRE, DVec3::ONE / CRANIUM_SEMI_AXES)
                    .radius(direction)
                    .unwrap()
                    .radius;
            assert!(
                radius >= cranium && radius < 0.27,
                "{direction:?}: {radius}"
            );
            let (point, normal) = surface_point(direction);
            assert!(point.dot(normal) > 0.0);
        }
        // The lowest point is the neck's bottom, the highest the top of the cranium.
        assert!((surface_point(DVec3::NEG_Y).0.y - NECK_BOTTOM_Y).abs() < 1e-3);
        let top = surface_point(DVec3::Y).0.y;
        assert!(
            (top - (CRANIUM_CENTRE.y + CRANIUM_SEMI_AXES.y)).abs() < 2e-3,
            "{top}"
        );
    }
}
