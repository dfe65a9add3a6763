// Clamped uniform B-spline of a strand, evaluated from the skeleton nodes (de Boor's algorithm).
// Mirrors `bspline.rs`: degree p = min(3, n - 1), knots t_i = clamp((i - p) / (n - p), 0, 1).

struct CurvePoint {
    position: vec3<f32>,
    // dC/du.
    derivative: vec3<f32>,
}

// Nodes of a strand's chain, or count 0 when the strand is unusable.
struct StrandChain {
    first_node: u32,
    node_count: u32,
}

fn strand_chain(strand: Strand) -> StrandChain {
    var chain: StrandChain;
    chain.first_node = 0u;
    chain.node_count = 0u;
    if (strand.chain + 1u >= arrayLength(&chain_offsets) || strand.chain >= globals.counts.y) {
        return chain;
    }
    let first = chain_offsets[strand.chain];
    let last = chain_offsets[strand.chain + 1u];
    if (last <= first || last > globals.counts.z) {
        return chain;
    }
    chain.first_node = first;
    chain.node_count = last - first;
    return chain;
}

fn knot(i: u32, n: u32, p: u32) -> f32 {
    return clamp((f32(i) - f32(p)) / f32(n - p), 0.0, 1.0);
}

// Control point k of a strand: node position plus the root offset in the node's (normal, binormal) plane.
fn strand_control_point(first_node: u32, k: u32, offset: vec2<f32>) -> vec3<f32> {
    let node = nodes[first_node + k];
    return node.position.xyz + offset.x * node.normal.xyz + offset.y * node.binormal.xyz;
}

fn evaluate_strand(chain: StrandChain, offset: vec2<f32>, u_in: f32) -> CurvePoint {
    var result: CurvePoint;
    result.position = vec3<f32>(0.0);
    result.derivative = vec3<f32>(0.0);
    let n = chain.node_count;
    if (n == 0u) {
        return result;
    }
    if (n == 1u) {
        result.position = strand_control_point(chain.first_node, 0u, offset);
        return result;
    }
    let p = min(3u, n - 1u);
    let segments = n - p;
    let u = clamp(u_in, 0.0, 1.0);
    let span = p + min(u32(floor(u * f32(segments))), segments - 1u);
    var d: array<vec3<f32>, 4>;
    for (var j = 0u; j < 4u; j++) {
        d[j] = strand_control_point(chain.first_node, span - p + min(j, p), offset);
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
