//! Draw batching: items (strands, clusters, patches) sorted by chain at upload, a per-frame chain
//! table with each chain's tessellation (chosen from its root's distance to the camera, §6), and
//! runs of consecutive items with equal tessellation, each drawn with one instanced call so that no
//! vertex is spent on collapsed points and chains without nodes (inactive skeletons) cost nothing.

use glam::Vec3;

use crate::inputs::SkeletonFrame;
use crate::settings::{ClusterGeometry, Tessellation};

/// One chain as the shaders read it (`Chain` in `common.wgsl`), 44 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuChain {
    pub first_node: u32,
    pub node_count: u32,
    pub along_segments: u32,
    pub around_segments: u32,
    /// First slot of the chain's `along_segments + 1` samples in the chain-curve buffer (chains
    /// with fewer than two nodes get none).
    pub first_sample: u32,
    /// 1 when the chain's strands are at most one pixel wide (drawn as lines), else 0.
    pub thin: u32,
    /// Fraction drawn, 0..=1 (see [`SkeletonFrame::chain_coverage`]).
    pub coverage: f32,
    /// 1 when the chain's surface gives way to another (see [`SkeletonFrame::chain_gives_way`]).
    pub gives_way: u32,
    /// Weight of each drawn strand's opacity in the light passes: the inverse of the fraction
    /// strand thinning draws (1 unthinned; see `thinning.rs`).
    pub shadow_weight: f32,
    /// How much wider than itself each drawn strand is drawn: 1, or more where thinning raises
    /// the widths of the strands it keeps (see `thinning.rs`).
    pub width_scale: f32,
    /// Which level's colour the colour-coded view gives the chain: 0 its own, 1 strand groups,
    /// 2 clusters, 3 patch (the level it is simulated at, see
    /// [`SkeletonFrame::chain_simulated_at`]).
    pub code_level: u32,
}

/// Bytes per chain-curve sample (`ChainSample` in `chain_curve_types.wgsl`: six `vec4<f32>`).
pub(crate) const CHAIN_SAMPLE_BYTES: u64 = 96;

/// The chain table of a (validated) frame: nodes, tessellation and chain-curve slots of every
/// chain, written into `out` (reusing its allocation). Returns the number of chain-curve samples.
/// `is_thin(distance)` says whether strands at that distance [m] are at most one pixel wide.
/// `root_distances` receives each chain's root distance to the camera [m] (infinite without
/// nodes). `ring_radii` holds the largest cluster ring radius [m] per chain (missing or 0: no
/// cluster), which with `focal_pixels` sets the segments around.
#[allow(clippy::too_many_arguments)]
pub(crate) fn chain_table(
    frame: &SkeletonFrame<'_>,
    tessellation: &Tessellation,
    cluster_geometry: ClusterGeometry,
    camera_position: Vec3,
    focal_pixels: f32,
    ring_radii: &[f32],
    is_thin: impl Fn(f32) -> bool,
    out: &mut Vec<GpuChain>,
    root_distances: &mut Vec<f32>,
) -> u32 {
    out.clear();
    root_distances.clear();
    let mut samples = 0u32;
    out.extend(
        frame
            .chain_offsets
            .windows(2)
            .enumerate()
            .map(|(chain, w)| {
                let (first, end) = (w[0], w[1]);
                let distance = frame
                    .node_positions
                    .get(first as usize)
                    .map_or(f32::INFINITY, |root| root.distance(camera_position));
                root_distances.push(distance);
                let along_segments = tessellation.segments_at(distance);
                let first_sample = samples;
                if end - first >= 2 {
                    samples = samples.saturating_add(along_segments + 1);
                }
                GpuChain {
                    first_node: first,
                    node_count: end - first,
                    along_segments,
                    around_segments: cluster_geometry.bands(
                        tessellation,
                        ring_radii.get(chain).copied().unwrap_or(0.0),
                        distance,
                        focal_pixels,
                    ),
                    first_sample,
                    thin: u32::from(is_thin(distance)),
                    coverage: frame.chain_coverage.get(chain).copied().unwrap_or(1.0),
                    gives_way: u32::from(
                        frame.chain_gives_way.get(chain).copied().unwrap_or(false),
                    ),
                    shadow_weight: 1.0,
                    width_scale: 1.0,
                    code_level: code_level(frame.chain_simulated_at.get(chain).copied().flatten()),
                }
            }),
    );
    samples
}

/// [`GpuChain::code_level`] of a chain simulated at `simulated_at` (`None`: its own level).
fn code_level(simulated_at: Option<hair_core::Level>) -> u32 {
    match simulated_at {
        None => 0,
        Some(hair_core::Level::StrandGroup) => 1,
        Some(hair_core::Level::Cluster) => 2,
        Some(hair_core::Level::Patch) => 3,
    }
}

/// Items of one kind sorted by chain (stable), with the runs of items sharing a chain.
#[derive(Debug, Clone, Default)]
pub(crate) struct ChainOrder {
    /// Input index of the item at each sorted position.
    pub sorted_to_input: Vec<u32>,
    /// `(chain, first item, end item)` per distinct chain, by chain, in sorted positions.
    pub runs: Vec<(u32, u32, u32)>,
    /// Dissolve rank in `(0, 1)` of the item at each sorted position, ascending within each run
    /// (empty when the items dissolve by screen door instead: surfaces). See
    /// [`ChainOrder::with_dissolve_ranks`].
    pub ranks: Vec<f32>,
}

/// A well-mixed hash of an item's input index (PCG's output permutation): the order in which a
/// chain's strands leave as it dissolves out, spread evenly over the group.
fn dissolve_hash(index: u32) -> u32 {
    let x = index.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let x = ((x >> ((x >> 28) + 4)) ^ x).wrapping_mul(277_803_737);
    (x >> 22) ^ x
}

impl ChainOrder {
    /// Sorts items by the chain each follows.
    pub fn new(item_chains: &[u32]) -> ChainOrder {
        let mut sorted_to_input: Vec<u32> = (0..item_chains.len() as u32).collect();
        sorted_to_input.sort_by_key(|&i| (item_chains[i as usize], i));
        let mut runs: Vec<(u32, u32, u32)> = Vec::new();
        for (position, &input) in sorted_to_input.iter().enumerate() {
            let chain = item_chains[input as usize];
            let position = position as u32;
            match runs.last_mut() {
                Some(run) if run.0 == chain => run.2 = position + 1,
                _ => runs.push((chain, position, position + 1)),
            }
        }
        ChainOrder {
            sorted_to_input,
            runs,
            ranks: Vec::new(),
        }
    }

    /// Sorts items by chain and, within a chain, by a hash of their input index, and ranks them:
    /// the `k`-th of a chain's `n` items gets rank `(k + ½)/n`. A chain at coverage `c` draws the
    /// items ranked below `c`, which are then a prefix of its run, `round(c·n)` of them (halves down) spread
    /// evenly over the chain's items: a dissolve draws (and costs) only what it shows.
    pub fn with_dissolve_ranks(item_chains: &[u32]) -> ChainOrder {
        let mut sorted_to_input: Vec<u32> = (0..item_chains.len() as u32).collect();
        sorted_to_input.sort_by_key(|&i| (item_chains[i as usize], dissolve_hash(i), i));
        let mut order = ChainOrder::new(&[]);
        order.sorted_to_input = sorted_to_input;
        for (position, &input) in order.sorted_to_input.iter().enumerate() {
            let chain = item_chains[input as usize];
            let position = position as u32;
            match order.runs.last_mut() {
                Some(run) if run.0 == chain => run.2 = position + 1,
                _ => order.runs.push((chain, position, position + 1)),
            }
        }
        order.ranks = vec![0.0; order.sorted_to_input.len()];
        for &(_, start, end) in &order.runs {
            let n = (end - start) as f32;
            for (k, rank) in order.ranks[start as usize..end as usize]
                .iter_mut()
                .enumerate()
            {
                *rank = (k as f32 + 0.5) / n;
            }
        }
        order
    }

    /// The part of run `(chain, start, end)` drawn at `coverage`: nothing at coverage 0 or below
    /// (a level at the last frame of its fade shows no pixel, and a screen-doored surface would
    /// still cost its whole fill), the whole run for items without ranks, else the prefix ranked
    /// below `coverage` (the shader draws exactly these).
    fn drawn_run(&self, (chain, start, end): (u32, u32, u32), coverage: f32) -> (u32, u32, u32) {
        if coverage <= 0.0 {
            return (chain, start, start);
        }
        if self.ranks.is_empty() || coverage >= 1.0 {
            return (chain, start, end);
        }
        let ranks = &self.ranks[start as usize..end as usize];
        let drawn = ranks.partition_point(|&rank| rank < coverage) as u32;
        (chain, start, start + drawn)
    }

    /// Number of items.
    pub fn item_count(&self) -> usize {
        self.sorted_to_input.len()
    }

    /// Chains the frame must have: the largest chain followed + 1 (0 without items).
    pub fn chains_needed(&self) -> u32 {
        self.runs.last().map_or(0, |run| run.0 + 1)
    }

    /// `items` (in input order) rearranged into sorted order.
    pub fn sorted<T: Copy>(&self, items: &[T]) -> Vec<T> {
        self.sorted_to_input
            .iter()
            .map(|&i| items[i as usize])
            .collect()
    }

    /// The draw batches of this frame's strands over a list of the items drawn: each run's
    /// drawn prefix (all of it, or the part its chain's coverage draws) is appended to `list`
    /// (reused) as sorted positions, and the batches cover positions in `list`. Runs of equal
    /// tessellation merge into one draw whether or not their chains are thinned or dissolving,
    /// so a frame of thinned strand groups costs a few draws, not one per chain.
    pub fn listed_batches(&self, chains: &[GpuChain], list: &mut Vec<u32>, out: &mut Vec<Batch>) {
        list.clear();
        let first_new = out.len();
        for &run in &self.runs {
            let coverage = chains.get(run.0 as usize).map_or(1.0, |c| c.coverage);
            let (chain, start, end) = self.drawn_run(run, coverage);
            let usable = chains
                .get(chain as usize)
                .is_some_and(|info| info.node_count >= 2);
            if !usable || start == end {
                continue;
            }
            let listed = list.len() as u32;
            list.extend(start..end);
            push_run(
                chains,
                (chain, listed, list.len() as u32),
                false,
                first_new,
                out,
            );
        }
    }

    /// [`ChainOrder::batches`] with the chains drawn nearest first (by `root_distances` [m], one
    /// per chain): opaque surfaces then hide what lies behind them before it is shaded. Runs
    /// merge into one draw only where they stay consecutive in that order; `scratch` is reused.
    pub fn batches_front_to_back(
        &self,
        chains: &[GpuChain],
        root_distances: &[f32],
        scratch: &mut Vec<(f32, u32)>,
        out: &mut Vec<Batch>,
    ) {
        scratch.clear();
        scratch.extend(self.runs.iter().enumerate().map(|(index, run)| {
            let distance = root_distances
                .get(run.0 as usize)
                .copied()
                .unwrap_or(f32::INFINITY);
            (distance, index as u32)
        }));
        // Stable and total: equal distances keep chain order, so the draws are deterministic.
        scratch.sort_by(|a, b| a.0.total_cmp(&b.0));
        let first_new = out.len();
        for &(_, index) in scratch.iter() {
            let run = self.runs[index as usize];
            let coverage = chains.get(run.0 as usize).map_or(1.0, |c| c.coverage);
            push_run(chains, self.drawn_run(run, coverage), true, first_new, out);
        }
    }
}

/// Appends run `(chain, start, end)` to the batches from `first_new` on: merged into the last
/// batch when it continues it with the same tessellation (and, where `split_fading`, fading),
/// skipped when its chain has fewer than two nodes or the run no items. Without
/// `split_fading` the batch is never marked dissolving (strands fade by rank in the shader).
fn push_run(
    chains: &[GpuChain],
    (chain, start, end): (u32, u32, u32),
    split_fading: bool,
    first_new: usize,
    out: &mut Vec<Batch>,
) {
    let Some(info) = chains.get(chain as usize) else {
        return;
    };
    if info.node_count < 2 || start == end {
        return;
    }
    let (along, around, thin) = (info.along_segments, info.around_segments, info.thin);
    let dissolving = split_fading && info.coverage < 1.0;
    let mergeable = out.len() > first_new;
    match out.last_mut() {
        Some(batch)
            if mergeable
                && batch.along_segments == along
                && batch.around_segments == around
                && batch.thin == (thin != 0)
                && batch.dissolving == dissolving
                && batch.items.end == start =>
        {
            batch.items.end = end;
        }
        _ => out.push(Batch {
            items: start..end,
            along_segments: along,
            around_segments: around,
            thin: thin != 0,
            dissolving,
        }),
    }
}

/// One instanced draw: items (sorted positions) that share a tessellation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Batch {
    pub items: std::ops::Range<u32>,
    pub along_segments: u32,
    pub around_segments: u32,
    /// Strands at most a pixel wide: drawn as lines, not ribbons.
    pub thin: bool,
    /// The chains fade in or out (coverage below 1): surfaces need the screen-door pipeline.
    pub dissolving: bool,
}

impl Batch {
    /// Vertices per strand ribbon (a strip straddling `along + 1` points).
    pub fn ribbon_vertices(&self) -> u32 {
        2 * (self.along_segments + 1)
    }

    /// Vertices per strand line strip.
    pub fn line_vertices(&self) -> u32 {
        self.along_segments + 1
    }

    /// Vertices per tube or strip of `bands` bands: a strip per band, joined by two degenerate
    /// vertices (`surfaces.wgsl`).
    pub fn surface_vertices(&self, bands: u32) -> u32 {
        bands * (2 * (self.along_segments + 1) + 2) - 2
    }

    /// The same batch tessellated for the light passes: every `stride`-th curve point along
    /// (`ceil(along / stride)` segments, `shadow_segments` in `shadows.wgsl`).
    pub fn for_light_passes(&self, stride: u32) -> Batch {
        Batch {
            along_segments: self.along_segments.div_ceil(stride.max(1)),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests;
