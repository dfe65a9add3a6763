// Copies the viewer's composed image (hair, head and HUD, sRGB RGBA8) onto the window's surface,
// pixel for pixel: a full-screen triangle that loads the texel under each fragment.

@group(0) @binding(0) var composed: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // (-1, -1), (3, -1), (-1, 3): one triangle covering the screen.
    let x = f32((index << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(index & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(composed, vec2<i32>(position.xy), 0);
}
