//! Grooms with skeletons finer than the presets': paper-curly with `smoothness = 0.00825` (32
//! nodes of 3–11 mm per skeleton). The default integrator cannot step them (docs/dynamics.md,
//! "Where the default fails"); a scene that picks XPBD for them must get a groom that hangs like
//! hair, which needs the hang to run with the scene's integrator too.

mod common;

use hairlod::Level;
use hairlod::core::dynamics::level_skeletons;
use hairlod::scene_file::SceneFile;

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
    // The presets' checks (tests/rest_pose.rs): no strand longer than 10 cm has its tip above
    // its root, and seen from behind the hair is at most 2.5 times as wide as the head. Hung
    // with the default integrator instead (before), this groom could not be built (the step
    // became unstable at t = 0), and at `smoothness = 0.0137` (20 nodes) it came out as a
    // porcupine.
    common::assert_hangs_like_hair("paper-curly, 32 nodes, xpbd", &scene);
}
