//! Every constructor encloses its points: checked with independent f64 distances (not the
//! crate's kernels), so the fitted radius must cover the exact real-number distance.

mod support;

use glam::Vec3;
use hair_collide::fit::{
    cluster_segment, enclosing_ball, head_volume, patch_segment, strand_group_segment,
};
use hair_collide::{Pss, SweptSphere};
use support::{Rng, point_rectangle_distance_f64, point_segment_distance_f64, uv_sphere};

/// The 4 control points of a circular cross-section of `radius` around `node`, in a plane with
/// normal `normal` (§3.4), rotated by `twist` [rad].
fn cross_section(node: Vec3, normal: Vec3, radius: f32, twist: f32) -> [Vec3; 4] {
    let a = normal.any_orthonormal_vector();
    let b = normal.cross(a);
    std::array::from_fn(|k| {
        let angle = twist + std::f32::consts::FRAC_PI_2 * k as f32;
        node + radius * (a * angle.cos() + b * angle.sin())
    })
}

#[test]
fn strand_group_lss_is_the_segment_with_its_thickness() {
    let lss = strand_group_segment(Vec3::ZERO, Vec3::Y, 0.002);
    assert_eq!(
        (lss.start, lss.end, lss.radius),
        (Vec3::ZERO, Vec3::Y, 0.002)
    );
    // A lone strand: radius 0, the volume is the segment; its own nodes are on it.
    let lone = SweptSphere::from(strand_group_segment(Vec3::ZERO, Vec3::Y, 0.0));
    assert!(lone.intersects(&SweptSphere::from(Pss {
        center: Vec3::Y * 0.5,
        radius: 0.0
    })));
}

#[test]
fn cluster_lss_encloses_its_eight_control_points() {
    let mut rng = Rng::new(11);
    for case in 0..2000 {
        let top = rng.vec3(0.3);
        let bottom = top + rng.direction() * rng.range(0.0, 0.05);
        let (r_top, r_bottom) = (rng.range(0.0, 0.02), rng.range(0.0, 0.02));
        // Cross-sections tilted at random (curly hair rotates them), or arbitrary points.
        let points: [Vec3; 8] = if case % 4 == 0 {
            std::array::from_fn(|_| top + rng.vec3(0.05))
        } else {
            let upper = cross_section(top, rng.direction(), r_top, rng.range(0.0, 6.3));
            let lower = cross_section(bottom, rng.direction(), r_bottom, rng.range(0.0, 6.3));
            std::array::from_fn(|k| if k < 4 { upper[k] } else { lower[k - 4] })
        };
        let lss = cluster_segment(top, bottom, &points);
        assert_eq!((lss.start, lss.end), (top, bottom));
        for p in points {
            assert!(
                point_segment_distance_f64(p, top, bottom) <= lss.radius as f64,
                "case {case}: {p} outside {lss:?}"
            );
        }
        // Tight on its axis: some point lies on the surface, up to the rounding slack.
        let farthest = points
            .iter()
            .map(|&p| point_segment_distance_f64(p, top, bottom))
            .fold(0.0, f64::max);
        assert!(lss.radius as f64 - farthest <= 1e-5);
        // Never looser than the bound from the cross-section radii (perpendicular or not).
        if case % 4 != 0 {
            assert!(lss.radius <= r_top.max(r_bottom) + 1e-5);
        }
    }
}

#[test]
fn patch_rss_encloses_its_four_control_points() {
    let mut rng = Rng::new(12);
    for case in 0..4000 {
        let top = rng.vec3(0.3);
        let bottom = top + rng.direction() * rng.range(0.0, 0.05);
        let width = rng.range(0.0, 0.03);
        let (side_top, side_bottom) = (rng.direction(), rng.direction());
        let mut points = [
            top - side_top * width,
            top + side_top * width,
            bottom - side_bottom * width,
            bottom + side_bottom * width,
        ];
        match case % 8 {
            // Degenerate: all coincident, collinear, zero width.
            0 => points = [top; 4],
            1 => points = [top, top, bottom, bottom],
            2 => points = std::array::from_fn(|k| top + (bottom - top) * k as f32),
            // Arbitrary points.
            3 => points = std::array::from_fn(|_| top + rng.vec3(0.05)),
            _ => {}
        }
        let rss = patch_segment(&points);
        let r = &rss.rectangle;
        assert!((r.axes[0].length() - 1.0).abs() < 1e-5 && (r.axes[1].length() - 1.0).abs() < 1e-5);
        assert!(r.axes[0].dot(r.axes[1]).abs() < 1e-5);
        assert!(r.half_extents.iter().all(|&h| h >= 0.0 && h.is_finite()));
        for p in points {
            let d = point_rectangle_distance_f64(p, r);
            assert!(
                d <= rss.radius as f64,
                "case {case}: {p} at {d} outside {rss:?}"
            );
        }
        // A planar patch (straight, untwisted) gets a thin RSS.
        if case % 8 == 4 {
            let flat = [
                top - side_top * width,
                top + side_top * width,
                bottom - side_top * width,
                bottom + side_top * width,
            ];
            assert!(patch_segment(&flat).radius <= 1e-5);
        }
    }
}

#[test]
fn head_pss_encloses_every_vertex() {
    let mesh = uv_sphere(Vec3::new(0.01, 1.6, -0.02), 0.1, 24, 48);
    let pss = head_volume(&mesh).expect("non-empty");
    for p in &mesh.positions {
        assert!((p.as_dvec3() - pss.center.as_dvec3()).length() <= pss.radius as f64);
    }
    // A sphere's bounding ball is the sphere itself, up to the tessellation and slack.
    assert!((pss.radius - 0.1).abs() < 1e-3);
    let mut rng = Rng::new(13);
    for _ in 0..200 {
        let points: Vec<Vec3> = (0..1 + rng.below(50)).map(|_| rng.vec3(2.0)).collect();
        let ball = enclosing_ball(&points).expect("non-empty");
        for p in &points {
            assert!((p.as_dvec3() - ball.center.as_dvec3()).length() <= ball.radius as f64);
        }
    }
    assert!(enclosing_ball(&[]).is_none());
}
