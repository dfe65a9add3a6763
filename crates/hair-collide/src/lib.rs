//! `hair-collide`: collision detection for hair (§5): swept-sphere volumes on parry3d shapes,
//! hierarchies of them over skeleton segments, and hair-against-body triangle queries.
//!
//! - [`volume`]: PSS / LSS / RSS with exact pairwise distance, intersection and triangle tests.
//! - [`fit`]: the volume of a segment for each representation (strand group, cluster, patch)
//!   and the head's top-level PSS.
//! - [`bvh`]: [`HairBvh`], a top-down hierarchy over the segment volumes of many chains,
//!   refitted from new positions each step.
//! - [`body`]: [`CollisionBody`], a rigid mesh with its triangle hierarchy.
//! - [`query`]: [`query_body`] and its brute-force reference [`query_body_brute_force`].
//!
//! Units are metres; vectors are `glam::Vec3` (the same type parry3d 0.31 uses).

pub mod body;
pub mod bvh;
pub mod error;
pub mod fit;
pub mod geometry;
pub mod query;
pub mod volume;

pub use body::CollisionBody;
pub use bvh::{ChainVolume, HairBvh, aabb_padding};
pub use error::{CollideError, Result};
pub use geometry::{Rectangle, Triangle};
pub use query::{SegmentContacts, query_body, query_body_brute_force};
pub use volume::{Lss, Pss, Rss, SweptSphere};
