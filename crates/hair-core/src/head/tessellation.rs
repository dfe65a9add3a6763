//! Tessellating the analytic head into a closed latitude-longitude triangle mesh with exact normals.
//!
//! Vertices lie exactly on the surface, at directions `(sin θ sin φ, cos θ, sin θ cos φ)`: `θ` is the
//! angle from +Y (the top pole), `φ` the azimuth from +Z (the face) towards +X. Each pole is one
//! vertex joined to its neighbouring ring by a fan of `longitude_bands` triangles (no degenerate
//! triangles); the other latitude bands are quads split into two triangles. Latitudes are spaced
//! evenly in arc length and turning of the surface along its meridians (not in angle), so the long
//! neck gets as many rows per centimetre as the cranium, and the curved places more.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::shape::surface_point;
use crate::mesh::TriangleMesh;

/// Number of angle steps used to measure the meridians.
const PROFILE_STEPS: usize = 2048;
/// Number of meridians measured.
const PROFILE_MERIDIANS: usize = 32;
/// How much a turn of the surface normal counts as length when spacing latitudes [m/rad].
const TURN_WEIGHT: f64 = 0.03;

/// The unit direction at polar angle `theta` from +Y and azimuth `phi` from +Z towards +X [rad].
pub fn direction(theta: f64, phi: f64) -> DVec3 {
    let (sin_theta, cos_theta) = theta.sin_cos();
    let (sin_phi, cos_phi) = phi.sin_cos();
    DVec3::new(sin_theta * sin_phi, cos_theta, sin_theta * cos_phi)
}

/// The polar angles [rad] of the `bands + 1` latitudes (0 and π included), evenly spaced in a
/// "cost" along the meridians: per angle step, the largest over [`PROFILE_MERIDIANS`] meridians of
/// the chord length plus [`TURN_WEIGHT`] times the turn of the normal. So every meridian gets rows at
/// most about `total / bands` apart, and curved places (chin, nose, the neck's rounded bottom) more.
fn latitude_angles(bands: usize) -> Vec<f64> {
    let step = PI / PROFILE_STEPS as f64;
    let meridian_points = |theta: f64| -> Vec<(DVec3, DVec3)> {
        (0..PROFILE_MERIDIANS)
            .map(|m| surface_point(direction(theta, TAU * m as f64 / PROFILE_MERIDIANS as f64)))
            .collect()
    };
    let mut cumulative = Vec::with_capacity(PROFILE_STEPS + 1);
    cumulative.push(0.0);
    let mut previous = meridian_points(0.0);
    let mut total = 0.0;
    for i in 1..=PROFILE_STEPS {
        let current = meridian_points(step * i as f64);
        let cost = previous
            .iter()
            .zip(&current)
            .map(|((p, n), (q, m))| p.distance(*q) + TURN_WEIGHT * n.angle_between(*m))
            .fold(0.0, f64::max);
        total += cost;
        cumulative.push(total);
        previous = current;
    }
    let mut angles = Vec::with_capacity(bands + 1);
    angles.push(0.0);
    let mut index = 0;
    for band in 1..bands {
        let target = total * band as f64 / bands as f64;
        while index + 1 < PROFILE_STEPS && cumulative[index + 1] < target {
            index += 1;
        }
        let (low, high) = (cumulative[index], cumulative[index + 1]);
        let fraction = if high > low {
            (target - low) / (high - low)
        } else {
            0.0
        };
        angles.push(step * (index as f64 + fraction));
    }
    angles.push(PI);
    angles
}

/// The closed mesh of the head: `longitude_bands · (latitude_bands - 1) + 2` vertices and
/// `2 · longitude_bands · (latitude_bands - 1)` triangles, counter-clockwise seen from outside, with
/// the surface's exact unit normals. Both counts must be at least 3 and 2 (validated by the caller).
pub fn tessellate(latitude_bands: usize, longitude_bands: usize) -> TriangleMesh {
    let angles = latitude_angles(latitude_bands);
    let rings = latitude_bands - 1;
    let vertex_count = longitude_bands * rings + 2;
    let mut positions = Vec::with_capacity(vertex_count);
    let mut normals = Vec::with_capacity(vertex_count);
    let mut push = |d: DVec3| {
        let (point, normal) = surface_point(d);
        positions.push(point.as_vec3());
        normals.push(normal.as_vec3());
    };
    push(DVec3::Y);
    for &theta in &angles[1..latitude_bands] {
        for j in 0..longitude_bands {
            push(direction(theta, TAU * j as f64 / longitude_bands as f64));
        }
    }
    push(DVec3::NEG_Y);

    let n = longitude_bands as u32;
    let ring_vertex = |ring: u32, j: u32| 1 + ring * n + j % n;
    let south = vertex_count as u32 - 1;
    let mut triangles = Vec::with_capacity(2 * longitude_bands * rings);
    for j in 0..n {
        triangles.push([0, ring_vertex(0, j), ring_vertex(0, j + 1)]);
    }
    for ring in 0..rings as u32 - 1 {
        for j in 0..n {
            let a = ring_vertex(ring, j);
            let b = ring_vertex(ring + 1, j);
            let c = ring_vertex(ring + 1, j + 1);
            let d = ring_vertex(ring, j + 1);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let last = rings as u32 - 1;
    for j in 0..n {
        triangles.push([south, ring_vertex(last, j + 1), ring_vertex(last, j)]);
    }
    TriangleMesh {
        positions,
        normals,
        triangles,
    }
}
