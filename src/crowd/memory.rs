//! A crowd's memory, estimated before its pipelines are built and checked against what the
//! machine has available: a crowd too large for the machine is refused in its first second,
//! with the estimate and what it is made of, instead of swapping for minutes and being killed.
//!
//! The estimate has two parts. Each distinct head's collision body (its triangles, their
//! hierarchy and pseudonormals, in head space), held once however many characters wear it: the
//! characters' pipelines share it and pose it by their own head's transform. And each
//! character's pipeline: its simulated state and scratch per skeleton node, and what it holds
//! whatever the size of its groom. The constants were measured on the default procedural head
//! (12,096 triangles): see `docs/lod.md`, "A crowd's memory".

use super::model::CrowdModel;
use crate::pipeline::{PipelineError, PipelineSettings, Result};

/// Bytes a collision body holds per triangle of its mesh, once per distinct head (its
/// characters share it): the triangles, the hierarchy over them, the pseudonormals and edge
/// structure. Calibrated on the default head's 12,096 triangles (2026-12-01): when each
/// character held its own posed copy, small characters took 3.3 MB each, 3.27 MB of it this.
pub const BYTES_PER_BODY_TRIANGLE: u64 = 270;

/// Bytes a character's pipeline holds whatever its groom and head: selector, level blocks,
/// solvers and reports. With [`BYTES_PER_NODE`], about twice what small characters (234 nodes)
/// were measured to hold, 92 KB each (10,000 of them in 1,072 MB resident, 2026-12-02).
pub const BYTES_PER_PIPELINE: u64 = 64 * 1024;

/// Bytes per skeleton node of a character's groom (all three levels' skeletons; the state is
/// four vectors a node at each level it is simulated at, and the solvers' scratch and the
/// collision stage's hierarchy a few times that).
pub const BYTES_PER_NODE: u64 = 512;

/// The estimated bytes of `model`'s pipelines under `settings` (see the module's header): each
/// distinct head's collision body once (characters that share a groom share its body), and each
/// character's pipeline and nodes.
pub fn estimated_bytes(model: &CrowdModel, settings: &PipelineSettings) -> u64 {
    let mut bodies: Vec<&hair_collide::CollisionBody> = Vec::new();
    let mut total = 0;
    for member in &model.members {
        if settings.collision && !bodies.iter().any(|b| b.shares_shape_with(&member.body)) {
            bodies.push(&member.body);
            total += member.body.triangle_count() as u64 * BYTES_PER_BODY_TRIANGLE;
        }
        let nodes = member.scene.groom.skeletons.node_count() as u64;
        total += BYTES_PER_PIPELINE + nodes * BYTES_PER_NODE;
    }
    total
}

pub use crate::host_memory::available_bytes;

/// Refuses `model` under `settings` when its estimate is over `available` bytes, naming the
/// character count, the estimate per character and in all, and what is available.
pub fn check_fits(
    model: &CrowdModel,
    settings: &PipelineSettings,
    available: Option<u64>,
) -> Result<()> {
    let Some(available) = available else {
        return Ok(());
    };
    let estimate = estimated_bytes(model, settings);
    if estimate <= available {
        return Ok(());
    }
    let characters = model.members.len();
    let gib = |bytes: u64| bytes as f64 / f64::from(1u32 << 30);
    Err(PipelineError::CrowdTooLarge {
        message: format!(
            "the crowd's {characters} characters need about {:.1} GiB ({:.1} MiB each on \
             average: {BYTES_PER_PIPELINE} bytes a character's pipeline, {BYTES_PER_NODE} bytes \
             a skeleton node, and {BYTES_PER_BODY_TRIANGLE} bytes a triangle of each distinct \
             head's collision mesh), more than the {:.1} GiB this machine has available: give \
             the scene fewer characters or smaller grooms",
            gib(estimate),
            estimate as f64 / characters.max(1) as f64 / f64::from(1u32 << 20),
            gib(available)
        ),
    })
}
