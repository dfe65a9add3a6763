//! Strands into sections and strand groups: every strand resampled and described by its root and
//! shape, balanced k-means into sections, small sections merged, then each section cut across its
//! width into 5 strand groups of equal size (within one strand).

use glam::Vec3;
use rayon::prelude::*;

use super::kmeans::{FEATURE_COUNT, Feature, balanced_kmeans};
use super::pca::principal_direction;
use super::resample::{at_fraction, resample_into};
use super::settings::{FitSettings, GroupSplit};
use crate::curves::Curves;
use crate::error::{HairError, Result};
use crate::frame::Frame;

/// Strand groups per section.
pub(crate) const GROUPS: usize = 5;

/// Fewest strands a section may hold: one per strand group.
pub(crate) const MIN_SECTION_STRANDS: usize = GROUPS;

/// Every strand resampled at equal arc-length steps, and its clustering features.
pub(crate) struct Prepared {
    /// Samples per strand.
    pub(crate) samples_per_strand: usize,
    /// `samples_per_strand` points per strand [m], strand-major.
    pub(crate) samples: Vec<Vec3>,
    /// Root, `w · (middle − root)`, `w · (tip − root)` of each strand [m].
    pub(crate) features: Vec<Feature>,
}

impl Prepared {
    /// The samples of strand `strand`.
    pub(crate) fn strand(&self, strand: usize) -> &[Vec3] {
        let m = self.samples_per_strand;
        &self.samples[strand * m..(strand + 1) * m]
    }

    /// Number of strands.
    pub(crate) fn strand_count(&self) -> usize {
        self.features.len()
    }
}

/// Checks the curves and resamples every one; errors name the first bad curve.
pub(crate) fn prepare(curves: &Curves, settings: &FitSettings) -> Result<Prepared> {
    curves
        .check_layout()
        .map_err(|message| HairError::invalid("curves", message, "a valid curve layout"))?;
    let n = curves.curve_count();
    if n < MIN_SECTION_STRANDS {
        return Err(HairError::invalid(
            "curve count",
            n,
            "at least 5 curves (a section has 5 strand groups of at least one strand)",
        ));
    }
    let m = settings.samples_per_strand;
    let mut samples = vec![Vec3::ZERO; n * m];
    let ok: Vec<bool> = samples
        .par_chunks_mut(m)
        .enumerate()
        .map(|(i, out)| resample_into(curves.curve(i), out))
        .collect();
    if let Some(bad) = ok.iter().position(|ok| !ok) {
        let points = curves.curve(bad);
        return Err(HairError::invalid(
            "curve",
            format!(
                "curve {bad}: {} points, length {} m",
                points.len(),
                super::resample::curve_length(points)
            ),
            "at least 2 finite points and a length > 0 m",
        ));
    }
    let weight = settings.shape_weight;
    let features = samples
        .par_chunks(m)
        .map(|strand| {
            let root = strand[0];
            let middle = (at_fraction(strand, 0.5) - root) * weight;
            let tip = (strand[m - 1] - root) * weight;
            let mut f = [0.0; FEATURE_COUNT];
            f[..3].copy_from_slice(&root.to_array());
            f[3..6].copy_from_slice(&middle.to_array());
            f[6..].copy_from_slice(&tip.to_array());
            f
        })
        .collect();
    Ok(Prepared {
        samples_per_strand: m,
        samples,
        features,
    })
}

/// The root of a feature [m].
fn root_of(feature: &Feature) -> Vec3 {
    Vec3::new(feature[0], feature[1], feature[2])
}

/// Mean root of `members` [m].
fn root_centroid(prepared: &Prepared, members: &[u32]) -> Vec3 {
    let sum = members.iter().fold(glam::DVec3::ZERO, |sum, &i| {
        sum + root_of(&prepared.features[i as usize]).as_dvec3()
    });
    (sum / members.len().max(1) as f64).as_vec3()
}

/// The sections' strands (each list in curve order; sections ordered by their first curve) and
/// how many clusters were merged away (or empty).
pub(crate) fn partition_sections(
    prepared: &Prepared,
    requested: usize,
    settings: &FitSettings,
) -> (Vec<Vec<u32>>, usize) {
    let n = prepared.strand_count();
    let k = requested.clamp(1, n);
    let labels = balanced_kmeans(
        &prepared.features,
        k,
        settings.section_size_slack,
        settings.seed,
    );
    let mut sections: Vec<Vec<u32>> = vec![Vec::new(); k];
    for (strand, &label) in labels.iter().enumerate() {
        sections[label as usize].push(strand as u32);
    }
    let before = requested;
    sections.retain(|members| !members.is_empty());
    // Merge the smallest section under the minimum into its nearest neighbour until none is left.
    while sections.len() > 1 {
        let Some(small) = (0..sections.len())
            .filter(|&s| sections[s].len() < MIN_SECTION_STRANDS)
            .min_by_key(|&s| (sections[s].len(), s))
        else {
            break;
        };
        let centre = root_centroid(prepared, &sections[small]);
        let target = (0..sections.len())
            .filter(|&s| s != small)
            .min_by(|&a, &b| {
                let da = root_centroid(prepared, &sections[a]).distance_squared(centre);
                let db = root_centroid(prepared, &sections[b]).distance_squared(centre);
                da.total_cmp(&db).then(a.cmp(&b))
            })
            .unwrap_or(0);
        let moved = std::mem::take(&mut sections[small]);
        sections[target].extend(moved);
        sections[target].sort_unstable();
        sections.remove(small);
    }
    sections.sort_by_key(|members| members[0]);
    let merged = before - sections.len();
    (sections, merged)
}

/// The root frame of a section: tangent = the mean direction of its strands' first steps (the
/// growth direction); binormal = the direction across which its roots spread most, made
/// perpendicular to the tangent (strand groups are laid along it, like a procedural section's
/// children); normal = binormal × tangent. Without a scalp the normal's sign is a convention:
/// integration will take the scalp normal at the attached root.
pub(crate) fn section_frame(prepared: &Prepared, members: &[u32]) -> Frame {
    let mut growth = Vec3::ZERO;
    let mut reach = Vec3::ZERO;
    for &i in members {
        let strand = prepared.strand(i as usize);
        growth += (strand[1] - strand[0]).normalize_or_zero();
        reach += strand[strand.len() - 1] - strand[0];
    }
    let tangent = growth
        .try_normalize()
        .or_else(|| reach.try_normalize())
        .unwrap_or(Vec3::NEG_Y);
    let roots: Vec<[f32; 3]> = members
        .iter()
        .map(|&i| root_of(&prepared.features[i as usize]).to_array())
        .collect();
    let spread = principal_direction(&roots).map(Vec3::from_array);
    let across = spread.and_then(|b| {
        let b = b - tangent * b.dot(tangent);
        b.try_normalize().filter(|_| b.length() > 1e-3)
    });
    // Without a spread across the tangent: the axis least along the tangent.
    let across = across.unwrap_or_else(|| {
        let axes = [Vec3::X, Vec3::Y, Vec3::Z];
        let axis = axes
            .into_iter()
            .min_by(|a, b| a.dot(tangent).abs().total_cmp(&b.dot(tangent).abs()))
            .unwrap_or(Vec3::X);
        (axis - tangent * axis.dot(tangent)).normalize()
    });
    Frame::from_tangent_and_normal(tangent, across.cross(tangent)).unwrap_or_default()
}

/// Cuts a section into 5 strand groups as `settings.group_split` says.
pub(crate) fn split_groups(
    prepared: &Prepared,
    members: &[u32],
    frame: &Frame,
    settings: &FitSettings,
) -> [Vec<u32>; 5] {
    match settings.group_split {
        GroupSplit::Slabs => split_slabs(prepared, members, frame),
        GroupSplit::KMeans => split_kmeans(prepared, members, frame, settings.seed),
    }
}

/// Cuts a section into 5 strand groups of alike strands: balanced k-means with sizes within one
/// (seeded from `seed` and the section's first strand), the groups numbered by their root
/// centroids' position along the binormal.
fn split_kmeans(prepared: &Prepared, members: &[u32], frame: &Frame, seed: u64) -> [Vec<u32>; 5] {
    let features: Vec<Feature> = members
        .iter()
        .map(|&i| prepared.features[i as usize])
        .collect();
    let seed = seed ^ u64::from(members[0]).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let labels = balanced_kmeans(&features, GROUPS, 0.0, seed);
    let mut groups: Vec<Vec<u32>> = vec![Vec::new(); GROUPS];
    for (&strand, &label) in members.iter().zip(&labels) {
        groups[label as usize].push(strand);
    }
    let mut keyed: Vec<(f32, Vec<u32>)> = groups
        .into_iter()
        .map(|group| {
            let key = root_centroid(prepared, &group).dot(frame.binormal);
            (key, group)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.first().cmp(&b.1.first())));
    let mut out: [Vec<u32>; 5] = Default::default();
    for (slot, (_, group)) in out.iter_mut().zip(keyed) {
        *slot = group;
    }
    out
}

/// Cuts a section into 5 strand groups across its width: the strands sorted by their features'
/// projection on the features' principal direction (root and weighted shape; oriented along the
/// section's binormal), then cut into 5 runs of `⌊m/5⌋` or `⌈m/5⌉` strands. Group 0 lies on the
/// binormal's negative side, as child 0 of a procedural section.
pub(crate) fn split_slabs(prepared: &Prepared, members: &[u32], frame: &Frame) -> [Vec<u32>; 5] {
    let features: Vec<Feature> = members
        .iter()
        .map(|&i| prepared.features[i as usize])
        .collect();
    let mut direction = principal_direction(&features).unwrap_or_else(|| {
        let mut d = [0.0; FEATURE_COUNT];
        d[..3].copy_from_slice(&frame.binormal.to_array());
        d
    });
    let along_binormal = Vec3::new(direction[0], direction[1], direction[2]).dot(frame.binormal);
    if along_binormal < 0.0 {
        direction.iter_mut().for_each(|d| *d = -*d);
    }
    let mut keyed: Vec<(f32, u32)> = members
        .iter()
        .zip(&features)
        .map(|(&i, f)| (f.iter().zip(&direction).map(|(a, b)| a * b).sum(), i))
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let m = keyed.len();
    std::array::from_fn(|g| {
        let mut group: Vec<u32> = keyed[g * m / GROUPS..(g + 1) * m / GROUPS]
            .iter()
            .map(|&(_, i)| i)
            .collect();
        group.sort_unstable();
        group
    })
}
