//! Head motion: the head's rigid transform over time (still, nod, shake, keyframed path), which
//! carries the roots of attached chains.

use glam::{Quat, Vec3};

use crate::dynamics::error::DynamicsError;
use crate::transform::RigidTransform;

/// One keyframe of a head path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadKeyframe {
    /// Time [s].
    pub time: f64,
    /// The head's transform at that time.
    pub transform: RigidTransform,
}

/// The head's pose as a function of time.
#[derive(Debug, Clone, PartialEq)]
pub enum HeadMotion {
    /// A fixed pose.
    Still(RigidTransform),
    /// Periodic rotation `angle(t) = amplitude·sin(2π·frequency·t)` about `axis` (head space, unit)
    /// through `pivot` (head space [m]), applied before `base`: nodding (axis X) and shaking
    /// (axis Y) are special cases. The peak angular speed is `2π·frequency·amplitude` [rad/s].
    Oscillate {
        /// The pose at angle 0.
        base: RigidTransform,
        /// Rotation axis in head space (unit).
        axis: Vec3,
        /// Pivot in head space [m] (the neck).
        pivot: Vec3,
        /// Amplitude [rad].
        amplitude: f32,
        /// Frequency [Hz].
        frequency: f32,
    },
    /// A keyframed path: translation interpolated linearly and rotation spherically between
    /// keyframes (sorted by time); held constant before the first and after the last.
    Keyframed(Vec<HeadKeyframe>),
}

impl Default for HeadMotion {
    fn default() -> Self {
        HeadMotion::Still(RigidTransform::IDENTITY)
    }
}

/// Neck pivot of the procedural head, in head space [m]: below and behind the head's centre.
pub const NECK_PIVOT: Vec3 = Vec3::new(0.0, -0.12, -0.02);

impl HeadMotion {
    /// Nodding (rotation about head X through the neck) with the given amplitude [rad] and peak
    /// angular speed [rad/s].
    pub fn nod(amplitude: f32, peak_angular_speed: f32) -> Self {
        Self::oscillation(Vec3::X, amplitude, peak_angular_speed)
    }

    /// Shaking (rotation about head Y through the neck) with the given amplitude [rad] and peak
    /// angular speed [rad/s].
    pub fn shake(amplitude: f32, peak_angular_speed: f32) -> Self {
        Self::oscillation(Vec3::Y, amplitude, peak_angular_speed)
    }

    fn oscillation(axis: Vec3, amplitude: f32, peak_angular_speed: f32) -> Self {
        let frequency = if amplitude > 0.0 {
            peak_angular_speed / (std::f32::consts::TAU * amplitude)
        } else {
            0.0
        };
        HeadMotion::Oscillate {
            base: RigidTransform::IDENTITY,
            axis,
            pivot: NECK_PIVOT,
            amplitude,
            frequency,
        }
    }

    /// A keyframed path; keyframes must be sorted by time with finite values.
    pub fn keyframed(keyframes: Vec<HeadKeyframe>) -> Result<Self, DynamicsError> {
        if keyframes.is_empty() {
            return Err(DynamicsError::invalid(
                "head keyframes",
                "none",
                "at least one keyframe",
            ));
        }
        for (index, pair) in keyframes.windows(2).enumerate() {
            if pair[1].time.is_nan() || pair[1].time < pair[0].time {
                return Err(DynamicsError::invalid(
                    "head keyframe time",
                    format!("{} s at keyframe {}", pair[1].time, index + 1),
                    "times sorted in increasing order [s]",
                ));
            }
        }
        for key in &keyframes {
            if !(key.time.is_finite()
                && key.transform.translation.is_finite()
                && key.transform.rotation.is_finite())
            {
                return Err(DynamicsError::invalid(
                    "head keyframe",
                    format!("{key:?}"),
                    "finite time, translation and rotation",
                ));
            }
        }
        Ok(HeadMotion::Keyframed(keyframes))
    }

    /// The same motion with the whole head placed by `placement` (world from the motion's
    /// space): every pose `p(t)` becomes `placement ∘ p(t)`. A crowd stands its characters
    /// where they are this way, each keeping its own shake, nod or keyframes.
    pub fn placed(self, placement: &RigidTransform) -> HeadMotion {
        match self {
            HeadMotion::Still(pose) => HeadMotion::Still(placement.after(&pose)),
            HeadMotion::Oscillate {
                base,
                axis,
                pivot,
                amplitude,
                frequency,
            } => HeadMotion::Oscillate {
                base: placement.after(&base),
                axis,
                pivot,
                amplitude,
                frequency,
            },
            HeadMotion::Keyframed(keys) => HeadMotion::Keyframed(
                keys.into_iter()
                    .map(|key| HeadKeyframe {
                        time: key.time,
                        transform: placement.after(&key.transform),
                    })
                    .collect(),
            ),
        }
    }

    /// The head's transform at `time` [s].
    pub fn transform_at(&self, time: f64) -> RigidTransform {
        match self {
            HeadMotion::Still(transform) => *transform,
            HeadMotion::Oscillate {
                base,
                axis,
                pivot,
                amplitude,
                frequency,
            } => {
                let angle =
                    amplitude * (std::f64::consts::TAU * *frequency as f64 * time).sin() as f32;
                let rotation = Quat::from_axis_angle(*axis, angle);
                // x ↦ base(pivot + R (x − pivot))
                let local = RigidTransform::new(rotation, *pivot - rotation * *pivot);
                RigidTransform::new(
                    (base.rotation * local.rotation).normalize(),
                    base.rotation * local.translation + base.translation,
                )
            }
            HeadMotion::Keyframed(keys) => {
                let after = keys.partition_point(|key| key.time <= time);
                if after == 0 {
                    return keys[0].transform;
                }
                if after == keys.len() {
                    return keys[keys.len() - 1].transform;
                }
                let (a, b) = (&keys[after - 1], &keys[after]);
                let span = b.time - a.time;
                let s = if span > 0.0 {
                    ((time - a.time) / span) as f32
                } else {
                    1.0
                };
                RigidTransform::new(
                    a.transform
                        .rotation
                        .slerp(b.transform.rotation, s)
                        .normalize(),
                    a.transform.translation.lerp(b.transform.translation, s),
                )
            }
        }
    }

    /// An upper bound of the head's angular speed [rad/s] (0 for keyframed paths, whose speed is
    /// not bounded here).
    pub fn peak_angular_speed(&self) -> f32 {
        match self {
            HeadMotion::Oscillate {
                amplitude,
                frequency,
                ..
            } => std::f32::consts::TAU * frequency * amplitude.abs(),
            _ => 0.0,
        }
    }
}

/// The angular velocity [rad/s] that turns `from` into `to` in `duration` [s] (world frame).
///
/// The angle is `2·atan2(|xyz|, w)` of the relative quaternion, which stays accurate for the tiny
/// rotations of short substeps (`2·acos(w)` in f32 turns rounding of `w` near 1 into spurious
/// spins of hundreds of rad/s).
pub fn angular_velocity(from: Quat, to: Quat, duration: f32) -> Vec3 {
    let delta = to * from.inverse();
    // Shortest way round.
    let delta = if delta.w < 0.0 { -delta } else { delta };
    let vector = Vec3::new(delta.x, delta.y, delta.z);
    let sin_half = vector.length();
    if !(sin_half > 0.0 && duration > 0.0) {
        return Vec3::ZERO;
    }
    let angle = 2.0 * sin_half.atan2(delta.w);
    vector * (angle / (sin_half * duration))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shake_has_the_asked_peak_speed_and_keeps_the_pivot() {
        let motion = HeadMotion::shake(0.5, 3.0);
        assert!((motion.peak_angular_speed() - 3.0).abs() < 1e-5);
        // Around t = 0 the angle grows at the peak rate: ω ≈ Δangle / Δt.
        let h = 1e-4;
        let w = angular_velocity(
            motion.transform_at(0.0).rotation,
            motion.transform_at(h).rotation,
            h as f32,
        );
        assert!((w - Vec3::Y * 3.0).length() < 1e-2, "{w}");
        let moved = motion.transform_at(0.3).transform_point(NECK_PIVOT);
        assert!((moved - NECK_PIVOT).length() < 1e-6);
    }

    #[test]
    fn a_placed_motion_is_the_placement_after_every_pose() {
        // placed(p)(t)(x) = placement(p(t)(x)) for every motion kind, at any time.
        let placement = RigidTransform::new(Quat::from_rotation_y(0.7), Vec3::new(1.5, 0.0, -12.0));
        let keys = vec![
            HeadKeyframe {
                time: 0.0,
                transform: RigidTransform::IDENTITY,
            },
            HeadKeyframe {
                time: 1.0,
                transform: RigidTransform::new(Quat::from_rotation_x(0.3), Vec3::Y * 0.1),
            },
        ];
        let x = Vec3::new(0.05, 0.1, -0.08);
        for motion in [
            HeadMotion::Still(RigidTransform::new(Quat::from_rotation_z(0.2), Vec3::X)),
            HeadMotion::shake(0.4, 5.0),
            HeadMotion::nod(0.2, 1.5),
            HeadMotion::keyframed(keys.clone()).unwrap(),
        ] {
            let placed = motion.clone().placed(&placement);
            for t in [0.0, 0.13, 0.5, 2.0] {
                let expected = placement.transform_point(motion.transform_at(t).transform_point(x));
                let got = placed.transform_at(t).transform_point(x);
                assert!(
                    (got - expected).length() < 1e-5,
                    "{motion:?} at {t}: {got} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn keyframes_interpolate_and_hold() {
        let a = RigidTransform::IDENTITY;
        let b = RigidTransform::new(Quat::from_rotation_y(1.0), Vec3::new(0.2, 0.0, 0.0));
        let motion = HeadMotion::keyframed(vec![
            HeadKeyframe {
                time: 1.0,
                transform: a,
            },
            HeadKeyframe {
                time: 2.0,
                transform: b,
            },
        ])
        .unwrap();
        assert_eq!(motion.transform_at(0.0), a);
        assert_eq!(motion.transform_at(5.0), b);
        let mid = motion.transform_at(1.5);
        assert!((mid.translation.x - 0.1).abs() < 1e-6);
        assert!((mid.rotation.angle_between(Quat::from_rotation_y(0.5))).abs() < 1e-4);
        assert!(
            HeadMotion::keyframed(vec![
                HeadKeyframe {
                    time: 2.0,
                    transform: a
                },
                HeadKeyframe {
                    time: 1.0,
                    transform: b
                },
            ])
            .is_err()
        );
    }
}
