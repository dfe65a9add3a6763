//! Tests of the clearances remembered between field queries (`field_memory.rs`): what a
//! certificate clears is clear by the exact distance to every triangle, and the contacts found
//! with a memory are the ones a fresh query finds.

use glam::{Quat, Vec3};
use hair_core::{Head, HeadParams};

use crate::body::CollisionBody;
use crate::field_contacts::{FieldContacts, query_body_field};
use crate::field_memory::{KEEP_MARGIN, Remembered};
use crate::geometry::Rectangle;
use crate::volume::{Lss, Pss, Rss, SweptSphere};

/// A small deterministic generator (64-bit LCG), uniform in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vector(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * 2.0 - Vec3::ONE
    }
}

fn head_body() -> CollisionBody {
    CollisionBody::from_mesh(&Head::procedural(&HeadParams::default()).unwrap().mesh).unwrap()
}

/// Volumes of all three kinds around the head: each starts 2–40 mm out along a vertex's normal
/// (a rectangle's half extents up to 1 × 1.5 cm, a segment's half length up to 1 cm).
fn volumes_around(body: &CollisionBody, count: usize, random: &mut Lcg) -> Vec<SweptSphere> {
    let triangles = body.local_triangles();
    (0..count)
        .map(|i| {
            let t = &triangles[(random.next() * triangles.len() as f32) as usize];
            let centre = t.vertices.iter().sum::<Vec3>() / 3.0;
            let at = centre + t.normal * (0.002 + 0.038 * random.next());
            let radius = 0.002 * random.next();
            let turn = Quat::from_scaled_axis(random.vector() * 3.0);
            match i % 3 {
                0 => SweptSphere::Point(Pss { center: at, radius }),
                1 => {
                    let half = turn * Vec3::X * 0.01 * random.next();
                    SweptSphere::Line(Lss {
                        start: at - half,
                        end: at + half,
                        radius,
                    })
                }
                _ => SweptSphere::Rectangle(Rss {
                    rectangle: Rectangle {
                        center: at,
                        axes: [turn * Vec3::X, turn * Vec3::Y],
                        half_extents: [0.01 * random.next(), 0.015 * random.next()],
                    },
                    radius,
                }),
            }
        })
        .collect()
}

/// `volume` moved by a random step of up to `step` \[m\] per end or corner, and turned a little.
fn moved(volume: &SweptSphere, step: f32, random: &mut Lcg) -> SweptSphere {
    let shift = random.vector() * step * 0.5;
    match *volume {
        SweptSphere::Point(v) => SweptSphere::Point(Pss {
            center: v.center + shift,
            ..v
        }),
        SweptSphere::Line(v) => SweptSphere::Line(Lss {
            start: v.start + shift + random.vector() * step * 0.3,
            end: v.end + shift + random.vector() * step * 0.3,
            ..v
        }),
        SweptSphere::Rectangle(v) => {
            let turn = Quat::from_scaled_axis(random.vector() * step * 10.0);
            let r = v.rectangle;
            SweptSphere::Rectangle(Rss {
                rectangle: Rectangle {
                    center: r.center + shift,
                    axes: [turn * r.axes[0], turn * r.axes[1]],
                    ..r
                },
                ..v
            })
        }
    }
}

/// The exact separation \[m\] of `volume` from the body: its core's distance to the nearest
/// triangle minus its radius (brute force over every triangle).
fn separation(body: &CollisionBody, volume: &SweptSphere) -> f32 {
    body.local_triangles()
        .iter()
        .map(|t| volume.triangle_distance(t))
        .fold(f32::MAX, f32::min)
}

#[test]
fn a_remembered_certificate_clears_only_volumes_clear_by_the_exact_distance() {
    // A certificate `clear` for the core at (c, u, w) and a core moved by
    // `|Δc| + |Δu| + |Δw|` leave every core point at least `clear − moved` from the surface
    // (1-Lipschitz distance), so a volume cleared must be separated by more than KEEP_MARGIN.
    let body = head_body();
    let field = body.distance_field();
    let mut random = Lcg(7);
    let mut volumes = volumes_around(&body, 36, &mut random);
    let mut memory = vec![Remembered::default(); volumes.len()];
    let (mut cleared, mut certified) = (0, 0);
    for _ in 0..30 {
        for (volume, remembered) in volumes.iter_mut().zip(&mut memory) {
            *volume = moved(volume, 0.0015, &mut random);
            if remembered.clears(volume) {
                cleared += 1;
                let gap = separation(&body, volume);
                assert!(
                    gap > KEEP_MARGIN,
                    "{volume:?} cleared {gap} m from the head"
                );
            } else if separation(&body, volume) > 0.0 {
                // Clear (as the samples would find it): certify where the bound allows.
                remembered.try_certify(field, volume);
                certified += usize::from(remembered.clears(volume));
            }
        }
    }
    // Most of these volumes lie far: most steps are cleared by memory, and some were certified.
    assert!(
        certified > 10 && cleared > 300,
        "{certified} certified, {cleared} cleared"
    );
}

#[test]
fn contacts_with_memory_are_the_contacts_of_a_fresh_query() {
    // The memory only clears volumes with KEEP_MARGIN to spare, where the samples say clear
    // too: frame for frame, the contacts are bit for bit those of a query that remembers
    // nothing, and the memory clears many of the volumes.
    let body = head_body();
    let mut random = Lcg(11);
    let mut volumes = volumes_around(&body, 240, &mut random);
    let mut remembering = FieldContacts::new();
    let (mut remembered, mut touching) = (0, 0);
    for _ in 0..40 {
        for volume in volumes.iter_mut() {
            *volume = moved(volume, 0.002, &mut random);
        }
        query_body_field(&volumes, &body, &mut remembering);
        let mut fresh = FieldContacts::new();
        query_body_field(&volumes, &body, &mut fresh);
        assert_eq!(remembering.contacts, fresh.contacts);
        assert_eq!(fresh.remembered, 0);
        remembered += remembering.remembered;
        touching += fresh.contacts.len();
    }
    assert!(
        remembered > 40 * 240 / 4 && touching > 0,
        "{remembered} remembered, {touching} touching"
    );
}
