//! Generating a groom on a head: sections on the scalp roots, skeletons at every level, strands.

use glam::Vec3;

use super::placement::generate_strands;
use super::{Groom, GroomParams, Section};
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::head::{Head, ScalpRoot};
use crate::level::Level;
use crate::skeleton::SkeletonRest;

/// Distance from the part line within which a section counts as along the part, in section widths.
const PART_BAND_IN_WIDTHS: f32 = 0.75;
/// Radius of a strand group's cross-section across the section, in section widths: the five
/// groups sit `w/5` apart, so at `0.2·w` each overlaps its neighbours by half its width and the
/// section's roots leave no gap between groups (the bare-scalp test, `tests/scalp_coverage.rs`,
/// measured 2.2 % of the hair's area from above at `0.16·w` and 1.8 % at `0.2·w`).
const GROUP_RADIUS_IN_WIDTHS: f32 = 0.2;

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
            None => params.section_coverage * root_spacing(head, &roots)?,
        };
        if !(width.is_finite() && width > 0.0) {
            return Err(HairError::invalid(
                "section width (m)",
                width,
                "a finite number > 0",
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
        let group_radius = GROUP_RADIUS_IN_WIDTHS * width;
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
            children_per_guide: 0,
        })
    }
}

/// A section at a scalp root.
fn make_section(root: &ScalpRoot, width: f32, lift_degrees: f32) -> Result<Section> {
    let (sin_lift, cos_lift) = lift_degrees.to_radians().sin_cos();
    let comb = level_where_climbing(root.comb_direction, root.normal);
    let growth = comb * cos_lift + root.normal * sin_lift;
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

/// The comb direction `comb` (a unit tangent of the scalp at a root with unit normal `normal`),
/// turned to the scalp's level line where it climbs (`comb.y > 0`), keeping its side.
///
/// Between a side part and the top of the head the comb field points across the head, uphill:
/// hair grown that way leaves the scalp rising, and a stiff (curly) style keeps it standing
/// above the head at rest. Turned level, it leaves along the head and drapes over it. The turn
/// is continuous: a direction just above level is turned by a small angle.
fn level_where_climbing(comb: Vec3, normal: Vec3) -> Vec3 {
    if comb.y <= 0.0 {
        return comb;
    }
    match normal.cross(Vec3::Y).try_normalize() {
        Some(level) if level.dot(comb) >= 0.0 => level,
        Some(level) => -level,
        // The scalp is horizontal here: every tangent is level already.
        None => comb,
    }
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

/// The spacing of the section roots [m]: the mean distance from each root to its nearest
/// neighbour. A single root has no neighbour: it takes the spacing of the two roots
/// [`Head::scalp_roots`] places for two sections (9.6 cm on the default head), so one section
/// is as wide as each of two (and of three to five, 9.6 to 11 cm apart), not the whole scalp's
/// width, which would put its outer strand groups over the ears.
fn root_spacing(head: &Head, roots: &[ScalpRoot]) -> Result<f32> {
    if roots.len() >= 2 {
        Ok(mean_nearest_neighbour_distance(roots))
    } else {
        Ok(mean_nearest_neighbour_distance(&head.scalp_roots(2)?))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A direction climbing the scalp turns to the level line on its side; others are kept.
    #[test]
    fn climbing_comb_directions_turn_level() {
        let normal = Vec3::new(0.6, 0.8, 0.0);
        let uphill = Vec3::new(-0.8, 0.6, 0.0);
        let climbing = (uphill + Vec3::Z).normalize();
        let turned = level_where_climbing(climbing, normal);
        assert!(turned.y.abs() < 1e-6 && turned.dot(normal).abs() < 1e-6);
        assert!((turned - Vec3::Z).length() < 1e-6, "{turned}");
        let downhill = -climbing;
        assert_eq!(level_where_climbing(downhill, normal), downhill);
        assert_eq!(level_where_climbing(Vec3::X, Vec3::Y), Vec3::X);
    }

    /// One section builds (it has no neighbour to take its width from): as wide as each of two,
    /// with every level's skeleton and strand in place.
    #[test]
    fn a_single_section_is_as_wide_as_each_of_two() {
        let head = Head::procedural(&crate::head::HeadParams::default()).unwrap();
        let params = |sections| GroomParams {
            section_count: sections,
            strands_per_group: 1,
            ..GroomParams::straight()
        };
        let one = Groom::generate(&params(1), &head).unwrap();
        let two = Groom::generate(&params(2), &head).unwrap();
        assert_eq!(one.section_count(), 1);
        let width = one.sections[0].width;
        assert_eq!(width, two.sections[0].width);
        // 1.5 × the 9.6 cm spacing of two roots: a patch, not the scalp (about 23 cm across).
        assert!((0.1..0.2).contains(&width), "{width}");
        assert_eq!(one.strands.strand_count(), 5);
        assert_eq!(one.patch_widths, [width]);
        let nodes = one
            .skeletons
            .rest_positions(&crate::RigidTransform::IDENTITY);
        assert!(!nodes.is_empty() && nodes.iter().all(|p| p.is_finite()));
    }
}
