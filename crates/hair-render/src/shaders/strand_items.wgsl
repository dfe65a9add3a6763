// Static data of one strand (`GpuStrand` in `inputs.rs`), uploaded once, sorted by chain.
struct Strand {
    chain: u32,
    shade: f32,
    root_offset: vec2<f32>,
}

@group(1) @binding(0) var<storage, read> strands: array<Strand>;
// The chain-curve samples written by `cs_chain_curves` this frame.
@group(1) @binding(1) var<storage, read> chain_samples: array<ChainSample>;
