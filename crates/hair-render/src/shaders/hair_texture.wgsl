// The hair texture of clusters and patches (§6: "a texture map using a similar color range"):
// fine strands across the surface, each with its own shade drifting along the hair and its own
// length, and fewer strands towards the silhouette, so that a tube or strip reads as strands.
// Returns (shade in 0..1, coverage in 0..1); coverage becomes MSAA samples by alpha-to-coverage.

// Cells of the along-the-hair value noise over a surface's length.
const ALONG_CELLS: f32 = 7.0;
// Strand lengths are 1 − TIP_VARIATION·h² for a per-strand h uniform in 0..1 (as the groom's).
const TIP_VARIATION: f32 = 0.3;

// Smooth value noise in 0..1 along `t` for one strand `key`.
fn along_noise(t: f32, key: u32) -> f32 {
    let cell = floor(t);
    let f = t - cell;
    let a = f32(hash_u32(key ^ hash_u32(u32(i32(cell) + 1024))) >> 8u) / 16777215.0;
    let b = f32(hash_u32(key ^ hash_u32(u32(i32(cell) + 1025))) >> 8u) / 16777215.0;
    return mix(a, b, smoothstep(0.0, 1.0, f));
}

// `x` across (0..1), `v` along (0 root, 1 tip), `stripes` coarse locks across, `silhouette` in
// 0..1 (0 where the surface is seen edge-on, 1 face-on).
fn hair_texture(x: f32, v: f32, seed: u32, stripes: f32, silhouette: f32) -> vec2<f32> {
    let fine_count = stripes * 3.0;
    let coarse = stripe_noise(x * stripes, stripes, seed);
    let fine = stripe_noise(x * fine_count, fine_count, seed * 7919u + 1u);
    let strand = u32(floor(fract(x) * fine_count));
    let key = hash_u32(seed * 31u + strand * 2654435761u + 17u);
    let h = f32(key >> 8u) / 16777215.0;
    let along = along_noise(v * ALONG_CELLS + 13.0 * h, key);
    let shade = clamp(0.45 * coarse + 0.3 * fine + 0.25 * along, 0.0, 1.0);
    let tip = 1.0 - smoothstep(1.0 - TIP_VARIATION * h * h - 0.03, 1.0 - TIP_VARIATION * h * h, v);
    let edge = clamp(3.0 * silhouette + h - 0.5, 0.0, 1.0);
    return vec2<f32>(shade, tip * edge);
}
