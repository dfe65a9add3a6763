//! Shared helpers of the rendering tests: renderers, straight and wavy chains, a sphere head,
//! pixel classification.

#![allow(dead_code)]

use glam::{Vec2, Vec3};
use hair_core::TriangleMesh;
use hair_render::{
    BackendChoice, Camera, DeviceOptions, FrameSettings, Renderer, RendererOptions, SkeletonFrame,
    StrandSet, StrandStyle,
};

/// A renderer on the backend from `HAIRLOD_BACKEND` (auto when unset).
pub fn renderer() -> Renderer {
    let options = RendererOptions::from_env().expect("HAIRLOD_BACKEND");
    let renderer =
        Renderer::new(&options).expect("a renderer (install mesa-vulkan-drivers or libegl-mesa0)");
    eprintln!("adapter: {}", renderer.adapter_report());
    renderer
}

/// A renderer on `backend`.
pub fn renderer_on(backend: BackendChoice) -> Renderer {
    let options = RendererOptions {
        device: DeviceOptions {
            backend,
            ..DeviceOptions::default()
        },
    };
    let renderer =
        Renderer::new(&options).unwrap_or_else(|e| panic!("a renderer on {backend}: {e}"));
    eprintln!("adapter: {}", renderer.adapter_report());
    renderer
}

/// A renderer without multisampling (every pixel holds exactly one fragment's colour) on
/// `backend`, or on the one from `HAIRLOD_BACKEND` for `None`.
pub fn single_sample_renderer(backend: Option<BackendChoice>) -> Renderer {
    let mut options = RendererOptions::from_env().expect("HAIRLOD_BACKEND");
    options.device = DeviceOptions {
        sample_count: 1,
        backend: backend.unwrap_or(options.device.backend),
        ..options.device
    };
    let renderer =
        Renderer::new(&options).expect("a renderer (install mesa-vulkan-drivers or libegl-mesa0)");
    eprintln!("adapter: {}", renderer.adapter_report());
    renderer
}

/// Two straight chains of 5 nodes: one along +X in the upper half of the default view, one along
/// -Y in the lower half (along and across a light from +X).
pub fn along_and_across_chains() -> Chains {
    let mut chains = Chains::default();
    chains.push_line(Vec3::new(-0.1, 0.06, 0.0), Vec3::new(0.1, 0.06, 0.0), 5);
    chains.push_line(Vec3::new(0.0, -0.01, 0.0), Vec3::new(0.0, -0.12, 0.0), 5);
    chains
}

/// White light from +X with ambient 0.1 and grey hair (base 0.4, diffuse 1, specular off), so a
/// strand's Kajiya-Kay colour is `0.4 · (0.1 + sin(T, L))`.
pub fn diffuse_light_from_x(settings: &mut FrameSettings) {
    settings.light.direction = Vec3::X;
    settings.light.color = Vec3::ONE;
    settings.light.ambient = Vec3::splat(0.1);
    let base = Vec3::splat(0.4);
    settings.hair.dark_color = base;
    settings.hair.light_color = base;
    settings.hair.diffuse = 1.0;
    settings.hair.specular = 0.0;
}

/// Node chains with frames, stored flat like the core will feed them.
#[derive(Default, Clone)]
pub struct Chains {
    pub offsets: Vec<u32>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub binormals: Vec<Vec3>,
}

impl Chains {
    /// Adds a chain through `points`, with a node frame orthogonal to the chain direction.
    pub fn push(&mut self, points: &[Vec3]) -> u32 {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        for (k, &point) in points.iter().enumerate() {
            let next = points[(k + 1).min(points.len() - 1)];
            let previous = points[k.saturating_sub(1)];
            let tangent = (next - previous).normalize_or(Vec3::NEG_Y);
            let normal = tangent.any_orthonormal_vector();
            self.positions.push(point);
            self.normals.push(normal);
            self.binormals.push(tangent.cross(normal));
        }
        self.offsets.push(self.positions.len() as u32);
        (self.offsets.len() - 2) as u32
    }

    /// A straight chain of `nodes` nodes from `start` to `end`.
    pub fn push_line(&mut self, start: Vec3, end: Vec3, nodes: usize) -> u32 {
        let points: Vec<Vec3> = (0..nodes)
            .map(|k| start.lerp(end, k as f32 / (nodes - 1) as f32))
            .collect();
        self.push(&points)
    }

    pub fn frame(&self) -> SkeletonFrame<'_> {
        SkeletonFrame {
            chain_offsets: &self.offsets,
            node_positions: &self.positions,
            node_normals: &self.normals,
            node_binormals: &self.binormals,
            chain_coverage: &[],
            chain_gives_way: &[],
            chain_simulated_at: &[],
        }
    }
}

/// One vertical chain of `nodes` nodes from y = `half_length` down to y = −`half_length` at
/// x = 0 [m], with fixed node frames: normal −Z, binormal +X (a patch on it spans x, facing the
/// camera).
pub fn vertical_chain(half_length: f32, nodes: usize) -> Chains {
    let mut chains = Chains::default();
    chains.offsets.push(0);
    for k in 0..nodes {
        let y = half_length - 2.0 * half_length * k as f32 / (nodes - 1) as f32;
        chains.positions.push(Vec3::new(0.0, y, 0.0));
        chains.normals.push(Vec3::NEG_Z);
        chains.binormals.push(Vec3::X);
    }
    chains.offsets.push(nodes as u32);
    chains
}

/// Strands, one per chain with zero offset, unless pushed otherwise.
#[derive(Default, Clone)]
pub struct Strands {
    pub chain: Vec<u32>,
    pub offsets: Vec<Vec2>,
    pub shades: Vec<f32>,
}

impl Strands {
    pub fn push(&mut self, chain: u32, offset: Vec2, shade: f32) {
        self.chain.push(chain);
        self.offsets.push(offset);
        self.shades.push(shade);
    }

    pub fn one_per_chain(chains: &Chains) -> Strands {
        let mut strands = Strands::default();
        for chain in 0..chains.offsets.len().saturating_sub(1) {
            strands.push(chain as u32, Vec2::ZERO, 0.5);
        }
        strands
    }

    pub fn set(&self) -> StrandSet<'_> {
        StrandSet {
            strand_chain: &self.chain,
            strand_root_offsets: &self.offsets,
            strand_shades: &self.shades,
        }
    }
}

/// A UV sphere of `radius` [m] around `centre`, counter-clockwise seen from outside.
pub fn sphere(centre: Vec3, radius: f32, rings: u32, segments: u32) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for ring in 0..=rings {
        let polar = std::f32::consts::PI * ring as f32 / rings as f32;
        for segment in 0..=segments {
            let azimuth = std::f32::consts::TAU * segment as f32 / segments as f32;
            let direction = Vec3::new(
                polar.sin() * azimuth.cos(),
                polar.cos(),
                polar.sin() * azimuth.sin(),
            );
            mesh.positions.push(centre + direction * radius);
        }
    }
    let row = segments + 1;
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * row + segment;
            let b = a + row;
            mesh.triangles.push([a, a + 1, b]);
            mesh.triangles.push([a + 1, b + 1, b]);
        }
    }
    mesh.compute_vertex_normals();
    mesh
}

/// Frame settings for tests: black background, camera 1 m in front on +Z, ribbons `width_px` wide.
pub fn settings(width: u32, height: u32, width_px: f32) -> FrameSettings {
    let mut settings = FrameSettings::new(width, height, Camera::default());
    settings.background = Vec3::ZERO;
    settings.strand_style = StrandStyle::Ribbons {
        width: 0.0,
        min_width_pixels: width_px,
    };
    settings
}

/// The 8-bit sRGB encoding of a linear value in 0..1 (what an Rgba8UnormSrgb target stores).
pub fn srgb8(linear: f32) -> u8 {
    let l = linear.clamp(0.0, 1.0);
    let encoded = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round() as u8
}

/// The pixel a world point projects to, if it is inside the image.
pub fn pixel_of(settings: &FrameSettings, point: Vec3) -> Option<(u32, u32)> {
    let p = settings
        .camera
        .project_to_pixel(point, settings.width, settings.height)?;
    let (x, y) = (p.x.floor(), p.y.floor());
    (x >= 0.0 && y >= 0.0 && x < settings.width as f32 && y < settings.height as f32)
        .then_some((x as u32, y as u32))
}

/// Whether a pixel differs from a black background.
pub fn is_lit(pixel: &image::Rgba<u8>) -> bool {
    pixel.0[..3].iter().any(|&c| c > 0)
}

/// Whether each of `points` is drawn by `renderer` in `frame`: unshadowed, 200×200, ribbons
/// 3 pixels wide, through the test camera ([`settings`]).
pub fn lit_at(renderer: &mut Renderer, frame: &SkeletonFrame<'_>, points: &[Vec3]) -> Vec<bool> {
    let mut settings = settings(200, 200, 3.0);
    settings.shadows = hair_render::SelfShadowing::off();
    let image = renderer.render(frame, &settings).unwrap();
    points
        .iter()
        .map(|&p| {
            let (x, y) = pixel_of(&settings, p).unwrap();
            is_lit(image.get_pixel(x, y))
        })
        .collect()
}

/// Rec. 709 luma of an 8-bit pixel.
pub fn luma(pixel: &image::Rgba<u8>) -> f32 {
    let [r, g, b, _] = pixel.0;
    0.2126 * f32::from(r) + 0.7152 * f32::from(g) + 0.0722 * f32::from(b)
}
