//! Distances between swept-sphere volumes, and from volumes to triangles, against closed forms,
//! dense sampling with a stated error bound, and parry3d's own queries.

mod support;

use glam::Vec3;
use hair_collide::{Lss, Pss, Rectangle, Rss, SweptSphere, Triangle};
use parry3d::math::Pose;
use parry3d::shape::SharedShape;
use support::{Rng, point_rectangle_distance_f64, point_segment_distance_f64};

/// f32 rounding at the 1 m scale of these configurations: a few hundred ulps of 1.
const ROUNDING: f64 = 2e-5;

fn random_ball(rng: &mut Rng) -> Pss {
    Pss {
        center: rng.vec3(1.0),
        radius: rng.range(0.0, 0.2),
    }
}

fn random_capsule(rng: &mut Rng) -> Lss {
    let start = rng.vec3(1.0);
    // Some degenerate (zero-length) segments too.
    let end = if rng.below(10) == 0 {
        start
    } else {
        start + rng.vec3(0.8)
    };
    Lss {
        start,
        end,
        radius: rng.range(0.0, 0.2),
    }
}

fn random_rectangle(rng: &mut Rng) -> Rectangle {
    let rotation = rng.rotation();
    let mut half_extents = [rng.range(0.0, 0.6), rng.range(0.0, 0.6)];
    match rng.below(8) {
        0 => half_extents[0] = 0.0,
        1 => half_extents = [0.0, 0.0],
        _ => {}
    }
    Rectangle {
        center: rng.vec3(1.0),
        axes: [rotation * Vec3::X, rotation * Vec3::Y],
        half_extents,
    }
}

fn random_rss(rng: &mut Rng) -> Rss {
    Rss::new(random_rectangle(rng), rng.range(0.0, 0.2))
}

/// Points of a rectangle on an `n × n` grid; returns them and the grid cell's half diagonal [m]
/// (every rectangle point is within it of a grid point).
fn rectangle_samples(rectangle: &Rectangle, n: usize) -> (Vec<Vec3>, f64) {
    let [hu, hv] = rectangle.half_extents;
    let mut points = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let a = -hu + 2.0 * hu * i as f32 / (n - 1) as f32;
            let b = -hv + 2.0 * hv * j as f32 / (n - 1) as f32;
            points.push(rectangle.center + rectangle.axes[0] * a + rectangle.axes[1] * b);
        }
    }
    let du = 2.0 * hu as f64 / (n - 1) as f64;
    let dv = 2.0 * hv as f64 / (n - 1) as f64;
    (points, 0.5 * (du * du + dv * dv).sqrt())
}

/// Points of a segment, and half the sample spacing [m].
fn segment_samples(a: Vec3, b: Vec3, n: usize) -> (Vec<Vec3>, f64) {
    let points = (0..n)
        .map(|i| a.lerp(b, i as f32 / (n - 1) as f32))
        .collect();
    (points, 0.5 * a.distance(b) as f64 / (n - 1) as f64)
}

/// Points of a triangle on a barycentric grid, and a bound on the distance from any triangle
/// point to the nearest sample (half the longest edge over `n`, times 2 for the grid's shape).
fn triangle_samples(t: &Triangle, n: usize) -> (Vec<Vec3>, f64) {
    let [a, b, c] = t.vertices;
    let mut points = Vec::new();
    for i in 0..=n {
        for j in 0..=n - i {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            points.push(a + (b - a) * u + (c - a) * v);
        }
    }
    let longest = a.distance(b).max(b.distance(c)).max(c.distance(a)) as f64;
    (points, longest / n as f64)
}

/// Asserts `computed` is within `[reference − sampling − ROUNDING, reference + ROUNDING]`, where
/// `reference` is a minimum over samples (an upper bound on the true minimum, at most
/// `sampling` above it).
fn assert_sampled(computed: f32, reference: f64, sampling: f64, what: &str) {
    let computed = computed as f64;
    assert!(
        computed <= reference + ROUNDING && computed >= reference - sampling - ROUNDING,
        "{what}: computed {computed}, sampled reference {reference} (sampling bound {sampling})"
    );
}

/// parry3d's distance between the *rounded* shapes runs GJK with margins, which stops early:
/// on these cases it was off by up to 4.5e-3 m (e.g. two capsules whose core segments parry
/// itself puts 0.43053 m apart, radii 0.0579 + 0.1092: parry says 0.2670, the exact value is
/// 0.2634). So the tight cross-check is on the core skeletons (parry `Ball` of radius 0,
/// `Segment`, flat `Cuboid`), where parry is accurate, and the rounded shapes are compared
/// loosely.
const PARRY_CORE_TOLERANCE: f32 = 1e-4;
/// Loose tolerance [m] for parry's rounded-shape GJK distance (see above).
const PARRY_TOLERANCE: f32 = 1e-2;

/// The core skeleton of a volume as a parry shape and pose.
fn parry_core(volume: &SweptSphere) -> (Pose, SharedShape) {
    match volume {
        SweptSphere::Point(v) => (Pose::from_translation(v.center), SharedShape::ball(0.0)),
        SweptSphere::Line(v) => (Pose::IDENTITY, SharedShape::segment(v.start, v.end)),
        SweptSphere::Rectangle(v) => {
            let (pose, _) = volume.to_parry();
            let [hu, hv] = v.rectangle.half_extents;
            (pose, SharedShape::cuboid(hu, hv, 0.0))
        }
    }
}

/// Asserts agreement with parry3d: core distance within [`PARRY_CORE_TOLERANCE`], rounded
/// shapes' distance and intersection within [`PARRY_TOLERANCE`].
fn assert_matches_parry(first: &SweptSphere, second: &SweptSphere) {
    let (core_pose1, core1) = parry_core(first);
    let (core_pose2, core2) = parry_core(second);
    let parry_core =
        parry3d::query::distance(&core_pose1, core1.as_ref(), &core_pose2, core2.as_ref())
            .expect("parry supports these shapes")
            .distance;
    let ours_core = first.core_distance(second);
    assert!(
        (ours_core - parry_core).abs() <= PARRY_CORE_TOLERANCE,
        "{first:?} vs {second:?}: core distance ours {ours_core}, parry {parry_core}"
    );
    let (pose1, shape1) = first.to_parry();
    let (pose2, shape2) = second.to_parry();
    let parry = parry3d::query::distance(&pose1, shape1.as_ref(), &pose2, shape2.as_ref())
        .expect("parry supports these shapes")
        .distance;
    let ours = first.distance(second).max(0.0);
    assert!(
        (ours - parry).abs() <= PARRY_TOLERANCE,
        "{first:?} vs {second:?}: ours {ours}, parry {parry}"
    );
    let parry_intersects =
        parry3d::query::intersection_test(&pose1, shape1.as_ref(), &pose2, shape2.as_ref())
            .expect("parry supports these shapes")
            .intersecting;
    if first.distance(second).abs() > PARRY_TOLERANCE {
        assert_eq!(
            first.intersects(second),
            parry_intersects,
            "{first:?} vs {second:?}"
        );
    }
}

#[test]
fn ball_ball_is_center_distance_minus_radii() {
    let mut rng = Rng::new(1);
    for _ in 0..2000 {
        let (a, b) = (random_ball(&mut rng), random_ball(&mut rng));
        // d = |c1 − c2| − r1 − r2.
        let expected = (a.center.as_dvec3() - b.center.as_dvec3()).length()
            - a.radius as f64
            - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert!((sa.distance(&sb) as f64 - expected).abs() <= ROUNDING);
        assert_eq!(sa.intersects(&sb), sa.distance(&sb) <= 0.0);
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn ball_capsule_is_point_segment_distance_minus_radii() {
    let mut rng = Rng::new(2);
    for _ in 0..2000 {
        let (a, b) = (random_ball(&mut rng), random_capsule(&mut rng));
        let expected = point_segment_distance_f64(a.center, b.start, b.end)
            - a.radius as f64
            - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert!((sa.distance(&sb) as f64 - expected).abs() <= ROUNDING);
        assert_eq!(sa.distance(&sb), sb.distance(&sa));
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn capsule_capsule_against_dense_sampling() {
    let mut rng = Rng::new(3);
    for _ in 0..300 {
        let (a, b) = (random_capsule(&mut rng), random_capsule(&mut rng));
        // min over samples s of the first segment of the exact point–segment distance to the
        // second: at most half a sample spacing above the true segment–segment distance.
        let (samples, sampling) = segment_samples(a.start, a.end, 4001);
        let core = samples
            .iter()
            .map(|&p| point_segment_distance_f64(p, b.start, b.end))
            .fold(f64::INFINITY, f64::min);
        let reference = core - a.radius as f64 - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert_sampled(sa.distance(&sb), reference, sampling, "capsule-capsule");
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn ball_rss_is_point_rectangle_distance_minus_radii() {
    let mut rng = Rng::new(4);
    for _ in 0..2000 {
        let (a, b) = (random_ball(&mut rng), random_rss(&mut rng));
        let expected = point_rectangle_distance_f64(a.center, &b.rectangle)
            - a.radius as f64
            - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert!(
            (sa.distance(&sb) as f64 - expected).abs() <= ROUNDING,
            "{a:?} {b:?}"
        );
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn capsule_rss_against_sampled_rectangle() {
    let mut rng = Rng::new(5);
    for _ in 0..200 {
        let (a, b) = (random_capsule(&mut rng), random_rss(&mut rng));
        let (samples, sampling) = rectangle_samples(&b.rectangle, 201);
        let core = samples
            .iter()
            .map(|&p| point_segment_distance_f64(p, a.start, a.end))
            .fold(f64::INFINITY, f64::min);
        let reference = core - a.radius as f64 - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert_sampled(sa.distance(&sb), reference, sampling, "capsule-rss");
        assert_eq!(sa.distance(&sb), sb.distance(&sa));
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn rss_rss_against_sampled_rectangle() {
    let mut rng = Rng::new(6);
    for _ in 0..200 {
        let (a, b) = (random_rss(&mut rng), random_rss(&mut rng));
        let (samples, sampling) = rectangle_samples(&a.rectangle, 201);
        let core = samples
            .iter()
            .map(|&p| point_rectangle_distance_f64(p, &b.rectangle))
            .fold(f64::INFINITY, f64::min);
        let reference = core - a.radius as f64 - b.radius as f64;
        let (sa, sb) = (SweptSphere::from(a), SweptSphere::from(b));
        assert_sampled(sa.distance(&sb), reference, sampling, "rss-rss");
        assert_matches_parry(&sa, &sb);
    }
}

#[test]
fn crossing_cores_have_zero_core_distance() {
    // A segment through the middle of a unit square, and two squares crossing at right angles.
    let square = Rectangle {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Y],
        half_extents: [0.5, 0.5],
    };
    let upright = Rectangle {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Z],
        half_extents: [0.5, 0.5],
    };
    let segment = SweptSphere::from(Lss {
        start: Vec3::new(0.1, 0.2, -1.0),
        end: Vec3::new(0.1, 0.2, 1.0),
        radius: 0.0,
    });
    let flat = SweptSphere::from(Rss::new(square, 0.0));
    assert_eq!(segment.core_distance(&flat), 0.0);
    assert!(segment.intersects(&flat));
    assert_eq!(
        flat.core_distance(&SweptSphere::from(Rss::new(upright, 0.0))),
        0.0
    );
    // Coplanar, one inside the other.
    let small = Rectangle {
        half_extents: [0.1, 0.1],
        ..square
    };
    assert_eq!(
        flat.core_distance(&SweptSphere::from(Rss::new(small, 0.0))),
        0.0
    );
    // Parallel squares 0.3 apart: distance 0.3 − radii.
    let above = Rectangle {
        center: Vec3::new(0.2, 0.0, 0.3),
        ..square
    };
    let d = SweptSphere::from(Rss::new(square, 0.1))
        .distance(&SweptSphere::from(Rss::new(above, 0.05)));
    assert!((d - 0.15).abs() < 1e-6);
}

#[test]
fn volume_triangle_distances_against_sampled_triangle() {
    let mut rng = Rng::new(7);
    for case in 0..600 {
        let a = rng.vec3(1.0);
        let (b, c) = if case % 20 == 0 {
            (a + rng.vec3(0.5), a)
        } else {
            (a + rng.vec3(0.8), a + rng.vec3(0.8))
        };
        let triangle = Triangle::new(a, b, c);
        let (samples, sampling) = triangle_samples(&triangle, 300);
        let volume: SweptSphere = match case % 3 {
            0 => random_ball(&mut rng).into(),
            1 => random_capsule(&mut rng).into(),
            _ => random_rss(&mut rng).into(),
        };
        let core = |p: Vec3| match &volume {
            SweptSphere::Point(v) => (p - v.center).as_dvec3().length(),
            SweptSphere::Line(v) => point_segment_distance_f64(p, v.start, v.end),
            SweptSphere::Rectangle(v) => point_rectangle_distance_f64(p, &v.rectangle),
        };
        let sampled = samples
            .iter()
            .map(|&p| core(p))
            .fold(f64::INFINITY, f64::min)
            - volume.radius() as f64;
        // Sampling the triangle alone misses the cases where the volume's core pierces it; the
        // reference is still an upper bound, and within `sampling` of the truth.
        assert_sampled(
            volume.triangle_distance(&triangle),
            sampled,
            sampling,
            "volume-triangle",
        );
        assert_eq!(
            volume.intersects_triangle(&triangle),
            volume.triangle_distance(&triangle) <= 0.0
        );
        // And parry agrees on the core (the triangle as a parry shape, when not degenerate).
        if triangle.normal != Vec3::ZERO {
            let (pose, shape) = parry_core(&volume);
            let parry_triangle = parry3d::shape::Triangle::new(a, b, c);
            let parry =
                parry3d::query::distance(&pose, shape.as_ref(), &Pose::IDENTITY, &parry_triangle)
                    .expect("supported")
                    .distance;
            let ours = (volume.triangle_distance(&triangle) + volume.radius()).max(0.0);
            assert!(
                (ours - parry).abs() <= PARRY_CORE_TOLERANCE,
                "{volume:?} vs {triangle:?}: core distance ours {ours}, parry {parry}"
            );
        }
    }
}

/// The leaf test's quick rejects (separating slabs along the triangle's normal, the segment's
/// axis, the triangle's edge normals within its plane and the axes across the segment and each
/// edge) never reject a pair that touches: volumes around small scalp-sized triangles, each
/// given a radius just above its core's exact distance to the triangle (must touch) and just
/// below it (must not). The core distance is `triangle_distance + radius`; 0.1 % either side
/// is far beyond the f32 rounding of these millimetre configurations (`ROUNDING`-scaled).
#[test]
fn quick_rejects_keep_every_touching_pair_near_the_boundary() {
    let mut rng = Rng::new(11);
    let mut touching = 0;
    for case in 0..4000 {
        // A 5 mm triangle 10 cm from the origin (a scalp triangle), hair within a centimetre.
        let at = Vec3::new(0.0, 0.1, 0.0) + rng.vec3(0.01);
        let a = at + rng.vec3(0.005);
        let triangle = Triangle::new(a, a + rng.vec3(0.005), a + rng.vec3(0.005));
        let near = |rng: &mut Rng| at + rng.vec3(0.01);
        let core = |radius: f32, rng: &mut Rng| -> SweptSphere {
            match case % 3 {
                0 => Pss {
                    center: near(rng),
                    radius,
                }
                .into(),
                1 => {
                    let start = near(rng);
                    Lss {
                        start,
                        end: start + rng.vec3(0.01),
                        radius,
                    }
                    .into()
                }
                _ => {
                    let mut r = random_rectangle(rng);
                    r.center = near(rng);
                    r.half_extents = r.half_extents.map(|e| e * 0.01);
                    Rss::new(r, radius).into()
                }
            }
        };
        let bare = core(0.0, &mut rng);
        let distance = bare.triangle_distance(&triangle);
        if distance < 1e-4 {
            continue; // the core touches or nearly: no radius below it to test.
        }
        for (factor, touches) in [(1.001, true), (0.999, false)] {
            let radius = distance * factor;
            let volume: SweptSphere = match bare {
                SweptSphere::Point(v) => Pss { radius, ..v }.into(),
                SweptSphere::Line(v) => Lss { radius, ..v }.into(),
                SweptSphere::Rectangle(v) => Rss::new(v.rectangle, radius).into(),
            };
            assert_eq!(
                volume.intersects_triangle(&triangle),
                touches,
                "case {case}: {volume:?} vs {triangle:?}, core distance {distance}"
            );
        }
        touching += 1;
    }
    assert!(touching > 2000, "{touching} cases tested");
}
