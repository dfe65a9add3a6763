//! `hair-collide`: collision detection for hair (§5): swept-sphere volumes on parry3d shapes,
//! hierarchies of them over skeleton segments, and hair-against-body triangle queries.
//!
//! - [`volume`]: PSS / LSS / RSS with exact pairwise distance, intersection and triangle tests.
//! - [`fit`]: the volume of a segment for each representation (strand group, cluster, patch)
//!   and the head's top-level PSS.
//! - [`bvh`]: [`HairBvh`], a top-down hierarchy over the segment volumes of many chains,
//!   refitted from new positions each step.
//! - [`body`]: [`CollisionBody`], a rigid mesh with its triangle hierarchy.
//! - [`broad_phase`]: [`BroadPhase`], how collision finds the hair near a body.
//! - [`distance_field`]: [`DistanceField`], certified distance bounds on a grid around a body,
//!   which let a query skip the hair that is clear of it.
//! - [`attach`]: [`attach_roots`], roots attached to a body's closest triangle (barycentric).
//! - [`query`]: [`query_body`] and its brute-force reference [`query_body_brute_force`].
//! - [`field_contacts`]: [`query_body_field`], contacts from a body's distance field.
//! - [`RestField`]: a deforming body's field, its rest mesh's read through the deformation.
//! - [`sight`]: [`LineOfSight`], whether a body hides a point from an eye.
//!
//! Units are metres; vectors are `glam::Vec3` (the same type parry3d 0.31 uses).

pub mod attach;
pub mod body;
mod body_deform;
pub mod broad_phase;
pub mod bvh;
mod chain_blocks;
mod clearance;
pub mod closest;
pub mod distance_field;
pub mod error;
mod field_bricks;
pub mod field_contacts;
mod field_map;
mod field_memory;
pub mod fit;
mod gather;
pub mod geometry;
pub mod hair_hair;
pub mod layout;
mod moving_field;
mod other_forces;
mod projection;
mod projection_pass;
mod pseudonormals;
pub mod query;
pub mod response;
mod rest_field;
pub mod sight;
pub mod solver;
mod solver_settings;
pub mod surface;
#[cfg(test)]
mod tests_field_memory;
mod triangle_groups;
pub mod volume;

pub use attach::{AttachmentReport, RootAttachment, attach_roots};
pub use body::CollisionBody;
pub use broad_phase::BroadPhase;
pub use bvh::{ChainVolume, HairBvh, aabb_padding};
pub use distance_field::DistanceField;
pub use error::{CollideError, Result};
pub use field_contacts::{FieldContacts, query_body_field};
pub use geometry::{Rectangle, Triangle};
pub use hair_hair::{HairHairSettings, add_repulsion_forces};
pub use layout::{
    ChainShape, CollisionChain, groom_active_chains, groom_chain, groom_level_chains,
};
pub use moving_field::RestBoxes;
pub use query::{
    SegmentContacts, query_body, query_body_brute_force, query_body_near, query_body_volumes,
};
pub use rest_field::{MOVING_REACH, RestField};
pub use sight::LineOfSight;
pub use solver::{
    CollisionSettings, CollisionSolver, CollisionStepReport, ContactReport, PENETRATION_TOLERANCE,
    ProjectionReport, STRETCH_WARNING, VelocityMemory,
};
pub use surface::SurfacePoint;
pub use volume::{Lss, Pss, Rss, SweptSphere};
