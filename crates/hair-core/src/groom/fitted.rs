//! A groom from a fitted hierarchy ([`crate::fit`]): the sections, skeletons, strands, radii and
//! widths a [`FittedHierarchy`] measured on a file's curves, in the [`Groom`] the pipeline runs.

use glam::Vec3;

use super::{Groom, GroomParams, Section, StrandSet};
use crate::curves::Curves;
use crate::error::{HairError, Result};
use crate::fit::{FittedHierarchy, curve_length};
use crate::level::Level;
use crate::random::SplitMix64;

/// Shades of fitted strands are drawn uniformly from this range (the presets' spread of tones).
const SHADE_RANGE: (f32, f32) = (0.25, 0.75);
/// The shortest strand drawn, as a fraction of its skeleton's length.
const MIN_LENGTH_FRACTION: f32 = 0.05;

/// Child strands interpolated around each strand of a fitted groom, as DCC tools grow them
/// around guides: for a sparse groom (guides only) whose strand groups would otherwise hold too
/// few strands to look like hair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChildStrands {
    /// Children per file strand, `0..=1000` (0: the file's strands only).
    pub per_strand: usize,
    /// Radius [m] of the disc around its guide's root offset in which a child's root offset is
    /// drawn (uniformly), `>= 0`.
    pub spread: f32,
    /// A child's offset from its skeleton at the tip as a fraction of that at the root, `0..=1`
    /// ([`StrandSet::tip_scales`]: 1 parallel, smaller gathers the children to the tip).
    pub clump: f32,
}

impl Default for ChildStrands {
    /// None.
    fn default() -> Self {
        ChildStrands {
            per_strand: 0,
            spread: 0.002,
            clump: 0.5,
        }
    }
}

impl ChildStrands {
    /// Checks every field, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        if self.per_strand > 1000 {
            return Err(HairError::invalid(
                "children per strand",
                self.per_strand,
                "0..=1000",
            ));
        }
        crate::error::require_non_negative("child spread (m)", self.spread)?;
        crate::error::require_in_range("child clump", self.clump, 0.0, 1.0, "a fraction in 0..=1")?;
        Ok(())
    }
}

impl Groom {
    /// The groom of `fit`, fitted on `curves` (the same curves, in the same order): its
    /// skeletons ([`FittedHierarchy::skeleton_rest`]), its strands bound as root offsets in their
    /// strand group's node frames, each drawn to its own length (its curve's length over its
    /// skeleton's, at most 1), and shades drawn from `params.seed`.
    ///
    /// Sizes come from the fit: a cluster's root and tip radii are the fitted enclosing radii
    /// at its first and last node, a patch's width the mean of its fitted widths (at least the
    /// section's root spread), a strand group's radius the farthest strand root from its
    /// skeleton. A section's crown distance is measured from the highest section root (+Y), the
    /// loaded groom's crown; no section is marked along a part or around the face.
    ///
    /// `params` is kept as the groom's parameters (its style gives the material,
    /// [`DynamicsParams::for_style`](crate::dynamics::DynamicsParams::for_style)); its section
    /// count, strands per group and hair length are set from the fit. Fails when `curves` is not
    /// the fit's (a count differs) or a skeleton cannot be measured.
    pub fn from_fit(fit: &FittedHierarchy, curves: &Curves, params: &GroomParams) -> Result<Groom> {
        Groom::from_fit_with_children(fit, curves, params, &ChildStrands::default())
    }

    /// [`Groom::from_fit`] with `children` strands interpolated around each file strand: in
    /// each strand group, every file strand (in [`FittedHierarchy::group_strands`] order) is
    /// followed by its `children.per_strand` children, so file strand `k` of the group order is
    /// strand `k · (1 + per_strand)` of the groom. A child's root offset is its guide's plus a
    /// random point of the `spread` disc, its length its guide's, its tip scale `clump` (the
    /// file strands keep 1), and its shade drawn like the others.
    pub fn from_fit_with_children(
        fit: &FittedHierarchy,
        curves: &Curves,
        params: &GroomParams,
        children: &ChildStrands,
    ) -> Result<Groom> {
        children.validate()?;
        let s = fit.section_count();
        if curves.curve_count() != fit.strand_groups.len() || s == 0 {
            return Err(HairError::SizeMismatch {
                what: "fitted curves",
                actual: curves.curve_count(),
                expected: fit.strand_groups.len(),
            });
        }
        let skeletons = fit.skeleton_rest()?;
        let crown = fit
            .sections
            .iter()
            .map(|section| section.root_position)
            .max_by(|a, b| a.y.total_cmp(&b.y))
            .unwrap_or(Vec3::ZERO);
        let sections: Vec<Section> = fit
            .sections
            .iter()
            .map(|section| Section {
                root_position: section.root_position,
                root_frame: section.root_frame,
                width: section.width.max(1e-4),
                crown_distance: section.root_position.distance(crown),
                part_distance: f32::MAX,
                along_part: false,
                around_face: false,
            })
            .collect();

        let per = 1 + children.per_strand;
        let mut strands = StrandSet {
            group_offsets: fit.group_offsets.iter().map(|&o| o * per as u32).collect(),
            ..StrandSet::default()
        };
        let mut random = SplitMix64::new(params.seed);
        let mut strand_group_radii = Vec::with_capacity(5 * s);
        let mut total_length = 0.0f64;
        for group in 0..5 * s {
            let chain = Level::StrandGroup.chains(s).start + group;
            let skeleton_length = skeletons.chain_length(chain).max(f32::EPSILON);
            let mut radius = 0.0f32;
            for &curve in fit.group_members(group) {
                let curve = curve as usize;
                let range = curves.offsets[curve] as usize..curves.offsets[curve + 1] as usize;
                let length = curve_length(&curves.points[range]);
                total_length += f64::from(length);
                let fraction = (length / skeleton_length).clamp(MIN_LENGTH_FRACTION, 1.0);
                let guide = fit.root_offsets[curve];
                for child in 0..per {
                    let offset = if child == 0 {
                        guide
                    } else {
                        // Uniform in the disc: radius ∝ √u.
                        let r = children.spread * random.next_f32().sqrt();
                        let angle = std::f32::consts::TAU * random.next_f32();
                        guide + r * glam::Vec2::from_angle(angle)
                    };
                    radius = radius.max(offset.length());
                    strands.root_offsets.push(offset);
                    strands.lengths.push(fraction);
                    strands
                        .tip_scales
                        .push(if child == 0 { 1.0 } else { children.clump });
                    strands
                        .shades
                        .push(random.range(SHADE_RANGE.0, SHADE_RANGE.1));
                }
            }
            strand_group_radii.push(radius.max(1e-4));
        }

        let node_value = |values: &[f32], chain: usize, last: bool| -> f32 {
            let nodes = fit.nodes(chain);
            values[if last { nodes.end - 1 } else { nodes.start }]
        };
        let clusters = Level::Cluster.chains(s);
        let cluster_root_radii = clusters
            .clone()
            .map(|chain| node_value(&fit.node_radii, chain, false).max(1e-4))
            .collect();
        let cluster_tip_radii = clusters
            .map(|chain| node_value(&fit.node_radii, chain, true).max(1e-4))
            .collect();
        let patch_widths = Level::Patch
            .chains(s)
            .zip(&sections)
            .map(|(chain, section)| {
                let widths = &fit.node_widths[fit.nodes(chain)];
                let mean = widths.iter().sum::<f32>() / widths.len().max(1) as f32;
                mean.max(section.width)
            })
            .collect();

        let file_strands = fit.group_strands.len();
        let params = GroomParams {
            section_count: s,
            strands_per_group: strands.strand_count().div_ceil(5 * s).max(1),
            hair_length: (total_length / file_strands.max(1) as f64) as f32,
            ..params.clone()
        };
        Ok(Groom {
            params,
            sections,
            skeletons,
            strands,
            cluster_root_radii,
            cluster_tip_radii,
            patch_widths,
            strand_group_radii,
            children_per_guide: children.per_strand,
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::fit::{FitSettings, NodeCountScope, SectionCount, fit_hierarchy};

    /// 60 straight strands on a 10 × 6 grid of roots 5 mm apart, hanging down, 10 cm to 15 cm
    /// long.
    fn grid_curves() -> Curves {
        let mut curves = Curves {
            offsets: vec![0],
            ..Curves::default()
        };
        for i in 0..60 {
            let root = Vec3::new((i % 10) as f32 * 0.005, 0.0, (i / 10) as f32 * 0.005);
            let length = 0.10 + 0.05 * (i % 7) as f32 / 6.0;
            for k in 0..8 {
                curves.points.push(root - Vec3::Y * length * k as f32 / 7.0);
            }
            curves.offsets.push(curves.points.len() as u32);
        }
        curves
    }

    fn fit(curves: &Curves) -> FittedHierarchy {
        let settings = FitSettings {
            sections: SectionCount::Fixed(2),
            node_counts: NodeCountScope::Uniform,
            ..FitSettings::default()
        };
        fit_hierarchy(curves, &settings).unwrap()
    }

    /// The groom of a fit has its sections, chains and strands, each strand drawn to its own
    /// length (the longest at most its skeleton's) and sizes enclosing its strands.
    #[test]
    fn a_fitted_groom_has_the_fits_counts_lengths_and_sizes() {
        let curves = grid_curves();
        let fit = fit(&curves);
        let groom = Groom::from_fit(&fit, &curves, &GroomParams::straight()).unwrap();
        let counts = groom.counts();
        assert_eq!((counts.sections, counts.strands), (2, 60));
        assert_eq!(groom.skeletons.chain_count(), 18);
        assert_eq!(groom.params.section_count, 2);
        assert!(
            (groom.params.hair_length - 0.125).abs() < 0.01,
            "{}",
            groom.params.hair_length
        );
        // Lengths are fractions of the skeleton's; the 10 cm strands are shorter than their
        // skeleton (a mean of 10 to 15 cm strands), and none is longer than 1.
        assert!(groom.strands.lengths.iter().all(|&l| l > 0.5 && l <= 1.0));
        assert!(groom.strands.lengths.iter().any(|&l| l < 0.95));
        for (group, &radius) in groom.strand_group_radii.iter().enumerate() {
            for strand in groom.strands.strands(group) {
                assert!(groom.strands.root_offsets[strand].length() <= radius + 1e-6);
            }
        }
        assert!(groom.cluster_root_radii.iter().all(|&r| r > 0.0));
        assert!(
            groom
                .patch_widths
                .iter()
                .zip(&groom.sections)
                .all(|(w, s)| *w >= s.width)
        );
        assert_eq!(
            Groom::from_fit(&fit, &grid_curves_short(), &GroomParams::straight()).err(),
            Some(HairError::SizeMismatch {
                what: "fitted curves",
                actual: 59,
                expected: 60
            })
        );
    }

    fn grid_curves_short() -> Curves {
        let mut curves = grid_curves();
        curves.offsets.pop();
        curves
            .points
            .truncate(*curves.offsets.last().unwrap() as usize);
        curves
    }

    /// Children follow their guide: `per_strand` after each file strand, their roots within the
    /// spread of its offset, their tip scale the clump; the file strands keep theirs.
    #[test]
    fn child_strands_follow_their_guides() {
        let curves = grid_curves();
        let fit = fit(&curves);
        let children = ChildStrands {
            per_strand: 3,
            spread: 0.001,
            clump: 0.25,
        };
        let plain = Groom::from_fit(&fit, &curves, &GroomParams::straight()).unwrap();
        let groom =
            Groom::from_fit_with_children(&fit, &curves, &GroomParams::straight(), &children)
                .unwrap();
        assert_eq!(groom.strands.strand_count(), 4 * 60);
        assert_eq!(groom.strands.group_count(), plain.strands.group_count());
        // The guides are the file strands, every fourth strand (`Groom::is_guide`).
        assert_eq!((plain.children_per_guide, groom.children_per_guide), (0, 3));
        assert_eq!(groom.guide_count(), 60);
        for (k, &guide) in plain.strands.root_offsets.iter().enumerate() {
            assert!(groom.is_guide(4 * k) && !groom.is_guide(4 * k + 1));
            assert_eq!(groom.strands.root_offsets[4 * k], guide);
            assert_eq!(groom.strands.tip_scales[4 * k], 1.0);
            for child in 4 * k + 1..4 * k + 4 {
                let offset: Vec2 = groom.strands.root_offsets[child];
                assert!(offset.distance(guide) <= 0.001 + 1e-6);
                assert_eq!(groom.strands.tip_scales[child], 0.25);
                assert_eq!(groom.strands.lengths[child], plain.strands.lengths[k]);
            }
        }
        let bad = ChildStrands {
            clump: 2.0,
            ..children
        };
        let error = Groom::from_fit_with_children(&fit, &curves, &GroomParams::straight(), &bad);
        assert!(error.unwrap_err().to_string().contains("clump"));
    }
}
