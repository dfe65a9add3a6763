//! Helpers shared by the root package's integration tests.

use hairlod::core::dynamics::strand_skeletons;
use hairlod::render::{ActiveSkeletons, Renderer, RendererOptions};
use hairlod::{Level, RigidTransform, Scene};

/// A renderer (backend from `HAIRLOD_BACKEND`) with `scene`'s groom and head mesh uploaded, and
/// the groom's rest pose gathered at the strand level.
#[allow(dead_code)] // not every test crate that shares this module draws
pub fn strands_at_rest(scene: &Scene) -> (Renderer, ActiveSkeletons) {
    let options = RendererOptions::from_env().expect("HAIRLOD_BACKEND");
    let mut renderer =
        Renderer::new(&options).expect("a renderer (install mesa-vulkan-drivers or libegl-mesa0)");
    renderer.upload_groom(&scene.groom).unwrap();
    renderer.set_head_mesh(Some(&scene.head.mesh)).unwrap();
    let mut active = ActiveSkeletons::new();
    active
        .gather_rest_pose(&scene.groom, Level::StrandGroup)
        .unwrap();
    (renderer, active)
}

/// Checks that `scene`'s groom hangs like hair at rest: no strand longer than 10 cm has its tip
/// above its root, and seen from behind (along X) the hair is at most 2.5 times as wide as the
/// head. `name` labels the failures.
#[allow(dead_code)] // not every test crate that shares this module checks a hang
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

/// `build` of every item, each on a thread of its own, in the items' order: for builds that are
/// mostly serial (a groom's hang uses little more than one core), several side by side.
#[allow(dead_code)] // not every test crate that shares this module builds several scenes
pub fn side_by_side<T: Sync, R: Send>(items: &[T], build: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let build = &build;
    std::thread::scope(|threads| {
        let handles: Vec<_> = items
            .iter()
            .map(|item| threads.spawn(move || build(item)))
            .collect();
        handles
            .into_iter()
            .map(|handle| {
                handle
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            })
            .collect()
    })
}
