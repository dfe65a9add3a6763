//! Hairstyles (§3.6): straight, wavy and ringlet-curly rest angles, and the automatic node count.

use std::f32::consts::{FRAC_PI_2, PI};

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result, require_in_range, require_positive};
use crate::skeleton::ChainAngles;

/// The kind of rest shape a skeleton holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StyleKind {
    /// θ0 = 0 and φ0 = 0 at every node.
    Straight,
    /// θ0 = wave factor; φ0 alternates +90° (even nodes) / −90° (odd nodes): a zigzag.
    Wavy,
    /// θ0 = curl factor; φ0 cycles 0°, 90°, 180°, −90° (from node 1, whose bend points away from the scalp): a ringlet spiral.
    Curly,
}

impl StyleKind {
    /// The style's name as used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            StyleKind::Straight => "straight",
            StyleKind::Wavy => "wavy",
            StyleKind::Curly => "curly",
        }
    }
}

/// A hairstyle: the rest shape of every skeleton of a groom (§3.6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HairStyle {
    /// Straight, wavy or curly.
    pub kind: StyleKind,
    /// The wave factor or curl factor: θ0 of every node after the root [degrees], `0..=90`.
    /// Ignored (θ0 = 0) for straight hair.
    pub factor_degrees: f32,
    /// The size of the wave or curl [m]: the zigzag's half peak-to-peak amplitude (wavy) or the
    /// spiral's radius (curly). Smaller means tighter: shorter segments and more nodes. Ignored for
    /// straight hair.
    pub size: f32,
    /// The smoothness setting: the longest segment any style uses [m].
    pub smoothness: f32,
}

/// The fewest segments a skeleton gets, so that a cubic NURBS (4 control points) can be built on it.
pub const MIN_SEGMENT_COUNT: usize = 3;

impl HairStyle {
    /// Straight hair with segments of at most `smoothness` metres.
    pub fn straight(smoothness: f32) -> Self {
        HairStyle {
            kind: StyleKind::Straight,
            factor_degrees: 0.0,
            size: 0.0,
            smoothness,
        }
    }

    /// Wavy hair: wave factor θ0 [degrees] and wave amplitude [m].
    pub fn wavy(wave_factor_degrees: f32, amplitude: f32, smoothness: f32) -> Self {
        HairStyle {
            kind: StyleKind::Wavy,
            factor_degrees: wave_factor_degrees,
            size: amplitude,
            smoothness,
        }
    }

    /// Ringlet curls: curl factor θ0 [degrees] and curl radius [m].
    pub fn curly(curl_factor_degrees: f32, radius: f32, smoothness: f32) -> Self {
        HairStyle {
            kind: StyleKind::Curly,
            factor_degrees: curl_factor_degrees,
            size: radius,
            smoothness,
        }
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        require_positive("smoothness (longest segment, m)", self.smoothness)?;
        match self.kind {
            StyleKind::Straight => Ok(()),
            StyleKind::Wavy | StyleKind::Curly => {
                let name = if self.kind == StyleKind::Wavy {
                    "wave factor"
                } else {
                    "curl factor"
                };
                let factor =
                    require_in_range(name, self.factor_degrees, 0.0, 90.0, "0..=90 degrees")?;
                if factor == 0.0 {
                    return Err(HairError::invalid(
                        name,
                        factor,
                        "> 0 degrees for wavy or curly hair (use the straight style for 0)",
                    ));
                }
                let size_name = if self.kind == StyleKind::Wavy {
                    "wave amplitude"
                } else {
                    "curl radius"
                };
                require_positive(size_name, self.size)?;
                Ok(())
            }
        }
    }

    /// θ0 [rad] of every node after the root.
    pub fn rest_polar_angle(&self) -> f32 {
        match self.kind {
            StyleKind::Straight => 0.0,
            _ => self.factor_degrees.to_radians(),
        }
    }

    /// Rest angles (θ0, φ0) [rad] of node `node_index` (0 = root, which has none).
    pub fn rest_angles(&self, node_index: usize) -> (f32, f32) {
        if node_index == 0 {
            return (0.0, 0.0);
        }
        let azimuth = match self.kind {
            StyleKind::Straight => 0.0,
            StyleKind::Wavy => {
                if node_index % 2 == 0 {
                    FRAC_PI_2
                } else {
                    -FRAC_PI_2
                }
            }
            // Node 1 bends towards the root frame's normal (away from the scalp), then the bend
            // turns a quarter each node: the first loop of the curl rises off the scalp instead of
            // dipping into it.
            StyleKind::Curly => match (node_index - 1) % 4 {
                0 => 0.0,
                1 => FRAC_PI_2,
                2 => PI,
                _ => -FRAC_PI_2,
            },
        };
        (self.rest_polar_angle(), azimuth)
    }

    /// The segment length the style asks for [m], before rounding to keep the hair's length.
    ///
    /// Straight: the smoothness. Wavy: segments alternately turn by +θ and −θ, so they lie at ±θ/2
    /// about the wave's mean line and the half peak-to-peak amplitude is `A = l·sin(θ/2)/2`, giving
    /// `l = 2A / sin(θ/2)`. Curly: the chain is a discrete helix; its radius is proportional to the
    /// segment length, `R = l·g(θ)` with `g` from [`curl_radius_per_segment`], so `l = R / g(θ)`.
    /// Either is capped by the smoothness.
    pub fn target_segment_length(&self) -> f32 {
        let theta = self.rest_polar_angle();
        let wanted = match self.kind {
            StyleKind::Straight => self.smoothness,
            StyleKind::Wavy => 2.0 * self.size / (0.5 * theta).sin(),
            StyleKind::Curly => self.size / curl_radius_per_segment(theta),
        };
        wanted.min(self.smoothness)
    }

    /// Number of segments for hair of length `hair_length` [m]: `⌈L / l⌉`, at least
    /// [`MIN_SEGMENT_COUNT`]. The segments are then shortened to `L / count` so the length is kept.
    pub fn segment_count(&self, hair_length: f32) -> Result<usize> {
        self.validate()?;
        let length = require_positive("hair length (m)", hair_length)?;
        let count = (length / self.target_segment_length() - 1e-4).ceil();
        if !(count.is_finite() && count < 100_000.0) {
            return Err(HairError::invalid(
                "hair length (m)",
                length,
                "at most 100,000 segments of the style's length",
            ));
        }
        Ok((count as usize).max(MIN_SEGMENT_COUNT))
    }

    /// The rest lengths and angles of one skeleton of length `hair_length` [m] (node count =
    /// segment count + 1).
    pub fn chain_angles(&self, hair_length: f32) -> Result<ChainAngles> {
        let segments = self.segment_count(hair_length)?;
        let node_count = segments + 1;
        let segment_length = hair_length / segments as f32;
        let mut angles = ChainAngles {
            segment_lengths: vec![segment_length; node_count],
            polar_angles: Vec::with_capacity(node_count),
            azimuth_angles: Vec::with_capacity(node_count),
        };
        angles.segment_lengths[0] = 0.0;
        for node in 0..node_count {
            let (polar, azimuth) = self.rest_angles(node);
            angles.polar_angles.push(polar);
            angles.azimuth_angles.push(azimuth);
        }
        Ok(angles)
    }
}

/// Radius of the ringlet helix per unit segment length, `R / l`, for curl factor `theta` [rad].
///
/// The ringlet's φ0 pattern repeats every 4 nodes, so one rigid screw motion `x ↦ Q·x + t` maps every
/// node `i` to node `i + 4`, and all nodes lie on a helix about that screw's axis `u`. For a node `p`,
/// the part of `p' − p` perpendicular to `u` is `(Q − I)` applied to the node's offset from the axis,
/// a rotation by the screw angle α minus the identity, whose length is `2·sin(α/2)·R`. So
/// `R = |(p' − p)⊥| / (2·sin(α/2))`, exact for the discrete chain (computed on a unit chain).
pub fn curl_radius_per_segment(theta: f32) -> f32 {
    use crate::frame::Frame;
    use glam::{Quat, Vec3};
    let style = HairStyle::curly(theta.to_degrees(), 1.0, 1.0);
    let mut frame = Frame::default();
    let mut position = Vec3::ZERO;
    let mut nodes = [Vec3::ZERO; 6];
    let mut frames = [Frame::default(); 6];
    for node in 1..6 {
        let (polar, azimuth) = style.rest_angles(node);
        let direction = frame.direction(polar, azimuth);
        position += direction;
        frame = frame.transported_to(direction);
        nodes[node] = position;
        frames[node] = frame;
    }
    let q = Quat::from_mat3(&(frames[5].to_mat3() * frames[1].to_mat3().transpose()));
    let (axis, angle) = q.to_axis_angle();
    let step = nodes[5] - nodes[1];
    let perpendicular = step - axis * step.dot(axis);
    perpendicular.length() / (2.0 * (0.5 * angle).sin()).max(1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Frame;
    use crate::skeleton::{build_chain, measure_chain};
    use glam::Vec3;

    fn build(style: &HairStyle, length: f32) -> (Frame, Vec<Vec3>, ChainAngles) {
        let frame = Frame::from_tangent_and_normal(Vec3::NEG_Y, Vec3::Z).unwrap();
        let angles = style.chain_angles(length).unwrap();
        let mut positions = vec![Vec3::ZERO; angles.node_count()];
        build_chain(
            Vec3::ZERO,
            &frame,
            &angles.segment_lengths,
            &angles.polar_angles,
            &angles.azimuth_angles,
            &mut positions,
        )
        .unwrap();
        (frame, positions, angles)
    }

    #[test]
    fn straight_hair_has_zero_angles() {
        let style = HairStyle::straight(0.02);
        let angles = style.chain_angles(0.3).unwrap();
        assert_eq!(angles.node_count(), 16); // ⌈0.3 / 0.02⌉ = 15 segments
        assert!(angles.polar_angles.iter().all(|&a| a == 0.0));
        assert!(angles.azimuth_angles.iter().all(|&a| a == 0.0));
        assert!((angles.length() - 0.3).abs() < 1e-5);
    }

    #[test]
    fn curly_rest_shape_has_the_curl_period_in_its_azimuths() {
        let style = HairStyle::curly(50.0, 0.008, 0.05);
        let (frame, positions, angles) = build(&style, 0.25);
        // Measured back from the built nodes, φ0 repeats every 4 nodes from node 1: 0°, 90°, 180°,
        // −90°.
        let measured = measure_chain(&frame, &positions).unwrap();
        let expected = [0.0f32, 90.0, 180.0, -90.0];
        for i in 1..angles.node_count() {
            let degrees = measured.azimuth_angles[i].to_degrees();
            let want = expected[(i - 1) % 4];
            let difference = (degrees - want + 180.0).rem_euclid(360.0) - 180.0;
            assert!(difference.abs() < 0.05, "node {i}: {degrees} vs {want}");
            assert!((measured.polar_angles[i].to_degrees() - 50.0).abs() < 0.01);
        }
        // The period is exactly 4: φ_i = φ_{i+4} and no shorter shift matches.
        for shift in 1..4 {
            let matches = (1..angles.node_count() - shift).all(|i| {
                (measured.azimuth_angles[i] - measured.azimuth_angles[i + shift]).abs() < 1e-3
            });
            assert_eq!(matches, shift == 4, "shift {shift}");
        }
    }

    #[test]
    fn wavy_azimuths_alternate() {
        let style = HairStyle::wavy(30.0, 0.005, 0.05);
        let (frame, positions, angles) = build(&style, 0.2);
        let measured = measure_chain(&frame, &positions).unwrap();
        for i in 1..angles.node_count() {
            let want = if i % 2 == 0 { 90.0 } else { -90.0 };
            assert!((measured.azimuth_angles[i].to_degrees() - want).abs() < 0.05);
        }
        // Zigzag amplitude about the mean line: segments lie at ±θ/2 about the mean direction (the
        // average of a pair of segments), so consecutive nodes sit ±A = ±l·sin(θ/2)/2 off the line.
        let mean = ((positions[2] - positions[1]) + (positions[3] - positions[2])).normalize();
        let side = (frame.binormal - mean * frame.binormal.dot(mean)).normalize();
        let offset = |i: usize| (positions[i] - positions[1]).dot(side);
        assert!(offset(3).abs() < 1e-6); // nodes 1 and 3 are on the same side
        // The segment was shortened from 2A/sin(θ/2) to L/⌈…⌉ to keep the length: use the actual l.
        let l = angles.segment_lengths[1];
        assert!(l <= 2.0 * 0.005 / 15f32.to_radians().sin() + 1e-6);
        assert!((offset(2).abs() - l * 15f32.to_radians().sin()).abs() < 1e-6);
    }

    #[test]
    fn tighter_curls_get_shorter_segments_and_keep_the_length() {
        let loose = HairStyle::curly(50.0, 0.012, 0.05);
        let tight = HairStyle::curly(50.0, 0.004, 0.05);
        let loose_angles = loose.chain_angles(0.3).unwrap();
        let tight_angles = tight.chain_angles(0.3).unwrap();
        assert!(tight_angles.node_count() > loose_angles.node_count());
        assert!(tight_angles.segment_lengths[1] < loose_angles.segment_lengths[1]);
        assert!((tight_angles.length() - 0.3).abs() < 1e-5);
        assert!((loose_angles.length() - 0.3).abs() < 1e-5);
    }

    #[test]
    fn helix_radius_follows_the_curl_size() {
        // An independent measure of the radius: over many turns (100 periods of 4 segments), the chord
        // is the helix axis and the centroid of the projected nodes its centre, up to end effects of
        // order R / turns (< 1%); every node's distance from that axis is then R.
        let radius = 0.01;
        let style = HairStyle::curly(20.0, radius, 1.0);
        // Exactly 100 curl periods (400 segments of the target length, so no rounding).
        let (_, positions, _) = build(&style, 400.0 * style.target_segment_length());
        // The helix axis direction: mean of the chord over many turns.
        let axis = (positions[positions.len() - 1] - positions[0]).normalize();
        let centre_of = |p: Vec3| p - axis * p.dot(axis);
        let centre = positions.iter().map(|&p| centre_of(p)).sum::<Vec3>() / positions.len() as f32;
        let mean_radius = positions
            .iter()
            .map(|&p| (centre_of(p) - centre).length())
            .sum::<f32>()
            / positions.len() as f32;
        assert!(
            (mean_radius - radius).abs() < 0.01 * radius,
            "mean radius {mean_radius}"
        );
    }

    #[test]
    fn invalid_styles_name_the_parameter() {
        let error = HairStyle::curly(95.0, 0.01, 0.02).validate().unwrap_err();
        assert!(error.to_string().contains("curl factor"), "{error}");
        assert!(error.to_string().contains("0..=90 degrees"));
        let error = HairStyle::wavy(20.0, -0.01, 0.02).validate().unwrap_err();
        assert!(error.to_string().contains("wave amplitude"));
        assert!(HairStyle::wavy(f32::NAN, 0.01, 0.02).validate().is_err());
        assert!(HairStyle::straight(0.0).validate().is_err());
        let error = HairStyle::straight(0.02).chain_angles(-1.0).unwrap_err();
        assert!(error.to_string().contains("hair length"));
    }

    #[test]
    fn curly_chains_rise_off_the_scalp_instead_of_dipping_into_it() {
        // A root on a flat scalp (normal +Y), growing along +Z lifted by 0°, 15° or 30°: the first
        // bend points away from the scalp, so no node of the helix goes below the scalp's plane
        // (with the opposite phase the first loop dipped 3.6 cm into the head at 15°).
        let style = HairStyle::curly(50.0, 0.008, 0.03);
        let angles = style.chain_angles(0.25).unwrap();
        for lift in [0.0f32, 15.0, 30.0] {
            let (sin, cos) = lift.to_radians().sin_cos();
            let frame = Frame::from_tangent_and_normal(Vec3::new(0.0, sin, cos), Vec3::Y).unwrap();
            let mut positions = vec![Vec3::ZERO; angles.node_count()];
            crate::skeleton::build_chain(
                Vec3::ZERO,
                &frame,
                &angles.segment_lengths,
                &angles.polar_angles,
                &angles.azimuth_angles,
                &mut positions,
            )
            .unwrap();
            let lowest = positions.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
            assert!(lowest > -1e-6, "lift {lift}°: lowest node {lowest} m");
        }
    }
}
