//! [`fit_hierarchy`]: curves in, sections with skeletons at every level and their errors out.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::element::{
    Candidate, FittedElement, MemberCurves, candidates, fit_element, nodes_needed,
};
use super::hierarchy::{CLUSTER_OF_GROUP, FittedHierarchy, FittedSection};
use super::partition::{
    GROUPS, Prepared, partition_sections, prepare, section_frame, split_groups,
};
use super::report::{ErrorStats, FitReport, LevelErrors};
use super::resample::resample_into;
use super::settings::{FitSettings, NodeCountScope};
use crate::curves::Curves;
use crate::error::Result;
use crate::frame::Frame;
use crate::level::Level;
use crate::per_level::PerLevel;

/// Elements per section: 1 patch, 3 clusters, 5 strand groups, in that order.
const ELEMENTS: usize = 9;

/// The level and child of element `e` of a section.
fn element_level(e: usize) -> (Level, usize) {
    match e {
        0 => (Level::Patch, 0),
        1..=3 => (Level::Cluster, e - 1),
        _ => (Level::StrandGroup, e - 4),
    }
}

/// A section after partition, before node counts are settled.
struct SectionPlan {
    frame: Frame,
    /// The strands of each element (patch, clusters, groups), each in curve order.
    elements: Vec<Vec<u32>>,
    candidates: Vec<Vec<Candidate>>,
    nodes_needed: usize,
}

/// A fitted section.
struct SectionFit {
    frame: Frame,
    elements: Vec<Vec<u32>>,
    fitted: Vec<FittedElement>,
    /// `(curve, (mean, largest))` discretisation error of each strand.
    floor: Vec<(u32, (f32, f32))>,
}

/// Plans a section: its frame, its 5 groups, 3 clusters and patch, their candidates and the
/// nodes they need.
fn plan_section(prepared: &Prepared, members: Vec<u32>, settings: &FitSettings) -> SectionPlan {
    let frame = section_frame(prepared, &members);
    let groups = split_groups(prepared, &members, &frame, settings);
    let mut elements: Vec<Vec<u32>> = Vec::with_capacity(ELEMENTS);
    elements.push(members);
    for cluster in 0..3 {
        let mut strands: Vec<u32> = (0..GROUPS)
            .filter(|&g| CLUSTER_OF_GROUP[g] == cluster)
            .flat_map(|g| groups[g].iter().copied())
            .collect();
        strands.sort_unstable();
        elements.push(strands);
    }
    elements.extend(groups);
    let candidates: Vec<Vec<Candidate>> = elements
        .iter()
        .map(|strands| candidates(prepared, strands, settings.representative))
        .collect();
    let nodes_needed = candidates
        .iter()
        .flatten()
        .map(|c| nodes_needed(c, &settings.smoothness))
        .max()
        .unwrap_or(4);
    SectionPlan {
        frame,
        elements,
        candidates,
        nodes_needed,
    }
}

/// Fits a planned section's elements at `node_count` nodes.
fn fit_section(
    curves: &Curves,
    prepared: &Prepared,
    plan: SectionPlan,
    node_count: usize,
) -> SectionFit {
    let all = &plan.elements[0];
    // Every strand of the section at the node count, from its original points.
    let at_nodes: Vec<Vec<Vec3>> = all
        .iter()
        .map(|&i| {
            let mut out = vec![Vec3::ZERO; node_count];
            // Curves were checked by `prepare`, so this succeeds.
            resample_into(curves.curve(i as usize), &mut out);
            out
        })
        .collect();
    let floor = all
        .iter()
        .zip(&at_nodes)
        .map(|(&i, nodes)| {
            let samples = prepared.strand(i as usize);
            let m = samples.len();
            let mut total = 0.0f64;
            let mut largest = 0.0f32;
            for (k, s) in samples.iter().enumerate() {
                let d = super::resample::at_fraction(nodes, k as f32 / (m - 1) as f32).distance(*s);
                total += f64::from(d);
                largest = largest.max(d);
            }
            (i, ((total / m as f64) as f32, largest))
        })
        .collect();
    let fitted = plan
        .elements
        .iter()
        .zip(&plan.candidates)
        .map(|(strands, candidates)| {
            // `all` is sorted and every element's strands are a subset of it.
            let member_nodes: Vec<Vec<Vec3>> = strands
                .iter()
                .map(|i| {
                    let at = all.binary_search(i).unwrap_or(0);
                    at_nodes[at].clone()
                })
                .collect();
            let members = MemberCurves {
                prepared,
                members: strands,
                at_nodes: &member_nodes,
            };
            fit_element(candidates, &members, node_count, &plan.frame)
        })
        .collect();
    SectionFit {
        frame: plan.frame,
        elements: plan.elements,
        fitted,
        floor,
    }
}

/// Fits the paper's hierarchy (§3) to a groom's curves: sections of 5 strand groups, 3 clusters
/// and 1 patch, each with a skeleton, and the errors of every level against the strands.
///
/// 1. Every curve is resampled to `samples_per_strand` points at equal arc-length steps and
///    described by its root and, weighted by `shape_weight`, its middle and tip relative to the
///    root.
/// 2. Sections: balanced k-means on those features (greedy k-means++ from `seed`, Lloyd, then a
///    capacity-limited reassignment so no section exceeds `(N/S)·(1 + slack)` strands). Sections
///    of fewer than 5 strands are merged into the nearest section (by root centroid), smallest
///    first, and counted in [`FitReport::merged_sections`].
/// 3. Strand groups: each section's strands cut into 5 groups of equal size (within one) by
///    balanced k-means on the same features, numbered along the section's binormal (or, with
///    [`GroupSplit::Slabs`](super::GroupSplit::Slabs), cut into runs along the features'
///    principal direction). Clusters: groups {0, 1}, {2}, {3, 4} ([`CLUSTER_OF_GROUP`]). Patch: all.
/// 4. Skeletons: each element's representative (mean, medoid or the better of the two by drawn
///    error), resampled at equal arc-length steps to the section's node count (the largest its
///    elements need by [`Smoothness`](super::Smoothness); or the groom's, with
///    [`NodeCountScope::Uniform`]), with the radius and width enclosing its strands per node.
/// 5. Errors per level ([`LevelErrors`]) and the discretisation floor, in [`FitReport`].
///
/// Deterministic whatever the thread count. Errors: invalid settings, fewer than 5 curves, a bad
/// curve layout, or a curve of zero length (named).
pub fn fit_hierarchy(curves: &Curves, settings: &FitSettings) -> Result<FittedHierarchy> {
    settings.validate()?;
    let prepared = prepare(curves, settings)?;
    let strand_count = prepared.strand_count();
    let requested = settings.section_count_for(strand_count);
    let (sections, merged) = partition_sections(&prepared, requested, settings);
    let plans: Vec<SectionPlan> = sections
        .into_par_iter()
        .map(|members| plan_section(&prepared, members, settings))
        .collect();
    let uniform = plans.iter().map(|p| p.nodes_needed).max().unwrap_or(4);
    let fits: Vec<SectionFit> = plans
        .into_par_iter()
        .map(|plan| {
            let n = match settings.node_counts {
                NodeCountScope::PerSection => plan.nodes_needed,
                NodeCountScope::Uniform => uniform,
            };
            fit_section(curves, &prepared, plan, n)
        })
        .collect();
    Ok(assemble(fits, strand_count, requested, merged))
}

/// Lays the fitted sections out in the groom's chain order and gathers the report.
fn assemble(
    fits: Vec<SectionFit>,
    strand_count: usize,
    requested: usize,
    merged: usize,
) -> FittedHierarchy {
    let s = fits.len();
    let mut hierarchy = FittedHierarchy {
        sections: Vec::with_capacity(s),
        chain_offsets: vec![0],
        node_positions: Vec::new(),
        node_radii: Vec::new(),
        node_widths: Vec::new(),
        group_offsets: vec![0],
        group_strands: Vec::with_capacity(strand_count),
        strand_groups: vec![0; strand_count],
        root_offsets: vec![Vec2::ZERO; strand_count],
        report: FitReport::default(),
    };
    // Chains level-major, section-major within a level.
    for level in Level::ALL {
        for fit in &fits {
            for (e, element) in fit.fitted.iter().enumerate() {
                if element_level(e).0 == level {
                    hierarchy.node_positions.extend_from_slice(&element.nodes);
                    hierarchy.node_radii.extend_from_slice(&element.radii);
                    hierarchy.node_widths.extend_from_slice(&element.widths);
                    hierarchy
                        .chain_offsets
                        .push(hierarchy.node_positions.len() as u32);
                }
            }
        }
    }
    // Per-strand errors at each level, in curve order.
    let mut errors: PerLevel<Vec<super::element::StrandErrors>> =
        PerLevel::from_fn(|_| vec![Default::default(); strand_count]);
    let mut floor = vec![(0.0, 0.0); strand_count];
    let mut medoids = PerLevel::from_fn(|_| 0usize);
    let mut max_centre_gap = 0.0f32;
    for (section, fit) in fits.iter().enumerate() {
        for (e, (strands, element)) in fit.elements.iter().zip(&fit.fitted).enumerate() {
            let (level, child) = element_level(e);
            medoids[level] += usize::from(element.is_medoid);
            for (k, &curve) in strands.iter().enumerate() {
                errors[level][curve as usize] = element.errors[k];
            }
            if level == Level::StrandGroup {
                let group = 5 * section + child;
                for (k, &curve) in strands.iter().enumerate() {
                    hierarchy.strand_groups[curve as usize] = group as u32;
                    hierarchy.root_offsets[curve as usize] = element.root_offsets[k];
                }
                hierarchy.group_strands.extend_from_slice(strands);
                hierarchy
                    .group_offsets
                    .push(hierarchy.group_strands.len() as u32);
            }
        }
        for &(curve, e) in &fit.floor {
            floor[curve as usize] = e;
        }
        let patch = &fit.fitted[0];
        let centre = &fit.fitted[2];
        if let (Some(a), Some(b)) = (patch.nodes.first(), centre.nodes.first()) {
            max_centre_gap = max_centre_gap.max(a.distance(*b));
        }
        let across: Vec<f32> = patch.root_offsets.iter().map(|offset| offset.y).collect();
        let width = across.iter().copied().fold(f32::NEG_INFINITY, f32::max)
            - across.iter().copied().fold(f32::INFINITY, f32::min);
        hierarchy.sections.push(FittedSection {
            root_position: patch.nodes.first().copied().unwrap_or(Vec3::ZERO),
            root_frame: fit.frame,
            width: if width.is_finite() { width } else { 0.0 },
            node_count: patch.nodes.len(),
            strand_count: fit.elements[0].len(),
        });
    }
    let node_counts = hierarchy.sections.iter().map(|s| s.node_count);
    let sizes = hierarchy.sections.iter().map(|s| s.strand_count);
    hierarchy.report = FitReport {
        strands: strand_count,
        requested_sections: requested,
        sections: s,
        merged_sections: merged,
        smallest_section: sizes.clone().min().unwrap_or(0),
        largest_section: sizes.max().unwrap_or(0),
        min_nodes: node_counts.clone().min().unwrap_or(0),
        max_nodes: node_counts.max().unwrap_or(0),
        errors: PerLevel::from_fn(|level| LevelErrors {
            drawn: ErrorStats::from_strands(errors[level].iter().map(|e| e.drawn)),
            per_node_offsets: ErrorStats::from_strands(errors[level].iter().map(|e| e.per_node)),
            centreline: ErrorStats::from_strands(errors[level].iter().map(|e| e.centreline)),
        }),
        discretisation: ErrorStats::from_strands(floor),
        medoid_elements: medoids,
        max_centre_gap,
    };
    hierarchy
}
