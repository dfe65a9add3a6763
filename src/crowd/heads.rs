//! The crowd's heads as the renderer draws them ([`CrowdHeads`]): each character's head at its
//! simulated pose, a rigid one tessellated as coarsely as its size on screen allows
//! ([`HeadLevels`]), a deforming one as its body's mesh at the time drawn; all joined into one
//! mesh, made again only when a pose, a tessellation or a deforming body changed.

use hair_core::{Camera, Head, RigidTransform, TriangleMesh};

use super::model::CrowdModel;
use crate::head_levels::{HEAD_PIXEL_TOLERANCE, HeadLevels};

/// The tessellation index that marks a head drawn as its deforming body's mesh.
const DEFORMED: usize = usize::MAX;

/// The crowd's heads: the distinct heads' tessellations and what was last joined.
#[derive(Debug, Clone, Default)]
pub(super) struct CrowdHeads {
    /// The distinct heads' tessellations (characters with equal heads share one).
    levels: Vec<HeadLevels>,
    /// Each character's index into `levels`.
    heads: Vec<usize>,
    /// The poses and tessellations (or [`DEFORMED`]) of the heads last joined (empty before the
    /// first frame).
    poses: Vec<(RigidTransform, usize)>,
}

impl CrowdHeads {
    /// The heads of `model`'s characters, in the shot's order.
    pub(super) fn new(model: &CrowdModel) -> Self {
        // Characters with the same procedural head share its tessellations; a mesh from a file
        // is its own.
        let mut distinct: Vec<&Head> = Vec::new();
        let mut heads = CrowdHeads::default();
        for member in &model.members {
            let head = &member.scene.head;
            let same = |other: &&Head| {
                head.is_procedural() && other.is_procedural() && other.params == head.params
            };
            let index = match distinct.iter().position(same) {
                Some(index) => index,
                None => {
                    distinct.push(head);
                    heads.levels.push(HeadLevels::new(head));
                    distinct.len() - 1
                }
            };
            heads.heads.push(index);
        }
        heads
    }

    /// The heads joined into one mesh [m, world] with each character's head at `poses[k]` (the
    /// shot's order) and, where `deformed[k]` holds one, drawn as that body mesh (head space)
    /// instead of a tessellation chosen through `camera` for an image `height` pixels tall;
    /// `None` when nothing changed since the last mesh made (no deforming body, every pose and
    /// tessellation the same).
    pub(super) fn mesh_to_draw(
        &mut self,
        poses: &[RigidTransform],
        deformed: &[Option<TriangleMesh>],
        camera: &Camera,
        height: u32,
    ) -> Option<TriangleMesh> {
        let body = |k: usize| deformed.get(k).and_then(Option::as_ref);
        let chosen: Vec<(RigidTransform, usize)> = poses
            .iter()
            .zip(&self.heads)
            .enumerate()
            .map(|(k, (&pose, &head))| match body(k) {
                Some(_) => (pose, DEFORMED),
                None => (
                    pose,
                    self.levels[head].select(camera, height, &pose, HEAD_PIXEL_TOLERANCE),
                ),
            })
            .collect();
        let deforms = chosen.iter().any(|&(_, level)| level == DEFORMED);
        if !deforms && chosen == self.poses {
            return None;
        }
        let placed: Vec<(&TriangleMesh, RigidTransform)> = chosen
            .iter()
            .zip(&self.heads)
            .enumerate()
            .map(|(k, (&(pose, level), &head))| match body(k) {
                Some(mesh) => (mesh, pose),
                None => (&self.levels[head].levels()[level].mesh, pose),
            })
            .collect();
        let mesh = merged_heads(&placed);
        self.poses = chosen;
        Some(mesh)
    }
}

/// The head meshes (head space) moved to their poses and joined into one mesh; vertex normals
/// only where every mesh has them.
pub(super) fn merged_heads(placed: &[(&TriangleMesh, RigidTransform)]) -> TriangleMesh {
    let mut merged = TriangleMesh::default();
    let normals = placed
        .iter()
        .all(|(mesh, _)| mesh.normals.len() == mesh.positions.len());
    for (mesh, pose) in placed {
        let base = merged.positions.len() as u32;
        merged
            .positions
            .extend(mesh.positions.iter().map(|&p| pose.transform_point(p)));
        if normals {
            merged
                .normals
                .extend(mesh.normals.iter().map(|&n| pose.transform_vector(n)));
        }
        merged
            .triangles
            .extend(mesh.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    merged
}
