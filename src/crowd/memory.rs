//! A crowd's memory, estimated before its pipelines are built and checked against what the
//! machine has available: a crowd too large for the machine is refused in its first second,
//! with the estimate and what it is made of, instead of swapping for minutes and being killed.
//!
//! The estimate is per character: its pipeline's collision body (the head's triangles posed in
//! world space and their bounding-volume hierarchy), which every character holds whatever the
//! size of its groom, and its simulated state and scratch per skeleton node. The constants were
//! measured on the default procedural head (12,096 triangles): see `docs/lod.md`, "Crowds".

use super::model::CrowdModel;
use crate::pipeline::{PipelineError, PipelineSettings, Result};

/// Bytes a character's pipeline holds per triangle of its head's collision mesh: the world-space
/// triangles, the hierarchy over them and its refit workspace, the pseudonormals, the local
/// copy of the mesh. Calibrated on the default head's 12,096 triangles: a crowd of small
/// characters (two sections, one strand a group) rendered for one frame held 134 MB resident
/// with 1 character, 464 MB with 100 and 1,432 MB with 400 (2026-12-01, `hairlod render`), 3.3 MB
/// a character, of which this constant is 3.27 MB.
pub const BYTES_PER_BODY_TRIANGLE: u64 = 270;

/// Bytes a character's pipeline holds whatever its groom and head: selector, level blocks,
/// solvers and reports.
pub const BYTES_PER_PIPELINE: u64 = 64 * 1024;

/// Bytes per skeleton node of a character's groom (all three levels' skeletons; the state is
/// four vectors a node at each level it is simulated at, and the solvers' scratch and the
/// collision stage's hierarchy a few times that).
pub const BYTES_PER_NODE: u64 = 512;

/// The estimated bytes of `model`'s pipelines under `settings` (see the module's header).
pub fn estimated_bytes(model: &CrowdModel, settings: &PipelineSettings) -> u64 {
    model
        .members
        .iter()
        .map(|member| {
            let body = if settings.collision {
                member.scene.head.mesh.triangles.len() as u64 * BYTES_PER_BODY_TRIANGLE
            } else {
                0
            };
            let nodes = member.scene.groom.skeletons.node_count() as u64;
            BYTES_PER_PIPELINE + body + nodes * BYTES_PER_NODE
        })
        .sum()
}

/// The memory available to a new allocation [bytes]: `MemAvailable` of `/proc/meminfo` on
/// Linux; `None` where it cannot be read (the check is then skipped).
pub fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_mem_available(&text)
}

/// `MemAvailable` of a `/proc/meminfo` text [bytes].
fn parse_mem_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kilobytes: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kilobytes.checked_mul(1024)
}

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
             average: mostly each head's collision mesh, {BYTES_PER_BODY_TRIANGLE} bytes a \
             triangle, and {BYTES_PER_NODE} bytes a skeleton node), more than the {:.1} GiB \
             this machine has available: give the scene fewer characters, or turn collision off \
             for it (`collision = false` in its [dynamics])",
            gib(estimate),
            estimate as f64 / characters.max(1) as f64 / f64::from(1u32 << 20),
            gib(available)
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_available_is_read_in_bytes() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   20000000 kB\n";
        assert_eq!(parse_mem_available(text), Some(20_000_000 * 1024));
        assert_eq!(parse_mem_available("MemTotal: 1 kB\n"), None);
        assert_eq!(parse_mem_available("MemAvailable: lots kB\n"), None);
    }
}
