//! The positional guarantee's kernels: a point projected out of a body, and a projected
//! segment given back its length with its end outside, which
//! [`CollisionSolver::after_step`](crate::CollisionSolver::after_step) runs node by node.

use glam::Vec3;

use crate::body::CollisionBody;
use crate::surface::SurfacePoint;

/// Gives the segment `pair[0] → pair[1]` its rest `length` [m] with `pair[1]` outside `body`.
/// First alternates giving the segment its length (moving `pair[1]` along it) and projecting
/// `pair[1]` out, a few rounds: on a smooth body the two meet within rounding in two or three.
/// Where they do not (a node driven deep into the head, or a crease), the segment is turned
/// about `pair[0]` instead, from its direction towards the surface's outward normal at
/// `pair[1]`, by the least angle (bisection) that puts `pair[1]`, at the segment's length, at
/// least half the skin outside: length and position then hold together. Only where even the
/// normal direction does not reach outside (the parent itself inside, a root set in the scalp)
/// does the position win and the segment keep the stretch, which the caller reports. The
/// searches start from triangle `hint` (where `pair[1]` was projected to).
pub(crate) fn restore_length(
    body: &CollisionBody,
    pair: &mut [Vec3],
    velocity: &mut Vec3,
    length: f32,
    skin: f32,
    hint: u32,
    surface_velocity: impl Fn(Vec3, u32) -> Vec3 + Copy,
) {
    const ROUNDS: usize = 4;
    let parent = pair[0];
    let kept = |p: Vec3| ((p - parent).length() - length).abs() <= LENGTH_KEPT * length;
    for _ in 0..ROUNDS {
        let Some(direction) = (pair[1] - parent).try_normalize() else {
            return;
        };
        if kept(pair[1]) {
            return;
        }
        pair[1] = parent + direction * length;
        if let Projection::Outside { .. } =
            project_out(body, &mut pair[1], velocity, skin, hint, surface_velocity)
        {
            return;
        }
    }
    if kept(pair[1]) {
        return;
    }
    // Turn the segment towards the outward normal: d(s) = normalize((1 − s)·d₀ + s·n), s ∈ [0, 1].
    let Some(start) = (pair[1] - parent).try_normalize() else {
        return;
    };
    let Some(surface) = body.closest_surface_point_near(pair[1], hint) else {
        return;
    };
    let normal = surface.normal;
    let at = |s: f32| {
        (start * (1.0 - s) + normal * s)
            .try_normalize()
            .map(|d| parent + d * length)
    };
    let outside = |p: Vec3| {
        body.closest_surface_point_near(p, hint)
            .is_none_or(|s| s.signed_distance >= 0.5 * skin)
    };
    // The far end is the normal direction itself; where even that is inside, the position wins.
    let (mut low, mut high) = (0.0f32, 1.0f32);
    match at(high) {
        Some(p) if outside(p) => {}
        _ => return,
    }
    for _ in 0..TURN_BISECTIONS {
        let middle = 0.5 * (low + high);
        match at(middle) {
            Some(p) if outside(p) => high = middle,
            _ => low = middle,
        }
    }
    if let Some(p) = at(high) {
        pair[1] = p;
        let relative = *velocity - surface_velocity(p, surface.triangle);
        let inward = relative.dot(normal);
        if inward < 0.0 {
            *velocity -= normal * inward;
        }
    }
}

/// Relative length error [1] within which the projection leaves a segment's length alone (about
/// the rounding of a 1 cm segment's length in f32 at head scale, far inside the 0.1 % that the
/// dynamics promise).
const LENGTH_KEPT: f32 = 1e-6;

/// Bisection steps of the segment turn in [`restore_length`] (the blend towards the normal is
/// then found within 2⁻²⁰, about 1e-6 rad).
const TURN_BISECTIONS: usize = 20;

/// Where a point lies against a body.
pub(crate) enum Probe {
    /// Outside, at least `clearance` \[m\] from the surface; `triangle` is the closest one where
    /// it was searched for (else the hint given).
    Outside { clearance: f32, triangle: u32 },
    /// Inside: the closest surface point.
    Inside(SurfacePoint),
}

/// Where `position` (world) lies against `body`, without moving it: points outside the body's
/// bounding ball are outside without a search (their clearance is the distance to the ball);
/// the search starts from triangle `hint` (the one found closest last time).
pub(crate) fn probe(body: &CollisionBody, position: Vec3, hint: u32) -> Probe {
    let bound = body.bounding_volume();
    let from_centre = position.distance(bound.center);
    if from_centre > bound.radius {
        return Probe::Outside {
            clearance: from_centre - bound.radius,
            triangle: hint,
        };
    }
    match body.closest_surface_point_near(position, hint) {
        None => Probe::Outside {
            clearance: 0.0,
            triangle: hint,
        },
        Some(surface) if surface.signed_distance >= 0.0 => Probe::Outside {
            clearance: surface.signed_distance,
            triangle: surface.triangle,
        },
        Some(surface) => Probe::Inside(surface),
    }
}

/// What [`project_out`] found.
pub(crate) enum Projection {
    /// The point is outside, at least `clearance` \[m\] from the surface, `triangle` the
    /// closest.
    Outside { clearance: f32, triangle: u32 },
    /// The point was `depth` \[m\] inside and has been moved out, onto `triangle`.
    Moved { depth: f32, triangle: u32 },
}

/// Moves `position` out of `body` when it is inside (to the closest surface point plus `skin`
/// along the way out) and removes the inward normal part of `velocity` relative to the surface
/// velocity `surface_velocity(p, t)` (`t` a triangle near `p`, where a search for its closest
/// point may start); where it is outside, see [`probe`] (`hint` starts its search).
pub(crate) fn project_out(
    body: &CollisionBody,
    position: &mut Vec3,
    velocity: &mut Vec3,
    skin: f32,
    hint: u32,
    surface_velocity: impl Fn(Vec3, u32) -> Vec3,
) -> Projection {
    let surface = match probe(body, *position, hint) {
        Probe::Outside {
            clearance,
            triangle,
        } => {
            return Projection::Outside {
                clearance,
                triangle,
            };
        }
        Probe::Inside(surface) => surface,
    };
    let depth = -surface.signed_distance;
    let outward = (surface.point - *position)
        .try_normalize()
        .unwrap_or(surface.normal);
    *position = surface.point + outward * skin;
    let relative = *velocity - surface_velocity(*position, surface.triangle);
    let inward = relative.dot(surface.normal);
    if inward < 0.0 {
        *velocity -= surface.normal * inward;
    }
    Projection::Moved {
        depth,
        triangle: surface.triangle,
    }
}
