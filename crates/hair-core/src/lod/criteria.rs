//! The criteria of §7 as pure functions: occlusion rays against a box inside the head (§7.1),
//! projected skeleton length and the distance limits that follow from a pixel tolerance (§7.2),
//! the motion measure (§7.3), a level with hysteresis, and how far errors change over a look ahead.

use glam::Vec3;

use crate::camera::Camera;
use crate::level::Level;
use crate::transform::RigidTransform;

/// Whether the segment from `from` to `to` [m] enters the axis-aligned box `(min, max)` before it
/// reaches `to` (a slab test; the end point itself inside the box counts as blocked).
pub fn segment_hits_box(from: Vec3, to: Vec3, min: Vec3, max: Vec3) -> bool {
    let direction = to - from;
    let mut enter = 0.0f32;
    let mut leave = 1.0f32;
    for axis in 0..3 {
        let (origin, step) = (from[axis], direction[axis]);
        let (low, high) = (min[axis], max[axis]);
        if step.abs() < 1e-12 {
            if origin < low || origin > high {
                return false;
            }
            continue;
        }
        let (mut t0, mut t1) = ((low - origin) / step, (high - origin) / step);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        enter = enter.max(t0);
        leave = leave.min(t1);
        if enter > leave {
            return false;
        }
    }
    true
}

/// The paper's occlusion test (§7.1), with a union of boxes: the segments from the camera to the
/// top (root) and to the bottom (tip) of a section both cross some box of `occluders` (head space
/// [m], all inside the head, see [`Head::occluder_boxes`](crate::Head::occluder_boxes)) posed by
/// `head`. It misses the rest of the section: a wavy or curly section, or one beside the head's
/// silhouette, can show between root and tip or beside them while both ends are hidden (see
/// [`is_section_occluded`]).
pub fn is_occluded(
    camera_position: Vec3,
    top: Vec3,
    bottom: Vec3,
    occluders: &[(Vec3, Vec3)],
    head: &RigidTransform,
) -> bool {
    is_section_occluded(camera_position, &[top, bottom], 0.0, occluders, head)
}

/// Whether every point of `points` [m] is hidden from `camera_position` by `occluders` (head space
/// [m], posed by `head`), each point widened by `radius` [m]: the sight lines to the point and to
/// the four points `radius` away from it across the line of sight (up, down, left, right) must all
/// cross some box. With a section's skeleton nodes as `points` and half its width as `radius`,
/// a section is hidden only when all of it is (the paper's "completely occluded", §7.1), as far
/// as the samples see. No occluders hide nothing.
pub fn is_section_occluded(
    camera_position: Vec3,
    points: &[Vec3],
    radius: f32,
    occluders: &[(Vec3, Vec3)],
    head: &RigidTransform,
) -> bool {
    if occluders.is_empty() || points.is_empty() {
        return false;
    }
    let to_head = head.inverse();
    let eye = to_head.transform_point(camera_position);
    let blocked = |point: Vec3| {
        occluders
            .iter()
            .any(|&(min, max)| segment_hits_box(eye, point, min, max))
    };
    points.iter().all(|&point| {
        let point = to_head.transform_point(point);
        if !blocked(point) {
            return false;
        }
        if radius <= 0.0 {
            return true;
        }
        let sight = (point - eye).normalize_or(Vec3::Z);
        let (across, up) = sight.any_orthonormal_pair();
        [across, -across, up, -up]
            .into_iter()
            .all(|offset| blocked(point + radius * offset))
    })
}

/// Length [pixels] of the line from `first` to `last` [m] projected into a `width`×`height` image;
/// infinite when either end is behind the camera (the section surrounds the eye: finest detail).
pub fn projected_length(camera: &Camera, first: Vec3, last: Vec3, width: u32, height: u32) -> f32 {
    match (
        camera.project_to_pixel(first, width, height),
        camera.project_to_pixel(last, width, height),
    ) {
        (Some(a), Some(b)) => a.distance(b),
        _ => f32::INFINITY,
    }
}

/// The projected lengths [pixels] above which a section needs clusters and strand groups:
/// `tolerance · L / e` with `e = w/6` for a patch and `w/10` for clusters (see
/// [`LodSettings`](super::LodSettings)); `chord` is `L`, the section's root-to-tip distance at
/// rest [m], `width` its width `w` [m].
pub fn distance_limits(chord: f32, width: f32, pixel_tolerance: f32) -> [f32; 2] {
    let patch_error = width / 6.0;
    let cluster_error = width / 10.0;
    [
        pixel_tolerance * chord / patch_error,
        pixel_tolerance * chord / cluster_error,
    ]
}

/// The level a value asks for against two ascending limits (`limits[0]`: patch → clusters,
/// `limits[1]`: clusters → strand groups), with hysteresis around the `current` level: a limit the
/// section is below counts as `limit·(1 + band)`, one it is above as `limit·(1 − band)`.
pub fn level_with_hysteresis(value: f32, limits: [f32; 2], current: Level, band: f32) -> Level {
    let current_rank = current as usize;
    let mut rank = 0;
    for (index, &limit) in limits.iter().enumerate() {
        let scaled = if current_rank > index {
            limit * (1.0 - band)
        } else {
            limit * (1.0 + band)
        };
        if value > scaled {
            rank = index + 1;
        }
    }
    Level::ALL[rank]
}

/// The factor by which a section's screen-space errors will have changed `lead_frames` frames
/// ahead, from its depth `previous` [m] a frame ago and `now` [m]: errors go as `1/z`, so it is
/// `z / z_ahead`. A receding depth is extrapolated linearly (`z + k·Δz`: exact at a constant
/// speed, short of an accelerating one), an approaching one geometrically
/// (`z·(z/z_prev)^k`: it never reaches the eye, short of a constant-speed approach), so that
/// the look ahead never foresees more change than a steady motion makes; bounded to `[1/4, 4]`.
/// 1 (no look ahead) when either depth is unknown, not finite or not beyond `near` [m], or when
/// `lead_frames` is 0.
pub fn error_ahead(previous: f32, now: f32, lead_frames: f32, near: f32) -> f32 {
    let known = |z: f32| z.is_finite() && z > near;
    if lead_frames <= 0.0 || !known(previous) || !known(now) {
        return 1.0;
    }
    let ahead = if now >= previous {
        now + lead_frames * (now - previous)
    } else {
        now * (now / previous).powf(lead_frames)
    };
    (now / ahead).clamp(0.25, 4.0)
}

/// The share of the blend time, in `(0, 1]`, for a switch to `level` that a look ahead of
/// `lead_frames` frames brought forward, where `level_at(k)` is the level the section's errors
/// `k` frames ahead ask for (monotone in `k`, as [`error_ahead`] is). A blend's new level is
/// fully in at half the blend, so a look ahead of half the blend has it fully in when the
/// tolerance is crossed. A switch foreseen only `k < lead_frames` frames ahead (the crossing
/// comes sooner than the look ahead: the first frames of a shot, or a section speeding up)
/// gets `k / lead_frames` of the blend, so that its new level is still fully in by the crossing
/// and the old one gone as far after it, rather than both overstaying: the frames drawing both
/// levels cost the sum of the two. 1 when the current frame's errors already ask for `level` (the
/// look ahead did not bring the switch forward) or there is no look ahead. `k` is found by
/// bisection to 1/4096 of the lead.
pub fn foreseen_share(level_at: impl Fn(f32) -> Level, level: Level, lead_frames: f32) -> f32 {
    if lead_frames.is_nan()
        || lead_frames <= 0.0
        || level_at(0.0) == level
        || level_at(lead_frames) != level
    {
        return 1.0;
    }
    // level_at(low) is not `level`, level_at(high) is.
    let (mut low, mut high) = (0.0f32, lead_frames);
    for _ in 0..12 {
        let middle = 0.5 * (low + high);
        if level_at(middle) == level {
            high = middle;
        } else {
            low = middle;
        }
    }
    high / lead_frames
}

/// The motion measure of one skeleton (§7.3): the strongest external force per unit mass on any of
/// its nodes [m/s²], gravity excluded: the wind's drag plus the inertial force of the moving head,
///
/// `max_k c_d · |w(x_k) − v_k| + |a_head(x_k)|`
///
/// with `c_d` the air drag rate [1/s], `w(x_k)` the wind velocity at the node [m/s], `v_k` its
/// velocity and `a_head(x_k)` the acceleration [m/s²] of the point rigidly attached to the head
/// at the node (what a head shake or nod forces on the hair). A steady wind keeps the measure up
/// even once the hair has come to rest in it (its strands show); a still head in calm air gives
/// zero however the springs ring, so a section does not flip level on its own vibration.
pub fn motion_measure(
    positions: &[Vec3],
    velocities: &[Vec3],
    drag_rate: f32,
    wind_at: impl Fn(Vec3) -> Vec3,
    head_acceleration_at: impl Fn(Vec3) -> Vec3,
) -> f32 {
    let mut strongest = 0.0f32;
    for (&x, &v) in positions.iter().zip(velocities) {
        let drag = drag_rate * (wind_at(x) - v).length();
        strongest = strongest.max(drag + head_acceleration_at(x).length());
    }
    strongest
}

/// The acceleration [m/s²] at time `time` [s] of the point rigidly attached to a head whose pose
/// over time is `pose_at`, passing through `point` [m] (world) at that time: the central second
/// difference of the point's path over `±step` [s] (exact for a uniform rotation's centripetal
/// term to O(step²)).
pub fn head_point_acceleration(
    pose_at: impl Fn(f64) -> RigidTransform,
    time: f64,
    step: f32,
    point: Vec3,
) -> Vec3 {
    let poses = [
        pose_at(time - f64::from(step)),
        pose_at(time),
        pose_at(time + f64::from(step)),
    ];
    head_point_acceleration_from_poses(&poses, step, point)
}

/// [`head_point_acceleration`] from the head's poses at `time − step`, `time` and `time + step`
/// (for many points in one frame: the poses are computed once).
pub fn head_point_acceleration_from_poses(
    poses: &[RigidTransform; 3],
    step: f32,
    point: Vec3,
) -> Vec3 {
    let [before, now, after] = poses;
    let local = now.inverse().transform_point(point);
    let before = before.transform_point(local);
    let after = after.transform_point(local);
    (after - 2.0 * point + before) / (step * step)
}
