// Strands: GPU B-spline evaluation by vertex pulling, camera-facing ribbons or lines, and
// Kajiya-Kay shading in the Heidrich-Seidel form (no surface normal, only the tangent).

struct StrandVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) @interpolate(flat) shade: f32,
}

// Segments for a strand whose root is at `root` [m]: fewer with distance to the camera (§6).
fn strand_segments(root: vec3<f32>) -> u32 {
    let max_segments = globals.tessellation.x;
    let min_segments = globals.tessellation.y;
    let distance = max(length(root - globals.camera_position.xyz), 1e-6);
    let wanted = min(ceil(max_segments * globals.tessellation.z / distance), max_segments);
    return u32(clamp(wanted, min_segments, max_segments));
}

// Point `point_index` of a strand, pushed `side` half widths sideways on screen (0 for lines).
// Points past the strand's segment count collapse onto its tip (degenerate primitives).
fn strand_vertex(strand_index: u32, point_index: u32, side: f32) -> StrandVertex {
    var out: StrandVertex;
    // Outside the clip volume: unusable strands draw nothing.
    out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    out.world_position = vec3<f32>(0.0);
    out.tangent = vec3<f32>(0.0, 1.0, 0.0);
    out.shade = 0.0;
    if (strand_index >= globals.counts.x) {
        return out;
    }
    let strand = strands[strand_index];
    let chain = strand_chain(strand);
    if (chain.node_count < 2u) {
        return out;
    }
    let segments = strand_segments(nodes[chain.first_node].position.xyz);
    let u = f32(min(point_index, segments)) / f32(segments);
    let curve = evaluate_strand(chain, strand.root_offset, u);
    var tangent = curve.derivative;
    if (dot(tangent, tangent) < 1e-20) {
        tangent = vec3<f32>(0.0, 1.0, 0.0);
    }
    tangent = normalize(tangent);
    let clip = globals.view_proj * vec4<f32>(curve.position, 1.0);
    var offset = vec2<f32>(0.0);
    if (side != 0.0) {
        // Screen direction of the curve: derivative of the projected point along the tangent.
        let w = max(clip.w, 1e-6);
        let clip_tangent = globals.view_proj * vec4<f32>(tangent, 0.0);
        let ndc_tangent = (clip_tangent.xy * w - clip.xy * clip_tangent.w) / (w * w);
        var screen = ndc_tangent * globals.viewport.xy;
        if (dot(screen, screen) < 1e-24) {
            screen = vec2<f32>(1.0, 0.0);
        }
        let along = normalize(screen);
        let across = vec2<f32>(-along.y, along.x);
        // Half width in pixels: the projected hair width, but at least the minimum.
        let half_pixels = max(globals.ribbon.x * globals.ribbon.z / w, globals.ribbon.y);
        offset = across * side * half_pixels * 2.0 / globals.viewport.xy * clip.w;
    }
    out.clip = vec4<f32>(clip.xy + offset, clip.zw);
    out.world_position = curve.position;
    out.tangent = tangent;
    out.shade = strand.shade;
    return out;
}

// Triangle strip per instance (one strand): vertices 2i and 2i + 1 straddle curve point i.
@vertex
fn vs_strand_ribbon(@builtin(vertex_index) vertex: u32, @builtin(instance_index) strand: u32) -> StrandVertex {
    let side = select(-1.0, 1.0, (vertex & 1u) == 1u);
    return strand_vertex(strand, vertex / 2u, side);
}

// Line strip per instance (one strand): vertex i is curve point i.
@vertex
fn vs_strand_line(@builtin(vertex_index) vertex: u32, @builtin(instance_index) strand: u32) -> StrandVertex {
    return strand_vertex(strand, vertex, 0.0);
}

// Heidrich-Seidel form of Kajiya-Kay: diffuse ∝ sin(T, L),
// specular ∝ (sin(T, L) sin(T, V) - (T·L)(T·V))^p.
fn kajiya_kay(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>) -> vec2<f32> {
    let tl = dot(tangent, to_light);
    let tv = dot(tangent, to_eye);
    let sin_tl = sqrt(max(0.0, 1.0 - tl * tl));
    let sin_tv = sqrt(max(0.0, 1.0 - tv * tv));
    let diffuse = sin_tl;
    let specular = pow(max(sin_tl * sin_tv - tl * tv, 1e-6), globals.shading.z);
    return vec2<f32>(diffuse, specular);
}

@fragment
fn fs_strand(in: StrandVertex) -> @location(0) vec4<f32> {
    if (globals.shading.w > 0.5) {
        return vec4<f32>(globals.strand_code_color.rgb, 1.0);
    }
    let tangent = normalize(in.tangent);
    let to_eye = normalize(globals.camera_position.xyz - in.world_position);
    let lighting = kajiya_kay(tangent, globals.light_direction.xyz, to_eye);
    let base = mix(globals.hair_dark.rgb, globals.hair_light.rgb, in.shade);
    let color = base * (globals.ambient.rgb + globals.light_color.rgb * globals.shading.x * lighting.x)
        + globals.light_color.rgb * globals.shading.y * lighting.y;
    return vec4<f32>(color, 1.0);
}
