//! Hair against a body through its distance field (issue 51): each segment volume touches the
//! body where the field's interpolated signed distance at its core comes within its radius, and
//! the contact's normal is the field's gradient there, as real-time hair systems collide hair
//! with a body's signed distance field (TressFX, Frostbite). No triangle is visited, so the cost
//! is a few field samples per segment whatever the volume's radius and the mesh's resolution.
//!
//! **The core's samples.** A point volume is sampled at its centre; a segment at its ends and
//! middle, then at the vertex of the parabola through those three distances (where it lies inside
//! the segment); a rectangle on a 3 × 3 grid (corners, edge midpoints, centre). On a convex
//! smooth surface of curvature radius `R` the distance along a core is close to a parabola of
//! curvature `1/R`, so the sampled minimum exceeds the true one by at most about `s²/(8R)` for
//! samples `s` apart: 0.16 mm for a 2 cm segment on an 8 cm head before the parabola's sample,
//! far less after it. The field's own interpolation error is of order `h²/R` (µm).
//!
//! **Where the field cannot decide** (a sample's cell without exact corners: the core farther
//! than [`EXACT_REACH`](crate::distance_field::EXACT_REACH) from the surface while the certified
//! bound does not clear it, a radius above about 8 mm, or an unsigned field on an open mesh), the
//! segment takes the exact path: the triangles its volume touches, and their mean normal, as
//! [`crate::query_body_volumes`] finds them. [`FieldContacts::exact_fallbacks`] counts those.

use glam::Vec3;
use rayon::prelude::*;

use crate::body::CollisionBody;
use crate::bvh::aabb_padding;
use crate::distance_field::DistanceField;
use crate::query::{CHUNK, aabb_touches_ball, ball_padding, for_each_touched};
use crate::volume::SweptSphere;

/// Contacts of hair segments with a body from its distance field: one unit normal per touching
/// segment.
#[derive(Debug, Clone, Default)]
pub struct FieldContacts {
    /// `(segment, normal)` of each segment that touches the body, ascending by segment: the
    /// normal is unit and outward, in the body's own frame.
    pub contacts: Vec<(u32, Vec3)>,
    /// Segments of the last query that the field could not decide and the exact triangle tests
    /// did (see the module documentation).
    pub exact_fallbacks: usize,
    /// Per chunk of volumes: its contacts and fallbacks, found side by side.
    chunks: Vec<(Vec<(u32, Vec3)>, usize)>,
}

impl FieldContacts {
    /// An empty contact set.
    pub fn new() -> Self {
        Self::default()
    }
}

/// What the field says of one volume.
enum Verdict {
    /// Clear of the body.
    Clear,
    /// Touching, with the outward unit normal (body frame).
    Touching(Vec3),
    /// The field cannot decide: take the exact path.
    Undecided,
}

/// The lowest interpolated distance over `samples` (each point with its
/// [`DistanceField::sample`]) and the gradient there (`None` when no point is in an exact cell),
/// or `Err(())` when a point outside the exact cells may lie within `radius` \[m\] of the
/// surface, so that the samples cannot decide. A point outside the exact cells lies farther than
/// [`DistanceField::exact_reach`] from the surface (inside the grid; beyond it, the certified
/// bound says how far): where that exceeds the radius, it cannot make the volume touch, and is
/// left out.
fn lowest(
    field: &DistanceField,
    radius: f32,
    samples: impl IntoIterator<Item = (Vec3, Option<(f32, Vec3)>)>,
) -> Result<Option<(f32, Vec3)>, ()> {
    let mut best: Option<(f32, Vec3)> = None;
    for (p, sample) in samples {
        match sample {
            Some((d, g)) => {
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, g));
                }
            }
            None if field.exact_reach() > radius || field.bound(p).0 > radius => {}
            None => return Err(()),
        }
    }
    Ok(best)
}

/// The field's verdict on `volume` (body frame).
fn verdict(field: &DistanceField, volume: &SweptSphere) -> Verdict {
    let radius = volume.radius();
    let sampled_at = |p: Vec3| (p, field.sample(p));
    let sampled = match volume {
        SweptSphere::Point(v) => lowest(field, radius, [sampled_at(v.center)]),
        SweptSphere::Line(v) => {
            let axis = v.end - v.start;
            let samples = [v.start, v.start + axis * 0.5, v.end].map(sampled_at);
            lowest(field, radius, samples).map(|best| {
                let (d, g) = best?;
                // The parabola through the three distances (all exact): its vertex, where inside.
                if let [(_, Some((d0, _))), (_, Some((d1, _))), (_, Some((d2, _)))] = samples {
                    let a = 2.0 * (d0 - 2.0 * d1 + d2);
                    let t = -(d2 - d0 - a) / (2.0 * a);
                    if a > 0.0
                        && t > 0.0
                        && t < 1.0
                        && let Some((dt, gt)) = field.sample(v.start + axis * t)
                        && dt < d
                    {
                        return Some((dt, gt));
                    }
                }
                Some((d, g))
            })
        }
        SweptSphere::Rectangle(v) => {
            let r = &v.rectangle;
            let (u, w) = (r.axes[0] * r.half_extents[0], r.axes[1] * r.half_extents[1]);
            let grid = [-1.0f32, 0.0, 1.0];
            lowest(
                field,
                radius,
                grid.into_iter()
                    .flat_map(|a| grid.map(|b| sampled_at(r.center + u * a + w * b))),
            )
        }
    };
    match sampled {
        Err(()) => Verdict::Undecided,
        Ok(None) => Verdict::Clear,
        Ok(Some((d, _))) if d > radius => Verdict::Clear,
        Ok(Some((_, g))) => g
            .try_normalize()
            .map_or(Verdict::Undecided, Verdict::Touching),
    }
}

/// Hair against `body` through its distance field: writes into `contacts` (reusing its memory)
/// the segments whose volume the field finds within its radius of the body, each with the
/// field's outward normal (see the module documentation for the samples and their error).
/// `volumes` are in the body's own frame and indexed as the hierarchy's segments, as for
/// [`crate::query_body_volumes`]. Chunks of volumes run side by side; the result does not
/// depend on the thread count.
pub fn query_body_field(
    volumes: &[SweptSphere],
    body: &CollisionBody,
    contacts: &mut FieldContacts,
) {
    contacts.contacts.clear();
    contacts.exact_fallbacks = 0;
    if body.triangle_count() == 0 {
        return;
    }
    let bound = body.local_bounding_volume();
    let bound_padding = ball_padding(&bound);
    let field = body.distance_field();
    let triangles = body.local_triangles();
    let chunks = volumes.len().div_ceil(CHUNK);
    contacts.chunks.resize_with(chunks, Default::default);
    contacts.chunks[..chunks]
        .par_iter_mut()
        .enumerate()
        .for_each(|(chunk, (found, fallbacks))| {
            found.clear();
            *fallbacks = 0;
            let first = chunk * CHUNK;
            let end = (first + CHUNK).min(volumes.len());
            for (segment, volume) in (first..end).zip(&volumes[first..end]) {
                // The body's ball culls the far hair; the samples decide the rest (the field's
                // certified `clears` would cost more lookups than the samples themselves).
                let padding = aabb_padding(volume);
                if !aabb_touches_ball(&volume.aabb(padding), &bound, bound_padding) {
                    continue;
                }
                match verdict(field, volume) {
                    Verdict::Clear => {}
                    Verdict::Touching(normal) => found.push((segment as u32, normal)),
                    Verdict::Undecided => {
                        *fallbacks += 1;
                        let mut sum = Vec3::ZERO;
                        for_each_touched(volume, body, |t| sum += triangles[t as usize].normal);
                        if let Some(normal) = sum.try_normalize() {
                            found.push((segment as u32, normal));
                        }
                    }
                }
            }
        });
    for (found, fallbacks) in &contacts.chunks[..chunks] {
        contacts.contacts.extend_from_slice(found);
        contacts.exact_fallbacks += fallbacks;
    }
}
