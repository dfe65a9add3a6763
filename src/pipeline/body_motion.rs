//! A deforming head in the frame loop ([`Scene::body_motion`](hair_core::Scene::body_motion)):
//! where each of the groom's skeleton chains rides the body (attached once per character, on
//! the rest mesh), the root carriers the level simulations step with, and the collision body at
//! the time a step ends (built once per frame and shared by the levels).

use std::sync::Arc;

use glam::Vec3;
use hair_collide::{CollisionBody, RestBoxes, RestField, attach_roots};
use hair_core::dynamics::{ChainRoots, DeformingBody, RootCarrier, SurfaceAttachment};
use hair_core::representation::drawn::ChainStart;
use hair_core::representation::roots::{for_each_strand_root, strand_roots};
use hair_core::{Groom, MeshSequence, RigidTransform, Scene, TriangleMesh};
use hair_render::{ActiveSkeletons, SkeletonFrame};

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
    /// Each strand's rest root as its offset in its triangle's rest frame
    /// ([`DeformingBody::rest_offset`]; `None` on a triangle of zero area).
    pub(crate) strand_offsets: Vec<Option<Vec3>>,
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
        // The strands' roots at rest: where each is drawn from on the rest skeletons.
        let groom = &scene.groom;
        let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
        let strand_roots = strand_roots(groom, &positions, &frames)?;
        let body = DeformingBody::new(motion.clone());
        let strand_attachments = surface(&strand_roots)?;
        let strand_offsets = strand_attachments
            .iter()
            .zip(&strand_roots)
            .map(|(attachment, &root)| body.rest_offset(attachment, root))
            .collect();
        Ok(Some(BodyRide {
            body: Arc::new(body),
            attachments: surface(&groom.skeletons.root_positions)?,
            strand_attachments,
            strand_offsets,
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
        let bracket = self.body.sequence().bracket(time);
        for (strand, range) in offsets.windows(2).enumerate() {
            let strand_points = &mut points[range[0] as usize..range[1] as usize];
            let Some(&root) = strand_points.first() else {
                continue;
            };
            let Some(carried) = self.carried_strand_root(head, bracket, strand) else {
                return;
            };
            let shift = carried - root;
            for point in strand_points {
                *point += shift;
            }
        }
    }

    /// Where the body carries strand `strand`'s root at the time between the samples
    /// `bracket` ([`hair_core::MeshSequence::bracket`]) with the head at `head` [m, world]: its
    /// rest root turned and moved with its triangle ([`DeformingBody::carry_offset`], the
    /// carry itself where that declines). `None` past the groom's strands.
    fn carried_strand_root(
        &self,
        head: &RigidTransform,
        bracket: (usize, usize, f32),
        strand: usize,
    ) -> Option<Vec3> {
        let attachment = self.strand_attachments.get(strand)?;
        let rest = self.strand_roots.get(strand)?;
        let offset = *self.strand_offsets.get(strand)?;
        let carried = offset
            .and_then(|offset| self.body.carry_offset(attachment, offset, bracket))
            .unwrap_or_else(|| {
                self.body
                    .carry_between(attachment, bracket)
                    .transform_point(*rest)
            });
        Some(head.transform_point(carried))
    }

    /// Appends to `shifts` one shift [m, world] per strand of `groom` (the groom this ride was
    /// made for), in its order: from where the renderer draws the strand's root on the
    /// skeletons of `frame` (its strand group's chain at `first_chain` plus the groom's chain
    /// number) to where the body carries it at `time` [s] with the head at `head`
    /// ([`hair_render::Renderer::set_strand_root_shifts`]). Zero for strands whose chain is not
    /// drawn (fewer than two nodes).
    pub(crate) fn append_strand_root_shifts(
        &self,
        groom: &Groom,
        head: &RigidTransform,
        time: f64,
        frame: &SkeletonFrame<'_>,
        first_chain: usize,
        shifts: &mut Vec<Vec3>,
    ) {
        let base = shifts.len();
        shifts.resize(base + groom.strands.strand_count(), Vec3::ZERO);
        let chain_start = |chain: usize| {
            let chain = first_chain + chain;
            let start = *frame.chain_offsets.get(chain)? as usize;
            let end = *frame.chain_offsets.get(chain + 1)? as usize;
            (end >= start + 2 && end <= frame.node_positions.len()).then(|| ChainStart {
                first: frame.node_positions[start],
                second: frame.node_positions[start + 1],
                normal: frame.node_normals[start],
                binormal: frame.node_binormals[start],
            })
        };
        let bracket = self.body.sequence().bracket(time);
        for_each_strand_root(groom, chain_start, |strand, root| {
            if let Some(carried) = self.carried_strand_root(head, bracket, strand) {
                shifts[base + strand] = carried - root;
            }
        });
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

/// One character's part of a frame's strand root shifts ([`strand_root_shifts`]).
pub(crate) struct ShiftedCharacter<'a> {
    /// Its groom, as uploaded.
    pub(crate) groom: &'a Groom,
    /// Where the groom rides its deforming head; `None` for a rigid head.
    pub(crate) ride: Option<&'a BodyRide>,
    /// Its head's pose at the time drawn.
    pub(crate) head: RigidTransform,
    /// The time drawn [s].
    pub(crate) time: f64,
}

/// Fills `shifts` (cleared first) with each strand's shift [m, world] onto where its
/// character's body carries its root, for the skeletons `active` holds (every character's
/// chains one after the other, in `characters`' order), every character's strands one after
/// the other (zeros for a rigid head's), as
/// [`hair_render::Renderer::set_strand_root_shifts`] takes them. Left empty where no head
/// deforms.
pub(crate) fn strand_root_shifts<'a>(
    characters: impl IntoIterator<Item = ShiftedCharacter<'a>>,
    active: &ActiveSkeletons,
    shifts: &mut Vec<Vec3>,
) {
    shifts.clear();
    let frame = active.frame();
    let (mut first_chain, mut deforming) = (0, false);
    for character in characters {
        let groom = character.groom;
        match character.ride {
            Some(ride) => {
                deforming = true;
                ride.append_strand_root_shifts(
                    groom,
                    &character.head,
                    character.time,
                    &frame,
                    first_chain,
                    shifts,
                );
            }
            None => shifts.resize(shifts.len() + groom.strands.strand_count(), Vec3::ZERO),
        }
        first_chain += groom.skeletons.chain_count();
    }
    if !deforming {
        shifts.clear();
    }
}

/// Each character's body mesh [m, head space, with vertex normals] at its time, for characters
/// given as their body motion (`None`: a rigid head) and time [s]: characters wearing one body
/// at one time share its sequence, so each instant is made once (its normals too) and copied
/// for the others.
pub(crate) fn body_meshes<'a>(
    characters: impl IntoIterator<Item = (Option<&'a Arc<MeshSequence>>, f64)>,
) -> Vec<Option<TriangleMesh>> {
    let mut made: Vec<(*const MeshSequence, f64, usize)> = Vec::new();
    let mut bodies: Vec<Option<TriangleMesh>> = Vec::new();
    for (motion, time) in characters {
        let body = motion.map(|motion| {
            let key = (Arc::as_ptr(motion), time);
            match made.iter().find(|(at, t, _)| (*at, *t) == key) {
                Some(&(_, _, first)) => bodies[first].clone(),
                None => {
                    made.push((key.0, key.1, bodies.len()));
                    Some(motion.mesh_at(time))
                }
            }
        });
        bodies.push(body.flatten());
    }
    bodies
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
