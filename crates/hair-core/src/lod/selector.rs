//! The selector: every section's level each frame (§7.4), by pixel tolerance or within a frame
//! budget, remembering the last choices, depths and blend shares; one section's choice is in
//! `section_choice`.

use glam::Vec3;

use super::cost_model::{CostModel, SectionWork};
use super::criteria::{distance_limits, error_ahead};
use super::deviation::{LevelDeviation, level_deviations};
use super::greedy::{BudgetOutcome, SectionOptions, refine_within_budget};
use super::observation::SectionObservation;
use super::section_choice::{
    Lookahead, Reason, SectionChoice, SectionConstants, choose, covered_pixels, depth_of,
    estimated_errors, hidden_reason, motion_level, rules_apply,
};
use super::settings::{ErrorModel, LodSettings};
use crate::camera::Camera;
use crate::error::{HairError, Result};
use crate::groom::Groom;
use crate::level::Level;
use crate::transform::RigidTransform;

/// Per-section buffers of a budgeted choice, kept between frames.
#[derive(Debug, Clone, Default)]
struct BudgetScratch {
    options: Vec<SectionOptions>,
    hidden: Vec<Option<Reason>>,
    motion: Vec<Level>,
    levels: Vec<Level>,
}

/// Chooses every section's level each frame, remembering the last choice for hysteresis.
#[derive(Debug, Clone)]
pub struct LodSelector {
    settings: LodSettings,
    constants: Vec<SectionConstants>,
    choices: Vec<SectionChoice>,
    occluders: Vec<(Vec3, Vec3)>,
    budget_scratch: BudgetScratch,
    /// Each section's depth [m] at the last choice (of its bound centre, where its errors are
    /// measured; 0: not seen yet), for looking ahead.
    depths: Vec<f32>,
    /// How many frames ahead the level choice looks
    /// ([`LodSettings::blend_lead`] · blend time / frame time; 0 until
    /// [`LodSelector::set_frame_time`]).
    lead_frames: f32,
    /// Each section's share of the blend time for a switch its last choice starts (see
    /// [`blend_shares`](LodSelector::blend_shares)).
    blend_shares: Vec<f32>,
}

impl LodSelector {
    /// The occluding boxes (head space \[m\], inside the head) the next choices test against:
    /// a deforming body's, which follow it ([`carried_boxes`](crate::lod::carried_boxes)).
    pub fn set_occluders(&mut self, occluders: &[(Vec3, Vec3)]) {
        self.occluders.clear();
        self.occluders.extend_from_slice(occluders);
    }

    /// A selector for `groom` on a head whose occluding boxes are `occluders` (head space [m],
    /// inside the head: [`Head::occluder_boxes`](crate::Head::occluder_boxes)); every section
    /// starts as a visible patch. With the error-driven model the sections' deviations are
    /// measured here ([`level_deviations`]).
    pub fn new(groom: &Groom, occluders: &[(Vec3, Vec3)], settings: LodSettings) -> Result<Self> {
        settings.validate()?;
        let deviations = match settings.error_model {
            ErrorModel::Deviation => level_deviations(groom)?,
            ErrorModel::Chord => vec![LevelDeviation::default(); groom.section_count()],
        };
        Self::with_deviations(groom, occluders, settings, &deviations)
    }

    /// [`LodSelector::new`] with the sections' deviations [m] already measured (one per section).
    pub fn with_deviations(
        groom: &Groom,
        occluders: &[(Vec3, Vec3)],
        settings: LodSettings,
        deviations: &[LevelDeviation],
    ) -> Result<Self> {
        settings.validate()?;
        if deviations.len() != groom.section_count() {
            return Err(HairError::SizeMismatch {
                what: "section deviations",
                actual: deviations.len(),
                expected: groom.section_count(),
            });
        }
        let patches = groom.level_chains(Level::Patch);
        let constants = groom
            .sections
            .iter()
            .zip(patches)
            .zip(deviations)
            .map(|((section, chain), &deviation)| {
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
                    deviation,
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
            budget_scratch: BudgetScratch::default(),
            depths: vec![0.0; groom.section_count()],
            lead_frames: 0.0,
            blend_shares: vec![1.0; groom.section_count()],
        })
    }

    /// Tells the selector how long a frame (one [`select`](Self::select) to the next) lasts [s],
    /// so that it can look [`LodSettings::blend_lead`] of the blend time ahead; errors when
    /// `frame_time` is not positive and finite.
    pub fn set_frame_time(&mut self, frame_time: f32) -> Result<()> {
        if !(frame_time.is_finite() && frame_time > 0.0) {
            return Err(HairError::invalid(
                "LOD frame time (s)",
                frame_time,
                "positive and finite",
            ));
        }
        self.lead_frames = self.settings.blend_lead * self.settings.blend_time / frame_time;
        Ok(())
    }

    /// How many frames ahead the level choice looks (0 until
    /// [`set_frame_time`](Self::set_frame_time)).
    pub fn lead_frames(&self) -> f32 {
        self.lead_frames
    }

    /// Each section's depth [m] at the last choice (of its bound centre, where its errors are
    /// measured; 0 where not seen yet or not finite, and negative behind the eye: unknown to the
    /// look ahead): what looking ahead compares the next frame's depths with. A run resumed from
    /// a checkpoint restores it with [`restore_depths`](Self::restore_depths).
    pub fn depths(&self) -> &[f32] {
        &self.depths
    }

    /// Restores the depths saved from [`depths`](Self::depths); an empty slice forgets them (the
    /// next choice does not look ahead); errors when the count is neither 0 nor the section count.
    pub fn restore_depths(&mut self, depths: &[f32]) -> Result<()> {
        if depths.is_empty() {
            self.depths.fill(0.0);
            return Ok(());
        }
        if depths.len() != self.depths.len() {
            return Err(HairError::SizeMismatch {
                what: "section depths",
                actual: depths.len(),
                expected: self.depths.len(),
            });
        }
        self.depths.copy_from_slice(depths);
        Ok(())
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

    /// Each section's share of the blend time, in `(0, 1]`, for a level switch its last choice
    /// starts. 1, the whole blend, unless the look ahead brought the switch forward: a switch
    /// foreseen `k` frames ahead, fewer than the [`lead_frames`](Self::lead_frames) `n`, gets
    /// `k / n` of the blend, so that its new level is fully in (at half the blend) by the frame
    /// the tolerance is crossed, as a switch foreseen a whole lead ahead is
    /// ([`foreseen_share`](super::foreseen_share)). That happens where the crossing comes sooner
    /// than the lead: at the start of a shot (the first choice has no depth to look ahead from)
    /// or when a section speeds up. A switch for motion, a rule, visibility or a budget gets the
    /// whole blend.
    pub fn blend_shares(&self) -> &[f32] {
        &self.blend_shares
    }

    /// The distance limits [pixels] of section `section` (patch → clusters, clusters → strands).
    pub fn distance_limits(&self, section: usize) -> [f32; 2] {
        self.constants[section].limits
    }

    /// The measured deviations [m] of section `section`'s patch and clusters from its strands
    /// (zero under the `Chord` error model, which does not measure them).
    pub fn deviation(&self, section: usize) -> LevelDeviation {
        self.constants[section].deviation
    }

    /// The estimated screen-space error [pixels] of each level of section `section` seen as in
    /// `observation` by `camera` (indexed by [`Level`] rank: patch, clusters, strand groups), under
    /// the selector's error model, without the crown boost; infinite for a coarse level when the
    /// section is at or behind the eye.
    pub fn estimated_errors(
        &self,
        section: usize,
        observation: &SectionObservation,
        camera: &Camera,
    ) -> [f32; 3] {
        estimated_errors(
            &self.constants[section],
            observation,
            camera,
            &self.settings,
        )
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
        for ((((choice, share), constants), observation), depth) in self
            .choices
            .iter_mut()
            .zip(&mut self.blend_shares)
            .zip(&self.constants)
            .zip(observations)
            .zip(&mut self.depths)
        {
            let now = depth_of(camera, observation.bound_centre);
            let look = Lookahead {
                previous: *depth,
                now,
                frames: self.lead_frames,
                near: camera.near,
            };
            *depth = if now.is_finite() { now } else { 0.0 };
            (*choice, *share) = choose(
                choice.level,
                constants,
                observation,
                camera,
                head,
                &self.occluders,
                &settings,
                aspect,
                &look,
            );
        }
        Ok(&self.choices)
    }

    /// Chooses the level of every section so that the predicted cost of the frame stays within
    /// `budget` [s] and the sum of the visible sections' estimated errors [pixels] is least
    /// ([`refine_within_budget`]); the pixel tolerance plays no part. Visibility, motion and the
    /// per-section rules set each section's floor as in [`select`](Self::select); hidden sections
    /// stay patches. Each section's cost comes from `model` for its `work` (one per section). A
    /// section keeps a finer current level unless the coarser one's error, raised by the
    /// hysteresis band, is still worth the cost saved. Returns the choices and the outcome.
    ///
    /// The same as [`budget_options`](Self::budget_options), [`refine_within_budget`] over them,
    /// then [`choose_levels`](Self::choose_levels); a crowd runs the refinement once over the
    /// options of every character's sections, so that one budget is shared.
    pub fn select_within_budget(
        &mut self,
        observations: &[SectionObservation],
        camera: &Camera,
        head: &RigidTransform,
        budget: f64,
        model: &CostModel,
        work: &[SectionWork],
    ) -> Result<(&[SectionChoice], BudgetOutcome)> {
        self.budget_options(observations, camera, head, model, work)?;
        let scratch = &mut self.budget_scratch;
        scratch.levels.resize(scratch.options.len(), Level::Patch);
        let outcome = refine_within_budget(&scratch.options, budget, &mut scratch.levels);
        let levels = std::mem::take(&mut self.budget_scratch.levels);
        let chosen = self.choose_levels(&levels).map(|_| ());
        self.budget_scratch.levels = levels;
        chosen?;
        Ok((&self.choices, outcome))
    }

    /// Every section's options for a budgeted choice: its estimated error [pixels] at each level
    /// (0 when hidden; finer levels than its current one raised by the hysteresis band), its cost
    /// [s] at each level from `model` for its `work`, and its floor (motion and the part/face rule
    /// for a visible section, patch for a hidden one). Kept for [`choose_levels`](Self::choose_levels).
    pub fn budget_options(
        &mut self,
        observations: &[SectionObservation],
        camera: &Camera,
        head: &RigidTransform,
        model: &CostModel,
        work: &[SectionWork],
    ) -> Result<&[SectionOptions]> {
        if work.len() != self.choices.len() {
            return Err(HairError::SizeMismatch {
                what: "section work",
                actual: work.len(),
                expected: self.choices.len(),
            });
        }
        if observations.len() != self.choices.len() {
            return Err(HairError::SizeMismatch {
                what: "section observations",
                actual: observations.len(),
                expected: self.choices.len(),
            });
        }
        camera.validate()?;
        let settings = self.settings;
        let (aspect, band) = (settings.aspect(), settings.hysteresis);
        let scratch = &mut self.budget_scratch;
        scratch.options.clear();
        scratch.hidden.clear();
        scratch.motion.clear();
        for (section, (choice, observation)) in self.choices.iter().zip(observations).enumerate() {
            // The budget weighs the errors the levels will make half a blend ahead, as the
            // tolerance controller does.
            let now = depth_of(camera, observation.bound_centre);
            let ahead = error_ahead(self.depths[section], now, self.lead_frames, camera.near);
            self.depths[section] = if now.is_finite() { now } else { 0.0 };
            let constants = &self.constants[section];
            let previous = choice.level;
            let hidden = hidden_reason(
                observation,
                camera,
                head,
                &self.occluders,
                &settings,
                aspect,
            );
            // Floors: motion and the part/face rule for a visible section large enough on
            // screen, patch for a hidden one.
            let rules = hidden.is_none() && rules_apply(observation, camera, &settings);
            let motion = if rules {
                motion_level(observation, previous, &settings)
            } else {
                Level::Patch
            };
            let floor = match hidden {
                Some(_) => Level::Patch,
                None if rules && constants.keep_clusters => motion.max(Level::Cluster),
                None => motion,
            };
            let mut errors = match hidden {
                Some(_) => [0.0; 3],
                None => estimated_errors(constants, observation, camera, &settings)
                    .map(|e| e * constants.crown_factor * ahead),
            };
            for level in Level::ALL {
                if level < previous {
                    errors[level as usize] *= 1.0 + band;
                }
                if !errors[level as usize].is_finite() {
                    errors[level as usize] = f32::MAX;
                }
            }
            let pixels = hidden
                .is_none()
                .then(|| covered_pixels(camera, observation, &settings));
            scratch.options.push(SectionOptions {
                errors,
                costs: model.section_costs(&work[section], pixels),
                floor,
            });
            scratch.hidden.push(hidden);
            scratch.motion.push(motion);
        }
        Ok(&scratch.options)
    }

    /// Takes `levels` (one per section, each at or above its floor) for the sections whose
    /// options [`budget_options`](Self::budget_options) made last, with the reasons: hidden
    /// sections keep theirs; a visible one is at `Distance` when above its floor (or a patch),
    /// else at `Motion` or `Rule`, whichever set the floor. Returns the choices.
    pub fn choose_levels(&mut self, levels: &[Level]) -> Result<&[SectionChoice]> {
        let scratch = &self.budget_scratch;
        if levels.len() != self.choices.len() || scratch.options.len() != self.choices.len() {
            return Err(HairError::SizeMismatch {
                what: "budgeted levels (make the options first)",
                actual: levels.len().min(scratch.options.len()),
                expected: self.choices.len(),
            });
        }
        self.blend_shares.fill(1.0);
        for (section, choice) in self.choices.iter_mut().enumerate() {
            let (level, option) = (
                levels[section].max(scratch.options[section].floor),
                &scratch.options[section],
            );
            *choice = match scratch.hidden[section] {
                Some(reason) => SectionChoice {
                    level,
                    visible: false,
                    reason,
                },
                None => SectionChoice {
                    level,
                    visible: true,
                    reason: if level > option.floor || level == Level::Patch {
                        Reason::Distance
                    } else if scratch.motion[section] == option.floor {
                        Reason::Motion
                    } else {
                        Reason::Rule
                    },
                },
            };
        }
        Ok(&self.choices)
    }
}
