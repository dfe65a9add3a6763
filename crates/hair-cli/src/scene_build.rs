//! A command's scene: the shot's groom and body built (read from files where the scene names
//! them), the camera framed on them where the scene asks for it, and what loading chose by
//! itself said on stderr.

use anyhow::{Context, Result};
use hairlod::Shot;
use hairlod::core::Scene;

/// Builds `shot`'s scene ([`Shot::build_framed_scene`]), framing `shot`'s camera on it where the
/// scene file names no camera target or distance, and says on stderr what was chosen: the
/// children grown on a sparse groom, the camera's framing.
pub fn build_scene(shot: &mut Shot) -> Result<Scene> {
    let (scene, loaded, framing) = shot
        .build_framed_scene()
        .context("could not build the groom")?;
    if let Some(grown) = loaded.as_ref().and_then(|l| l.report.grown_children) {
        eprintln!(
            "the groom is sparse ({:.2} strands per cm² of scalp): grew {} children around each \
             strand, spread over {:.1} mm (groom.children_per_strand = 0 turns this off)",
            grown.root_density * 1e-4,
            grown.per_strand,
            grown.spread * 1e3
        );
    }
    if let Some(framing) = framing {
        eprintln!(
            "camera: framing the body and groom (bounds {:.3?} to {:.3?} m), looking at {:.3?} \
             from {:.2} m; give [camera] target or distance to choose",
            framing.min.to_array(),
            framing.max.to_array(),
            framing.target.to_array(),
            framing.distance
        );
    }
    Ok(scene)
}
