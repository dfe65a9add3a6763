// Clusters (§3.4, closed tubes: 4 control points per node, periodic cubic around) and patches
// (§3.3, ruled strips: 2 control points per node, linear across), evaluated from the skeleton nodes
// by vertex pulling and shaded with Kajiya-Kay along the hair, a light-facing term from the surface
// normal, and a procedural stripe texture in the hair colour range.

// Static data of one cluster or patch (`GpuSurface` in `surfaces.rs`), uploaded once, sorted by
// chain. Clusters: scales are the root and tip radii [m]; patches: both are half the width [m].
struct Surface {
    chain: u32,
    root_scale: f32,
    tip_scale: f32,
    seed: u32,
}

@group(1) @binding(0) var<storage, read> surfaces: array<Surface>;

// Texture stripes around a cluster and across a patch.
const STRIPES_AROUND: f32 = 14.0;
const STRIPES_ACROSS: f32 = 22.0;

struct SurfaceVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) tangent: vec3<f32>,
    @location(2) normal: vec3<f32>,
    // x: across (0..1 around a tube, 0..1 across a strip), y: along the hair (0 root, 1 tip).
    @location(3) texcoord: vec2<f32>,
    // 1: cluster, 2: patch.
    @location(4) @interpolate(flat) kind: u32,
    @location(5) @interpolate(flat) seed: u32,
    @location(6) @interpolate(flat) coverage: f32,
    // Control radius (clusters) or half width (patches) here [m].
    @location(7) scale: f32,
    // Fraction of the light that reaches the vertex through the hair (self-shadowing, looked up
    // per vertex as strand lines do, interpolated between: the opacity map's texels are as
    // large as the tessellation's spacing; 1 in the light passes and without shadows).
    @location(8) light: f32,
    // 1: the surface gives way to another level's (its screen door is the complement).
    @location(9) @interpolate(flat) gives_way: u32,
}

// Offset direction on the unit control circle [cos(j·90°), sin(j·90°)], j = 0..3, blended by the
// periodic uniform cubic B-spline at u ∈ [0, 1] (span s uses points s..s+3 mod 4).
fn ring_offset(u: f32) -> vec2<f32> {
    let x = fract(u) * 4.0;
    let span = u32(floor(x)) % 4u;
    let t = x - floor(x);
    let t2 = t * t;
    let t3 = t2 * t;
    let weights = vec4<f32>(
        (1.0 - t) * (1.0 - t) * (1.0 - t),
        3.0 * t3 - 6.0 * t2 + 4.0,
        -3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0,
        t3,
    ) / 6.0;
    let directions = array<vec2<f32>, 4>(
        vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(-1.0, 0.0), vec2<f32>(0.0, -1.0));
    var offset = vec2<f32>(0.0);
    for (var m = 0u; m < 4u; m++) {
        offset += weights[m] * directions[(span + m) % 4u];
    }
    return offset;
}

// Vertex `vertex` of surface `index`: one triangle strip per band around (clusters) or a single
// band (patches), bands joined by two degenerate vertices.
fn surface_vertex(index: u32, vertex: u32, kind: u32) -> SurfaceVertex {
    var out: SurfaceVertex;
    out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    out.world_position = vec3<f32>(0.0);
    out.tangent = vec3<f32>(0.0, 1.0, 0.0);
    out.normal = vec3<f32>(0.0, 0.0, 1.0);
    out.texcoord = vec2<f32>(0.0);
    out.kind = kind;
    out.seed = 0u;
    out.coverage = 1.0;
    out.gives_way = 0u;
    out.scale = 0.0;
    out.light = 1.0;
    if (index >= arrayLength(&surfaces)) {
        return out;
    }
    let surface = surfaces[index];
    let chain = chain_at(surface.chain);
    if (chain.node_count < 2u) {
        return out;
    }
    var segments = chain.along_segments;
    var bands = 1u;
    if (kind == 1u) {
        bands = chain.around_segments;
    }
    if (globals.shadow.w > 0.5) {
        // Light passes: a coarser tessellation (`SelfShadowing::along_stride`).
        segments = shadow_segments(segments);
        bands = min(bands, max(u32(globals.shadow_surfaces.w), 3u));
    }
    let band_vertices = 2u * (segments + 1u);
    let block = band_vertices + 2u;
    var band = vertex / block;
    let local = vertex % block;
    var point = local / 2u;
    var side = local & 1u;
    if (local == band_vertices) {
        // Repeat the band's last vertex.
        point = segments;
        side = 1u;
    } else if (local == band_vertices + 1u) {
        // Start the next band.
        band += 1u;
        point = 0u;
        side = 0u;
    }
    if (band >= bands) {
        return out;
    }
    let across = f32(band + side) / f32(bands);
    let v = f32(point) / f32(segments);
    let frame = frame_at(chain, v);
    let scale = mix(surface.root_scale, surface.tip_scale, v);
    var position: vec3<f32>;
    var tangent: vec3<f32>;
    var normal: vec3<f32>;
    var x = across;
    if (kind == 1u && cluster_impostors()) {
        // The tube's silhouette seen from the eye (`ClusterGeometry::Impostor`): a band, `s` = -1
        // at one edge and 1 at the other, in the plane that touches the tube on the side nearest
        // the eye (axis + ρ·(s·side + front)), so that nothing the tube hides shows through it
        // and the head hides no more of it than of the tube. Seen from the eye a point of the
        // tube at `s` projects where the band's point at `s` does (up to the perspective of the
        // depth ρ), and `s` is linear across the band, so the fragment stage rebuilds the tube's
        // normal exactly (`surface_point`). Faces the eye, so it is counter-clockwise from it
        // (the tube's back-face culling keeps it). `normal` carries the node frame's normal for
        // the texture's angle around.
        let axis = evaluate_curve(chain, vec2<f32>(0.0), 0.0, 0.0, v);
        tangent = unit_tangent(axis.derivative);
        let view = tube_view_frame(tangent, eye_direction(axis.position), frame[0]);
        x = 2.0 * across - 1.0;
        position = axis.position + RING_RADIUS * scale * (x * view[0] + view[1]);
        normal = frame[0];
    } else {
        var offset = vec2<f32>(0.0, 2.0 * across - 1.0);
        if (kind == 1u) {
            offset = ring_offset(across);
        }
        let curve = evaluate_curve(chain, offset, surface.root_scale, surface.tip_scale, v);
        position = curve.position;
        tangent = unit_tangent(curve.derivative);
        if (kind == 1u) {
            normal = offset.x * frame[0] + offset.y * frame[1];
        } else {
            normal = cross(tangent, frame[1]);
        }
    }
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.world_position = position;
    out.tangent = tangent;
    out.normal = normal;
    out.texcoord = vec2<f32>(x, v);
    out.seed = surface.seed;
    out.coverage = chain.coverage;
    out.gives_way = chain.gives_way;
    out.scale = scale;
    if (globals.shadow.w < 0.5) {
        out.light = shadow_transmittance(position);
    }
    return out;
}

// The unit direction of a curve derivative, +Y where it vanishes.
fn unit_tangent(derivative: vec3<f32>) -> vec3<f32> {
    if (dot(derivative, derivative) < 1e-20) {
        return vec3<f32>(0.0, 1.0, 0.0);
    }
    return normalize(derivative);
}

// Whether clusters are drawn as view-facing stand-ins of their tubes
// (`ClusterGeometry::Impostor`) rather than as tessellated tubes.
fn cluster_impostors() -> bool {
    return globals.line_coverage.z > 0.5;
}

// The drawn ring's radius over the control radius: the periodic cubic B-spline of four control
// points on a circle of radius r runs at 0.648·r to 0.667·r from its centre (mean 0.657·r,
// `lod::DRAWN_TUBE_RADIUS`).
const RING_RADIUS: f32 = 0.657;

// Direction towards the eye at `position`: the camera in the main pass, the (directional) light
// in the light passes.
fn eye_direction(position: vec3<f32>) -> vec3<f32> {
    if (globals.shadow.w > 0.5) {
        return globals.light_direction.xyz;
    }
    return normalize(globals.camera_position.xyz - position);
}

// The unit vectors across a tube seen from `eye` (unit): `side` across its silhouette and `front`
// towards the eye, both normal to the unit `tangent`; `fallback` (any vector across the tube)
// when the tube points at the eye.
fn tube_view_frame(tangent: vec3<f32>, eye: vec3<f32>, fallback: vec3<f32>) -> mat2x3<f32> {
    var side = cross(tangent, eye);
    if (dot(side, side) < 1e-12) {
        side = cross(tangent, fallback);
    }
    side = normalize(side);
    return mat2x3<f32>(side, cross(side, tangent));
}

// A surface fragment's unit normal and its coordinate across (0..1 around a tube from the node
// frame's binormal, as `ring_offset`; 0..1 across a strip). An impostor's normal is the tube's at
// the fragment's `s`, its angle around measured in the node frame, so the texture stays on the
// hair as the eye moves.
struct SurfacePoint {
    normal: vec3<f32>,
    across: f32,
}

fn surface_point(in: SurfaceVertex) -> SurfacePoint {
    var point: SurfacePoint;
    if (in.kind == 1u && cluster_impostors()) {
        let tangent = normalize(in.tangent);
        let view = tube_view_frame(tangent, eye_direction(in.world_position), in.normal);
        let s = clamp(in.texcoord.x, -1.0, 1.0);
        point.normal = s * view[0] + sqrt(max(1.0 - s * s, 0.0)) * view[1];
        var f0 = in.normal - dot(in.normal, tangent) * tangent;
        if (dot(f0, f0) < 1e-20) {
            f0 = view[0];
        }
        f0 = normalize(f0);
        let f1 = cross(tangent, f0);
        point.across = fract(atan2(dot(point.normal, f1), dot(point.normal, f0)) / 6.2831853 - 0.25);
        return point;
    }
    point.normal = in.normal;
    if (dot(point.normal, point.normal) < 1e-20) {
        point.normal = eye_direction(in.world_position);
    }
    point.normal = normalize(point.normal);
    point.across = in.texcoord.x;
    return point;
}

@vertex
fn vs_cluster(@builtin(vertex_index) vertex: u32, @builtin(instance_index) index: u32) -> SurfaceVertex {
    return surface_vertex(index, vertex, 1u);
}

@vertex
fn vs_patch(@builtin(vertex_index) vertex: u32, @builtin(instance_index) index: u32) -> SurfaceVertex {
    return surface_vertex(index, vertex, 2u);
}

// A well-mixed 32-bit hash (PCG output function).
fn hash_u32(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Smooth value noise in 0..1 over stripes `x` (period `period` stripes), per surface `seed`.
fn stripe_noise(x: f32, period: f32, seed: u32) -> f32 {
    let cell = floor(x);
    let f = x - cell;
    let a = u32(cell - period * floor(cell / period));
    let b = (a + 1u) % u32(period);
    let ha = f32(hash_u32(seed ^ hash_u32(a)) >> 8u) / 16777215.0;
    let hb = f32(hash_u32(seed ^ hash_u32(b)) >> 8u) / 16777215.0;
    return mix(ha, hb, smoothstep(0.0, 1.0, f));
}

// Fully drawn surfaces. No `discard` here: a shader that may discard makes a rasterizer test
// depth after shading (no early depth test), which on a CPU rasterizer shades every hidden
// fragment of the overlapping tubes too.
@fragment
fn fs_surface(in: SurfaceVertex) -> @location(0) vec4<f32> {
    return surface_color(in);
}

// Surfaces fading in or out (chain coverage below 1): screen-door dissolve, then shading.
@fragment
fn fs_surface_dissolving(in: SurfaceVertex) -> @location(0) vec4<f32> {
    if (!screen_door_keeps(in.clip.xy, in.coverage, in.gives_way)) {
        discard;
    }
    return surface_color(in);
}

// The same screen door without `discard`, for multisampled targets whose surface pipelines turn
// alpha into coverage: a dropped pixel returns alpha 0 (no sample written, colour nor depth)
// before any shading, and the fragment stage keeps no `discard`.
@fragment
fn fs_surface_dissolving_coverage(in: SurfaceVertex) -> @location(0) vec4<f32> {
    if (!screen_door_keeps(in.clip.xy, in.coverage, in.gives_way)) {
        return vec4<f32>(0.0);
    }
    return surface_color(in);
}

fn surface_color(in: SurfaceVertex) -> vec4<f32> {
    if (globals.shading.w > 0.5) {
        if (in.kind == 1u) {
            return vec4<f32>(globals.cluster_code_color.rgb, 1.0);
        }
        return vec4<f32>(globals.patch_code_color.rgb, 1.0);
    }
    var stripes = STRIPES_ACROSS;
    if (in.kind == 1u) {
        stripes = STRIPES_AROUND;
    }
    let to_eye = normalize(globals.camera_position.xyz - in.world_position);
    let point = surface_point(in);
    var normal = point.normal;
    if (in.kind == 2u && dot(normal, to_eye) < 0.0) {
        normal = -normal;
    }
    var shade: f32;
    var coverage = 1.0;
    if (globals.ribbon.w > 0.5) {
        // Hair texture: strands with shades along the hair, own lengths, a broken silhouette.
        var silhouette = abs(dot(normal, to_eye));
        if (in.kind == 2u) {
            silhouette = 2.0 * min(in.texcoord.x, 1.0 - in.texcoord.x);
        }
        let texture = hair_texture(point.across, in.texcoord.y, in.seed, stripes, silhouette);
        shade = texture.x;
        coverage = texture.y;
    } else {
        // Stripes: coarse locks and fine strands across the surface, constant along the hair.
        let coarse = stripe_noise(point.across * stripes, stripes, in.seed);
        let fine = stripe_noise(point.across * stripes * 3.0, stripes * 3.0, in.seed * 7919u + 1u);
        shade = clamp(0.6 * coarse + 0.4 * fine, 0.0, 1.0);
    }
    let base = mix(globals.hair_dark.rgb, globals.hair_light.rgb, shade);
    // Light-facing term: the side of a tube or strip away from the light is darker. With
    // self-shadowing the opacity map shades that side by the strands in front of it, so the
    // term would count that shadow twice.
    var facing = 0.35 + 0.65 * max(dot(normal, globals.light_direction.xyz), 0.0);
    if (globals.shadow.x > 0.5) {
        facing = 1.0;
    }
    let occlusion = facing * in.light;
    return vec4<f32>(hair_color(base, normalize(in.tangent), in.world_position, occlusion), coverage);
}

// Depth pass: the fragment's light-space depth (the depth test keeps the nearest).
@fragment
fn fs_surface_depth(in: SurfaceVertex) -> @location(0) vec4<f32> {
    return vec4<f32>(in.clip.z, 0.0, 0.0, 0.0);
}

// Opacity pass: a cluster or patch fragment adds the optical depth of the strands it stands for.
// A tube of radius R holding N strands of width w has optical depth N·w·chord/(πR²) along a
// ray; the chord at the point where the ray meets the surface at cosine c to its normal is 2Rc,
// all of it put on the tube's lit (front) face: 2·N·w·c/(πR). A strip of width W holding N
// strands side by side covers N·w/W of it seen face-on, N·w/(W·c) at cosine c. The ring of the
// periodic cubic through control points at radius r has radius ⅔·r.
@fragment
fn fs_surface_opacity(in: SurfaceVertex) -> @location(0) vec4<f32> {
    let c = max(abs(dot(surface_point(in).normal, globals.light_direction.xyz)), 0.05);
    var tau: f32;
    if (in.kind == 1u) {
        let ring = max(0.6667 * in.scale, 1e-5);
        tau = 2.0 * globals.shadow_surfaces.x * c / (3.14159265 * ring);
    } else {
        tau = globals.shadow_surfaces.y / (max(2.0 * in.scale, 1e-5) * c);
    }
    return min(tau, 8.0) * in.coverage * opacity_layer(in.clip.xy, in.clip.z);
}
