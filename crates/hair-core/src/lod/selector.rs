//! The per-frame level choice of every section (§7.4): occlusion and frustum first, then the higher
//! of the distance and motion levels, per-section rules, hysteresis.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::criteria::{distance_limits, is_occluded, level_with_hysteresis, projected_length};
use super::settings::LodSettings;
use crate::camera::Camera;
use crate::error::{HairError, Result};
use crate::groom::Groom;
use crate::level::Level;
use crate::transform::RigidTransform;

/// What the selector sees of one section this frame, measured on its active skeletons.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SectionObservation {
    /// Root (top) of the section's centre skeleton [m], world space.
    pub top: Vec3,
    /// Tip (bottom) of the centre skeleton [m], world space.
    pub bottom: Vec3,
    /// Centre of a sphere around all the section's active nodes [m].
    pub bound_centre: Vec3,
    /// Radius of that sphere [m], the section's half width included.
    pub bound_radius: f32,
    /// Motion measure [m/s²] (see [`motion_measure`](super::motion_measure)).
    pub motion: f32,
}

impl SectionObservation {
    /// The observation of section `section` of `groom` from the positions [m] of its skeletons at
    /// `level` (section-local, chain-major: 1, 3 or 5 chains) and its motion measure [m/s²].
    pub fn of_section(
        groom: &Groom,
        section: usize,
        level: Level,
        positions: &[Vec3],
        motion: f32,
    ) -> Self {
        let chains = groom.section_chains(section, level);
        let centre = groom.centre_chain(section, level);
        let before: usize = (chains.start..centre)
            .map(|chain| groom.skeletons.chain_node_count(chain))
            .sum();
        let count = groom.skeletons.chain_node_count(centre);
        let (top, bottom) = (positions[before], positions[before + count - 1]);
        let (min, max) = positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(min, max), &p| (min.min(p), max.max(p)),
        );
        let bound_centre = 0.5 * (min + max);
        let bound_radius = positions
            .iter()
            .map(|p| p.distance(bound_centre))
            .fold(0.0f32, f32::max)
            + 0.5 * groom.sections[section].width;
        SectionObservation {
            top,
            bottom,
            bound_centre,
            bound_radius,
            motion,
        }
    }
}

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
struct SectionConstants {
    limits: [f32; 2],
    crown_factor: f32,
    keep_clusters: bool,
}

/// Chooses every section's level each frame, remembering the last choice for hysteresis.
#[derive(Debug, Clone)]
pub struct LodSelector {
    settings: LodSettings,
    constants: Vec<SectionConstants>,
    choices: Vec<SectionChoice>,
    occluders: Vec<(Vec3, Vec3)>,
}

impl LodSelector {
    /// A selector for `groom` on a head whose occluding boxes are `occluders` (head space [m],
    /// inside the head: [`Head::occluder_boxes`](crate::Head::occluder_boxes)); every section
    /// starts as a visible patch.
    pub fn new(groom: &Groom, occluders: &[(Vec3, Vec3)], settings: LodSettings) -> Result<Self> {
        settings.validate()?;
        let patches = groom.level_chains(Level::Patch);
        let constants = groom
            .sections
            .iter()
            .zip(patches)
            .map(|(section, chain)| {
                let mut rest = vec![Vec3::ZERO; groom.skeletons.chain_node_count(chain)];
                groom
                    .skeletons
                    .rest_positions_of(chain, &RigidTransform::IDENTITY, &mut rest);
                let chord = rest[0].distance(rest[rest.len() - 1]);
                let crown_factor = if settings.crown_radius > 0.0 {
                    1.0 + settings.crown_boost
                        * (1.0 - section.crown_distance / settings.crown_radius).max(0.0)
                } else {
                    1.0
                };
                SectionConstants {
                    limits: distance_limits(chord, section.width, settings.pixel_tolerance),
                    crown_factor,
                    keep_clusters: settings.keep_part_and_face_detailed
                        && (section.along_part || section.around_face),
                }
            })
            .collect();
        let choices = vec![
            SectionChoice {
                level: Level::Patch,
                visible: true,
                reason: Reason::Distance,
            };
            groom.section_count()
        ];
        Ok(LodSelector {
            settings,
            constants,
            choices,
            occluders: occluders.to_vec(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &LodSettings {
        &self.settings
    }

    /// Changes the settings (for example the pixel tolerance of a frame-budget controller); the
    /// distance limits are recomputed from the new tolerance.
    pub fn set_pixel_tolerance(&mut self, pixel_tolerance: f32) -> Result<()> {
        let settings = LodSettings {
            pixel_tolerance,
            ..self.settings
        };
        settings.validate()?;
        let scale = pixel_tolerance / self.settings.pixel_tolerance;
        for constants in &mut self.constants {
            constants.limits = constants.limits.map(|limit| limit * scale);
        }
        self.settings = settings;
        Ok(())
    }

    /// The last choices, one per section.
    pub fn choices(&self) -> &[SectionChoice] {
        &self.choices
    }

    /// Restores the last choices (the hysteresis memory) saved from [`choices`](Self::choices),
    /// for a run resumed from a checkpoint; errors when the count is not the section count.
    pub fn restore_choices(&mut self, choices: &[SectionChoice]) -> Result<()> {
        if choices.len() != self.choices.len() {
            return Err(HairError::SizeMismatch {
                what: "section choices",
                actual: choices.len(),
                expected: self.choices.len(),
            });
        }
        self.choices.copy_from_slice(choices);
        Ok(())
    }

    /// The distance limits [pixels] of section `section` (patch → clusters, clusters → strands).
    pub fn distance_limits(&self, section: usize) -> [f32; 2] {
        self.constants[section].limits
    }

    /// Chooses the level of every section from `observations` (one per section) seen by `camera`
    /// with the head posed by `head`; returns the choices.
    pub fn select(
        &mut self,
        observations: &[SectionObservation],
        camera: &Camera,
        head: &RigidTransform,
    ) -> Result<&[SectionChoice]> {
        if observations.len() != self.choices.len() {
            return Err(HairError::SizeMismatch {
                what: "section observations",
                actual: observations.len(),
                expected: self.choices.len(),
            });
        }
        camera.validate()?;
        let settings = self.settings;
        let aspect = settings.aspect();
        for ((choice, constants), observation) in self
            .choices
            .iter_mut()
            .zip(&self.constants)
            .zip(observations)
        {
            *choice = choose(
                choice.level,
                constants,
                observation,
                camera,
                head,
                &self.occluders,
                &settings,
                aspect,
            );
        }
        Ok(&self.choices)
    }
}

/// One section's choice (§7.4).
#[allow(clippy::too_many_arguments)]
fn choose(
    current: Level,
    constants: &SectionConstants,
    observation: &SectionObservation,
    camera: &Camera,
    head: &RigidTransform,
    occluders: &[(Vec3, Vec3)],
    settings: &LodSettings,
    aspect: f32,
) -> SectionChoice {
    let hidden = |reason| SectionChoice {
        level: Level::Patch,
        visible: false,
        reason,
    };
    if !camera.sphere_in_frustum(observation.bound_centre, observation.bound_radius, aspect) {
        return hidden(Reason::OutsideView);
    }
    if settings.occlusion
        && is_occluded(
            camera.position,
            observation.top,
            observation.bottom,
            occluders,
            head,
        )
    {
        return hidden(Reason::Occluded);
    }
    let length = projected_length(
        camera,
        observation.top,
        observation.bottom,
        settings.image_width,
        settings.image_height,
    ) * constants.crown_factor;
    let band = settings.hysteresis;
    let by_distance = level_with_hysteresis(length, constants.limits, current, band);
    let by_motion = level_with_hysteresis(
        observation.motion,
        [
            settings.cluster_force_threshold,
            settings.strand_force_threshold,
        ],
        current,
        band,
    );
    let (mut level, mut reason) = if by_motion > by_distance {
        (by_motion, Reason::Motion)
    } else {
        (by_distance, Reason::Distance)
    };
    if constants.keep_clusters && level < Level::Cluster {
        level = Level::Cluster;
        reason = Reason::Rule;
    }
    SectionChoice {
        level,
        visible: true,
        reason,
    }
}
