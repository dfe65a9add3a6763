//! One section's level choice (§7.4): why it is hidden, the error-driven (or the paper's distance)
//! level and the motion level, the per-section rules, hysteresis and the look ahead.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::criteria::{
    error_ahead, foreseen_share, is_occluded, is_section_occluded, level_with_hysteresis,
    projected_length,
};
use super::deviation::LevelDeviation;
use super::observation::SectionObservation;
use super::settings::{ErrorModel, LodSettings, OcclusionTest};
use crate::camera::Camera;
use crate::level::Level;
use crate::transform::RigidTransform;

/// Why a section has its level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reason {
    /// Outside the view frustum: patch, not drawn.
    OutsideView,
    /// Hidden behind the head: patch, not drawn.
    Occluded,
    /// Its screen size asked for the level.
    Distance,
    /// Its motion asked for more than its screen size.
    Motion,
    /// A per-section rule (part line, face) raised it.
    Rule,
    /// A fixed level was forced on every section.
    Fixed,
}

/// The choice for one section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SectionChoice {
    /// The level to simulate (and draw, when visible).
    pub level: Level,
    /// Whether the section is drawn (in view and not occluded).
    pub visible: bool,
    /// What decided the level.
    pub reason: Reason,
}

/// Per-section constants of the selector, from the groom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SectionConstants {
    /// The paper's distance limits [pixels of projected chord] (error model `Chord`).
    pub(super) limits: [f32; 2],
    /// The measured deviations [m] (error model `Deviation`).
    pub(super) deviation: LevelDeviation,
    /// The factor the crown's sections raise their errors by.
    pub(super) crown_factor: f32,
    /// Whether the part/face rule keeps the section at clusters or finer.
    pub(super) keep_clusters: bool,
}

/// The estimated screen-space error [pixels] of each level of a section with `constants` (see
/// [`LodSelector::estimated_errors`](crate::lod::LodSelector::estimated_errors)).
pub(super) fn estimated_errors(
    constants: &SectionConstants,
    observation: &SectionObservation,
    camera: &Camera,
    settings: &LodSettings,
) -> [f32; 3] {
    match settings.error_model {
        ErrorModel::Deviation => {
            let scale = pixels_per_metre(camera, observation.bound_centre, settings);
            Level::ALL.map(|level| scaled_error(constants.deviation.at(level), scale))
        }
        ErrorModel::Chord => {
            // e·ℓ/L = tolerance·ℓ/limit (the limits are tolerance·L/e).
            let length = chord_pixels(camera, observation, settings);
            let [patch, cluster] = constants.limits;
            [
                settings.pixel_tolerance * length / patch,
                settings.pixel_tolerance * length / cluster,
                0.0,
            ]
        }
    }
}

/// Why a section is not drawn (outside the view frustum, or hidden behind the head, §7.1), or
/// `None` when it is visible.
pub(super) fn hidden_reason(
    observation: &SectionObservation,
    camera: &Camera,
    head: &RigidTransform,
    occluders: &[(Vec3, Vec3)],
    settings: &LodSettings,
    aspect: f32,
) -> Option<Reason> {
    if !camera.sphere_in_frustum(observation.bound_centre, observation.bound_radius, aspect) {
        return Some(Reason::OutsideView);
    }
    let occluded = settings.occlusion
        && match settings.occlusion_test {
            OcclusionTest::Section => is_section_occluded(
                camera.position,
                &observation.sight,
                observation.sight_radius,
                occluders,
                head,
            ),
            OcclusionTest::Ends => is_occluded(
                camera.position,
                observation.top,
                observation.bottom,
                occluders,
                head,
            ),
        };
    occluded.then_some(Reason::Occluded)
}

/// Whether the motion criterion and the part/face rule apply to a section seen as in
/// `observation`: its projected chord spans at least [`LodSettings::rules_min_pixels`].
pub(super) fn rules_apply(
    observation: &SectionObservation,
    camera: &Camera,
    settings: &LodSettings,
) -> bool {
    settings.rules_min_pixels <= 0.0
        || chord_pixels(camera, observation, settings) >= settings.rules_min_pixels
}

/// The level a section's motion asks for (§7.3), with hysteresis around `current`.
pub(super) fn motion_level(
    observation: &SectionObservation,
    current: Level,
    settings: &LodSettings,
) -> Level {
    level_with_hysteresis(
        observation.motion,
        [
            settings.cluster_force_threshold,
            settings.strand_force_threshold,
        ],
        current,
        settings.hysteresis,
    )
}

/// The projected length [pixels] of the section's centre skeleton's root-to-tip line (§7.2).
pub(super) fn chord_pixels(
    camera: &Camera,
    observation: &SectionObservation,
    settings: &LodSettings,
) -> f32 {
    projected_length(
        camera,
        observation.top,
        observation.bottom,
        settings.image_width,
        settings.image_height,
    )
}

/// The depth [m] of `point` [m] along `camera`'s view direction.
pub(super) fn depth_of(camera: &Camera, point: Vec3) -> f32 {
    let forward = (camera.target - camera.position).normalize_or_zero();
    (point - camera.position).dot(forward)
}

/// Pixels a metre covers at the depth of `point` [m] seen by `camera` in the selector's image
/// (`f / z`, `f` the focal length in pixels); infinite at or behind the near plane.
pub(super) fn pixels_per_metre(camera: &Camera, point: Vec3, settings: &LodSettings) -> f32 {
    let depth = depth_of(camera, point);
    if depth <= camera.near {
        return f32::INFINITY;
    }
    camera.focal_length_pixels(settings.image_height) / depth
}

/// The screen area [pixels] of the disc that `observation`'s bounding sphere projects to in the
/// selector's image, at most the whole image: `π (r·f/z)²`.
pub fn covered_pixels(
    camera: &Camera,
    observation: &SectionObservation,
    settings: &LodSettings,
) -> f64 {
    let image = f64::from(settings.image_width) * f64::from(settings.image_height);
    let radius = f64::from(
        observation.bound_radius * pixels_per_metre(camera, observation.bound_centre, settings),
    );
    (std::f64::consts::PI * radius * radius).min(image)
}

/// `deviation · scale` [pixels], 0 for a zero deviation even at an infinite scale.
pub(super) fn scaled_error(deviation: f32, scale: f32) -> f32 {
    if deviation == 0.0 {
        0.0
    } else {
        deviation * scale
    }
}

/// A section's look ahead: its depth a frame ago and now [m], how many frames ahead the choice
/// looks, and the camera's near plane [m] ([`error_ahead`]).
pub(super) struct Lookahead {
    pub(super) previous: f32,
    pub(super) now: f32,
    pub(super) frames: f32,
    pub(super) near: f32,
}

impl Lookahead {
    /// The factor the section's errors will have changed by `frames` frames ahead.
    fn factor(&self, frames: f32) -> f32 {
        error_ahead(self.previous, self.now, frames, self.near)
    }
}

/// One section's choice (§7.4), its screen-space errors scaled to where they will be at the look
/// ahead `look` ([`error_ahead`]), and the share of the blend time a switch to it blends over
/// ([`LodSelector::blend_shares`](crate::lod::LodSelector::blend_shares)).
#[allow(clippy::too_many_arguments)]
pub(super) fn choose(
    current: Level,
    constants: &SectionConstants,
    observation: &SectionObservation,
    camera: &Camera,
    head: &RigidTransform,
    occluders: &[(Vec3, Vec3)],
    settings: &LodSettings,
    aspect: f32,
    look: &Lookahead,
) -> (SectionChoice, f32) {
    if let Some(reason) = hidden_reason(observation, camera, head, occluders, settings, aspect) {
        let choice = SectionChoice {
            level: Level::Patch,
            visible: false,
            reason,
        };
        return (choice, 1.0);
    }
    let band = settings.hysteresis;
    // The level the section's screen size asks for, its errors scaled by `ahead`.
    let by_distance_at = |ahead: f32| match settings.error_model {
        ErrorModel::Chord => {
            let length =
                chord_pixels(camera, observation, settings) * constants.crown_factor * ahead;
            level_with_hysteresis(length, constants.limits, current, band)
        }
        ErrorModel::Deviation => {
            // The error of a level is its deviation times the pixels a metre covers, so a level
            // is good enough while that scale stays below tolerance / deviation. A patch never
            // counts as closer than the clusters.
            let scale = pixels_per_metre(camera, observation.bound_centre, settings)
                * constants.crown_factor
                * ahead;
            let deviation = constants.deviation;
            let limit = |error: f32| settings.pixel_tolerance / error.max(f32::MIN_POSITIVE);
            let limits = [
                limit(deviation.patch.max(deviation.cluster)),
                limit(deviation.cluster),
            ];
            level_with_hysteresis(scale, limits, current, band)
        }
    };
    let by_distance = by_distance_at(look.factor(look.frames));
    let rules = rules_apply(observation, camera, settings);
    let by_motion = if rules {
        motion_level(observation, current, settings)
    } else {
        Level::Patch
    };
    let (mut level, mut reason) = if by_motion > by_distance {
        (by_motion, Reason::Motion)
    } else {
        (by_distance, Reason::Distance)
    };
    if rules && constants.keep_clusters && level < Level::Cluster {
        level = Level::Cluster;
        reason = Reason::Rule;
    }
    let share = if reason == Reason::Distance && level != current {
        foreseen_share(
            |frames| by_distance_at(look.factor(frames)),
            level,
            look.frames,
        )
    } else {
        1.0
    };
    let choice = SectionChoice {
        level,
        visible: true,
        reason,
    };
    (choice, share)
}
