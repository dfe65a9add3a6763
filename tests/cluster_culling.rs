//! Back-face culling of cluster tubes removes only faces that another face of the tube hides:
//! the paper-curly groom drawn as clusters close up looks the same with culling on and off.
//! (Wound the wrong way, culling keeps the inside of each tube's far wall and changes about a fifth
//! of the frame's pixels, measured when the culling was added.)
//!
//! One test in this binary: it sets an environment variable, which is only sound while no other
//! thread reads the environment.

use hairlod::benchmark::{SETTLE_TIME, paper_shot, resized};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::{RendererOptions, ShadingMode};
use hairlod::{Level, Pipeline, Scene};

#[test]
#[allow(unsafe_code)] // `set_var`, see the SAFETY note below.
fn culling_cluster_back_faces_changes_almost_nothing() {
    let benchmark = resized(&paper_shot(false), 60, 320, 180);
    let settings = PipelineSettings {
        lod: LodMode::Fixed(Level::Cluster),
        ..PipelineSettings::default()
    };
    let mut pipeline = Pipeline::new(
        Scene::preset("curly").unwrap(),
        benchmark.environment.clone(),
        settings,
    )
    .unwrap();
    pipeline.settle(SETTLE_TIME).unwrap();
    let camera = benchmark.camera(0);
    pipeline.advance(&camera).unwrap();
    let mut render = |cull: &str| {
        // SAFETY: the only test of this binary; no other thread reads the environment.
        unsafe { std::env::set_var("HAIRLOD_CLUSTER_CULL", cull) };
        let options = RendererOptions::from_env().unwrap();
        let mut renderer = PipelineRenderer::new(&options, pipeline.scene()).unwrap();
        let (w, h) = (benchmark.width, benchmark.height);
        renderer
            .render(&mut pipeline, &camera, w, h, ShadingMode::Shaded)
            .unwrap()
            .0
    };
    let both_sides = render("none");
    let culled = render("back");
    // Everything but the background colour (the top-left corner, which no hair reaches).
    let background = *both_sides.get_pixel(0, 0);
    let hair = both_sides.pixels().filter(|&&p| p != background).count();
    let changed = both_sides
        .pixels()
        .zip(culled.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 8))
        .count();
    let total = (benchmark.width * benchmark.height) as usize;
    assert!(
        hair > total / 10,
        "hair and head fill the frame: {hair} of {total}"
    );
    // Only where a tube's open end or a crease shows a back face: under 1 % of the frame
    // (0.06 % at 1280×720 when measured); a wrong winding changes about 20 %.
    assert!(changed * 100 < total, "{changed} of {total} pixels changed");
}
