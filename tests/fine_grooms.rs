//! Grooms with skeletons finer than the presets': paper-curly with `smoothness = 0.00825` (32
//! nodes of 3–11 mm per skeleton). The default integrator cannot step them (docs/dynamics.md,
//! "Where the default fails"); a scene that picks XPBD for them must get a groom that hangs like
//! hair, which needs the hang to run with the scene's integrator too.

use hairlod::core::dynamics::{level_skeletons, strand_skeletons};
use hairlod::scene_file::SceneFile;
use hairlod::{Level, RigidTransform};

const FINE_XPBD: &str = r#"
version = 2
[groom]
preset = "paper-curly"
smoothness = 0.00825
[dynamics]
integrator = "xpbd"
"#;

#[test]
fn a_fine_curly_groom_hangs_like_hair_with_the_scenes_integrator() {
    let shot = SceneFile::parse(FINE_XPBD).unwrap().resolve().unwrap();
    let scene = shot.build_scene().unwrap();
    let groups = level_skeletons(&scene.groom, Level::StrandGroup).unwrap();
    assert_eq!(
        groups.nodes(0).len(),
        32,
        "the premise: 32 nodes per skeleton"
    );
    // The checks of tests/rest_pose.rs: no strand longer than 10 cm has its tip above its root,
    // and seen from behind the hair is at most 2.5 times as wide as the head. Hung with the
    // default integrator instead (before), this groom could not be built (the step became
    // unstable at t = 0), and at `smoothness = 0.0137` (20 nodes) it came out as a porcupine.
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
                "strand {chain} has its tip {} m above its root",
                tip.y - root.y
            );
        }
    }
    let head = &scene.head.mesh.positions;
    let head_width = head.iter().map(|p| p.x).fold(f32::NEG_INFINITY, f32::max)
        - head.iter().map(|p| p.x).fold(f32::INFINITY, f32::min);
    let ratio = (high - low) / head_width;
    eprintln!(
        "hair {:.3} m wide, head {head_width:.3} m: {ratio:.2}×",
        high - low
    );
    assert!(ratio <= 2.5, "the hair is {ratio}× the head's width");
}
