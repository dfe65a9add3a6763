//! Builds each preset groom on the procedural head and prints its counts.
//!
//! `cargo run --example groom_counts`

use hairlod::Scene;
use hairlod::core::PRESET_NAMES;

fn main() -> Result<(), hairlod::HairError> {
    for name in PRESET_NAMES {
        let started = std::time::Instant::now();
        let scene = Scene::preset(name)?;
        let counts = scene.groom.counts();
        println!(
            "{name:12} {:>4} sections {:>5} clusters {:>5} strand groups {:>6} strands, \
             {:>3} nodes per skeleton, {:>6} nodes in all ({:.0} ms)",
            counts.sections,
            counts.clusters,
            counts.strand_groups,
            counts.strands,
            counts.nodes_per_skeleton,
            counts.skeleton_nodes,
            started.elapsed().as_secs_f64() * 1e3
        );
    }
    Ok(())
}
