// Chain-curve pass: evaluates every chain's curve frame (`ChainSample`) at its tessellation's
// points, once per frame, for the strand vertex shader.

@group(1) @binding(0) var<storage, read_write> samples_out: array<ChainSample>;

// Thread (chain, point) with point = 0..=MAX_POINTS - 1; the point count per chain slot is
// globals.counts.w (max segments + 1).
@compute @workgroup_size(64)
fn cs_chain_curves(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    let slots = globals.counts.w;
    if (slots == 0u) {
        return;
    }
    let chain_index = index / slots;
    let point = index % slots;
    if (chain_index >= globals.counts.y) {
        return;
    }
    let chain = chain_at(chain_index);
    if (chain.node_count < 2u || point > chain.along_segments) {
        return;
    }
    let slot = chain.first_sample + point;
    if (slot >= arrayLength(&samples_out)) {
        return;
    }
    let u = f32(point) / f32(chain.along_segments);
    let c = evaluate_curve(chain, vec2<f32>(0.0), 1.0, 1.0, u);
    // Offsets (1, 0) and (0, 1) minus the axis give N(u) and B(u) (linearity of de Boor).
    let n = evaluate_curve(chain, vec2<f32>(1.0, 0.0), 1.0, 1.0, u);
    let b = evaluate_curve(chain, vec2<f32>(0.0, 1.0), 1.0, 1.0, u);
    var out: ChainSample;
    out.position = vec4<f32>(c.position, 1.0);
    out.normal = vec4<f32>(n.position - c.position, 0.0);
    out.binormal = vec4<f32>(b.position - c.position, 0.0);
    out.d_position = vec4<f32>(c.derivative, 0.0);
    out.d_normal = vec4<f32>(n.derivative - c.derivative, 0.0);
    out.d_binormal = vec4<f32>(b.derivative - c.derivative, 0.0);
    samples_out[slot] = out;
}
