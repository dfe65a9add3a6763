//! A deforming head in the frame loop ([`Scene::body_motion`](hair_core::Scene::body_motion)):
//! where each of the groom's skeleton chains rides the body (attached once per character, on
//! the rest mesh), the root carriers the level simulations step with, and the collision body at
//! the time a step ends (built once per frame and shared by the levels).

use std::sync::Arc;

use hair_collide::{CollisionBody, attach_roots};
use hair_core::dynamics::{DeformingBody, RootCarrier, SurfaceAttachment};
use hair_core::{Scene, TriangleMesh};

use super::error::Result;

/// A deforming body and where the groom's skeleton chains ride it.
#[derive(Debug, Clone)]
pub(crate) struct BodyRide {
    /// The body's samples (head space).
    pub(crate) body: Arc<DeformingBody>,
    /// Where each skeleton chain of the groom rides (its root's closest point on the rest
    /// mesh), indexed as `groom.skeletons`.
    pub(crate) attachments: Vec<SurfaceAttachment>,
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
        let (attached, _) = attach_roots(rest, &scene.groom.skeletons.root_positions)?;
        Ok(Some(BodyRide {
            body: Arc::new(DeformingBody::new(motion.clone())),
            attachments: attached
                .iter()
                .map(|a| SurfaceAttachment {
                    triangle: a.triangle,
                    barycentric: a.barycentric,
                })
                .collect(),
        }))
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
    /// farthest any vertex moved over that step [m].
    pub(crate) fn collision_body(&self, time: f64, time_step: f32) -> Result<(CollisionBody, f32)> {
        let sequence = self.body.sequence();
        // Collision needs no vertex normals (its pseudonormals come from the triangles).
        let mut mesh = TriangleMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            triangles: sequence.triangles().to_vec(),
        };
        sequence.positions_at(time, &mut mesh.positions);
        let mut earlier = Vec::new();
        sequence.positions_at(time - f64::from(time_step), &mut earlier);
        let mut moved = 0.0f32;
        let velocities = mesh
            .positions
            .iter()
            .zip(&earlier)
            .map(|(now, before)| {
                moved = moved.max(now.distance(*before));
                (*now - *before) / time_step
            })
            .collect();
        Ok((CollisionBody::from_moving_mesh(&mesh, velocities)?, moved))
    }
}
