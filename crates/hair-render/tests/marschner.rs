//! Marschner shading on the GPU against its CPU reference (`hair_render::marschner`): a short
//! straight strand, single-sampled and shaded per fragment, lit from in front, from the side and
//! from behind, with the diffuse term and the ambient light off so that the pixels are the
//! lobes alone, `light · S · cos θ_i`.

mod common;

use common::*;
use glam::Vec3;
use hair_render::{
    BackendChoice, FrameSettings, HairShading, LineShading, Marschner, SelfShadowing, StrandStyle,
};

/// The colour of the strand's pixels in the row through the origin (the brightest there, so
/// that the 1-pixel line is found whichever column it falls in).
fn strand_pixel(image: &image::RgbaImage, settings: &FrameSettings) -> [u8; 3] {
    let (x0, y0) = pixel_of(settings, Vec3::ZERO).expect("the origin is on screen");
    (x0.saturating_sub(2)..=x0 + 2)
        .map(|x| image.get_pixel(x, y0).0)
        .max_by_key(|p| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]))
        .map(|p| [p[0], p[1], p[2]])
        .unwrap()
}

/// Each channel of `pixel` within 2 levels of the sRGB encoding of `expected` (one level for
/// the target's rounding, one for f32 differences between the shader's and the CPU's `asin`,
/// `exp` and `pow`); the row's pixel sees the eye from the origin within half a pixel (0.3 mm at
/// 1 m: 3·10⁻⁴ rad, 0.5 % of the TT lobe's width).
fn close(pixel: [u8; 3], expected: Vec3) -> bool {
    (0..3).all(|c| pixel[c].abs_diff(srgb8(expected[c])) <= 2)
}

#[test]
fn marschner_strands_match_the_cpu_model_on_vulkan() {
    strands_match_the_cpu_model(single_sample_renderer(Some(BackendChoice::Vulkan)));
}

#[test]
fn marschner_strands_match_the_cpu_model_on_gl() {
    strands_match_the_cpu_model(single_sample_renderer(Some(BackendChoice::Gl)));
}

fn strands_match_the_cpu_model(mut renderer: hair_render::Renderer) {
    let mut chains = Chains::default();
    // Root above, tip below: the tangent (root to tip) is −Y.
    let (root, tip) = (Vec3::new(0.0, 0.01, 0.0), Vec3::new(0.0, -0.01, 0.0));
    chains.push_line(root, tip, 3);
    renderer
        .upload_strands(&Strands::one_per_chain(&chains).set())
        .unwrap();
    let tangent = (tip - root).normalize();
    let absorption = Vec3::new(0.8, 0.5, 0.3);
    let model = Marschner::default();

    let mut settings = settings(160, 160, 1.0);
    settings.strand_style = StrandStyle::Lines;
    settings.line_shading = LineShading::PerFragment;
    settings.shadows = SelfShadowing::off();
    settings.light.ambient = Vec3::ZERO;
    settings.hair.dark_color = absorption;
    settings.hair.light_color = absorption;
    settings.hair.diffuse = 0.0;
    settings.hair.shading = HairShading::Marschner(model);
    let to_eye = (settings.camera.position - Vec3::ZERO).normalize();

    // In front, a little above (R and TRT); from the side (φ = 90°); from behind (TT).
    let lights = [
        Vec3::new(0.3, 0.4, 1.0),
        Vec3::new(1.0, -0.2, 0.05),
        Vec3::new(0.15, 0.1, -1.0),
    ];
    let mut differs_from_kajiya_kay = false;
    for direction in lights {
        let to_light = direction.normalize();
        settings.light.direction = to_light;
        // The light is scaled so that the brightest channel is 0.6: each lobe's pixels are
        // resolved within the 8-bit target.
        let scatter = model.scatter(tangent, to_light, to_eye, absorption);
        assert!(scatter.max_element() > 1e-3, "light {to_light}: {scatter}");
        settings.light.color = Vec3::splat(0.6 / scatter.max_element());
        let expected = settings.light.color * scatter;
        let image = renderer.render(&chains.frame(), &settings).unwrap();
        let pixel = strand_pixel(&image, &settings);
        eprintln!("light {to_light}: pixel {pixel:?}, model {expected}");
        assert!(
            close(pixel, expected),
            "light {to_light}: pixel {pixel:?}, model {expected} = {:?}",
            expected.to_array().map(srgb8)
        );

        // Switched off (Kajiya-Kay's specular lobe instead), the strand is another colour.
        let kajiya_kay = FrameSettings {
            hair: hair_render::HairMaterial {
                shading: HairShading::KajiyaKay,
                ..settings.hair
            },
            ..settings
        };
        let image = renderer.render(&chains.frame(), &kajiya_kay).unwrap();
        differs_from_kajiya_kay |= !close(strand_pixel(&image, &kajiya_kay), expected);
    }
    assert!(differs_from_kajiya_kay);
}
