//! Self-shadowing (deep opacity maps): hair between a point and the light darkens it, by the
//! optical depth of what lies in between, whatever level casts and whatever level receives; a
//! point with nothing between it and the light is lit as without shadows.
//!
//! The light comes from +X; the receiver stands at x = 0 and the caster at x = 0.02..0.04 in
//! front of the receiver's lower half only (y < 0), so the receiver's upper half is a control.
//! The camera looks from +Z, where caster and receiver lie side by side on screen.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{ClusterSet, FrameSettings, PatchSet, Renderer, SelfShadowing};

/// Node count of every test chain.
const NODES: usize = 5;
/// Fibre width used for the optical depth [m] (the default).
const HAIR_WIDTH: f32 = 80e-6;

/// A chain from `top` straight down `length` [m], node normal `normal`, binormal `binormal`.
fn push_vertical(chains: &mut Chains, top: Vec3, length: f32, normal: Vec3, binormal: Vec3) -> u32 {
    if chains.offsets.is_empty() {
        chains.offsets.push(0);
    }
    for k in 0..NODES {
        let t = k as f32 / (NODES - 1) as f32;
        chains.positions.push(top - Vec3::Y * (length * t));
        chains.normals.push(normal);
        chains.binormals.push(binormal);
    }
    chains.offsets.push(chains.positions.len() as u32);
    (chains.offsets.len() - 2) as u32
}

/// What casts the shadow.
#[derive(Clone, Copy, Debug)]
enum Caster {
    /// A block of vertical strands, 11 planes 2 mm apart along the light (x = 0.02..0.04), each
    /// with strands every 0.25 mm across it (z = ±6 mm).
    Strands,
    /// One cluster tube of radius 10 mm at x = 0.03 standing for [`SURFACE_STRANDS`] strands.
    Cluster,
    /// One patch 20 mm wide at x = 0.03, facing the light, standing for [`SURFACE_STRANDS`].
    Patch,
}

/// What receives it, at x = 0 from y = 0.1 down to y = -0.1.
#[derive(Clone, Copy, Debug)]
enum Receiver {
    Strand,
    Cluster,
    Patch,
}

/// Strands a caster cluster or patch stands for (uploaded on a chain without nodes, so that the
/// renderer's strands per surface is this).
const SURFACE_STRANDS: usize = 400;

/// Builds the scene on `renderer` and returns its frame's chains.
fn scene(renderer: &mut Renderer, caster: Caster, receiver: Receiver) -> Chains {
    let mut chains = Chains::default();
    let mut strands = Strands::default();
    let (mut clusters, mut cluster_radii) = (Vec::new(), Vec::new());
    let (mut patches, mut patch_widths) = (Vec::new(), Vec::new());
    // Receiver: node normal -Z, binormal +X (a patch then spans x and faces the camera).
    let chain = push_vertical(
        &mut chains,
        Vec3::new(0.0, 0.1, 0.0),
        0.2,
        Vec3::NEG_Z,
        Vec3::X,
    );
    match receiver {
        Receiver::Strand => strands.push(chain, Vec2::ZERO, 0.5),
        Receiver::Cluster => {
            clusters.push(chain);
            cluster_radii.push(0.006);
        }
        Receiver::Patch => {
            patches.push(chain);
            patch_widths.push(0.012);
        }
    }
    match caster {
        Caster::Strands => {
            for plane in 0..11 {
                for row in 0..49 {
                    let top = Vec3::new(
                        0.02 + 0.002 * plane as f32,
                        0.0,
                        -0.006 + 0.00025 * row as f32,
                    );
                    let chain = push_vertical(&mut chains, top, 0.1, Vec3::NEG_Z, Vec3::X);
                    strands.push(chain, Vec2::ZERO, 0.5);
                }
            }
        }
        Caster::Cluster | Caster::Patch => {
            // Binormal +Z: the patch spans z and faces the light (normal ±X).
            let top = Vec3::new(0.03, 0.0, 0.0);
            let chain = push_vertical(&mut chains, top, 0.1, Vec3::X, Vec3::Z);
            if matches!(caster, Caster::Cluster) {
                clusters.push(chain);
                cluster_radii.push(0.010);
            } else {
                patches.push(chain);
                patch_widths.push(0.020);
            }
            // The strands the surface stands for, on a chain without nodes (drawn nowhere).
            chains.offsets.push(chains.positions.len() as u32);
            let inactive = (chains.offsets.len() - 2) as u32;
            for _ in 0..SURFACE_STRANDS {
                strands.push(inactive, Vec2::ZERO, 0.5);
            }
        }
    }
    renderer.upload_strands(&strands.set()).unwrap();
    renderer
        .upload_clusters(&ClusterSet {
            cluster_chain: &clusters,
            cluster_root_radii: &cluster_radii,
            cluster_tip_radii: &cluster_radii,
        })
        .unwrap();
    renderer
        .upload_patches(&PatchSet {
            patch_chain: &patches,
            patch_widths: &patch_widths,
        })
        .unwrap();
    chains
}

fn shadow_settings(enabled: bool) -> FrameSettings {
    let mut settings = settings(320, 320, 3.0);
    diffuse_light_from_x(&mut settings);
    settings.camera.position = Vec3::new(0.0, 0.0, 0.5);
    settings.shadows = if enabled {
        SelfShadowing::default()
    } else {
        SelfShadowing::off()
    };
    settings
}

/// Luma of the receiver's pixel at height `y` [m], with and without self-shadowing.
fn receiver_luma(caster: Caster, receiver: Receiver, y: f32) -> (f32, f32) {
    let mut renderer = single_sample_renderer(None);
    let chains = scene(&mut renderer, caster, receiver);
    let mut lumas = [0.0; 2];
    for (slot, enabled) in [(0, true), (1, false)] {
        let settings = shadow_settings(enabled);
        let image = renderer.render(&chains.frame(), &settings).unwrap();
        let (x, py) = pixel_of(&settings, Vec3::new(0.0, y, 0.0)).unwrap();
        lumas[slot] = luma(image.get_pixel(x, py));
    }
    (lumas[0], lumas[1])
}

/// Strands behind a block of strands: the block's optical depth is known, so the shadowed
/// colour is too. Each plane of the block has strands every 0.25 mm, each covering 80 µm of it
/// and stopping 40 % of the light it covers: τ = 11 · 0.4 · 0.08/0.25 = 1.41 in all. A vertical
/// strand across a light from +X has Kajiya-Kay diffuse 1, so its linear colour is
/// `0.4 · (0.1 + e^(−τ))` = 0.138 shadowed and 0.44 lit. The block gives each texel column the
/// strands that cross it (2.1 per plane on average, 2 or 3 in fact): τ is asked within ±30 %.
#[test]
fn strands_behind_strands_receive_the_blocks_optical_depth() {
    let (shadowed, unshadowed) = receiver_luma(Caster::Strands, Receiver::Strand, -0.05);
    let tau = 11.0 * 0.4 * HAIR_WIDTH / 0.00025;
    let expect = |t: f32| f32::from(srgb8(0.4 * (0.1 + (-t).exp())));
    assert!(
        shadowed <= expect(0.7 * tau) && shadowed >= expect(1.3 * tau),
        "shadowed luma {shadowed}, expected {} (τ = {tau}) within [{}, {}]",
        expect(tau),
        expect(1.3 * tau),
        expect(0.7 * tau)
    );
    assert!(
        (unshadowed - expect(0.0)).abs() <= 2.0,
        "without shadows: {unshadowed}, expected {}",
        expect(0.0)
    );
    // Above the block nothing is between the strand and the light: lit as without shadows.
    let (free, reference) = receiver_luma(Caster::Strands, Receiver::Strand, 0.05);
    assert!((free - reference).abs() <= 2.0, "{free} vs {reference}");
}

/// A cluster and a patch cast the shadow of the strands they stand for: 400 fibres of 80 µm
/// stopping 40 % of the light, through a tube of 6.7 mm ring radius along its diameter,
/// τ = 2·400·80 µm·0.4/(π·6.7 mm) = 1.2; across a 20 mm strip facing the light, 0.64. The
/// receiver is asked to be darker than unshadowed by at least half the expected drop (the ray
/// meets the tube off its diameter over most of the pixel's texel footprint).
#[test]
fn clusters_and_patches_cast_shadows() {
    for (caster, tau) in [(Caster::Cluster, 1.2f32), (Caster::Patch, 0.64)] {
        let (shadowed, unshadowed) = receiver_luma(caster, Receiver::Strand, -0.05);
        let lit = f32::from(srgb8(0.44));
        let expected = f32::from(srgb8(0.4 * (0.1 + (-tau).exp())));
        assert!(
            shadowed <= unshadowed - 0.5 * (lit - expected),
            "{caster:?}: shadowed {shadowed}, unshadowed {unshadowed}, expected about {expected}"
        );
        let (free, reference) = receiver_luma(caster, Receiver::Strand, 0.05);
        assert!(
            (free - reference).abs() <= 2.0,
            "{caster:?}: {free} vs {reference}"
        );
    }
}

/// Clusters and patches receive shadows too: with self-shadowing on, the receiver's point
/// behind the block is darker than its point above it (by at least a quarter), while without
/// it the two are lit alike. (The free point is not compared across the switch: a tube shades
/// its own far side by the strands it stands for, as a clump of strands would.)
#[test]
fn clusters_and_patches_receive_shadows() {
    for receiver in [Receiver::Cluster, Receiver::Patch] {
        let (behind_on, behind_off) = receiver_luma(Caster::Strands, receiver, -0.05);
        let (free_on, free_off) = receiver_luma(Caster::Strands, receiver, 0.05);
        assert!(
            behind_on < 0.75 * free_on,
            "{receiver:?}: behind the block {behind_on}, above it {free_on}"
        );
        assert!(
            (behind_off - free_off).abs() <= 2.0,
            "{receiver:?} without shadows: {behind_off} vs {free_off}"
        );
    }
}

/// Bad shadow settings are errors, not NaNs.
#[test]
fn bad_shadow_settings_are_errors() {
    let mut renderer = single_sample_renderer(None);
    let chains = scene(&mut renderer, Caster::Strands, Receiver::Strand);
    let mut settings = shadow_settings(true);
    settings.shadows.layer_ends = [0.0, 0.01, 0.02, 0.03];
    let error = renderer.render(&chains.frame(), &settings).unwrap_err();
    assert!(error.to_string().contains("layer"), "{error}");
}
