// Evaluation pass: the strands' B-spline points at evenly spaced parameters, written to a buffer
// so that the GPU curve can be compared with the CPU reference (`bspline.rs`).

// xyz: point [m]; w: 1 when the strand is drawable, 0 otherwise.
@group(2) @binding(0) var<storage, read_write> evaluated: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_evaluate(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    let samples = globals.counts.w;
    if (samples == 0u || index >= globals.counts.x * samples || index >= arrayLength(&evaluated)) {
        return;
    }
    let strand = strands[index / samples];
    let sample = index % samples;
    let u = f32(sample) / f32(max(samples, 2u) - 1u);
    let chain = chain_at(strand.chain);
    let curve = evaluate_curve(chain, strand.root_offset, 1.0, 1.0, u);
    evaluated[index] = vec4<f32>(curve.position, select(0.0, 1.0, chain.node_count >= 1u));
}
