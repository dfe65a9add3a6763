//! `hair-core`: the model of *Simplified Representations for Modeling Hair* (§3), without GPU or
//! collision code.
//!
//! Hair is split into sections; each section can be a patch (1 skeleton), three clusters or five
//! strand groups, all built as D-NURBS on the same kind of base skeleton: a chain of nodes with fixed
//! segment lengths and rest angles (θ0, φ0) that hold a straight, wavy or curly shape.
//!
//! Units are metres, seconds and kilograms; right-handed, +Y up, the face looking along +Z.

pub mod atomic_file;
pub mod camera;
pub mod curves;
pub mod dynamics;
pub mod error;
pub mod fit;
pub mod frame;
pub mod groom;
pub mod head;
pub mod level;
pub mod lod;
pub mod mesh;
pub mod mesh_sequence;
pub mod named;
pub mod nurbs;
pub mod per_level;
pub mod random;
pub mod representation;
pub mod samples;
pub mod scene;
pub mod skeleton;
pub mod style;
pub mod transform;

pub use camera::Camera;
pub use curves::Curves;
pub use error::{HairError, Result};
pub use frame::Frame;
pub use groom::{
    Groom, GroomCounts, GroomParams, GroomPreset, NO_PROFILE, PRESET_NAMES, PROFILE_SAMPLES,
    Section, StrandSet,
};
pub use head::{Head, HeadParams, ScalpRoot};
pub use level::Level;
pub use mesh::TriangleMesh;
pub use mesh_sequence::{MeshSequence, MeshSequenceError, SequenceClock};
pub use named::{Named, UnknownName};
pub use per_level::PerLevel;
pub use scene::Scene;
pub use skeleton::SkeletonRest;
pub use style::{HairStyle, StyleKind};
pub use transform::RigidTransform;
