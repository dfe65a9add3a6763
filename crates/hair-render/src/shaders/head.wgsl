// The head mesh: ordinary Lambert lighting with depth, so it hides the hair behind it.

struct HeadVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct HeadVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) world_position: vec3<f32>,
}

@vertex
fn vs_head(in: HeadVertexIn) -> HeadVertex {
    var out: HeadVertex;
    out.clip = globals.view_proj * vec4<f32>(in.position, 1.0);
    out.normal = in.normal;
    out.world_position = in.position;
    return out;
}

@fragment
fn fs_head(in: HeadVertex) -> @location(0) vec4<f32> {
    if (globals.shading.w > 0.5) {
        return vec4<f32>(globals.head_code_color.rgb, 1.0);
    }
    var normal = in.normal;
    if (dot(normal, normal) < 1e-20) {
        normal = globals.light_direction.xyz;
    }
    // Lit where it faces the light, through the hair between it and the light.
    let lambert = max(dot(normalize(normal), globals.light_direction.xyz), 0.0)
        * shadow_transmittance(in.world_position);
    let color = globals.head_color.rgb * (globals.ambient.rgb + globals.light_color.rgb * lambert);
    return vec4<f32>(color, 1.0);
}
