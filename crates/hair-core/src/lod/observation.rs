//! What the selector sees of one section each frame: its ends, bound, motion measure and the
//! samples of the occlusion test, measured on its active skeletons.

use glam::Vec3;

use crate::groom::Groom;
use crate::level::Level;

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
    /// Samples of the section for the occlusion test [m]: nodes of the centre skeleton from root
    /// to tip, then of the outermost skeletons (the centre's again at patch level).
    pub sight: [Vec3; SIGHT_SAMPLES],
    /// How far the section reaches across its skeletons [m]: half its width, the margin by
    /// which the occlusion test widens each sample.
    pub sight_radius: f32,
}

/// Samples of a section in the occlusion test: 7 along the centre skeleton, 3 along each of the
/// two outermost.
pub const SIGHT_SAMPLES: usize = 13;

/// The `k`-th of `n` samples along a chain of `count` nodes starting at `first` in `positions`:
/// node `round(k·(count − 1)/(n − 1))`, or `round((k + 1)·(count − 1)/n)` with `skip_root`.
fn chain_sample(
    positions: &[Vec3],
    first: usize,
    count: usize,
    k: usize,
    n: usize,
    skip_root: bool,
) -> Vec3 {
    let last = count.saturating_sub(1) as f32;
    let t = if skip_root {
        (k + 1) as f32 / n as f32
    } else {
        k as f32 / (n - 1).max(1) as f32
    };
    positions[first + (t * last).round() as usize]
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
        // The outermost skeletons: the first and the last of the section's chains at this level.
        let first_count = groom.skeletons.chain_node_count(chains.start);
        let last_count = groom.skeletons.chain_node_count(chains.end - 1);
        let last_start = positions.len() - last_count;
        let mut sight = [top; SIGHT_SAMPLES];
        for (k, point) in sight[..7].iter_mut().enumerate() {
            *point = chain_sample(positions, before, count, k, 7, false);
        }
        for k in 0..3 {
            sight[7 + k] = chain_sample(positions, 0, first_count, k, 3, true);
            sight[10 + k] = chain_sample(positions, last_start, last_count, k, 3, true);
        }
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
            sight,
            sight_radius: 0.5 * groom.sections[section].width,
        }
    }
}
