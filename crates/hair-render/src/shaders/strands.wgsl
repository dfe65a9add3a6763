// Strands: GPU B-spline evaluation by vertex pulling, camera-facing ribbons or lines, and
// Kajiya-Kay shading in the Heidrich-Seidel form (no surface normal, only the tangent).
// Curve points come from the chain-curve pass (one evaluation per chain sample, shared by all the
// strands of the chain); the CPU draws strands in batches of equal segment count (the chain's
// `along_segments`), so no vertex is wasted on collapsed points.

struct StrandVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(perspective, centroid) world_position: vec3<f32>,
    @location(1) @interpolate(perspective, centroid) tangent: vec3<f32>,
    @location(2) @interpolate(flat) shade: f32,
    // The share of a pixel the strand covers (`LineCoverage`), and the strand for its hash.
    @location(3) coverage: f32,
    @location(4) @interpolate(flat) strand: u32,
    // The colour-coded view's level of the strand's chain (`Chain::code_level`).
    @location(5) @interpolate(flat) code_level: u32,
}

// The strands this frame draws, by sorted position: instance i of a batch draws strand
// `drawn_strands[i]` (`ChainOrder::listed_batches`), so that the thinned or dissolving chains'
// drawn strands merge into few instanced draws.
@group(1) @binding(3) var<storage, read> drawn_strands: array<u32>;

// The strand an instance draws (past the list: none, which draws nothing).
fn listed_strand(instance: u32) -> u32 {
    if (instance >= arrayLength(&drawn_strands)) {
        return 0xffffffffu;
    }
    return drawn_strands[instance];
}

// Sideways offset in clip space that widens a curve point to a camera-facing ribbon of
// `half_pixels` half width; `side` is -1 or 1.
fn ribbon_offset(clip: vec4<f32>, tangent: vec3<f32>, side: f32, half_pixels: f32) -> vec2<f32> {
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
    return across * side * half_pixels * 2.0 / globals.viewport.xy * clip.w;
}

// The orthonormal frame (N̂, B̂, T̂) of a chain point as columns (`ChainPoint::residual_basis` in
// hair-core, step for step).
fn residual_frame(n: vec3<f32>, b: vec3<f32>, dc: vec3<f32>) -> mat3x3<f32> {
    var t = vec3<f32>(0.0, 1.0, 0.0);
    if (dot(dc, dc) > 1e-24) {
        t = normalize(dc);
    }
    // |N| and |B| are about 1: a part under 1e-6 is rounding, not a direction.
    // `!(x > 1e-12)` rather than `x <= 1e-12`: a NaN falls back too, as on the CPU.
    var np = n - dot(n, t) * t;
    if (!(dot(np, np) > 1e-12)) {
        np = cross(b, t);
    }
    if (!(dot(np, np) > 1e-12)) {
        // Any perpendicular of t (drawn.rs's any_perpendicular: Frisvad, -0 taken as positive).
        let sign = select(-1.0, 1.0, t.z >= 0.0);
        let a = -1.0 / (sign + t.z);
        np = vec3<f32>(t.x * t.y * a, sign + t.y * t.y * a, -t.y);
    }
    np = normalize(np);
    return mat3x3<f32>(np, cross(t, np), t);
}

// Point `point_index` of a strand, pushed `side` half widths sideways on screen (0 for lines).
fn strand_vertex(strand_index: u32, point_index: u32, side: f32) -> StrandVertex {
    var out: StrandVertex;
    // Outside the clip volume: unusable strands draw nothing.
    out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    out.world_position = vec3<f32>(0.0);
    out.tangent = vec3<f32>(0.0, 1.0, 0.0);
    out.shade = 0.0;
    out.coverage = 1.0;
    out.strand = strand_index;
    out.code_level = 0u;
    if (strand_index >= globals.counts.x || strand_index >= arrayLength(&strands)) {
        return out;
    }
    let strand = strands[strand_index];
    let chain = chain_at(strand.chain);
    if (chain.node_count < 2u || strand.dissolve_rank >= chain.coverage) {
        return out;
    }
    out.code_level = chain.code_level;
    // A strand of length l takes the chain points up to l and ends exactly at u = l, between
    // two of them; later vertices repeat its end (`representation::drawn` in hair-core).
    let segments = chain.along_segments;
    if (segments == 0u) {
        return out;
    }
    let last = min(max(1u, u32(ceil(strand.length * f32(segments) - 1e-4))), segments);
    let point = min(point_index, last);
    let u = min(f32(point) / f32(segments), strand.length);
    let s = u * f32(segments);
    let k = min(u32(floor(s)), segments - 1u);
    let f = s - f32(k);
    let slot = chain.first_sample + k;
    if (slot + 1u >= arrayLength(&chain_samples)) {
        return out;
    }
    let a = chain_samples[slot];
    let b = chain_samples[slot + 1u];
    let c = mix(a.position.xyz, b.position.xyz, f);
    let n = mix(a.normal.xyz, b.normal.xyz, f);
    let bn = mix(a.binormal.xyz, b.binormal.xyz, f);
    let dc = mix(a.d_position.xyz, b.d_position.xyz, f);
    let dn = mix(a.d_normal.xyz, b.d_normal.xyz, f);
    let dbn = mix(a.d_binormal.xyz, b.d_binormal.xyz, f);
    // Residual r(v) at v = u / l, linear between profile entries, and dr/du.
    var r = vec3<f32>(0.0);
    var dr = vec3<f32>(0.0);
    if (strand.profile != NO_PROFILE) {
        let l = max(strand.length, 1e-6); // MIN_PROFILE_LENGTH
        let sv = clamp(u / l, 0.0, 1.0) * f32(PROFILE_SAMPLES - 1u);
        let j = min(u32(floor(sv)), PROFILE_SAMPLES - 2u);
        let entry = strand.profile * PROFILE_SAMPLES + j;
        if (entry + 1u < arrayLength(&strand_profiles)) {
            let r0 = strand_profiles[entry].xyz;
            let r1 = strand_profiles[entry + 1u].xyz;
            r = mix(r0, r1, sv - f32(j));
            dr = (r1 - r0) * (f32(PROFILE_SAMPLES - 1u) / l);
        }
    }
    // Offset σ(u)·o with σ(u) = 1 + (tip_scale − 1)·u (strands gather towards the chain), plus
    // the residual in the orthonormal frame (N̂, B̂, T̂) (`ChainPoint::residual_basis`).
    let scale = 1.0 + (strand.tip_scale - 1.0) * u;
    let o = strand.root_offset;
    let across = o.x * n + o.y * bn;
    var position = c + scale * across;
    // dP/du; the residual's part leaves out the turning of its frame.
    var tangent = dc + scale * (o.x * dn + o.y * dbn) + (strand.tip_scale - 1.0) * across;
    if (strand.profile != NO_PROFILE) {
        let frame = residual_frame(n, bn, dc);
        position += frame * r;
        tangent += frame * dr;
    }
    // The whole strand moved onto its carried root (`HairItems::set_strand_root_shifts`).
    position += strand_shift(strand_index);
    if (dot(tangent, tangent) < 1e-20) {
        tangent = vec3<f32>(0.0, 1.0, 0.0);
    }
    tangent = normalize(tangent);
    let clip = globals.view_proj * vec4<f32>(position, 1.0);
    var offset = vec2<f32>(0.0);
    if (side != 0.0) {
        // Half width in pixels: the projected hair width, but at least the minimum.
        // A thinned strand standing for several is widened by the chain's width scale.
        let half_pixels = max(globals.ribbon.x * globals.ribbon.z / max(clip.w, 1e-6), globals.ribbon.y) * chain.width_scale;
        offset = ribbon_offset(clip, tangent, side, half_pixels);
    }
    out.clip = vec4<f32>(clip.xy + offset, clip.zw);
    out.world_position = position;
    out.tangent = tangent;
    out.shade = strand.shade;
    if (globals.line_coverage.x > 0.0) {
        // The fibre's projected width w·f/z [pixels] (widened with a thinned strand), at most
        // the whole pixel.
        out.coverage = clamp(globals.line_coverage.x * globals.ribbon.z * chain.width_scale / max(clip.w, 1e-6), 0.0, 1.0);
    }
    return out;
}

// Triangle strip per instance (one strand): vertices 2i and 2i + 1 straddle curve point i.
@vertex
fn vs_strand_ribbon(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> StrandVertex {
    let side = select(-1.0, 1.0, (vertex & 1u) == 1u);
    return strand_vertex(listed_strand(instance), vertex / 2u, side);
}

// A strand line vertex shaded at the curve point.
struct LineVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(perspective, centroid) color: vec3<f32>,
    @location(1) coverage: f32,
    @location(2) @interpolate(flat) strand: u32,
}

// Line strip per instance (one strand): vertex i is curve point i (shaded per fragment).
@vertex
fn vs_strand_line(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> StrandVertex {
    return strand_vertex(listed_strand(instance), vertex, 0.0);
}

// Line strip per instance (one strand): vertex i is curve point i, shaded here; the colour is
// interpolated along the segment (`LineShading::PerVertex`).
@vertex
fn vs_strand_line_shaded(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> LineVertex {
    let v = strand_vertex(listed_strand(instance), vertex, 0.0);
    var out: LineVertex;
    out.clip = v.clip;
    out.color = strand_color(v);
    out.coverage = v.coverage;
    out.strand = v.strand;
    return out;
}

@fragment
fn fs_strand_line(in: LineVertex) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color, 1.0);
}

// A fragment of a strand line that covers only some of the pixel's samples.
struct CoveredFragment {
    @location(0) color: vec4<f32>,
    @builtin(sample_mask) mask: u32,
}

// A 32-bit hash of a strand and a pixel (integer mixing in the manner of PCG and murmur's
// finaliser), so that overlapping strands pick their samples independently.
fn coverage_hash(strand: u32, pixel: vec2<f32>) -> u32 {
    var h = strand * 747796405u + 2891336453u;
    h = (h ^ (u32(pixel.x) * 277803737u)) * 0x85ebca6bu;
    h = (h ^ (h >> 13u) ^ (u32(pixel.y) * 0x27d4eb2fu)) * 0xc2b2ae35u;
    return h ^ (h >> 16u);
}

// The samples a strand covering `coverage` of a pixel takes: k = ⌊c·n + ξ⌋ of the n samples,
// a run of k at a rotation hashed from the strand and the pixel. ξ is uniform and the strand's
// own (E[k] = c·n over strands): along a strand k stays put where c does, so a sparse strand
// reads as a fainter line rather than as grain (per-pixel ξ measured 0.002–0.01 lower SSIM
// against the supersampled reference).
fn coverage_mask(strand: u32, pixel: vec2<f32>, coverage: f32) -> u32 {
    let n = clamp(u32(globals.line_coverage.y), 1u, 16u);
    let h = coverage_hash(strand, pixel);
    let xi = f32(coverage_hash(strand, vec2<f32>(0.0)) & 0xffffu) / 65536.0;
    let k = min(u32(floor(clamp(coverage, 0.0, 1.0) * f32(n) + xi)), n);
    let all = (1u << n) - 1u;
    let run = (1u << k) - 1u;
    let rotation = (h >> 16u) % n;
    return ((run << rotation) | (run >> (n - rotation))) & all;
}

// Whether a strand covering `coverage` of a pixel keeps the whole fragment (probability c over
// strands, from the strand's own ξ): the covered lines single-sampled, or where the sample mask
// cannot be written.
fn coverage_keeps(strand: u32, coverage: f32) -> bool {
    let h = coverage_hash(strand, vec2<f32>(0.0));
    return f32(h & 0xffffu) / 65536.0 < coverage;
}

@fragment
fn fs_strand_line_kept(in: LineVertex) -> @location(0) vec4<f32> {
    if (!coverage_keeps(in.strand, in.coverage)) {
        discard;
    }
    return vec4<f32>(in.color, 1.0);
}

@fragment
fn fs_strand_kept(in: StrandVertex) -> @location(0) vec4<f32> {
    if (!coverage_keeps(in.strand, in.coverage)) {
        discard;
    }
    return vec4<f32>(strand_color(in), 1.0);
}

@fragment
fn fs_strand_line_covered(in: LineVertex) -> CoveredFragment {
    var out: CoveredFragment;
    out.color = vec4<f32>(in.color, 1.0);
    out.mask = coverage_mask(in.strand, in.clip.xy, in.coverage);
    return out;
}

fn strand_color(in: StrandVertex) -> vec3<f32> {
    if (globals.shading.w > 0.5) {
        // The level the strand's motion is simulated at (its own unless rebuilt).
        if (in.code_level == 2u) {
            return globals.cluster_code_color.rgb;
        }
        if (in.code_level == 3u) {
            return globals.patch_code_color.rgb;
        }
        return globals.strand_code_color.rgb;
    }
    let base = mix(globals.hair_dark.rgb, globals.hair_light.rgb, in.shade);
    let light = shadow_transmittance(in.world_position);
    return hair_color(base, normalize(in.tangent), in.world_position, light);
}

@fragment
fn fs_strand(in: StrandVertex) -> @location(0) vec4<f32> {
    return vec4<f32>(strand_color(in), 1.0);
}

@fragment
fn fs_strand_covered(in: StrandVertex) -> CoveredFragment {
    var out: CoveredFragment;
    out.color = vec4<f32>(strand_color(in), 1.0);
    out.mask = coverage_mask(in.strand, in.clip.xy, in.coverage);
    return out;
}

// A vertex of the light passes (depth map and opacity map, `shadows.wgsl`).
struct ShadowVertex {
    @builtin(position) clip: vec4<f32>,
    // The chain's shadow weight: a thinned group's drawn strands stand for all of its strands.
    @location(0) @interpolate(flat) weight: f32,
}

// Line strip per instance (one strand) in the light passes: vertex i is curve point
// i · stride (clamped to the last), projected by the light's view (the light passes' globals).
@vertex
fn vs_strand_shadow(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> ShadowVertex {
    let strand = listed_strand(instance);
    let stride = max(u32(globals.shadow_surfaces.z), 1u);
    var out: ShadowVertex;
    out.clip = strand_vertex(strand, vertex * stride, 0.0).clip;
    out.weight = 1.0;
    if (strand < arrayLength(&strands)) {
        out.weight = chain_at(strands[strand].chain).shadow_weight;
    }
    return out;
}

// Depth pass: the fragment's light-space depth (the depth test keeps the nearest).
@fragment
fn fs_strand_depth(in: ShadowVertex) -> @location(0) vec4<f32> {
    return vec4<f32>(in.clip.z, 0.0, 0.0, 0.0);
}

// Opacity pass: a strand line adds its optical depth to its layer.
@fragment
fn fs_strand_opacity(in: ShadowVertex) -> @location(0) vec4<f32> {
    return globals.shadow.z * in.weight * opacity_layer(in.clip.xy, in.clip.z);
}
