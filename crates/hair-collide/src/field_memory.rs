//! Certified clearances remembered between queries (issue 51): a segment volume that a rigid
//! body's distance field certified far from the surface stays clear, without a sample, until it
//! has moved that far.
//!
//! **The certificate.** Every volume's core is `c + a·u + b·w` for `|a|, |b| ≤ 1` (a point:
//! `u = w = 0`; a segment: `u` half its axis, `w = 0`; a rectangle: its half-extent axes), so
//! every core point lies within `reach = max(|u + w|, |u − w|)` of `c` (the farthest point of a
//! parallelogram from its centre is a corner). The field's certified lower bound `B` at `c`
//! (eight exact or bounding corners, `DistanceField::bound`) then clears every core point by
//! `B − reach`. It is remembered with `(c, u, w)` where it exceeds the radius by
//! [`KEEP_MARGIN`].
//!
//! **Its use.** A later core `c' + a·u' + b·w'` lies within `|c' − c| + |u' − u| + |w' − w|`
//! of the remembered one, point for point, and the distance to the surface is 1-Lipschitz, so
//! the volume is clear while `clear − moved > radius + `[`KEEP_MARGIN`]. The margin keeps the
//! answer the one the samples would give (they read the field within micrometres of the true
//! distance), so the contacts do not depend on what was remembered: a resumed run, a fresh
//! solver and any thread count find the same ones.
//!
//! **Where a certificate fails** (a volume between the field's exact reach and its own reach
//! plus the radius), trying again costs a bound every query for nothing: a failed try waits
//! [`RETRY_AFTER`] queries, and the centre's sample, where the field has one, rules the bound
//! out first where it cannot reach.

use std::sync::{Arc, Weak};

use glam::Vec3;

use crate::body::{BodyShape, CollisionBody};
use crate::distance_field::DistanceField;
use crate::volume::SweptSphere;

/// Clearance \[m\] beyond the radius that a remembered certificate keeps: a certificate is only
/// kept, and only used, with this much to spare.
pub(crate) const KEEP_MARGIN: f32 = 1.0e-3;

/// Queries a segment waits after a certificate it could not get before it tries again.
pub(crate) const RETRY_AFTER: u8 = 8;

/// What one segment remembers.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Remembered {
    /// The core's centre and axes (see the module documentation) when certified \[m\].
    core: [Vec3; 3],
    /// Certified distance \[m\] from every point of that core to the surface; 0 for none.
    clear: f32,
    /// Queries to wait before the next try.
    wait: u8,
}

/// The remembered certificates of one body's field, per segment.
#[derive(Debug, Clone, Default)]
pub(crate) struct BodyMemory {
    /// The body's shape (whose field it is); a weak reference keeps its address from being
    /// reused by another shape while remembered.
    shape: Weak<BodyShape>,
    /// Per segment, in the volumes' order.
    pub(crate) segments: Vec<Remembered>,
}

/// Memories of at most this many bodies are kept (the oldest is forgotten).
const BODIES: usize = 4;

/// The memory of `body`'s field among `memories` (made, or the oldest forgotten, when missing),
/// sized for `segments` volumes.
pub(crate) fn memory_of<'a>(
    memories: &'a mut Vec<BodyMemory>,
    body: &CollisionBody,
    segments: usize,
) -> &'a mut Vec<Remembered> {
    let found = memories
        .iter()
        .position(|m| std::ptr::eq(m.shape.as_ptr(), Arc::as_ptr(&body.shape)));
    let index = found.unwrap_or_else(|| {
        if memories.len() == BODIES {
            memories.remove(0);
        }
        memories.push(BodyMemory {
            shape: Arc::downgrade(&body.shape),
            segments: Vec::new(),
        });
        memories.len() - 1
    });
    let memory = &mut memories[index].segments;
    memory.resize(segments, Remembered::default());
    memory
}

/// A volume's core as a centre and two half axes \[m\] (see the module documentation).
fn core(volume: &SweptSphere) -> [Vec3; 3] {
    match volume {
        SweptSphere::Point(v) => [v.center, Vec3::ZERO, Vec3::ZERO],
        SweptSphere::Line(v) => [(v.start + v.end) * 0.5, (v.end - v.start) * 0.5, Vec3::ZERO],
        SweptSphere::Rectangle(v) => {
            let r = &v.rectangle;
            [
                r.center,
                r.axes[0] * r.half_extents[0],
                r.axes[1] * r.half_extents[1],
            ]
        }
    }
}

impl Remembered {
    /// Whether the remembered certificate still clears `volume` by its radius plus
    /// [`KEEP_MARGIN`]; a certificate that no longer does is forgotten.
    pub(crate) fn clears(&mut self, volume: &SweptSphere) -> bool {
        if self.clear <= 0.0 {
            return false;
        }
        let [c, u, w] = core(volume);
        let moved = c.distance(self.core[0]) + u.distance(self.core[1]) + w.distance(self.core[2]);
        let clear = self.clear - moved > volume.radius() + KEEP_MARGIN;
        if !clear {
            self.clear = 0.0;
        }
        clear
    }

    /// After the samples found `volume` clear: certifies it from `field`'s bound at its core's
    /// centre where that clears it by its radius plus [`KEEP_MARGIN`], else waits
    /// [`RETRY_AFTER`] queries before trying again.
    pub(crate) fn try_certify(&mut self, field: &DistanceField, volume: &SweptSphere) {
        if self.wait > 0 {
            self.wait -= 1;
            return;
        }
        let [c, u, w] = core(volume);
        let reach = (u + w).length().max((u - w).length());
        let needed = reach + volume.radius() + KEEP_MARGIN;
        // The centre's sample (one brick, where the bound reads eight corners of the dense
        // grid) says when the bound cannot reach: the sample lies within micrometres of the
        // distance, which the bound never exceeds.
        let near = field
            .sample(c)
            .is_some_and(|(distance, _)| distance < needed);
        match (!near)
            .then(|| field.outside_clearance(c, needed))
            .flatten()
        {
            Some(bound) => {
                *self = Remembered {
                    core: [c, u, w],
                    clear: bound - reach,
                    wait: 0,
                }
            }
            None => self.wait = RETRY_AFTER,
        }
    }
}
