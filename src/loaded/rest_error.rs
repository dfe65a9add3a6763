//! How far a loaded groom's rest pose lies from its file: each curve compared, at equal fractions
//! of its length, with the strand the groom draws for it, and with the model of its strand group,
//! cluster and patch (the element's rest skeleton plus the curve's root offset carried in the node
//! frames).

use glam::Vec3;
use hair_core::Curves;
use hair_core::fit::{ErrorStats, FittedHierarchy, resample_into};
use hair_core::representation::geometry::strand_polylines;
use hair_core::{Groom, Level, PerLevel, RigidTransform};
use serde::Serialize;

use crate::pipeline::Result;

/// Points compared per curve (at equal fractions of its length).
pub const REST_ERROR_SAMPLES: usize = 32;

/// The rest pose's distances from the file's curves [m] (each statistic over the curves of a
/// curve's mean distance over its samples, [`ErrorStats`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LevelRestErrors {
    /// The strands as drawn: each curve's strand evaluated on its strand-group skeleton's rest
    /// shape (the NURBS through the nodes, offset in the node frames, to its own length).
    pub drawn_strands: ErrorStats,
    /// Per level, each curve against its element's rest skeleton (a polyline through the nodes)
    /// plus its root offset from the skeleton's root in the node frames.
    pub levels: PerLevel<ErrorStats>,
}

/// The rest errors of `groom` (built by [`Groom::from_fit_with_children`] from `fit` of
/// `curves`, its rest shapes possibly changed since) against `curves` (the file strands only,
/// not their children).
pub fn rest_errors(
    groom: &Groom,
    fit: &FittedHierarchy,
    curves: &Curves,
) -> Result<LevelRestErrors> {
    let head = RigidTransform::IDENTITY;
    let (positions, frames) = groom.skeletons.rest_pose(&head);
    let curve_of = |curve: usize| -> &[Vec3] {
        &curves.points[curves.offsets[curve] as usize..curves.offsets[curve + 1] as usize]
    };
    let mut a = vec![Vec3::ZERO; REST_ERROR_SAMPLES];
    let mut b = vec![Vec3::ZERO; REST_ERROR_SAMPLES];
    let mut compare = |file: &[Vec3], model: &[Vec3]| -> (f32, f32) {
        if !(resample_into(file, &mut a) && resample_into(model, &mut b)) {
            return (f32::INFINITY, f32::INFINITY);
        }
        let d = a.iter().zip(&b).map(|(p, q)| p.distance(*q));
        let (sum, max) = d.fold((0.0f32, 0.0f32), |(s, m), d| (s + d, m.max(d)));
        (sum / REST_ERROR_SAMPLES as f32, max)
    };

    // File strand k (in group order) is groom strand k · per (children follow their guide).
    let file_strands = fit.group_strands.len().max(1);
    let per = groom.strands.strand_count() / file_strands;
    if per == 0 || per * file_strands != groom.strands.strand_count() {
        return Err(hair_core::HairError::SizeMismatch {
            what: "groom strands (file strands and their children)",
            actual: groom.strands.strand_count(),
            expected: file_strands,
        }
        .into());
    }
    let drawn = strand_polylines(groom, &positions, &frames, 4)?;
    let mut errors = Vec::with_capacity(fit.group_strands.len());
    for (k, &curve) in fit.group_strands.iter().enumerate() {
        let strand = k * per;
        let range = drawn.offsets[strand] as usize..drawn.offsets[strand + 1] as usize;
        errors.push(compare(curve_of(curve as usize), &drawn.points[range]));
    }
    let drawn_strands = ErrorStats::from_strands(errors);

    let s = groom.section_count();
    let mut model = Vec::new();
    let levels = PerLevel::from_fn(|level| {
        let mut errors = Vec::with_capacity(fit.group_strands.len());
        for group in 0..5 * s {
            let chain = match level {
                Level::StrandGroup => Level::StrandGroup.chains(s).start + group,
                Level::Cluster => fit.cluster_of_group(group),
                Level::Patch => group / 5,
            };
            let nodes = groom.skeletons.nodes(chain);
            let (root, root_frame) = (positions[nodes.start], frames[nodes.start]);
            for &curve in fit.group_members(group) {
                let file = curve_of(curve as usize);
                let offset = file[0] - root;
                let (x, y) = (
                    offset.dot(root_frame.normal),
                    offset.dot(root_frame.binormal),
                );
                model.clear();
                model.extend(
                    nodes
                        .clone()
                        .map(|k| positions[k] + x * frames[k].normal + y * frames[k].binormal),
                );
                errors.push(compare(file, &model));
            }
        }
        ErrorStats::from_strands(errors)
    });
    Ok(LevelRestErrors {
        drawn_strands,
        levels,
    })
}
