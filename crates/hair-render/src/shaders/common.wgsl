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
    // x: ribbon half width [m], y: minimum half width [pixels], z: focal length [pixels].
    ribbon: vec4<f32>,
    // x: strand count, y: chain count, z: node count, w: samples per strand (evaluation pass).
    counts: vec4<u32>,
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
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<storage, read> nodes: array<Node>;
@group(0) @binding(2) var<storage, read> chains: array<Chain>;
