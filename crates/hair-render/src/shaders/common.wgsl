// Shared declarations of the hair-render shaders: per-frame globals and the storage buffers that
// hair geometry is pulled from. Must match `uniforms.rs` and `inputs.rs`.

struct Globals {
    view_proj: mat4x4<f32>,
    // xyz: camera position [m].
    camera_position: vec4<f32>,
    // xyz: unit direction towards the light.
    light_direction: vec4<f32>,
    light_color: vec4<f32>,
    ambient: vec4<f32>,
    hair_dark: vec4<f32>,
    hair_light: vec4<f32>,
    head_color: vec4<f32>,
    strand_code_color: vec4<f32>,
    cluster_code_color: vec4<f32>,
    patch_code_color: vec4<f32>,
    head_code_color: vec4<f32>,
    // x, y: image size [pixels].
    viewport: vec4<f32>,
    // x: diffuse, y: specular, z: specular exponent, w: 1 in colour-coding mode.
    shading: vec4<f32>,
    // x: ribbon half width [m], y: minimum half width [pixels], z: focal length [pixels], w: 1
    // for the hair texture on clusters and patches, 0 for stripes.
    ribbon: vec4<f32>,
    // x: strand count, y: chain count, z: node count, w: samples per strand (evaluation pass).
    counts: vec4<u32>,
    // The light's orthographic view-projection (self-shadowing, `shadows.wgsl`).
    light_view_proj: mat4x4<f32>,
    // x: 1 with self-shadowing on, y: the light view's depth range [m], z: optical depth a strand
    // line adds to a texel it crosses, w: 1 in the light passes.
    shadow: vec4<f32>,
    // Ends of the four opacity layers behind the first hair [m].
    shadow_layers: vec4<f32>,
    // x, y: strands per cluster and per patch × hair width × strand opacity [m], z: the light
    // passes' stride along the curves, w: their most segments around a cluster tube.
    shadow_surfaces: vec4<f32>,
    // x: 1 for Marschner shading (0: Kajiya-Kay), y: its shift α_R [rad], z: its width β_R [rad],
    // w: the fibre's refractive index.
    hair_model: vec4<f32>,
    // x: the hair width [m] whose share of a pixel a strand line covers (0: a whole pixel), y: the
    // target's samples per pixel, z: 1 when clusters are drawn as impostors
    // (`ClusterGeometry::Impostor`), 0 as tubes.
    line_coverage: vec4<f32>,
}

// One skeleton node and its frame (w components unused).
struct Node {
    position: vec4<f32>,
    normal: vec4<f32>,
    binormal: vec4<f32>,
}

// One chain of the frame: its nodes and the tessellation chosen for it on the CPU from its root's
// distance to the camera (§6).
struct Chain {
    first_node: u32,
    node_count: u32,
    // Segments along the hair.
    along_segments: u32,
    // Segments around a cluster tube.
    around_segments: u32,
    // Index of the chain's first sample in the chain-curve buffer (`chain_curves.wgsl`).
    first_sample: u32,
    // 1 when the chain's strands are drawn as lines (at most a pixel wide).
    thin: u32,
    // Fraction drawn, 0..1: a level fading in or out during a transition.
    coverage: f32,
    // 1 when a surface gives way to another coming in at 1 − coverage: it keeps the screen-door
    // pixels the other drops (see `screen_door_keeps`).
    gives_way: u32,
    // Weight of a drawn strand's opacity in the light passes: 1 / the fraction strand thinning
    // draws (`thinning.rs`).
    shadow_weight: f32,
    // How much wider than itself each drawn strand is drawn (thinning that raises widths).
    width_scale: f32,
    // The colour-coded view's level: 0 the chain's own, 1 strand groups, 2 clusters, 3 patch.
    code_level: u32,
}

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> nodes: array<Node>;
@group(0) @binding(2) var<storage, read> chains: array<Chain>;

// Screen-door threshold in 0..1 of a pixel (4×4 Bayer matrix): a surface with coverage c keeps the
// pixels whose threshold is below c.
fn screen_door_threshold(pixel: vec2<f32>) -> f32 {
    let x = u32(pixel.x) & 3u;
    let y = u32(pixel.y) & 3u;
    let bayer = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return (f32(bayer[y * 4u + x]) + 0.5) / 16.0;
}

// Whether a surface at `coverage` keeps `pixel`: the pixels whose threshold is below it, or, for
// a surface giving way to one at c = 1 − coverage, those whose threshold is at or above c, so
// that the two share no pixel and leave none out where both cover (a dithered cross-fade).
fn screen_door_keeps(pixel: vec2<f32>, coverage: f32, gives_way: u32) -> bool {
    let threshold = screen_door_threshold(pixel);
    if (gives_way != 0u) {
        return threshold >= 1.0 - coverage;
    }
    return threshold < coverage;
}
