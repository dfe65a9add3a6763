//! A section of hair: one area of the scalp that is a patch, three clusters or five strand groups.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::frame::Frame;

/// One section (§4.2, §7.2): the same area of hair at every level of detail.
///
/// All its skeletons share the root frame; their roots are laid across the section's width along the
/// frame's binormal: the patch at the centre, clusters at `−w/3, 0, +w/3`, strand groups at
/// `−2w/5, −w/5, 0, +w/5, +2w/5` (each the centre of an equal share of the width), projected onto
/// the scalp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Root of the centre skeleton on the scalp, head space [m].
    pub root_position: Vec3,
    /// Root frame shared by the section's skeletons: tangent = growth direction, normal = away from
    /// the scalp, binormal = across the section.
    pub root_frame: Frame,
    /// Width across the section [m].
    pub width: f32,
    /// Distance of the root from the crown [m] (crown sections keep strands longer, §7.4).
    pub crown_distance: f32,
    /// Distance of the root from the part line [m].
    pub part_distance: f32,
    /// The root lies along the part line: the section never goes below clusters when visible (§6).
    pub along_part: bool,
    /// The root lies around the face: the section never goes below clusters when visible (§6).
    pub around_face: bool,
}

impl Section {
    /// Offset of child `child` of `count` side-by-side skeletons from the section's centre, along
    /// the binormal [m]: `(child + ½) · w / count − w / 2`.
    pub fn child_offset(&self, child: usize, count: usize) -> f32 {
        (child as f32 + 0.5) * self.width / count as f32 - 0.5 * self.width
    }
}
