//! Hair against a body through its distance field (issue 51): each segment volume touches the
//! body where the field's interpolated signed distance at its core comes within its radius, and
//! the contact's normal is the field's gradient there, as real-time hair systems collide hair
//! with a body's signed distance field (TressFX, Frostbite). No triangle is visited, so the cost
//! is a few field samples per segment whatever the volume's radius and the mesh's resolution.
//!
//! **The core's samples.** A point volume is sampled at its centre; a segment at its ends and
//! middle, then at the vertex of the parabola through those three distances (where it lies inside
//! the segment); a rectangle on a 3 × 3 grid (corners, edge midpoints, centre). A segment that
//! starts where the one before it ended (the next of a chain) takes that end's sample as its
//! start: about two samples a segment instead of three. On a convex smooth surface of curvature
//! radius `R` the distance along a core is close to a parabola of curvature `1/R`, so the
//! sampled minimum exceeds the true one by at most about `s²/(8R)` for samples `s` apart:
//! 0.16 mm for a 2 cm segment on an 8 cm head before the parabola's sample, far less after it.
//! The field's own interpolation error is of order `h²/R` (µm).
//!
//! **Where the field cannot decide** (a sample's cell without exact corners: the core farther
//! than [`EXACT_REACH`](crate::distance_field::EXACT_REACH) from the surface while the certified
//! bound does not clear it, a radius above about 8 mm, or an unsigned field on an open mesh), the
//! segment takes the exact path: the triangles its volume touches, and their mean normal, as
//! [`crate::query_body_volumes`] finds them. [`FieldContacts::exact_fallbacks`] counts those.
//!
//! **Far segments cost nothing** (a rigid body's field): a segment the samples found clear is
//! certified by the field's bound where it lies far enough, and stays clear without a sample
//! until it has moved that far (`field_memory.rs`); [`FieldContacts::remembered`] counts those.
//! The contacts found are the ones the samples would find.

use glam::Vec3;
use rayon::prelude::*;

use crate::body::CollisionBody;
use crate::bvh::aabb_padding;
use crate::distance_field::DistanceField;
use crate::field_memory::{BodyMemory, Remembered, memory_of};
use crate::moving_field::MovedField;
use crate::query::{CHUNK, aabb_touches_ball, ball_padding, for_each_touched};
use crate::volume::SweptSphere;

/// Contacts of hair segments with a body from its distance field: one unit normal per touching
/// segment.
#[derive(Debug, Clone, Default)]
pub struct FieldContacts {
    /// `(segment, normal)` of each segment that touches the body, ascending by segment: the
    /// normal is unit and outward, in the body's own frame.
    pub contacts: Vec<(u32, Vec3)>,
    /// Per contact of a deforming body, in the order of `contacts`: the surface's own velocity
    /// \[m/s\] (body frame) where the segment touches it, blended from its carrier triangle's
    /// vertices (the touched triangles' mean on the exact path). Empty for a rigid body.
    pub velocities: Vec<Vec3>,
    /// Segments of the last query that the field could not decide and the exact triangle tests
    /// did (see the module documentation).
    pub exact_fallbacks: usize,
    /// Segments of the last query that a certified clearance remembered from an earlier one
    /// cleared without a sample (a rigid body's field; see the module documentation).
    pub remembered: usize,
    /// Per chunk of volumes: what it found, side by side.
    chunks: Vec<ChunkContacts>,
    /// Per segment, the carrier triangle a moving field last found for it (`moving_field.rs`):
    /// where its next samples start. A stale one (the segments renumbered) only costs lookups.
    carriers: Vec<Option<u32>>,
    /// Per rigid body's field, the clearances certified per segment (`field_memory.rs`).
    memories: Vec<BodyMemory>,
    /// What a deforming body's query zips its volumes with instead (never read).
    spare: Vec<Remembered>,
}

/// How much farther from the surface than a volume's radius \[m\] its sample points are
/// searched for where a moving field's lookups find no carrier: beyond it a point only says
/// that it is far. A segment's core dips below its samples by at most `s²/(8R)` (0.16 mm for
/// 2 cm segments on an 8 cm head), well within it.
const SAMPLE_MARGIN: f32 = 0.002;

/// What one chunk of volumes found.
#[derive(Debug, Clone, Default)]
struct ChunkContacts {
    contacts: Vec<(u32, Vec3)>,
    velocities: Vec<Vec3>,
    fallbacks: usize,
    remembered: usize,
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
    /// Touching, with the outward unit normal (body frame) and, through a moving field, the
    /// carrier triangle and the weights of its vertices there.
    Touching(Vec3, Option<(u32, Vec3)>),
    /// The field cannot decide: take the exact path.
    Undecided,
}

/// One field sample: distance \[m\], gradient (a moving field's still in its rest frame:
/// [`Sampler::turned`]), and the carrier (triangle, weights) of a moving field.
type Sample = (f32, Vec3, Option<(u32, Vec3)>);

/// A field that contacts are read from: a rigid body's own, or a deforming body's moving one.
trait Sampler {
    /// The interpolated signed distance and its gradient at `p`, where the field is exact;
    /// `carrier` is a moving field's carrier to start from, and becomes this point's. `None`
    /// may also stand for a point farther than `reach` \[m\] from the surface.
    fn sample(&self, p: Vec3, carrier: &mut Option<u32>, reach: f32) -> Option<Sample>;
    /// A certified lower bound on the distance at `p`.
    fn bound(&self, p: Vec3) -> f32;
    /// How close to the surface every point samples exactly.
    fn exact_reach(&self) -> f32;
    /// A sample's gradient in the body's frame now (only the contact's own sample needs it).
    fn turned(&self, gradient: Vec3, carrier: Option<(u32, Vec3)>) -> Vec3;
    /// Whether a chain's segments carry the certified bound at a far end on to the segments
    /// after it ([`ChainEnd::far`]): worth it where a sample costs more than a bound.
    fn carries_far_bounds(&self) -> bool;
}

/// A chain segment's end, left for the next segment of the chain, which starts there.
#[derive(Clone, Copy)]
struct ChainEnd {
    /// The end \[m\] (body frame).
    at: Vec3,
    /// Its sample (`None` where the field is not exact there); `None` where it was not sampled
    /// (the segment was cleared by `far` alone).
    sample: Option<Option<Sample>>,
    /// A certified lower bound on the distance \[m\] from `at` to the surface (0 where none is
    /// known).
    far: f32,
}

impl Sampler for DistanceField {
    fn sample(&self, p: Vec3, _: &mut Option<u32>, _: f32) -> Option<Sample> {
        DistanceField::sample(self, p).map(|(d, g)| (d, g, None))
    }
    fn bound(&self, p: Vec3) -> f32 {
        DistanceField::bound(self, p).0
    }
    fn exact_reach(&self) -> f32 {
        DistanceField::exact_reach(self)
    }
    fn turned(&self, gradient: Vec3, _: Option<(u32, Vec3)>) -> Vec3 {
        gradient
    }
    fn carries_far_bounds(&self) -> bool {
        // A rigid field's sample is one brick lookup, cheaper than a bound's eight corners.
        false
    }
}

impl Sampler for MovedField<'_> {
    fn sample(&self, p: Vec3, carrier: &mut Option<u32>, reach: f32) -> Option<Sample> {
        MovedField::sample_unturned(self, p, carrier, reach)
            .map(|s| (s.distance, s.gradient, Some((s.triangle, s.weights))))
    }
    fn bound(&self, p: Vec3) -> f32 {
        MovedField::bound(self, p).0
    }
    fn exact_reach(&self) -> f32 {
        MovedField::exact_reach(self)
    }
    fn turned(&self, gradient: Vec3, carrier: Option<(u32, Vec3)>) -> Vec3 {
        // A degenerate carrier turns to zero: no normal, so the exact path decides.
        carrier
            .and_then(|(triangle, _)| self.turned(triangle, gradient))
            .unwrap_or(Vec3::ZERO)
    }
    fn carries_far_bounds(&self) -> bool {
        // A far sample costs carrier lookups and a bound; a carried bound costs nothing.
        true
    }
}

/// The lowest interpolated distance over `samples` (each point with its sample) and the
/// gradient there (`None` when no point is in an exact cell), or `Err(())` when a point outside
/// the exact cells may lie within `radius` \[m\] of the surface, so that the samples cannot
/// decide. A point outside the exact cells lies farther than the field's exact reach from the
/// surface (inside the grid; beyond it, the certified bound says how far): where that exceeds
/// the radius, it cannot make the volume touch, and is left out.
fn lowest(
    field: &impl Sampler,
    radius: f32,
    samples: impl IntoIterator<Item = (Vec3, Option<Sample>)>,
) -> Result<Option<Sample>, ()> {
    let mut best: Option<Sample> = None;
    for (p, sample) in samples {
        match sample {
            Some(sample) => {
                if best.is_none_or(|(b, _, _)| sample.0 < b) {
                    best = Some(sample);
                }
            }
            None if field.exact_reach() > radius || field.bound(p) > radius => {}
            None => return Err(()),
        }
    }
    Ok(best)
}

/// The field's verdict on `volume` (body frame); `carrier` is a moving field's carrier to start
/// from (this segment's last), and becomes the last one its samples found.
///
/// `shared` is the last segment's end ([`ChainEnd`]): a segment that starts where the last one
/// ended (the next segment of a chain) reads its start's sample from it instead of sampling it
/// again, and leaves its own end there. Where that start was far (its certified bound above the
/// radius), the segment first tries the bound at its own end: the distance to a surface changes
/// by at most the distance moved, so the two bounds clear the whole segment without a sample
/// where `(far_start + far_end − length) / 2` exceeds the radius.
fn verdict(
    field: &impl Sampler,
    volume: &SweptSphere,
    carrier_out: &mut Option<u32>,
    shared: &mut Option<ChainEnd>,
) -> Verdict {
    let radius = volume.radius();
    // A sample point farther from the surface than the radius cannot make the volume touch;
    // a little more keeps the parabola's three samples where the core dips between them.
    let reach = radius + SAMPLE_MARGIN;
    let carrier = std::cell::Cell::new(*carrier_out);
    let sampled_at = |p: Vec3| {
        let mut hint = carrier.get();
        let sample = field.sample(p, &mut hint, reach);
        carrier.set(hint);
        (p, sample)
    };
    let last_end = shared.take();
    let sampled = match volume {
        SweptSphere::Point(v) => lowest(field, radius, [sampled_at(v.center)]),
        SweptSphere::Line(v) => {
            let axis = v.end - v.start;
            let last_end = last_end.filter(|end| end.at == v.start);
            // The end's bound, where the start's is known to exceed the radius: a point `t`
            // along the segment (length `L`) lies at least `max(far_start − t, far_end −
            // (L − t)) ≥ (far_start + far_end − L) / 2` from the surface.
            let far_end = last_end.filter(|end| end.far > radius).map(|end| {
                let length = axis.length();
                let far_end = field.bound(v.end).max(end.far - length);
                (far_end, (end.far + far_end - length) * 0.5)
            });
            if let Some((far, least)) = far_end
                && least > radius
            {
                *shared = Some(ChainEnd {
                    at: v.end,
                    sample: None,
                    far,
                });
                return Verdict::Clear;
            }
            let start = match last_end {
                Some(ChainEnd {
                    at,
                    sample: Some(sample),
                    ..
                }) => {
                    // Its carrier is where the middle's search starts.
                    if let Some((_, _, Some((triangle, _)))) = sample {
                        carrier.set(Some(triangle));
                    }
                    (at, sample)
                }
                _ => sampled_at(v.start),
            };
            let samples = [start, sampled_at(v.start + axis * 0.5), sampled_at(v.end)];
            let far = match (samples[2].1, far_end) {
                (None, Some((far, _))) => far,
                (None, None) if field.carries_far_bounds() => field.bound(v.end),
                _ => 0.0,
            };
            *shared = Some(ChainEnd {
                at: v.end,
                sample: Some(samples[2].1),
                far,
            });
            lowest(field, radius, samples).map(|best| {
                let (d, _, _) = best?;
                // The parabola through the three distances (all exact): its vertex, where inside.
                if let [
                    (_, Some((d0, _, _))),
                    (_, Some((d1, _, _))),
                    (_, Some((d2, _, _))),
                ] = samples
                {
                    let a = 2.0 * (d0 - 2.0 * d1 + d2);
                    let t = -(d2 - d0 - a) / (2.0 * a);
                    if a > 0.0
                        && t > 0.0
                        && t < 1.0
                        && let Some(vertex) = sampled_at(v.start + axis * t).1
                        && vertex.0 < d
                    {
                        return Some(vertex);
                    }
                }
                best
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
    *carrier_out = carrier.get();
    match sampled {
        Err(()) => Verdict::Undecided,
        Ok(None) => Verdict::Clear,
        Ok(Some((d, _, _))) if d > radius => Verdict::Clear,
        Ok(Some((_, g, carrier))) => field
            .turned(g, carrier)
            .try_normalize()
            .map_or(Verdict::Undecided, |n| Verdict::Touching(n, carrier)),
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
    contacts.velocities.clear();
    contacts.exact_fallbacks = 0;
    contacts.remembered = 0;
    if body.triangle_count() == 0 {
        return;
    }
    let bound = body.local_bounding_volume();
    let bound_padding = ball_padding(&bound);
    // A deforming body reads its rest field moved with it, or (reading none) takes the exact
    // path everywhere: a field of one instant would be built again at the next.
    let deforming = body.is_deforming();
    let moved = body.moved_field();
    let rigid = (!deforming).then(|| body.distance_field());
    let triangles = body.local_triangles();
    let chunks = volumes.len().div_ceil(CHUNK);
    contacts.chunks.resize_with(chunks, Default::default);
    // Each segment's last carrier (a moving field's), where the next frame's samples start.
    contacts.carriers.resize(volumes.len(), None);
    // A rigid body's remembered clearances (none are kept for a deforming one, whose surface
    // moves under them).
    let memory = match rigid {
        Some(_) => memory_of(&mut contacts.memories, body, volumes.len()),
        None => &mut contacts.spare,
    };
    memory.resize(volumes.len(), Remembered::default());
    contacts.chunks[..chunks]
        .par_iter_mut()
        .zip(contacts.carriers.par_chunks_mut(CHUNK))
        .zip(memory.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(chunk, ((found, carriers), memory))| {
            found.contacts.clear();
            found.velocities.clear();
            found.fallbacks = 0;
            found.remembered = 0;
            let first = chunk * CHUNK;
            let end = (first + CHUNK).min(volumes.len());
            // The last segment's end and its sample, which the next segment of a chain starts
            // from.
            let mut shared = None;
            for (segment, volume) in (first..end).zip(&volumes[first..end]) {
                // The body's ball culls the far hair; the samples decide the rest (the field's
                // certified `clears` would cost more lookups than the samples themselves).
                let padding = aabb_padding(volume);
                if !aabb_touches_ball(&volume.aabb(padding), &bound, bound_padding) {
                    continue;
                }
                let carrier = &mut carriers[segment - first];
                let said = match (rigid, &moved) {
                    (Some(field), _) => {
                        let remembered = &mut memory[segment - first];
                        if remembered.clears(volume) {
                            found.remembered += 1;
                            shared = None;
                            continue;
                        }
                        let said = verdict(field, volume, carrier, &mut shared);
                        if matches!(said, Verdict::Clear) {
                            remembered.try_certify(field, volume);
                        }
                        said
                    }
                    (None, Some(moved)) => verdict(moved, volume, carrier, &mut shared),
                    (None, None) => Verdict::Undecided,
                };
                match said {
                    Verdict::Clear => {}
                    Verdict::Touching(normal, carrier) => {
                        found.contacts.push((segment as u32, normal));
                        if deforming {
                            let velocity = carrier.map_or(Vec3::ZERO, |(t, weights)| {
                                body.local_deformation_velocity_at(t, weights)
                            });
                            found.velocities.push(velocity);
                        }
                    }
                    Verdict::Undecided => {
                        found.fallbacks += 1;
                        let (mut sum, mut count) = (Vec3::ZERO, 0);
                        let mut velocity = Vec3::ZERO;
                        for_each_touched(volume, body, |t| {
                            sum += triangles[t as usize].normal;
                            count += 1;
                            if deforming {
                                velocity +=
                                    body.local_deformation_velocity_at(t, Vec3::splat(1.0 / 3.0));
                            }
                        });
                        if let Some(normal) = sum.try_normalize() {
                            found.contacts.push((segment as u32, normal));
                            if deforming {
                                found.velocities.push(velocity / count as f32);
                            }
                        }
                    }
                }
            }
        });
    for found in &contacts.chunks[..chunks] {
        contacts.contacts.extend_from_slice(&found.contacts);
        contacts.velocities.extend_from_slice(&found.velocities);
        contacts.exact_fallbacks += found.fallbacks;
        contacts.remembered += found.remembered;
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use hair_core::{Head, HeadParams};

    use super::{ChainEnd, Verdict, verdict};
    use crate::body::CollisionBody;
    use crate::rest_field::RestField;
    use crate::volume::{Lss, SweptSphere};

    /// Chains on a squashed, stretched and bulged head read through its moving field: each
    /// leaves the surface along a tilted normal for eight 12 mm segments, then comes back. The
    /// segments that the carried bounds clear without a sample (the end left unsampled) are
    /// clear by the exact distance from their core to every triangle (brute force), and a
    /// segment asked alone says so too; some are cleared, and the returning chains touch.
    #[test]
    fn segments_cleared_by_carried_bounds_are_clear_of_every_triangle() {
        let mesh = Head::procedural(&HeadParams::default()).unwrap().mesh;
        let field = RestField::of(&CollisionBody::from_mesh(&mesh).unwrap());
        let moved: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| {
                Vec3::new(p.x * 0.96, p.y * 1.08, p.z * 0.97) + Vec3::Z * 0.01 * (p.y * 20.0).sin()
            })
            .collect();
        let zero = vec![Vec3::ZERO; moved.len()];
        let body = CollisionBody::from_moving_mesh(&mesh, zero.clone())
            .unwrap()
            .reading_rest_field(&field)
            .unwrap()
            .deformed(&moved, zero)
            .unwrap();
        let moving = body.moved_field().unwrap();
        let triangles = body.local_triangles();
        let radius = 5.0e-4;
        let (mut cleared, mut touching) = (0, 0);
        for triangle in triangles.iter().step_by(149) {
            let centre = triangle.vertices.iter().sum::<Vec3>() / 3.0;
            let normal = triangle.normal;
            let across = normal.any_orthonormal_vector() * 0.3;
            let mut start = centre + normal * 1.0e-3;
            let (mut shared, mut carrier) = (None, None);
            for segment in 0..16 {
                let out = if segment < 8 { normal } else { -normal };
                let end = start + (out + across).normalize() * 0.012;
                let volume = SweptSphere::Line(Lss { start, end, radius });
                let said = verdict(&moving, &volume, &mut carrier, &mut shared);
                if matches!(shared, Some(ChainEnd { sample: None, .. })) {
                    cleared += 1;
                    assert!(matches!(said, Verdict::Clear));
                    let core = SweptSphere::Line(Lss {
                        start,
                        end,
                        radius: 0.0,
                    });
                    let nearest = triangles
                        .iter()
                        .map(|t| core.triangle_distance(t))
                        .fold(f32::MAX, f32::min);
                    assert!(
                        nearest > radius,
                        "{start} → {end}: {nearest} m from the head"
                    );
                    let alone = verdict(&moving, &volume, &mut None, &mut None);
                    assert!(matches!(alone, Verdict::Clear), "{start} → {end} alone");
                } else if matches!(said, Verdict::Touching(..)) {
                    touching += 1;
                }
                start = end;
            }
        }
        assert!(
            cleared > 500 && touching > 0,
            "{cleared} cleared, {touching} touching"
        );
    }
}
