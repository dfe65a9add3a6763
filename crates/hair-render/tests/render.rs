//! Rendering tests on whatever adapter is found (llvmpipe/lavapipe in CI): coverage, occlusion,
//! Kajiya-Kay shading, colour coding, GPU versus CPU B-splines, and bad input.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::bspline;
use hair_render::{BackendChoice, LevelColors, Renderer, ShadingMode, StrandStyle};

/// A fan of five wavy strands hanging in front of the camera, 7 nodes each.
fn hanging_strands() -> (Chains, Strands) {
    let mut chains = Chains::default();
    for s in 0..5 {
        let x = -0.08 + 0.04 * s as f32;
        let points: Vec<Vec3> = (0..7)
            .map(|k| {
                let t = k as f32 / 6.0;
                Vec3::new(
                    x + 0.012 * (t * 9.0).sin(),
                    0.1 - 0.2 * t,
                    0.02 * (t * 5.0).cos(),
                )
            })
            .collect();
        chains.push(&points);
    }
    let strands = Strands::one_per_chain(&chains);
    (chains, strands)
}

/// CPU samples of every strand's curve.
fn cpu_curves(chains: &Chains, strands: &Strands, samples: usize) -> Vec<Vec<Vec3>> {
    let frame = chains.frame();
    (0..strands.chain.len())
        .map(|s| {
            let points = frame.strand_control_points(strands.chain[s] as usize, strands.offsets[s]);
            bspline::sample(&points, samples)
        })
        .collect()
}

/// (a) Strands cover the pixels along their curves; nothing outside their projected bounding box
/// (grown by the ribbon half width and one pixel of MSAA blur) is touched.
fn strands_cover_their_screen_region(mut renderer: Renderer) {
    let (chains, strands) = hanging_strands();
    renderer.upload_strands(&strands.set()).unwrap();
    let settings = settings(160, 120, 3.0);
    let image = renderer.render(&chains.frame(), &settings).unwrap();

    let curves = cpu_curves(&chains, &strands, 65);
    let pixels: Vec<Vec2> = curves
        .iter()
        .flatten()
        .map(|&p| {
            settings
                .camera
                .project_to_pixel(p, settings.width, settings.height)
                .unwrap()
        })
        .collect();
    let margin = 1.5 + 1.0;
    let lo = pixels.iter().fold(Vec2::splat(f32::MAX), |a, &p| a.min(p)) - margin;
    let hi = pixels.iter().fold(Vec2::splat(f32::MIN), |a, &p| a.max(p)) + margin;
    let mut inside_lit = 0;
    for (x, y, pixel) in image.enumerate_pixels() {
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let inside = centre.cmpge(lo).all() && centre.cmple(hi).all();
        if inside {
            inside_lit += usize::from(is_lit(pixel));
        } else {
            assert!(
                !is_lit(pixel),
                "pixel ({x}, {y}) outside the strands' box {lo}..{hi} is {pixel:?}"
            );
        }
    }
    // Every pixel a curve passes through (away from the clamped ends) is hair.
    let mut missed = Vec::new();
    for curve in &curves {
        for &point in &curve[1..curve.len() - 1] {
            let (x, y) = pixel_of(&settings, point).unwrap();
            if !is_lit(image.get_pixel(x, y)) {
                missed.push((x, y));
            }
        }
    }
    assert!(
        missed.is_empty(),
        "curve pixels left as background: {missed:?}"
    );
    assert!(inside_lit > 5 * 60, "only {inside_lit} hair pixels");

    // A new frame moves the nodes only: the image follows them.
    let mut moved = chains.clone();
    for p in &mut moved.positions {
        p.x += 0.05;
    }
    let shifted = renderer.render(&moved.frame(), &settings).unwrap();
    let root = moved.positions[0] + (moved.positions[1] - moved.positions[0]) * 0.01;
    let (x, y) = pixel_of(&settings, root).unwrap();
    assert!(is_lit(shifted.get_pixel(x, y)));
    assert_ne!(image, shifted);
}

#[test]
fn strands_cover_their_screen_region_on_the_default_backend() {
    strands_cover_their_screen_region(renderer());
}

#[test]
fn strands_cover_their_screen_region_on_vulkan() {
    strands_cover_their_screen_region(renderer_on(BackendChoice::Vulkan));
}

#[test]
fn strands_cover_their_screen_region_on_gl() {
    strands_cover_their_screen_region(renderer_on(BackendChoice::Gl));
}

/// (b) A sphere between the camera and the strands hides them; strands in front of it stay visible.
#[test]
fn head_occludes_hair_behind_it() {
    let mut renderer = renderer();
    let mut chains = Chains::default();
    // Behind the sphere (z = -0.05), crossing its silhouette.
    for x in [-0.02f32, 0.0, 0.02] {
        chains.push_line(Vec3::new(x, 0.25, -0.05), Vec3::new(x, -0.25, -0.05), 6);
    }
    // In front of the sphere's nearest point (z = 0.3).
    chains.push_line(
        Vec3::new(-0.15, -0.03, 0.35),
        Vec3::new(0.15, -0.03, 0.35),
        6,
    );
    let strands = Strands::one_per_chain(&chains);
    renderer.upload_strands(&strands.set()).unwrap();
    let centre = Vec3::new(0.0, 0.0, 0.2);
    let radius = 0.1;
    renderer
        .set_head_mesh(Some(&sphere(centre, radius, 24, 48)))
        .unwrap();

    let mut settings = settings(160, 160, 3.0);
    settings.mode = ShadingMode::LevelColors;
    let colors = LevelColors::default();
    let yellow = [255u8, 255, 0];
    let grey = [srgb8(colors.head.x); 3];
    let image = renderer.render(&chains.frame(), &settings).unwrap();

    // The silhouette of a sphere of radius r at distance d subtends asin(r/d) from the eye.
    let eye = settings.camera.position;
    let silhouette = (radius / (centre - eye).length()).asin();
    let front_row = pixel_of(&settings, Vec3::new(0.0, -0.03, 0.35)).unwrap().1;
    let mut hidden = 0;
    let mut shown = 0;
    for chain in 0..3 {
        let nodes = chains.frame().strand_control_points(chain, Vec2::ZERO);
        let curve = bspline::sample(&nodes, 41);
        // Interior samples: a clamped end lies on a pixel edge and may cover it partly.
        for &point in &curve[1..curve.len() - 1] {
            let (x, y) = pixel_of(&settings, point).unwrap();
            if y.abs_diff(front_row) <= 3 {
                continue; // where the front strand crosses
            }
            let pixel = image.get_pixel(x, y).0;
            let angle = (point - eye).angle_between(centre - eye);
            if angle < silhouette * 0.9 {
                assert_eq!(pixel[..3], grey, "hair behind the head shows at ({x}, {y})");
                hidden += 1;
            } else if angle > silhouette * 1.1 {
                assert_eq!(
                    pixel[..3],
                    yellow,
                    "hair beside the head missing at ({x}, {y})"
                );
                shown += 1;
            }
        }
    }
    assert!(
        hidden > 20 && shown > 20,
        "{hidden} hidden, {shown} shown samples"
    );
    // The strand in front of the head is drawn over it.
    let (x, y) = pixel_of(&settings, Vec3::new(0.0, -0.03, 0.35)).unwrap();
    assert_eq!(image.get_pixel(x, y).0[..3], yellow);

    // Without the head the same pixels show hair.
    renderer.set_head_mesh(None).unwrap();
    let bare = renderer.render(&chains.frame(), &settings).unwrap();
    let (x, y) = pixel_of(&settings, Vec3::new(0.0, 0.0, -0.05)).unwrap();
    assert_eq!(bare.get_pixel(x, y).0[..3], yellow);
}

/// (c) Kajiya-Kay: with specular off, a strand has colour `base · (ambient + light · sin(T, L))`.
/// A strand along the light (sin = 0) gets the ambient term only; one across it gets the full
/// diffuse term; with the default specular the across strand is still the brighter one.
#[test]
fn strand_along_the_light_is_darker_than_one_across_it() {
    let mut renderer = renderer();
    // Along the light (+X), in the upper half; across it (along -Y), in the lower half.
    let chains = along_and_across_chains();
    let strands = Strands::one_per_chain(&chains);
    renderer.upload_strands(&strands.set()).unwrap();

    let mut settings = settings(128, 128, 4.0);
    diffuse_light_from_x(&mut settings);
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let along = image.get_pixel(
        64,
        pixel_of(&settings, Vec3::new(0.0, 0.06, 0.0)).unwrap().1,
    );
    let (ax, ay) = pixel_of(&settings, Vec3::new(0.0, -0.06, 0.0)).unwrap();
    let across = image.get_pixel(ax, ay);
    let expected_along = srgb8(0.4 * 0.1);
    let expected_across = srgb8(0.4 * (0.1 + 1.0));
    for c in 0..3 {
        assert!(
            along.0[c].abs_diff(expected_along) <= 2,
            "along: {along:?} vs {expected_along}"
        );
        assert!(
            across.0[c].abs_diff(expected_across) <= 2,
            "across: {across:?} vs {expected_across}"
        );
    }

    // Default brown hair with a specular highlight: still darker along the light, comparing the
    // mean luma of every hair pixel in each half.
    settings.hair = hair_render::HairMaterial::default();
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let mean = |rows: std::ops::Range<u32>| {
        let lit: Vec<f32> = rows
            .flat_map(|y| (0..128).map(move |x| (x, y)))
            .map(|(x, y)| image.get_pixel(x, y))
            .filter(|p| is_lit(p))
            .map(luma)
            .collect();
        assert!(lit.len() > 50, "{} hair pixels", lit.len());
        lit.iter().sum::<f32>() / lit.len() as f32
    };
    let (upper, lower) = (mean(0..60), mean(68..128));
    assert!(
        upper * 2.0 < lower,
        "along the light {upper}, across {lower}"
    );
}

/// (d) Colour-coded strands and head: every pixel is a blend of yellow, the grey head and the
/// black background, so red equals green and blue is at most red (no other hue), and both pure
/// colours appear.
#[test]
fn color_coded_render_has_only_the_level_colors() {
    let mut renderer = renderer();
    let (chains, strands) = hanging_strands();
    renderer.upload_strands(&strands.set()).unwrap();
    renderer
        .set_head_mesh(Some(&sphere(Vec3::new(0.0, 0.0, -0.1), 0.06, 16, 32)))
        .unwrap();
    let mut settings = settings(128, 128, 2.0);
    settings.mode = ShadingMode::LevelColors;
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let grey = srgb8(LevelColors::default().head.x);
    let (mut yellow, mut head) = (0, 0);
    for (x, y, pixel) in image.enumerate_pixels() {
        let [r, g, b, _] = pixel.0;
        assert!(
            r.abs_diff(g) <= 1 && b <= r.max(g),
            "pixel ({x}, {y}) has another hue: {pixel:?}"
        );
        yellow += usize::from([r, g, b] == [255, 255, 0]);
        head += usize::from([r, g, b] == [grey; 3]);
    }
    assert!(
        yellow > 100 && head > 100,
        "{yellow} yellow and {head} head pixels"
    );
}

/// (e) The vertex shader's B-spline is the CPU one: the evaluation pass runs the same WGSL
/// functions, and drawn 1-pixel lines end on the root and tip pixels.
#[test]
fn gpu_bspline_matches_the_cpu_reference() {
    let mut renderer = renderer();
    let mut chains = Chains::default();
    let mut strands = Strands::default();
    // Chains of 2 to 9 nodes (degrees 1 to 3), two strands each at different root offsets.
    for n in 2..10 {
        let points: Vec<Vec3> = (0..n)
            .map(|k| {
                let t = k as f32;
                Vec3::new(
                    0.03 * (t * 1.7).sin() + 0.01 * n as f32,
                    0.1 - 0.03 * t,
                    0.02 * (t * 0.9).cos(),
                )
            })
            .collect();
        let chain = chains.push(&points);
        strands.push(chain, Vec2::ZERO, 0.2);
        strands.push(chain, Vec2::new(0.004, -0.003), 0.8);
    }
    renderer.upload_strands(&strands.set()).unwrap();
    let samples = 33;
    let gpu = renderer.evaluate_strands(&chains.frame(), samples).unwrap();
    let cpu = cpu_curves(&chains, &strands, samples as usize);
    assert_eq!(gpu.len(), cpu.len() * samples as usize);
    for (s, curve) in cpu.iter().enumerate() {
        for (i, &expected) in curve.iter().enumerate() {
            let got = gpu[s * samples as usize + i];
            // f32 de Boor on coordinates ~0.1 m: a few ulps.
            assert!(
                (got - expected).length() < 1e-6,
                "strand {s} sample {i}: GPU {got}, CPU {expected}"
            );
        }
    }

    // Lines: the root and tip pixels (the first and last control points) are drawn.
    let mut settings = settings(200, 200, 1.0);
    settings.strand_style = StrandStyle::Lines;
    settings.mode = ShadingMode::LevelColors;
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    for (s, curve) in cpu.iter().enumerate() {
        for point in [curve[0], curve[curve.len() - 1], curve[curve.len() / 2]] {
            let (x, y) = pixel_of(&settings, point).unwrap();
            let near: Vec<_> = (x.saturating_sub(1)..=x + 1)
                .flat_map(|px| (y.saturating_sub(1)..=y + 1).map(move |py| (px, py)))
                .filter(|&(px, py)| image.get_pixel(px, py).0[0] > 0)
                .collect();
            assert!(
                !near.is_empty(),
                "strand {s}: no line pixel near ({x}, {y}) for {point}"
            );
        }
    }
}

/// Bad input gets clear errors, never a panic.
#[test]
fn bad_input_is_rejected_with_clear_errors() {
    let mut renderer = renderer();
    let (chains, strands) = hanging_strands();
    renderer.upload_strands(&strands.set()).unwrap();
    let good = settings(32, 32, 1.0);

    let zero = hair_render::FrameSettings { width: 0, ..good };
    let message = renderer
        .render(&chains.frame(), &zero)
        .unwrap_err()
        .to_string();
    assert!(message.contains("0x32"), "{message}");

    let mut nan = chains.clone();
    nan.positions[3] = Vec3::new(f32::NAN, 0.0, 0.0);
    let message = renderer
        .render(&nan.frame(), &good)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("node 3") && message.contains("position"),
        "{message}"
    );

    let mut short = chains.clone();
    short.normals.pop();
    let message = renderer
        .render(&short.frame(), &good)
        .unwrap_err()
        .to_string();
    assert!(message.contains("differ"), "{message}");

    let mut fewer = Chains::default();
    fewer.push_line(Vec3::ZERO, Vec3::NEG_Y, 3);
    let message = renderer
        .render(&fewer.frame(), &good)
        .unwrap_err()
        .to_string();
    assert!(message.contains("frame has 1 chains"), "{message}");

    let mismatched = hair_render::StrandSet {
        strand_shades: &[0.5],
        ..strands.set()
    };
    assert!(renderer.upload_strands(&mismatched).is_err());

    let mut broken_head = sphere(Vec3::ZERO, 0.1, 4, 8);
    broken_head.triangles.push([0, 1, 10_000]);
    let message = renderer
        .set_head_mesh(Some(&broken_head))
        .unwrap_err()
        .to_string();
    assert!(message.contains("10000"), "{message}");
    let mut nan_head = sphere(Vec3::ZERO, 0.1, 4, 8);
    nan_head.positions[2].y = f32::NAN;
    let error = renderer.set_head_mesh(Some(&nan_head)).unwrap_err();
    assert!(
        matches!(
            error,
            hair_render::RenderError::InvalidMesh(hair_core::mesh::MeshError::NonFinitePosition {
                vertex: 2,
                ..
            })
        ),
        "{error}"
    );

    let too_big = hair_render::FrameSettings {
        width: 1 << 20,
        ..good
    };
    assert!(renderer.render(&chains.frame(), &too_big).is_err());

    // The renderer still works after all that.
    assert!(renderer.render(&chains.frame(), &good).is_ok());
}

/// Strands with a single node or an empty chain draw nothing and do not disturb the others.
#[test]
fn degenerate_chains_draw_nothing() {
    let mut renderer = renderer();
    let mut chains = Chains::default();
    chains.push(&[Vec3::ZERO]);
    chains.offsets.push(chains.offsets[1]); // an empty chain
    chains.push_line(Vec3::new(0.05, 0.05, 0.0), Vec3::new(0.05, -0.05, 0.0), 4);
    let mut strands = Strands::default();
    for chain in 0..3 {
        strands.push(chain, Vec2::ZERO, 0.5);
    }
    renderer.upload_strands(&strands.set()).unwrap();
    let settings = settings(64, 64, 2.0);
    let image = renderer.render(&chains.frame(), &settings).unwrap();
    let (x, y) = pixel_of(&settings, Vec3::ZERO).unwrap();
    assert!(!is_lit(image.get_pixel(x, y)));
    let (x, y) = pixel_of(&settings, Vec3::new(0.05, 0.0, 0.0)).unwrap();
    assert!(is_lit(image.get_pixel(x, y)));
}
