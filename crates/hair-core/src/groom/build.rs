//! Generating a groom on a head: sections on the scalp roots, skeletons at every level, strands.

use glam::{Vec2, Vec3};

use super::{Groom, GroomParams, Section, StrandSet};
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::head::{Head, ScalpRoot};
use crate::level::Level;
use crate::random::SplitMix64;
use crate::skeleton::SkeletonRest;

/// Distance from the part line within which a section counts as along the part, in section widths.
const PART_BAND_IN_WIDTHS: f32 = 0.75;

impl Groom {
    /// Generates a groom on `head` from `params` (validated first; every error names the parameter).
    ///
    /// Section roots come from [`Head::scalp_roots`] (crown to nape). Each section's root frame has
    /// its tangent (growth direction) lifted `root_lift_degrees` from the comb direction towards the
    /// scalp normal. Deterministic for a given seed, whatever the thread count.
    pub fn generate(params: &GroomParams, head: &Head) -> Result<Groom> {
        params.validate()?;
        let roots = head.scalp_roots(params.section_count)?;
        let width = match params.section_width {
            Some(width) => width,
            None => params.section_coverage * mean_nearest_neighbour_distance(&roots),
        };
        if !(width.is_finite() && width > 0.0) {
            return Err(HairError::invalid(
                "section width (m)",
                width,
                "a finite number > 0 (set it explicitly when there is a single section)",
            ));
        }
        let sections = roots
            .iter()
            .map(|root| make_section(root, width, params.root_lift_degrees))
            .collect::<Result<Vec<_>>>()?;
        let angles = params.style.chain_angles(params.hair_length)?;

        let mut skeletons = SkeletonRest::default();
        for level in Level::ALL {
            let count = level.skeletons_per_section();
            for section in &sections {
                for child in 0..count {
                    let root = child_root(head, section, child, count);
                    skeletons.push_chain(root, section.root_frame, &angles)?;
                }
            }
        }

        let s = sections.len();
        let cluster_root_radii = vec![width / 6.0; 3 * s];
        let cluster_tip_radii = vec![width / 6.0 * params.cluster_tip_scale; 3 * s];
        let patch_widths = vec![width; s];
        let group_radius = width / 10.0;
        let strand_group_radii = vec![group_radius; 5 * s];
        let strands = generate_strands(5 * s, params.strands_per_group, group_radius, params.seed);
        Ok(Groom {
            params: params.clone(),
            sections,
            skeletons,
            strands,
            cluster_root_radii,
            cluster_tip_radii,
            patch_widths,
            strand_group_radii,
        })
    }
}

/// A section at a scalp root.
fn make_section(root: &ScalpRoot, width: f32, lift_degrees: f32) -> Result<Section> {
    let (sin_lift, cos_lift) = lift_degrees.to_radians().sin_cos();
    let growth = root.comb_direction * cos_lift + root.normal * sin_lift;
    let root_frame = Frame::from_tangent_and_normal(growth, root.normal).ok_or_else(|| {
        HairError::invalid(
            "scalp root",
            format!("{:?}", root.position),
            "a root whose comb direction is not along its normal",
        )
    })?;
    Ok(Section {
        root_position: root.position,
        root_frame,
        width,
        crown_distance: root.crown_distance,
        part_distance: root.part_distance,
        along_part: root.part_distance < PART_BAND_IN_WIDTHS * width,
        around_face: root.near_face,
    })
}

/// The root of child `child` of `count`: the section root moved across the width along the
/// binormal and put back on the scalp. The centre child is the section root exactly.
fn child_root(head: &Head, section: &Section, child: usize, count: usize) -> Vec3 {
    if 2 * child + 1 == count {
        return section.root_position;
    }
    let moved =
        section.root_position + section.root_frame.binormal * section.child_offset(child, count);
    match moved.try_normalize() {
        Some(direction) => head.surface_point(direction).0,
        None => moved,
    }
}

/// Mean distance from each root to its nearest neighbour [m] (0 for fewer than two roots).
fn mean_nearest_neighbour_distance(roots: &[ScalpRoot]) -> f32 {
    if roots.len() < 2 {
        return 0.0;
    }
    let total: f32 = roots
        .iter()
        .enumerate()
        .map(|(i, a)| {
            roots
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, b)| a.position.distance(b.position))
                .fold(f32::INFINITY, f32::min)
        })
        .sum();
    total / roots.len() as f32
}

/// Strand roots spread over a half-ellipse above the scalp, `|y| ≤ r` across and `0 ≤ x ≤ r/2`
/// away from the scalp (`(y/r)² + (2x/r)² ≤ 1`), and shades uniform in `0..1`; one random stream per
/// group, so the result does not depend on the order groups are generated in.
fn generate_strands(
    group_count: usize,
    strands_per_group: usize,
    group_radius: f32,
    seed: u64,
) -> StrandSet {
    let total = group_count * strands_per_group;
    let mut strands = StrandSet {
        group_offsets: Vec::with_capacity(group_count + 1),
        root_offsets: Vec::with_capacity(total),
        shades: Vec::with_capacity(total),
    };
    strands.group_offsets.push(0);
    for group in 0..group_count {
        let mut rng = SplitMix64::for_item(seed, group as u64);
        for _ in 0..strands_per_group {
            let offset = loop {
                let y = rng.range(-1.0, 1.0);
                let x = rng.range(0.0, 1.0);
                if x * x + y * y <= 1.0 {
                    break Vec2::new(0.5 * x * group_radius, y * group_radius);
                }
            };
            strands.root_offsets.push(offset);
            strands.shades.push(rng.next_f32());
        }
        strands
            .group_offsets
            .push(strands.root_offsets.len() as u32);
    }
    strands
}
