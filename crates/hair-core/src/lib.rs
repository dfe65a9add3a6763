//! `hair-core`: the model of *Simplified Representations for Modeling Hair* (§3), without GPU or
//! collision code.
//!
//! Hair is split into sections; each section can be a patch (1 skeleton), three clusters or five
//! strand groups, all built as D-NURBS on the same kind of base skeleton: a chain of nodes with fixed
//! segment lengths and rest angles (θ0, φ0) that hold a straight, wavy or curly shape.
//!
//! Units are metres, seconds and kilograms; right-handed, +Y up, the face looking along +Z.

pub mod error;
pub mod frame;
pub mod mesh;
pub mod skeleton;
pub mod style;
pub mod transform;
// (modules are added below as they land)

pub use error::{HairError, Result};
pub use frame::Frame;
pub use mesh::TriangleMesh;
pub use skeleton::SkeletonRest;
pub use style::{HairStyle, StyleKind};
pub use transform::RigidTransform;
