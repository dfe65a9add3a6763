//! Grooms with skeletons finer than the presets': paper-curly with `smoothness = 0.00825` (32
//! nodes of 3–11 mm per skeleton). Linear-implicit, the default until 2026-11-28, cannot step
//! them (docs/dynamics.md, "Where linear-implicit fails"), and a scene that picks it must be
//! refused with the fix named; XPBD, the default now, must give a groom that hangs like hair,
//! which needs the hang to run with the scene's integrator too.

mod common;

use hairlod::core::dynamics::IntegratorKind;
use hairlod::core::dynamics::level_skeletons;
use hairlod::scene_file::SceneFile;
use hairlod::{Level, PipelineError};

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
    // with linear-implicit instead (before), this groom could not be built (the step became
    // unstable at t = 0), and at `smoothness = 0.0137` (20 nodes) it came out as a porcupine.
    common::assert_hangs_like_hair("paper-curly, 32 nodes, xpbd", &scene);
}

const FINE_LINEAR_IMPLICIT: &str = r#"
version = 2
[groom]
preset = "paper-curly"
smoothness = 0.0137
[dynamics]
integrator = "linear-implicit"
"#;

#[test]
fn a_fine_curly_groom_on_linear_implicit_is_refused_with_the_fix_named() {
    // 20 nodes per skeleton: linear-implicit does not blow up on them but flails, and
    // the groom used to hang as a porcupine with no error. The hang starts at rest with
    // gravity the only input, so a chain's kinetic energy per unit mass can never pass
    // `2·g·L`; flailing passes it several times over.
    let shot = SceneFile::parse(FINE_LINEAR_IMPLICIT)
        .unwrap()
        .resolve()
        .unwrap();
    let error = shot.build_scene().unwrap_err();
    let PipelineError::Unsettled {
        nodes,
        energy_per_mass,
        limit,
        integrator,
        ..
    } = &error
    else {
        panic!("expected the hang to be refused as unsettled, got: {error}");
    };
    assert_eq!(*integrator, IntegratorKind::LinearImplicit);
    assert_eq!(*nodes, 20);
    assert!(energy_per_mass > limit, "{error}");
    assert!(error.is_unstable());
    let message = error.to_string();
    assert!(message.contains("integrator = \"xpbd\""), "{message}");
}

#[test]
fn a_groom_whose_fall_blows_up_is_refused_with_the_level_and_the_fix_named() {
    // 32 nodes on linear-implicit: a step of the fall itself fails (a non-finite velocity),
    // and the error says it was the hang, at which level, and what to change.
    let fine_linear_implicit =
        FINE_XPBD.replace("integrator = \"xpbd\"", "integrator = \"linear-implicit\"");
    let shot = SceneFile::parse(&fine_linear_implicit)
        .unwrap()
        .resolve()
        .unwrap();
    let error = shot.build_scene().unwrap_err();
    let PipelineError::HangUnstable {
        level, integrator, ..
    } = &error
    else {
        panic!("expected the hang's step to fail, got: {error}");
    };
    assert_eq!(*level, Level::StrandGroup);
    assert_eq!(*integrator, IntegratorKind::LinearImplicit);
    assert!(error.is_unstable());
    let message = error.to_string();
    assert_eq!(message.matches("became unstable").count(), 1, "{message}");
    assert!(message.contains("integrator = \"xpbd\""), "{message}");
}
