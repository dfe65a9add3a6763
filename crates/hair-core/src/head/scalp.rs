//! Where hair grows: the hairline, the crown, the part line and the comb-direction field.
//!
//! Azimuth `ψ = atan2(x, z)` is measured around the vertical axis from the face (+Z, ψ = 0) towards
//! the head's left (+X, ψ = π/2); the nape is ψ = ±π. The hairline is the curve on the surface at
//! height `y_h(ψ) = a0 + a1 cos ψ + a2 cos 2ψ`, the one smooth even curve through the three heights
//! of [`HeadParams`]: `y_h(0)` = front, `y_h(±π/2)` = ears, `y_h(π)` = nape. The scalp is the part
//! of the surface above it.
//!
//! The part line is the curve where the plane `x = part_offset` cuts the surface, from the front
//! hairline back over the top to the crown; the crown (the whorl) is the point of that curve at
//! [`CROWN_ELEVATION`] (28° behind the top).

use std::f64::consts::FRAC_PI_2;

use glam::{DVec3, Vec3};

use super::params::HeadParams;
use super::shape::surface_point;

/// Angle [rad] of the crown in the y-z plane, from +Z (the face) over +Y (the top): 118°.
pub const CROWN_ELEVATION: f64 = 118.0 * std::f64::consts::PI / 180.0;
/// Number of points sampled on the part line.
const PART_LINE_POINTS: usize = 97;
/// Number of points sampled on the hairline loop.
const HAIRLINE_POINTS: usize = 360;
/// Distance behind the crown [m] over which the comb field turns from "away from the part" to
/// "radially away from the crown".
const CROWN_BLEND_DISTANCE: f64 = 0.03;

/// Height of the hairline [m] at azimuth `azimuth` [rad] (see the module documentation).
pub fn hairline_height(params: &HeadParams, azimuth: f64) -> f64 {
    let front = f64::from(params.hairline_front_height);
    let ear = f64::from(params.hairline_ear_height);
    let nape = f64::from(params.hairline_nape_height);
    let a1 = 0.5 * (front - nape);
    let a0 = 0.5 * (0.5 * (front + nape) + ear);
    let a2 = 0.5 * (0.5 * (front + nape) - ear);
    a0 + a1 * azimuth.cos() + a2 * (2.0 * azimuth).cos()
}

/// How far [m] a surface point lies above the hairline (negative below it).
pub fn height_above_hairline(params: &HeadParams, surface: DVec3) -> f64 {
    surface.y - hairline_height(params, surface.x.atan2(surface.z))
}

/// The surface point [m] where the plane `x = x0` meets the half-plane of directions
/// `(s, sin β, cos β)`, `s ∈ [-1, 1]`, found by bisection on `s` (`|x0|` up to ~0.05 m).
pub fn point_in_sagittal_plane(x0: f64, elevation: f64) -> DVec3 {
    let (sin_b, cos_b) = elevation.sin_cos();
    let point = |s: f64| surface_point(DVec3::new(s, sin_b, cos_b)).0;
    let (mut low, mut high) = (-1.0, 1.0);
    for _ in 0..60 {
        let middle = 0.5 * (low + high);
        if point(middle).x < x0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    point(0.5 * (low + high))
}

/// Bisection for the root of `f` on `[low, high]`, assuming `f(low) < 0 <= f(high)`.
fn bisect(mut low: f64, mut high: f64, f: impl Fn(f64) -> f64) -> f64 {
    for _ in 0..60 {
        let middle = 0.5 * (low + high);
        if f(middle) < 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// The crown [m]: the part-line point at [`CROWN_ELEVATION`].
pub fn crown(params: &HeadParams) -> DVec3 {
    point_in_sagittal_plane(f64::from(params.part_offset), CROWN_ELEVATION)
}

/// The part line [m], 97 points from the front hairline to the crown.
pub fn part_line(params: &HeadParams) -> Vec<Vec3> {
    let x0 = f64::from(params.part_offset);
    let above =
        |elevation: f64| height_above_hairline(params, point_in_sagittal_plane(x0, elevation));
    // Below the brow (elevation 0) the face is bare; the crown is on the scalp (validated heights).
    let start = if above(0.0) >= 0.0 {
        0.0
    } else {
        bisect(0.0, CROWN_ELEVATION, above)
    };
    (0..PART_LINE_POINTS)
        .map(|i| {
            let t = i as f64 / (PART_LINE_POINTS - 1) as f64;
            point_in_sagittal_plane(x0, start + (CROWN_ELEVATION - start) * t).as_vec3()
        })
        .collect()
}

/// The hairline loop [m], 360 points by azimuth from the face (ψ = 0) towards +X.
///
/// At each azimuth the point is found by bisection on the elevation of the direction in the
/// vertical half-plane, where the surface's height grows with the elevation on the upper head.
pub fn hairline(params: &HeadParams) -> Vec<Vec3> {
    (0..HAIRLINE_POINTS)
        .map(|i| {
            let azimuth = std::f64::consts::TAU * i as f64 / HAIRLINE_POINTS as f64;
            let (sin_a, cos_a) = azimuth.sin_cos();
            let at = |elevation: f64| {
                let (sin_e, cos_e) = elevation.sin_cos();
                surface_point(DVec3::new(cos_e * sin_a, sin_e, cos_e * cos_a)).0
            };
            let target = hairline_height(params, azimuth);
            let elevation = bisect(-1.4, FRAC_PI_2, |e| at(e).y - target);
            at(elevation).as_vec3()
        })
        .collect()
}

/// The part of a [`hairline`] loop in front of the ears (|ψ| ≤ 90°), as one polyline from the right
/// ear (ψ = -90°) across the forehead to the left ear (ψ = 90°).
pub fn front_hairline(hairline: &[Vec3]) -> Vec<Vec3> {
    let count = hairline.len();
    if count == 0 {
        return Vec::new();
    }
    let quarter = count / 4;
    (count - quarter..count)
        .chain(0..=quarter.min(count - 1))
        .map(|i| hairline[i])
        .collect()
}

/// Distance [m] from `point` to the polyline `line` (straight-line distance in 3-D to the nearest
/// point of its segments); infinite for an empty line.
pub fn distance_to_polyline(point: Vec3, line: &[Vec3]) -> f32 {
    match line {
        [] => f32::INFINITY,
        [single] => point.distance(*single),
        _ => line
            .windows(2)
            .map(|segment| {
                let (a, b) = (segment[0], segment[1]);
                let ab = b - a;
                let t = ((point - a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE))
                    .clamp(0.0, 1.0);
                point.distance(a + ab * t)
            })
            .fold(f32::INFINITY, f32::min),
    }
}

/// The unit vector along the tangent-plane part of `v` at a point with unit normal `normal`.
fn tangent_part(v: DVec3, normal: DVec3) -> Option<DVec3> {
    (v - normal * v.dot(normal)).try_normalize()
}

/// The direction hair lies from surface point `point` with unit normal `normal`: unit and tangent.
///
/// In front of the crown it is `side · X - Y - 0.3 Z` projected onto the tangent plane, with
/// `side = +1` on the `x ≥ part_offset` side of the part and -1 on the other: away from the part
/// across the top, downwards and slightly backwards on the sides, sideways and down on the
/// forehead. Behind the crown it turns, over `CROWN_BLEND_DISTANCE` (3 cm), to the tangent direction
/// away from the crown (hair radiates from the whorl, so it runs down the back). At the crown itself
/// the first rule applies, so the field is defined everywhere; where a projection vanishes it falls
/// back to "down", then "back".
pub fn comb_direction(params: &HeadParams, crown: DVec3, point: DVec3, normal: DVec3) -> DVec3 {
    let side = if point.x >= f64::from(params.part_offset) {
        1.0
    } else {
        -1.0
    };
    let across = DVec3::new(side, -1.0, -0.3);
    let behind = ((crown.z - point.z) / CROWN_BLEND_DISTANCE).clamp(0.0, 1.0);
    let weight = behind * behind * (3.0 - 2.0 * behind);
    let from_crown = tangent_part(point - crown, normal).unwrap_or(DVec3::ZERO);
    let across = tangent_part(across, normal).unwrap_or(DVec3::ZERO);
    let blended = across * (1.0 - weight) + from_crown * weight;
    tangent_part(blended, normal)
        .or_else(|| tangent_part(DVec3::NEG_Y, normal))
        .or_else(|| tangent_part(DVec3::NEG_Z, normal))
        .unwrap_or(DVec3::X)
}
