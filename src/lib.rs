//! # hairlod
//!
//! Hair simulation with automatic levels of detail, after *Simplified Representations for Modeling
//! Hair*: every section of hair is a patch, three clusters or five strand groups, all D-NURBS built
//! on the same base skeleton.
//!
//! This crate is the one to depend on. It re-exports the workspace crates:
//! - [`core`] (`hair-core`): skeletons, hairstyles, NURBS, representations, grooms, the procedural
//!   head;
//! - [`formats`] (`hair-formats`): groom and body files read and written, OBJ export;
//! - [`collide`] (`hair-collide`): swept-sphere volumes and collision queries;
//! - [`render`] (`hair-render`): the headless wgpu renderer.
//!
//! ```
//! use hairlod::{Level, Scene};
//!
//! let scene = Scene::preset("curly")?;
//! let counts = scene.groom.counts();
//! assert_eq!(counts.strand_groups, 5 * counts.sections);
//! assert_eq!(scene.groom.level_chains(Level::Cluster).len(), 3 * counts.sections);
//! # Ok::<(), hairlod::HairError>(())
//! ```

pub mod accuracy;
pub mod benchmark;
pub mod body_animation;
pub mod cache;
pub mod crowd;
pub mod framing;
pub mod head_levels;
pub mod host_memory;
pub mod loaded;
pub mod metrics;
pub mod pipeline;
pub mod popping;
pub mod rest_pose;
pub mod run;
pub mod scene_file;
pub mod shot;
pub mod usd_export;

pub use crowd::{Crowd, CrowdModel, CrowdRenderer};
pub use hair_collide as collide;
pub use hair_formats as formats;
pub use hair_render as render;

/// `hair-core`, the model ([`hair_core`] whole), with the file readers and writers where they
/// were before they moved to [`formats`] (`hair-formats`): `core::formats`, `core::obj` and
/// `core::export` are [`formats`], [`formats::obj`] and [`formats::export`].
pub mod core {
    pub use hair_core::*;
    pub use hair_formats as formats;
    pub use hair_formats::{export, obj};
}
pub use pipeline::{Checkpoint, LodMode, Pipeline, PipelineError, PipelineSettings, PipelineState};
pub use rest_pose::{HangSettings, RestPose, hang_groom};
pub use scene_file::SceneFile;
pub use shot::{Character, Shot};

pub use hair_core::{
    Camera, Frame, Groom, GroomCounts, GroomParams, HairError, HairStyle, Head, HeadParams, Level,
    RigidTransform, Scene, SkeletonRest, StyleKind, TriangleMesh,
};
