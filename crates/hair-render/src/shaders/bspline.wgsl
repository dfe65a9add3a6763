// Clamped uniform B-spline along a chain, evaluated from the skeleton nodes (de Boor's algorithm).
// Mirrors `bspline.rs`: degree p = min(3, n - 1), knots t_i = clamp((i - p) / (n - p), 0, 1).
//
// Strands, cluster tubes and patch strips all have control points `node_k + s_k · (o.x · n_k +
// o.y · b_k)`: a fixed offset o in the node frame, scaled by s_k interpolated from root to tip
// (1 for strands, the cluster radius for tubes, the half width for patches).

struct CurvePoint {
    position: vec3<f32>,
    // dC/du.
    derivative: vec3<f32>,
}

// The chain `index`, or one with no nodes when the index or its nodes are out of range.
fn chain_at(index: u32) -> Chain {
    var chain: Chain;
    chain.first_node = 0u;
    chain.node_count = 0u;
    chain.along_segments = 1u;
    chain.around_segments = 1u;
    chain.first_sample = 0u;
    if (index >= arrayLength(&chains) || index >= globals.counts.y) {
        return chain;
    }
    let found = chains[index];
    if (found.first_node + found.node_count > globals.counts.z
        || found.first_node + found.node_count > arrayLength(&nodes)) {
        return chain;
    }
    chain = found;
    chain.along_segments = max(chain.along_segments, 1u);
    chain.around_segments = max(chain.around_segments, 1u);
    return chain;
}

fn knot(i: u32, n: u32, p: u32) -> f32 {
    return clamp((f32(i) - f32(p)) / f32(n - p), 0.0, 1.0);
}

// Control point k: node position plus the scaled offset in the node's (normal, binormal) plane.
fn control_point(chain: Chain, k: u32, offset: vec2<f32>, root_scale: f32, tip_scale: f32) -> vec3<f32> {
    let node = nodes[chain.first_node + k];
    let t = f32(k) / f32(max(chain.node_count, 2u) - 1u);
    let o = offset * mix(root_scale, tip_scale, t);
    return node.position.xyz + o.x * node.normal.xyz + o.y * node.binormal.xyz;
}

fn evaluate_curve(chain: Chain, offset: vec2<f32>, root_scale: f32, tip_scale: f32, u_in: f32) -> CurvePoint {
    var result: CurvePoint;
    result.position = vec3<f32>(0.0);
    result.derivative = vec3<f32>(0.0);
    let n = chain.node_count;
    if (n == 0u) {
        return result;
    }
    if (n == 1u) {
        result.position = control_point(chain, 0u, offset, root_scale, tip_scale);
        return result;
    }
    let p = min(3u, n - 1u);
    let segments = n - p;
    let u = clamp(u_in, 0.0, 1.0);
    let span = p + min(u32(floor(u * f32(segments))), segments - 1u);
    var d: array<vec3<f32>, 4>;
    for (var j = 0u; j < 4u; j++) {
        d[j] = control_point(chain, span - p + min(j, p), offset, root_scale, tip_scale);
    }
    // Fixed trip counts (levels r = 1..3, points j = 3..r), skipping steps above the degree.
    for (var r = 1u; r < 4u; r++) {
        if (r > p) {
            break;
        }
        if (r == p) {
            // C'(u) = p (d_p - d_{p-1}) / (t_{k+1} - t_k) from the level p - 1 points.
            let width = knot(span + 1u, n, p) - knot(span, n, p);
            result.derivative = (d[p] - d[p - 1u]) * (f32(p) / width);
        }
        for (var step = 0u; step < 3u; step++) {
            let j = p - step;
            if (j < r || step >= p) {
                break;
            }
            let i = span - p + j;
            let start = knot(i, n, p);
            let end = knot(i + p + 1u - r, n, p);
            var alpha = 0.0;
            if (end > start) {
                alpha = (u - start) / (end - start);
            }
            d[j] = mix(d[j - 1u], d[j], alpha);
        }
    }
    result.position = d[p];
    return result;
}

// The node frame (normal, binormal) interpolated at curve parameter u (for surface shading).
fn frame_at(chain: Chain, u: f32) -> mat2x3<f32> {
    let x = clamp(u, 0.0, 1.0) * f32(chain.node_count - 1u);
    let k = min(u32(floor(x)), chain.node_count - 1u);
    let k1 = min(k + 1u, chain.node_count - 1u);
    let t = x - f32(k);
    let a = nodes[chain.first_node + k];
    let b = nodes[chain.first_node + k1];
    return mat2x3<f32>(mix(a.normal.xyz, b.normal.xyz, t), mix(a.binormal.xyz, b.binormal.xyz, t));
}

// Kajiya-Kay in the Heidrich-Seidel form: diffuse ∝ sin(T, L),
// specular ∝ (sin(T, L) sin(T, V) - (T·L)(T·V))^p. Returns (diffuse, specular).
fn kajiya_kay(tangent: vec3<f32>, to_light: vec3<f32>, to_eye: vec3<f32>) -> vec2<f32> {
    let tl = dot(tangent, to_light);
    let tv = dot(tangent, to_eye);
    let sin_tl = sqrt(max(0.0, 1.0 - tl * tl));
    let sin_tv = sqrt(max(0.0, 1.0 - tv * tv));
    let diffuse = sin_tl;
    let specular = pow(max(sin_tl * sin_tv - tl * tv, 1e-6), globals.shading.z);
    return vec2<f32>(diffuse, specular);
}

// Hair colour lit by Kajiya-Kay: `base · (ambient + light · kd · diffuse · occlusion) +
// light · ks · specular · occlusion`; with Marschner shading (`globals.hair_model.x` = 1) the
// specular term is the Marschner lobes `light · S · cos θ_i · occlusion` (`marschner.wgsl`), with
// the base colour as the fibre's transmittance, and the diffuse term stays.
fn hair_color(base: vec3<f32>, tangent: vec3<f32>, world_position: vec3<f32>, occlusion: f32) -> vec3<f32> {
    let to_eye = normalize(globals.camera_position.xyz - world_position);
    let lighting = kajiya_kay(tangent, globals.light_direction.xyz, to_eye);
    let diffuse = base * (globals.ambient.rgb + globals.light_color.rgb * globals.shading.x * lighting.x * occlusion);
    if (globals.hair_model.x > 0.5) {
        let scatter = marschner_scatter(tangent, globals.light_direction.xyz, to_eye, base, globals.hair_model);
        return diffuse + globals.light_color.rgb * scatter * occlusion;
    }
    return diffuse + globals.light_color.rgb * globals.shading.y * lighting.y * occlusion;
}
