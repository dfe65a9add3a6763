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
    // First entry of the residual profile in `strand_profiles`, in profiles
    // (PROFILE_SAMPLES entries each); 0xffffffff: none.
    profile: u32,
}

// Entries per residual profile (`hair_core::PROFILE_SAMPLES`).
const PROFILE_SAMPLES: u32 = 64u;
const NO_PROFILE: u32 = 0xffffffffu;

@group(1) @binding(0) var<storage, read> strands: array<Strand>;
// The chain-curve samples written by `cs_chain_curves` this frame.
@group(1) @binding(1) var<storage, read> chain_samples: array<ChainSample>;
// The strands' residual profiles: xyz the offset [m] in the chain's orthonormal (N̂, B̂, T̂) frame at fraction
// j / (PROFILE_SAMPLES − 1) of the strand's run (`StrandSet::profiles` in hair-core).
@group(1) @binding(2) var<storage, read> strand_profiles: array<vec4<f32>>;
// Each strand's shift [m] (xyz; w unused), by sorted position: where its root is carried off
// the place its skeleton's rest offsets draw it (a stretching skin); zeros otherwise.
@group(1) @binding(4) var<storage, read> strand_shifts: array<vec4<f32>>;

// The shift of the strand at sorted position `index` (none past the buffer's end).
fn strand_shift(index: u32) -> vec3<f32> {
    if (index >= arrayLength(&strand_shifts)) {
        return vec3<f32>(0.0);
    }
    return strand_shifts[index].xyz;
}
