//! Back-face culling of (tessellated) cluster tubes removes only faces that another face of the tube hides:
//! the paper-curly groom drawn as clusters close up looks the same with culling on and off.
//! (Wound the wrong way, culling keeps the inside of each tube's far wall and changes about a fifth
//! of the frame's pixels, measured when the culling was added.)
//!
//! The renderer reads the setting from `HAIRLOD_CLUSTER_CULL` when it is built, so the test re-runs
//! this test binary once per setting, with the variable set for that child process; each child
//! renders the frame and writes it as a PNG, and the parent compares the two.

use std::path::PathBuf;
use std::process::Command;

use hairlod::benchmark::{SETTLE_TIME, paper_shot, resized};
use hairlod::pipeline::{DrawStyle, LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::{ClusterGeometry, RendererOptions, ShadingMode};
use hairlod::{Level, Pipeline, Scene};

/// The variable the renderer reads: `none` draws both sides of cluster tubes, `back` culls.
const CULL_ENV: &str = "HAIRLOD_CLUSTER_CULL";
/// Set in a child run, which renders one frame with the culling its [`CULL_ENV`] says.
const CHILD_MARKER: &str = "HAIRLOD_CHILD";
/// Frame width [pixels].
const WIDTH: u32 = 320;
/// Frame height [pixels].
const HEIGHT: u32 = 180;

#[test]
fn culling_cluster_back_faces_changes_almost_nothing() {
    if std::env::var_os(CHILD_MARKER).is_some() {
        let cull = std::env::var(CULL_ENV).expect("the parent run sets HAIRLOD_CLUSTER_CULL");
        render_clusters().save(image_path(&cull)).unwrap();
        return;
    }
    let both_sides = render_in_child("none");
    let culled = render_in_child("back");
    // Everything but the background colour (the top-left corner, which no hair reaches).
    let background = *both_sides.get_pixel(0, 0);
    let hair = both_sides.pixels().filter(|&&p| p != background).count();
    let changed = both_sides
        .pixels()
        .zip(culled.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 8))
        .count();
    let total = (WIDTH * HEIGHT) as usize;
    assert!(
        hair > total / 10,
        "hair and head fill the frame: {hair} of {total}"
    );
    // Only where a tube's open end, a crease or the hair texture's thinned silhouette and tips
    // (alpha-to-coverage) show a back face: under 5 % of the frame (3.2 % with the hair texture,
    // 0.06 % at 1280×720 with the former opaque stripes, when measured); a wrong winding changes
    // about 20 %.
    assert!(changed * 20 < total, "{changed} of {total} pixels changed");
    // And the setting reached the renderer: open tube ends show somewhere (72 of the 57,600 pixels
    // when measured), so identical frames mean both children drew the same way.
    assert!(
        changed > 0,
        "{CULL_ENV} changed nothing: both frames drew the same"
    );
}

/// Where the child run with culling `cull` writes its frame.
fn image_path(cull: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cluster_culling_{cull}.png"))
}

/// Runs this test in a child process with [`CULL_ENV`] set to `cull` and reads back the frame it
/// wrote; a frame a former run left is removed first, so only this run's frame can be read.
fn render_in_child(cull: &str) -> image::RgbaImage {
    let path = image_path(cull);
    if let Err(error) = std::fs::remove_file(&path) {
        assert_eq!(error.kind(), std::io::ErrorKind::NotFound, "{error}");
    }
    let output = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "culling_cluster_back_faces_changes_almost_nothing",
            "--nocapture",
        ])
        .env(CHILD_MARKER, "1")
        .env(CULL_ENV, cull)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the child run with {CULL_ENV}={cull} failed ({}):\n{}\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let image = image::open(&path)
        .unwrap_or_else(|error| {
            panic!("no frame from the child run at {}: {error}", path.display())
        })
        .into_rgba8();
    assert_eq!(image.dimensions(), (WIDTH, HEIGHT), "{CULL_ENV}={cull}");
    image
}

/// In a child run: the paper-curly groom settled and drawn as clusters close up, with the culling
/// of cluster back faces that [`CULL_ENV`] says.
fn render_clusters() -> image::RgbaImage {
    let benchmark = resized(&paper_shot(false), 60, WIDTH, HEIGHT);
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
    let options = RendererOptions::from_env().unwrap();
    let mut renderer = PipelineRenderer::new(&options, pipeline.scene()).unwrap();
    // Culling concerns tessellated tubes; impostors face the eye whatever the culling.
    renderer.set_style(DrawStyle {
        cluster_geometry: ClusterGeometry::Tube,
        ..DrawStyle::default()
    });
    renderer
        .render(&mut pipeline, &camera, WIDTH, HEIGHT, ShadingMode::Shaded)
        .unwrap()
        .0
}
