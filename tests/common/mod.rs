//! Helpers shared by the root package's integration tests.

use hairlod::core::dynamics::strand_skeletons;
use hairlod::{RigidTransform, Scene};

/// Checks that `scene`'s groom hangs like hair at rest: no strand longer than 10 cm has its tip
/// above its root, and seen from behind (along X) the hair is at most 2.5 times as wide as the
/// head. `name` labels the failures.
pub fn assert_hangs_like_hair(name: &str, scene: &Scene) {
    let strands = strand_skeletons(&scene.groom).unwrap();
    let positions = strands.rest_positions(&RigidTransform::IDENTITY);
    let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
    for chain in 0..strands.chain_count() {
        let nodes = &positions[strands.nodes(chain)];
        for p in nodes {
            low = low.min(p.x);
            high = high.max(p.x);
        }
        if strands.chain_length(chain) > 0.10 {
            let (root, tip) = (nodes[0], nodes[nodes.len() - 1]);
            assert!(
                tip.y <= root.y,
                "{name}: strand {chain} has its tip {} m above its root",
                tip.y - root.y
            );
        }
    }
    let head = &scene.head.mesh.positions;
    let head_width = head.iter().map(|p| p.x).fold(f32::NEG_INFINITY, f32::max)
        - head.iter().map(|p| p.x).fold(f32::INFINITY, f32::min);
    let ratio = (high - low) / head_width;
    eprintln!(
        "{name}: hair {:.3} m wide, head {head_width:.3} m: {ratio:.2}×",
        high - low
    );
    assert!(
        ratio <= 2.5,
        "{name}: the hair is {ratio}× the head's width"
    );
}
