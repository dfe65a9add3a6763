// Static data of one strand (`GpuStrand` in `inputs.rs`), uploaded once, sorted by chain.
struct Strand {
    chain: u32,
    shade: f32,
    root_offset: vec2<f32>,
    // Fraction of the chain the strand runs, (0, 1].
    length: f32,
    // Scale of the offset at the tip (the offset shrinks linearly in u from 1 at the root).
    tip_scale: f32,
    // Rank in (0, 1) within its chain (ascending along the chain's run): drawn while below the
    // chain's coverage, so a dissolving chain's drawn strands are a prefix of its run.
    dissolve_rank: f32,
    pad: u32,
}

@group(1) @binding(0) var<storage, read> strands: array<Strand>;
// The chain-curve samples written by `cs_chain_curves` this frame.
@group(1) @binding(1) var<storage, read> chain_samples: array<ChainSample>;
