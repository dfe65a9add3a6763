// Self-shadowing with deep opacity maps (Yuksel & Keyser 2008), see `shadows.rs`: the light-space
// depth map of the hair nearest the light, the opacity map of four layers behind it, the lookup
// of the light a point receives, and the fragment shaders of the opacity pass.

// Depth [0, 1] of the hair nearest the light, per texel (a colour texture: GLSL cannot load
// from depth textures).
@group(2) @binding(0) var shadow_depth: texture_2d<f32>;
// Optical depth gathered in each of the four layers behind it (r, g, b, a).
@group(2) @binding(1) var shadow_opacity: texture_2d<f32>;
@group(2) @binding(2) var shadow_sampler: sampler;

// Optical depth in front of a point `d` [m] behind the first hair: the layers that end before
// `d`, and the part of the one it lies in (linear within a layer).
fn layered_optical_depth(layers: vec4<f32>, d: f32) -> f32 {
    let ends = globals.shadow_layers;
    let starts = vec4<f32>(0.0, ends.x, ends.y, ends.z);
    let fraction = clamp((vec4<f32>(d) - starts) / (ends - starts), vec4<f32>(0.0), vec4<f32>(1.0));
    return dot(layers, fraction);
}

// A world point in the light's map: xy texture coordinates (0..1, y down), z depth (0..1).
fn light_space(p: vec3<f32>) -> vec3<f32> {
    let clip = globals.light_view_proj * vec4<f32>(p, 1.0);
    return vec3<f32>(clip.x * 0.5 + 0.5, 0.5 - clip.y * 0.5, clip.z);
}

// Fraction of the light that reaches world point `p` through the hair between it and the light
// (1 with self-shadowing off or outside the map).
fn shadow_transmittance(p: vec3<f32>) -> f32 {
    if (globals.shadow.x < 0.5) {
        return 1.0;
    }
    let s = light_space(p);
    if (any(s.xy < vec2<f32>(0.0)) || any(s.xy > vec2<f32>(1.0))) {
        return 1.0;
    }
    let size = vec2<i32>(textureDimensions(shadow_depth));
    // The first hair over the bilinear footprint of the opacity lookup (the nearest of 4 texels).
    let corner = vec2<i32>(floor(s.xy * vec2<f32>(size) - 0.5));
    var z0 = 1.0;
    for (var k = 0; k < 4; k++) {
        let texel = clamp(corner + vec2<i32>(k & 1, k >> 1), vec2<i32>(0), size - 1);
        z0 = min(z0, textureLoad(shadow_depth, texel, 0).r);
    }
    let d = max(s.z - z0, 0.0) * globals.shadow.y;
    let layers = textureSampleLevel(shadow_opacity, shadow_sampler, s.xy, 0.0);
    return exp(-layered_optical_depth(layers, d));
}

// The layer (one-hot) of a fragment at light-space pixel `pixel`, depth `z`, in the opacity pass.
fn opacity_layer(pixel: vec2<f32>, z: f32) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(shadow_depth));
    let texel = clamp(vec2<i32>(pixel), vec2<i32>(0), size - 1);
    let d = max(z - textureLoad(shadow_depth, texel, 0).r, 0.0) * globals.shadow.y;
    let ends = globals.shadow_layers;
    if (d < ends.x) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    if (d < ends.y) {
        return vec4<f32>(0.0, 1.0, 0.0, 0.0);
    }
    if (d < ends.z) {
        return vec4<f32>(0.0, 0.0, 1.0, 0.0);
    }
    return vec4<f32>(0.0, 0.0, 0.0, 1.0);
}

// Curve points drawn in the light passes: every `stride`-th of the chain's `segments` (the
// last always), so `ceil(segments / stride)` segments.
fn shadow_segments(segments: u32) -> u32 {
    let stride = max(u32(globals.shadow_surfaces.z), 1u);
    return (segments + stride - 1u) / stride;
}
