//! The user-facing knobs of level-of-detail selection (§7) and transitions (§4.2), with defaults.

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result, require_non_negative, require_positive};

crate::named_enum! {
    /// How the selector estimates the screen-space error [pixels] a coarse level makes.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum ErrorModel {
        /// Error-driven: each section's own measured deviation of its patch and of its clusters from
        /// its strands ([`LevelDeviation`](super::LevelDeviation), metres, measured at rest when the
        /// selector is built) times the pixels a metre covers at the section's depth,
        /// `e_px = e · f / z` (`f` the focal length in pixels, `z` the depth of the section's bound
        /// centre).
        #[default]
        Deviation = "deviation",
        /// The paper's rule (§7.4): one error per level from the section's width, `w/6` for a patch
        /// and `w/10` for clusters, scaled by the section's projected chord, `e_px = e · ℓ / L`.
        Chord = "chord",
    }
}

crate::named_enum! {
    /// How the occlusion test (§7.1) decides that a section is hidden behind the head.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum OcclusionTest {
        /// The whole section: sight lines to samples of its centre skeleton's nodes (root to tip)
        /// and of its outermost skeletons', each widened by half the section's width across the line
        /// of sight, must all be blocked
        /// ([`is_section_occluded`](super::criteria::is_section_occluded)).
        #[default]
        Section = "section",
        /// The paper's test: the root and the tip of the centre skeleton
        /// ([`is_occluded`](super::criteria::is_occluded)). It hides sections that show between or
        /// beside their ends (wavy and curly hair, sections beside the head's silhouette).
        Ends = "ends",
    }
}

/// Settings of the level-of-detail selector.
///
/// A section takes the cheapest level whose estimated screen-space error is within one pixel
/// tolerance (§7.4), at least the level its motion asks for. [`ErrorModel`] says how the error is
/// estimated: from each section's measured deviations (the default), or as in the paper from its
/// width and projected chord: a level whose geometric error is `e` [m] on a section of length `L`
/// [m] that projects to `ℓ` pixels makes an error of about `e · ℓ / L` pixels, so it is good
/// enough while `ℓ ≤ tolerance · L / e`, with `e = w/6` for a patch (the depth a flat strip cannot
/// show) and `w/10` for clusters (the radius of the strand groups they replace).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LodSettings {
    /// Screen-space error tolerance [pixels]: larger means coarser levels sooner.
    pub pixel_tolerance: f32,
    /// Image height [pixels] the screen sizes are measured for.
    pub image_height: u32,
    /// Image width [pixels] (for the frustum's aspect ratio).
    pub image_width: u32,
    /// Motion measure (strongest force per unit mass on a node, gravity excluded [m/s²]) above
    /// which a section is at least clusters.
    pub cluster_force_threshold: f32,
    /// Motion measure [m/s²] above which a section is strand groups.
    pub strand_force_threshold: f32,
    /// Relative hysteresis band: a level is entered above `limit·(1 + band)` and left below
    /// `limit·(1 − band)`, so a section sitting on a threshold does not flip every frame.
    pub hysteresis: f32,
    /// Distance from the crown [m] within which sections keep strands longer (§7.4).
    pub crown_radius: f32,
    /// Screen-size boost at the crown itself (falls linearly to 1 at `crown_radius`): crown sections
    /// are judged as if `1 + crown_boost` times larger.
    pub crown_boost: f32,
    /// Visible sections along the part line and around the face never go below clusters (§7.4).
    pub keep_part_and_face_detailed: bool,
    /// Occlusion test on (§7.1): hidden sections become patches and are not drawn.
    pub occlusion: bool,
    /// Which occlusion test decides that a section is hidden.
    pub occlusion_test: OcclusionTest,
    /// Duration of a transition's blend [s] (0: instant switching, as in the paper).
    pub blend_time: f32,
    /// How far ahead the error-driven choice looks, as a fraction of
    /// [`blend_time`](Self::blend_time), `0..=1`: each section's screen-space errors are
    /// extrapolated that far ahead from the change of its depth over the last frame (errors go as
    /// `1/z`), so that a transition's blend is under way when the tolerance is crossed rather than
    /// starting then. At 0.5 (the default) a receding section's coarser level has dissolved fully
    /// in (a new level's coverage reaches 1 at half the blend) by the time its error comes within
    /// tolerance, and an approaching section's finer level is fully in by the time the coarser
    /// one's error leaves it. 0: the choice sees the current frame only. The tolerance
    /// controller and the budgeted choice (on its estimated errors) both look ahead, only when
    /// told the frame time
    /// ([`LodSelector::set_frame_time`](super::LodSelector::set_frame_time), as the pipeline does).
    pub blend_lead: f32,
    /// How a coarse level's screen-space error is estimated.
    pub error_model: ErrorModel,
    /// The motion criterion (§7.3) and the part/face rule raise a section's level only while its
    /// root-to-tip chord projects to at least this many pixels; smaller sections follow their
    /// screen-space error alone [pixels]. A head 30 m away spans a few pixels: its shaking is
    /// not worth strands. 0: always (the paper's rule, for one head near the camera).
    pub rules_min_pixels: f32,
    /// Strand thinning: a strand group at the strand level draws this many strands per pixel of
    /// its projected width, at least one and at most all (a stochastic simplification; the
    /// renderer's `StrandThinning`). 0 (the default) draws every strand.
    pub strands_per_pixel: f32,
    /// With thinning: each strand drawn is widened to stand for the strands left out (`1/φ` its
    /// width for a drawn fraction φ, at most its group's width on screen), so that a thinned
    /// group covers the pixels all its strands cover (the renderer's `raise_widths`).
    pub raise_thinned_widths: bool,
}

impl Default for LodSettings {
    fn default() -> Self {
        LodSettings {
            pixel_tolerance: 2.0,
            image_height: 720,
            image_width: 1280,
            cluster_force_threshold: 4.0,
            strand_force_threshold: 8.0,
            hysteresis: 0.1,
            crown_radius: 0.05,
            crown_boost: 0.5,
            keep_part_and_face_detailed: true,
            occlusion: true,
            occlusion_test: OcclusionTest::Section,
            blend_time: 0.25,
            blend_lead: 0.5,
            error_model: ErrorModel::Deviation,
            rules_min_pixels: 20.0,
            strands_per_pixel: 0.0,
            raise_thinned_widths: false,
        }
    }
}

impl LodSettings {
    /// Checks every setting, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        require_positive("LOD pixel tolerance (pixels)", self.pixel_tolerance)?;
        if self.image_height == 0 || self.image_width == 0 {
            return Err(HairError::invalid(
                "LOD image size (pixels)",
                format!("{}x{}", self.image_width, self.image_height),
                "at least 1x1",
            ));
        }
        require_non_negative(
            "cluster force threshold (m/s²)",
            self.cluster_force_threshold,
        )?;
        require_non_negative("strand force threshold (m/s²)", self.strand_force_threshold)?;
        if self.strand_force_threshold < self.cluster_force_threshold {
            return Err(HairError::invalid(
                "strand force threshold (m/s²)",
                self.strand_force_threshold,
                "at least the cluster force threshold",
            ));
        }
        if !(0.0..0.9).contains(&self.hysteresis) {
            return Err(HairError::invalid(
                "LOD hysteresis band",
                self.hysteresis,
                "0 <= band < 0.9",
            ));
        }
        require_non_negative("crown radius (m)", self.crown_radius)?;
        require_non_negative("rules' smallest section (pixels)", self.rules_min_pixels)?;
        require_non_negative(
            "strand thinning (strands per pixel)",
            self.strands_per_pixel,
        )?;
        require_non_negative("crown boost", self.crown_boost)?;
        require_non_negative("LOD blend time (s)", self.blend_time)?;
        if !(0.0..=1.0).contains(&self.blend_lead) {
            return Err(HairError::invalid(
                "LOD blend lead (fraction of the blend time)",
                self.blend_lead,
                "0..=1",
            ));
        }
        Ok(())
    }

    /// Aspect ratio of the image the levels are chosen for.
    pub fn aspect(&self) -> f32 {
        self.image_width as f32 / self.image_height as f32
    }
}
