//! A deforming head in the frame loop ([`Scene::body_motion`](hair_core::Scene::body_motion)):
//! where each of the groom's skeleton chains rides the body (attached once per character, on
//! the rest mesh), the root carriers the level simulations step with, and the collision body at
//! the time a step ends (built once per frame and shared by the levels).

use std::sync::Arc;

use glam::Vec3;
use hair_collide::{CollisionBody, RestBoxes, RestField, attach_roots};
use hair_core::dynamics::{ChainRoots, DeformingBody, RootCarrier, SurfaceAttachment};
use hair_core::representation::geometry::strand_polylines;
use hair_core::{RigidTransform, Scene, TriangleMesh};

use super::error::Result;

/// A deforming body and where the groom's skeleton chains ride it.
#[derive(Debug, Clone)]
pub(crate) struct BodyRide {
    /// The body's samples (head space).
    pub(crate) body: Arc<DeformingBody>,
    /// Where each skeleton chain of the groom rides (its root's closest point on the rest
    /// mesh), indexed as `groom.skeletons`.
    pub(crate) attachments: Vec<SurfaceAttachment>,
    /// Every strand's root at rest [m, head space], in the groom's strand order.
    pub(crate) strand_roots: Vec<Vec3>,
    /// Where each strand's root rides (its closest point on the rest mesh).
    pub(crate) strand_attachments: Vec<SurfaceAttachment>,
    /// The rest mesh's distance field that the collision bodies read (field contacts), if any.
    pub(crate) rest_field: Option<RestField>,
    /// The head's occluder boxes prepared on the rest field, to follow the body.
    pub(crate) rest_occluders: Option<RestBoxes>,
}

impl BodyRide {
    /// The ride of `scene`'s groom on its body motion; `None` for a rigid head. `rest` is the
    /// collision body of the head mesh where one is built already (unposed); else one is built
    /// to attach the roots.
    pub(crate) fn of(scene: &Scene, rest: Option<&CollisionBody>) -> Result<Option<BodyRide>> {
        let Some(motion) = &scene.body_motion else {
            return Ok(None);
        };
        let built;
        let rest = match rest {
            Some(rest) => rest,
            None => {
                built = CollisionBody::from_mesh(&scene.head.mesh)?;
                &built
            }
        };
        let surface = |roots: &[Vec3]| -> Result<Vec<SurfaceAttachment>> {
            let (attached, _) = attach_roots(rest, roots)?;
            Ok(attached
                .iter()
                .map(|a| SurfaceAttachment {
                    triangle: a.triangle,
                    barycentric: a.barycentric,
                })
                .collect())
        };
        // The strands' roots at rest: the first point of each drawn strand on the rest
        // skeletons (one point per segment is enough for the roots).
        let groom = &scene.groom;
        let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
        let lines = strand_polylines(groom, &positions, &frames, 1)?;
        let strand_roots: Vec<Vec3> = lines.offsets[..lines.offsets.len() - 1]
            .iter()
            .map(|&start| lines.points[start as usize])
            .collect();
        Ok(Some(BodyRide {
            body: Arc::new(DeformingBody::new(motion.clone())),
            attachments: surface(&groom.skeletons.root_positions)?,
            strand_attachments: surface(&strand_roots)?,
            strand_roots,
            rest_field: None,
            rest_occluders: None,
        }))
    }

    /// Moves each strand of `points` (laid out by `offsets`, the groom's strands in order, [m,
    /// world]) so that its root is where the body carries it at `time` [s] with the head at
    /// `head`: the strands are drawn from their skeletons by rest offsets, which a stretching
    /// skin does not keep, so each is shifted by what its root is off (a fraction of a
    /// millimetre for a few percent of stretch).
    pub(crate) fn place_strand_roots(
        &self,
        head: &RigidTransform,
        time: f64,
        points: &mut [Vec3],
        offsets: &[u32],
    ) {
        for (strand, range) in offsets.windows(2).enumerate() {
            let (Some(attachment), Some(&rest)) = (
                self.strand_attachments.get(strand),
                self.strand_roots.get(strand),
            ) else {
                return;
            };
            let pose = head.after(&self.body.carry(attachment, time));
            let strand_points = &mut points[range[0] as usize..range[1] as usize];
            let Some(&root) = strand_points.first() else {
                continue;
            };
            let shift = pose.transform_point(rest) - root;
            for point in strand_points {
                *point += shift;
            }
        }
    }

    /// The carrier of a simulation of the groom's skeleton chains `chains`, in that order.
    pub(crate) fn carrier(&self, chains: &[usize]) -> RootCarrier {
        RootCarrier {
            body: self.body.clone(),
            attachments: chains.iter().map(|&c| self.attachments[c]).collect(),
        }
    }

    /// The collision body of the mesh at `time` [s] (head space; posed by the collision stage),
    /// its vertices moving at their mean velocity over the `time_step` [s] before it, and the
    /// farthest any vertex moved over that step [m]. From `previous` (the body at an earlier
    /// time) its tree is refitted ([`CollisionBody::deformed_reusing`], in the memory of
    /// `spare`, an instant no longer needed, where nothing else holds it); without it, built.
    /// With a rest field, the body reads it.
    pub(crate) fn collision_body(
        &self,
        time: f64,
        time_step: f32,
        previous: Option<&CollisionBody>,
        spare: Option<CollisionBody>,
    ) -> Result<(CollisionBody, f32)> {
        let sequence = self.body.sequence();
        let mut positions = Vec::new();
        sequence.positions_at(time, &mut positions);
        let mut earlier = Vec::new();
        sequence.positions_at(time - f64::from(time_step), &mut earlier);
        let mut moved = 0.0f32;
        let velocities = positions
            .iter()
            .zip(&earlier)
            .map(|(now, before)| {
                moved = moved.max(now.distance(*before));
                (*now - *before) / time_step
            })
            .collect();
        let body = match previous {
            Some(previous) => previous.deformed_reusing(&positions, velocities, spare)?,
            None => {
                // Collision needs no vertex normals (its pseudonormals come from the triangles).
                let mesh = TriangleMesh {
                    positions,
                    normals: Vec::new(),
                    triangles: sequence.triangles().to_vec(),
                };
                let body = CollisionBody::from_moving_mesh(&mesh, velocities)?;
                match &self.rest_field {
                    Some(rest) => body.reading_rest_field(rest)?,
                    None => body,
                }
            }
        };
        Ok((body, moved))
    }
}

/// Where the groom's chains have their roots at `time` [s] with the head at `head` (its pose at
/// `time`): carried by the body where `ride` is given, else on the rigid head.
pub(crate) fn chain_roots<'a>(
    ride: Option<&'a BodyRide>,
    head: &RigidTransform,
    time: f64,
) -> ChainRoots<'a> {
    match ride {
        Some(ride) => ChainRoots::carried(*head, &ride.body, &ride.attachments, time),
        None => ChainRoots::rigid(*head),
    }
}
