//! Bodies deformed by the project's own code, so a deforming scene needs nothing outside the
//! repository: [`BodyAnimation::Talk`] opens and closes the procedural head's jaw and squashes
//! and stretches the whole head about the neck, sampled into a
//! [`MeshSequence`] the frame loop carries the roots on and collides with
//! (`scenes/talking-head.toml`).

use std::f32::consts::TAU;

use glam::Vec3;
use hair_core::dynamics::NECK_PIVOT;
use hair_core::{HairError, MeshSequence, TriangleMesh};
use serde::Serialize;

hair_core::named_enum! {
    /// `body.animation`: how the procedural head deforms by itself.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum BodyAnimationKind {
        /// It does not (the default).
        #[default]
        None = "none",
        /// Talking: the jaw opens and closes, and the head squashes and stretches.
        Talk = "talk",
    }
}

/// A deformation of the procedural head over time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum BodyAnimation {
    /// The jaw drops by up to `jaw_drop` [m] at `2·frequency` [Hz] (the lower front of the
    /// head moved down, blended into the rest over 4 cm), and the head squashes and stretches
    /// about the neck, `1 + stretch·sin(2π·f·t)` vertically and its inverse square root across
    /// (its volume kept), at `frequency` [Hz]. Never folds: the drop's blend changes by at most
    /// 1.5/(4 cm) per metre, so the map's Jacobian determinant stays at least
    /// `1 − 37.5·jaw_drop` > 0 for drops under 2.6 cm (before the stretch's, which is 1).
    Talk {
        /// The jaw's lowest drop [m], `0..=0.02`.
        jaw_drop: f32,
        /// The vertical stretch's amplitude, a fraction in `0..0.5`.
        stretch: f32,
        /// The squash and stretch's frequency [Hz].
        frequency: f32,
    },
}

/// Samples per second of a procedural animation (the scenes' default frame rate).
pub const SAMPLES_PER_SECOND: f64 = 60.0;

/// `0` at or beyond `edge0`, `1` at or beyond `edge1`, smooth between.
fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl BodyAnimation {
    /// Talking with its defaults: a 1.2 cm jaw drop and a 6 % squash and stretch at 1 Hz.
    pub fn talk() -> Self {
        BodyAnimation::Talk {
            jaw_drop: 0.012,
            stretch: 0.06,
            frequency: 1.0,
        }
    }

    /// Where `point` of the rest head [m] is at `time` [s]. Continuous in the point (the jaw's
    /// weight blends from the face's lower front to the rest), so no triangle tears.
    pub fn deform(&self, point: Vec3, time: f64) -> Vec3 {
        match *self {
            BodyAnimation::Talk {
                jaw_drop,
                stretch,
                frequency,
            } => {
                let t = time as f32;
                // The jaw: the lower front dropped, blended over 4 cm downwards and backwards.
                let opening = 0.5 * (1.0 - (TAU * 2.0 * frequency * t).cos());
                let weight = smoothstep(-0.03, -0.07, point.y) * smoothstep(-0.01, 0.03, point.z);
                let turned = point - Vec3::Y * (jaw_drop * opening * weight);
                // Squash and stretch about the neck, volume kept.
                let vertical = 1.0 + stretch * (TAU * frequency * t).sin();
                let across = 1.0 / vertical.sqrt();
                NECK_PIVOT + (turned - NECK_PIVOT) * Vec3::new(across, vertical, across)
            }
        }
    }

    /// The animation of `mesh` (the rest head) sampled at [`SAMPLES_PER_SECOND`] from 0 to at
    /// least `duration` [s]; its first sample is `mesh` itself. Fails on a parameter out of range
    /// or a duration that is not finite and ≥ 0.
    pub fn sample(&self, mesh: &TriangleMesh, duration: f64) -> hair_core::Result<MeshSequence> {
        let BodyAnimation::Talk {
            jaw_drop,
            stretch,
            frequency,
        } = *self;
        if !(jaw_drop.is_finite() && (0.0..=0.02).contains(&jaw_drop)) {
            return Err(HairError::invalid("jaw drop (m)", jaw_drop, "0..=0.02 m"));
        }
        if !(stretch.is_finite() && (0.0..0.5).contains(&stretch)) {
            return Err(HairError::invalid(
                "stretch",
                stretch,
                "a fraction in 0..0.5",
            ));
        }
        if !(frequency.is_finite() && (0.0..=100.0).contains(&frequency)) {
            return Err(HairError::invalid(
                "frequency (Hz)",
                frequency,
                "0..=100 Hz",
            ));
        }
        if !(duration.is_finite() && duration >= 0.0) {
            return Err(HairError::invalid(
                "duration (s)",
                duration,
                "a finite time ≥ 0 s",
            ));
        }
        let count = (duration * SAMPLES_PER_SECOND).ceil() as usize + 1;
        let times: Vec<f64> = (0..count).map(|k| k as f64 / SAMPLES_PER_SECOND).collect();
        let samples = times
            .iter()
            .enumerate()
            .map(|(k, &time)| {
                if k == 0 {
                    mesh.positions.clone()
                } else {
                    mesh.positions
                        .iter()
                        .map(|&p| self.deform(p, time))
                        .collect()
                }
            })
            .collect();
        MeshSequence::new(mesh.triangles.clone(), times, samples)
            .map_err(|error| HairError::invalid("body animation", error, "a valid mesh sequence"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn talking_keeps_the_volume_and_the_neck_and_opens_the_jaw_only_below_the_face() {
        let talk = BodyAnimation::talk();
        // At rest at t = 0 and at whole periods (the jaw's cosine and the stretch's sine).
        let p = Vec3::new(0.03, 0.08, -0.02);
        assert!((talk.deform(p, 0.0) - p).length() < 1e-7);
        assert!((talk.deform(p, 1.0) - p).length() < 1e-5);
        // The neck pivot never moves; a quarter period in, a point above it on the scalp is
        // stretched by 1.06 vertically and 1/√1.06 across, about the pivot.
        assert!((talk.deform(NECK_PIVOT, 0.25) - NECK_PIVOT).length() < 1e-7);
        let scale = Vec3::new(1.0 / 1.06f32.sqrt(), 1.06, 1.0 / 1.06f32.sqrt());
        let expected = NECK_PIVOT + (p - NECK_PIVOT) * scale;
        assert!((talk.deform(p, 0.25) - expected).length() < 1e-6);
        // The product of the three scales is 1: the volume is kept.
        assert!((scale.x * scale.y * scale.z - 1.0).abs() < 1e-6);
        // The chin (low, in front) drops at half a jaw period (t = 0.25 s at 2 Hz): fully open,
        // 1.2 cm down; the scalp point does not.
        let chin = Vec3::new(0.0, -0.09, 0.06);
        let opened = chin - Vec3::Y * 0.012;
        let expected = NECK_PIVOT + (opened - NECK_PIVOT) * scale;
        assert!((talk.deform(chin, 0.25) - expected).length() < 1e-6);
        assert!(talk.deform(chin, 0.25).y < chin.y - 0.005);
    }

    /// No triangle of the procedural head folds over while it talks: every triangle's normal
    /// stays within 45° of its rest normal at every sample of a period (a fold turns it by about
    /// 180°, and the collision's inside and outside with it).
    #[test]
    fn the_talking_head_never_folds() {
        let mesh = hair_core::Head::procedural(&hair_core::HeadParams::default())
            .unwrap()
            .mesh;
        let sequence = BodyAnimation::talk().sample(&mesh, 1.0).unwrap();
        let normal = |p: &[Vec3], t: &[u32; 3]| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        };
        let mut worst = 1.0f32;
        for sample in 1..sequence.sample_count() {
            let positions = sequence.sample_positions(sample);
            for t in &mesh.triangles {
                let (rest, now) = (normal(&mesh.positions, t), normal(positions, t));
                if rest != Vec3::ZERO {
                    worst = worst.min(rest.dot(now));
                }
            }
        }
        assert!(worst > 45f32.to_radians().cos(), "cos {worst}");
    }

    #[test]
    fn sampled_talking_starts_at_rest_and_refuses_bad_parameters() {
        let mesh = hair_core::Head::procedural(&hair_core::HeadParams::default())
            .unwrap()
            .mesh;
        let sequence = BodyAnimation::talk().sample(&mesh, 0.5).unwrap();
        assert_eq!(sequence.sample_count(), 31);
        assert_eq!(sequence.sample_positions(0), mesh.positions.as_slice());
        assert!(sequence.is_animated());
        let bad = BodyAnimation::Talk {
            jaw_drop: 0.01,
            stretch: 0.7,
            frequency: 1.0,
        };
        let error = bad.sample(&mesh, 1.0).unwrap_err().to_string();
        assert!(error.contains("stretch"), "{error}");
        assert!(BodyAnimation::talk().sample(&mesh, f64::NAN).is_err());
    }
}
