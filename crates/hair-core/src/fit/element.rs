//! One element (a patch, cluster or strand group): its representative curve (mean or medoid of
//! its strands), its skeleton at a node count, the radius and width enclosing its strands at each
//! node, and each strand's errors against it.

use glam::{Vec2, Vec3};

use super::partition::Prepared;
use super::resample::{at_fraction, curve_length, resample_curve, total_turning};
use super::settings::{Representative, Smoothness};
use crate::frame::Frame;
use crate::skeleton::node_frames;

/// Most medoid candidates tried per element (evenly spread over its strands); each is compared
/// with every strand of the element.
const MEDOID_CANDIDATES: usize = 256;

/// A representative curve at the strands' sample count, and what it is.
#[derive(Debug, Clone)]
pub(crate) struct Candidate {
    /// The curve [m], `samples_per_strand` points at equal fractions of its length.
    pub(crate) samples: Vec<Vec3>,
    /// Whether it is a member strand (a medoid) rather than a mean.
    pub(crate) is_medoid: bool,
}

/// The mean of `members`' samples, point by point.
fn mean_curve(prepared: &Prepared, members: &[u32]) -> Vec<Vec3> {
    let m = prepared.samples_per_strand;
    let mut sum = vec![glam::DVec3::ZERO; m];
    for &i in members {
        for (s, p) in sum.iter_mut().zip(prepared.strand(i as usize)) {
            *s += p.as_dvec3();
        }
    }
    let count = members.len().max(1) as f64;
    sum.iter().map(|s| (*s / count).as_vec3()).collect()
}

/// The member whose shape (samples minus root) has the smallest summed distance to the other
/// members' shapes; candidates are at most [`MEDOID_CANDIDATES`] members evenly spread.
///
/// The distance between two shapes is the sum of their samples' distances, a metric, so a seed
/// member `s` (the candidate nearest the mean shape, likely close to the medoid) bounds every
/// candidate's sum from below by the triangle inequality: `Σₒ |d(c, s) − d(s, o)|`. A candidate
/// whose bound exceeds the best sum so far (the seed's to begin with, with a margin for rounding)
/// is skipped; the sum of any other stops as soon as it exceeds that best. The sums that run to
/// the end add the same terms in the same order as a full evaluation, so the result is the
/// brute-force medoid's bit for bit (ties go to the earlier candidate).
fn medoid(prepared: &Prepared, members: &[u32]) -> u32 {
    let m = prepared.samples_per_strand;
    let n = m.saturating_sub(1);
    if n == 0 || members.len() < 2 {
        return members[0];
    }
    let stride = members.len().div_ceil(MEDOID_CANDIDATES).max(1);
    // Every member's shape, member-major: samples 1.. minus the root.
    let shapes: Vec<Vec3> = members
        .iter()
        .flat_map(|&i| {
            let strand = prepared.strand(i as usize);
            strand[1..].iter().map(move |&p| p - strand[0])
        })
        .collect();
    let shape = |index: usize| &shapes[index * n..(index + 1) * n];
    let distance = |a: &[Vec3], b: &[Vec3]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(a, b)| f64::from(a.distance(*b)))
            .sum::<f64>()
    };
    // The summed distance from member `index` to every member; `None` once it exceeds `bound`.
    let total_within = |index: usize, bound: f64| {
        let mine = shape(index);
        let mut total = 0.0f64;
        for other in shapes.chunks_exact(n) {
            total += distance(mine, other);
            if total > bound {
                return None;
            }
        }
        Some(total)
    };
    let mut mean = vec![Vec3::ZERO; n];
    for other in shapes.chunks_exact(n) {
        for (sum, p) in mean.iter_mut().zip(other) {
            *sum += *p;
        }
    }
    let scale = 1.0 / members.len() as f32;
    for sum in &mut mean {
        *sum *= scale;
    }
    let near_mean = |index: usize| -> f32 {
        shape(index)
            .iter()
            .zip(&mean)
            .map(|(p, centre)| p.distance_squared(*centre))
            .sum()
    };
    let seed = (0..members.len())
        .step_by(stride)
        .min_by(|&a, &b| near_mean(a).total_cmp(&near_mean(b)))
        .unwrap_or(0);
    let from_seed: Vec<f64> = shapes
        .chunks_exact(n)
        .map(|other| distance(shape(seed), other))
        .collect();
    let seed_total: f64 = from_seed.iter().sum();
    // Each term of the bound is off by at most a few f32 ulps of `d(c, s) + d(s, o)` (the
    // samples' distances are f32): `MARGIN · (n·d(c, s) + Σₒ d(s, o))` covers their sum.
    const MARGIN: f64 = 1e-5;
    let count = members.len() as f64;
    let mut best = (members[0], f64::INFINITY);
    for (index, &candidate) in members.iter().enumerate().step_by(stride) {
        let bound = best.1.min(seed_total);
        let to_seed = distance(shape(index), shape(seed));
        let lower: f64 = from_seed.iter().map(|d| (to_seed - d).abs()).sum();
        if lower > bound + MARGIN * (count * to_seed + seed_total) {
            continue;
        }
        if let Some(total) = total_within(index, bound)
            && total < best.1
        {
            best = (candidate, total);
        }
    }
    best.0
}

/// The candidate representatives of an element: the mean, the medoid, or both. A mean that
/// collapses (shorter than a thousandth of the members' mean length) gives way to the medoid.
pub(crate) fn candidates(
    prepared: &Prepared,
    members: &[u32],
    representative: Representative,
) -> Vec<Candidate> {
    let medoid_candidate = || Candidate {
        samples: prepared.strand(medoid(prepared, members) as usize).to_vec(),
        is_medoid: true,
    };
    let mean_candidate = || {
        let mean = mean_curve(prepared, members);
        let member_length = members
            .iter()
            .map(|&i| curve_length(prepared.strand(i as usize)))
            .sum::<f32>()
            / members.len().max(1) as f32;
        (curve_length(&mean) > 1e-3 * member_length).then_some(Candidate {
            samples: mean,
            is_medoid: false,
        })
    };
    match representative {
        Representative::Medoid => vec![medoid_candidate()],
        Representative::Mean => vec![mean_candidate().unwrap_or_else(medoid_candidate)],
        Representative::Best => match mean_candidate() {
            Some(mean) => vec![mean, medoid_candidate()],
            None => vec![medoid_candidate()],
        },
    }
}

/// Nodes a candidate needs by the smoothness rule.
pub(crate) fn nodes_needed(candidate: &Candidate, smoothness: &Smoothness) -> usize {
    super::resample::node_count_for(
        curve_length(&candidate.samples),
        total_turning(&candidate.samples),
        smoothness,
    )
}

/// One strand's errors against one element: `(mean, largest)` distance [m] for each model.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StrandErrors {
    /// Skeleton plus the constant root offset in the node frames.
    pub(crate) drawn: (f32, f32),
    /// Skeleton plus a free offset per node in its (normal, binormal) plane.
    pub(crate) per_node: (f32, f32),
    /// The skeleton itself.
    pub(crate) centreline: (f32, f32),
}

/// A fitted element: skeleton nodes, their frames, enclosing radii and widths, and per member
/// (in `members` order) its root offset and errors.
#[derive(Debug, Clone)]
pub(crate) struct FittedElement {
    /// Skeleton nodes [m].
    pub(crate) nodes: Vec<Vec3>,
    /// Radius enclosing the members at each node, across the node's tangent [m].
    pub(crate) radii: Vec<f32>,
    /// Twice the members' largest distance along each node's binormal [m].
    pub(crate) widths: Vec<f32>,
    /// Each member's root offset in the root frame's (normal, binormal) plane [m].
    pub(crate) root_offsets: Vec<Vec2>,
    /// Each member's errors.
    pub(crate) errors: Vec<StrandErrors>,
    /// Whether the representative is a medoid.
    pub(crate) is_medoid: bool,
}

/// The strands of an element at its node count and at the sample count.
pub(crate) struct MemberCurves<'a> {
    /// The prepared strands (samples).
    pub(crate) prepared: &'a Prepared,
    /// The element's strands (curve indices).
    pub(crate) members: &'a [u32],
    /// Each member resampled to the node count, member-major (same order as `members`).
    pub(crate) at_nodes: &'a [Vec<Vec3>],
}

/// `(mean, largest)` distance between the polyline `control` (read at equal fractions of its node
/// range) and `samples` (at equal fractions of the strand's length).
fn polyline_error(control: &[Vec3], samples: &[Vec3]) -> (f32, f32) {
    let m = samples.len();
    let mut total = 0.0f64;
    let mut largest = 0.0f32;
    for (k, sample) in samples.iter().enumerate() {
        let u = k as f32 / (m - 1) as f32;
        let d = at_fraction(control, u).distance(*sample);
        total += f64::from(d);
        largest = largest.max(d);
    }
    ((total / m as f64) as f32, largest)
}

/// The error of every member against `nodes` (with `frames`), with their root offsets.
fn member_errors(
    members: &MemberCurves<'_>,
    nodes: &[Vec3],
    frames: &[Frame],
    drawn_only: bool,
) -> (Vec<Vec2>, Vec<StrandErrors>) {
    let n = nodes.len();
    let mut control = vec![Vec3::ZERO; n];
    let mut offsets = Vec::with_capacity(members.members.len());
    let mut errors = Vec::with_capacity(members.members.len());
    for (&strand, at_nodes) in members.members.iter().zip(members.at_nodes) {
        let samples = members.prepared.strand(strand as usize);
        let root = samples[0] - nodes[0];
        let offset = Vec2::new(root.dot(frames[0].normal), root.dot(frames[0].binormal));
        for ((c, node), frame) in control.iter_mut().zip(nodes).zip(frames) {
            *c = *node + frame.normal * offset.x + frame.binormal * offset.y;
        }
        let mut result = StrandErrors {
            drawn: polyline_error(&control, samples),
            ..StrandErrors::default()
        };
        if !drawn_only {
            for (((c, node), frame), q) in control.iter_mut().zip(nodes).zip(frames).zip(at_nodes) {
                let d = *q - *node;
                *c = *node + d - frame.tangent * d.dot(frame.tangent);
            }
            result.per_node = polyline_error(&control, samples);
            result.centreline = polyline_error(nodes, samples);
        }
        offsets.push(offset);
        errors.push(result);
    }
    (offsets, errors)
}

/// Fits an element: each candidate resampled to `node_count` nodes, framed from `root_frame`; the
/// one with the lowest mean drawn error kept (the first on a tie); then its radii, widths, offsets
/// and errors.
pub(crate) fn fit_element(
    candidates: &[Candidate],
    members: &MemberCurves<'_>,
    node_count: usize,
    root_frame: &Frame,
) -> FittedElement {
    let mut best: Option<(f64, usize, Vec<Vec3>, Vec<Frame>)> = None;
    for (index, candidate) in candidates.iter().enumerate() {
        // Candidates have a positive length (a mean that collapsed was dropped; a medoid is a
        // strand), so resampling succeeds; a failure falls back on the samples themselves.
        let nodes = resample_curve(&candidate.samples, node_count)
            .unwrap_or_else(|_| candidate.samples.clone());
        let mut frames = vec![Frame::default(); nodes.len()];
        node_frames(root_frame, &nodes, &mut frames);
        let score = if candidates.len() > 1 {
            let (_, errors) = member_errors(members, &nodes, &frames, true);
            errors.iter().map(|e| f64::from(e.drawn.0)).sum::<f64>()
        } else {
            0.0
        };
        if best.as_ref().is_none_or(|(s, ..)| score < *s) {
            best = Some((score, index, nodes, frames));
        }
    }
    let Some((_, index, nodes, frames)) = best else {
        return FittedElement {
            nodes: Vec::new(),
            radii: Vec::new(),
            widths: Vec::new(),
            root_offsets: Vec::new(),
            errors: Vec::new(),
            is_medoid: false,
        };
    };
    let n = nodes.len();
    let mut radii = vec![0.0f32; n];
    let mut widths = vec![0.0f32; n];
    for at_nodes in members.at_nodes {
        for i in 0..n.min(at_nodes.len()) {
            let d = at_nodes[i] - nodes[i];
            let across = d - frames[i].tangent * d.dot(frames[i].tangent);
            radii[i] = radii[i].max(across.length());
            widths[i] = widths[i].max(2.0 * d.dot(frames[i].binormal).abs());
        }
    }
    let (root_offsets, errors) = member_errors(members, &nodes, &frames, false);
    FittedElement {
        nodes,
        radii,
        widths,
        root_offsets,
        errors,
        is_medoid: candidates[index].is_medoid,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64 as Rng;

    /// The medoid by its definition: every candidate's full sum, the smallest first one wins.
    fn brute_force_medoid(prepared: &Prepared, members: &[u32]) -> u32 {
        let stride = members.len().div_ceil(MEDOID_CANDIDATES).max(1);
        let shape = |i: u32, k: usize| {
            let strand = prepared.strand(i as usize);
            strand[k] - strand[0]
        };
        let m = prepared.samples_per_strand;
        let mut best = (members[0], f64::INFINITY);
        for &candidate in members.iter().step_by(stride) {
            let total: f64 = members
                .iter()
                .map(|&other| {
                    (1..m)
                        .map(|k| f64::from(shape(candidate, k).distance(shape(other, k))))
                        .sum::<f64>()
                })
                .sum();
            if total < best.1 {
                best = (candidate, total);
            }
        }
        best.0
    }

    /// Random wavy strands, some of them repeated (ties), as prepared samples.
    fn random_strands(rng: &mut Rng, strands: usize, samples: usize) -> Prepared {
        let mut points = Vec::new();
        for s in 0..strands {
            if s % 7 == 3 {
                // A copy of the previous strand: equal sums, the earlier one must win.
                let previous = points[(s - 1) * samples..s * samples].to_vec();
                points.extend(previous);
                continue;
            }
            let root = Vec3::new(rng.range(-0.1, 0.1), 0.0, rng.range(-0.1, 0.1));
            let bend = Vec3::new(rng.range(-0.05, 0.05), 0.0, rng.range(-0.05, 0.05));
            for k in 0..samples {
                let t = k as f32 / (samples - 1) as f32;
                points.push(root + Vec3::new(0.0, -0.3 * t, 0.0) + bend * (6.0 * t).sin());
            }
        }
        Prepared {
            samples_per_strand: samples,
            samples: points,
            features: vec![Default::default(); strands],
        }
    }

    #[test]
    fn the_pruned_medoid_is_the_brute_force_one() {
        let mut rng = Rng::new(11);
        for (strands, samples) in [(1, 8), (2, 8), (40, 16), (300, 12), (700, 9)] {
            let prepared = random_strands(&mut rng, strands, samples);
            let all: Vec<u32> = (0..strands as u32).collect();
            // Every member, a strided subset, and the members in a shuffled order.
            let mut shuffled = all.clone();
            for i in (1..shuffled.len()).rev() {
                let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                shuffled.swap(i, j);
            }
            let odd: Vec<u32> = all.iter().copied().filter(|i| i % 2 == 1).collect();
            for members in [&all, &shuffled, &odd] {
                if members.is_empty() {
                    continue;
                }
                assert_eq!(
                    medoid(&prepared, members),
                    brute_force_medoid(&prepared, members),
                    "{strands} strands of {samples} samples"
                );
            }
        }
    }
}
