//! Allocation-free parallel iteration over chains: the per-node arrays are split at chain
//! boundaries recursively with `rayon::join`, so every chain is worked on by exactly one task and
//! no float is reduced across chains (results do not depend on the thread count). Chains can also
//! be visited in fixed batches of [`LANES`] (chains `LANES·k .. LANES·(k + 1)`), which the
//! lane-parallel position-based integrator steps together.

use glam::{Mat3, Vec3, Vec4};

use crate::dynamics::error::ChainFailure;
use crate::dynamics::integrators::{ChainArrays, ImplicitArrays};
use crate::dynamics::lanes::LANES;

/// Below this many nodes a run of chains is processed as one task. A node's step costs 0.3–1 µs
/// at 8–16 substeps (XPBD), so a task of 256 nodes is 0.1–0.3 ms of work, far above a task's
/// hand-over (about a microsecond), while a patch-level model (91 chains, 1,183 nodes) still
/// splits into six tasks (at 2,048 it ran on one core while the other waited).
const NODES_PER_TASK: u32 = 256;

/// Per-node and per-chain arrays of a contiguous range of chains starting at `first_chain`.
pub(crate) struct ChainSlices<'a> {
    pub first_chain: usize,
    pub positions: &'a mut [Vec3],
    pub velocities: &'a mut [Vec3],
    pub collision: &'a [Vec3],
    /// Wind velocities [m/s] at the nodes, sampled once per step.
    pub wind: &'a mut [Vec3],
    pub forces: &'a mut [Vec3],
    pub corrections: &'a mut [Vec3],
    pub work: &'a mut [Vec4],
    pub backup_positions: &'a mut [Vec3],
    pub backup_velocities: &'a mut [Vec3],
    /// Empty unless the implicit integrator runs.
    pub diagonal: &'a mut [Mat3],
    pub first: &'a mut [Mat3],
    pub second: &'a mut [Mat3],
    pub rhs: &'a mut [Vec3],
    /// One per chain.
    pub failures: &'a mut [Option<ChainFailure>],
    /// One per chain.
    pub halvings: &'a mut [u32],
}

/// The arrays of one chain.
pub(crate) struct ChainWork<'a> {
    pub arrays: ChainArrays<'a>,
    pub backup_positions: &'a mut [Vec3],
    pub backup_velocities: &'a mut [Vec3],
    pub failure: &'a mut Option<ChainFailure>,
    pub halvings: &'a mut u32,
}

fn split<T>(slice: &mut [T], at: usize) -> (&mut [T], &mut [T]) {
    if slice.is_empty() {
        (&mut [], &mut [])
    } else {
        slice.split_at_mut(at)
    }
}

impl<'a> ChainSlices<'a> {
    /// Splits at chain `chain` (absolute index): the first part holds `first_chain..chain`.
    fn split_at_chain(self, offsets: &[u32], chain: usize) -> (ChainSlices<'a>, ChainSlices<'a>) {
        let node = (offsets[chain] - offsets[self.first_chain]) as usize;
        let chains = chain - self.first_chain;
        let (positions_a, positions_b) = self.positions.split_at_mut(node);
        let (velocities_a, velocities_b) = self.velocities.split_at_mut(node);
        let (collision_a, collision_b) = self.collision.split_at(node);
        let (wind_a, wind_b) = self.wind.split_at_mut(node);
        let (forces_a, forces_b) = self.forces.split_at_mut(node);
        let (corrections_a, corrections_b) = self.corrections.split_at_mut(node);
        let (work_a, work_b) = self.work.split_at_mut(node);
        let (backup_p_a, backup_p_b) = self.backup_positions.split_at_mut(node);
        let (backup_v_a, backup_v_b) = self.backup_velocities.split_at_mut(node);
        let (diagonal_a, diagonal_b) = split(self.diagonal, node);
        let (first_a, first_b) = split(self.first, node);
        let (second_a, second_b) = split(self.second, node);
        let (rhs_a, rhs_b) = split(self.rhs, node);
        let (failures_a, failures_b) = self.failures.split_at_mut(chains);
        let (halvings_a, halvings_b) = self.halvings.split_at_mut(chains);
        (
            ChainSlices {
                first_chain: self.first_chain,
                positions: positions_a,
                velocities: velocities_a,
                collision: collision_a,
                wind: wind_a,
                forces: forces_a,
                corrections: corrections_a,
                work: work_a,
                backup_positions: backup_p_a,
                backup_velocities: backup_v_a,
                diagonal: diagonal_a,
                first: first_a,
                second: second_a,
                rhs: rhs_a,
                failures: failures_a,
                halvings: halvings_a,
            },
            ChainSlices {
                first_chain: chain,
                positions: positions_b,
                velocities: velocities_b,
                collision: collision_b,
                wind: wind_b,
                forces: forces_b,
                corrections: corrections_b,
                work: work_b,
                backup_positions: backup_p_b,
                backup_velocities: backup_v_b,
                diagonal: diagonal_b,
                first: first_b,
                second: second_b,
                rhs: rhs_b,
                failures: failures_b,
                halvings: halvings_b,
            },
        )
    }

    /// The arrays of a single chain.
    fn into_work(self) -> ChainWork<'a> {
        let implicit = if self.diagonal.is_empty() {
            None
        } else {
            Some(ImplicitArrays {
                diagonal: self.diagonal,
                first: self.first,
                second: self.second,
                rhs: self.rhs,
            })
        };
        ChainWork {
            arrays: ChainArrays {
                positions: self.positions,
                velocities: self.velocities,
                collision: self.collision,
                wind: self.wind,
                forces: self.forces,
                corrections: self.corrections,
                work: self.work,
                implicit,
            },
            backup_positions: self.backup_positions,
            backup_velocities: self.backup_velocities,
            failure: &mut self.failures[0],
            halvings: &mut self.halvings[0],
        }
    }
}

/// Calls `work(chain, arrays)` for every chain of `slices` (which must start at chain 0 and cover
/// all chains of `offsets`), in parallel.
pub(crate) fn for_each_chain<'a, F>(offsets: &[u32], slices: ChainSlices<'a>, work: &F)
where
    F: Fn(usize, ChainWork<'_>) + Sync,
{
    let chain_count = offsets.len() - 1;
    recurse(offsets, slices, chain_count, work);
}

/// Calls `work(first_chain, end_chain, slices)` for every batch of chains
/// `LANES·k .. min(LANES·(k + 1), chain_count)` (`slices` covering exactly those chains), in
/// parallel over groups of batches. The batches are fixed by chain index, so what each batch
/// computes does not depend on the thread count.
pub(crate) fn for_each_batch<'a, F>(offsets: &[u32], slices: ChainSlices<'a>, work: &F)
where
    F: Fn(usize, usize, ChainSlices<'_>) + Sync,
{
    let chain_count = offsets.len() - 1;
    recurse_batches(offsets, slices, chain_count, work);
}

fn recurse_batches<F>(offsets: &[u32], slices: ChainSlices<'_>, end_chain: usize, work: &F)
where
    F: Fn(usize, usize, ChainSlices<'_>) + Sync,
{
    let first = slices.first_chain;
    let batches = (end_chain - first).div_ceil(LANES);
    if batches == 0 {
        return;
    }
    let nodes = offsets[end_chain] - offsets[first];
    if batches > 1 && nodes > NODES_PER_TASK {
        let middle = first + LANES * (batches / 2);
        let (a, b) = slices.split_at_chain(offsets, middle);
        rayon::join(
            || recurse_batches(offsets, a, middle, work),
            || recurse_batches(offsets, b, end_chain, work),
        );
        return;
    }
    let mut rest = slices;
    let mut start = first;
    while start < end_chain {
        let end = (start + LANES).min(end_chain);
        let (batch, tail) = rest.split_at_chain(offsets, end);
        work(start, end, batch);
        rest = tail;
        start = end;
    }
}

fn recurse<F>(offsets: &[u32], slices: ChainSlices<'_>, end_chain: usize, work: &F)
where
    F: Fn(usize, ChainWork<'_>) + Sync,
{
    let first = slices.first_chain;
    let chains = end_chain - first;
    if chains == 0 {
        return;
    }
    let nodes = offsets[end_chain] - offsets[first];
    if chains > 1 && nodes > NODES_PER_TASK {
        let middle = first + chains / 2;
        let (a, b) = slices.split_at_chain(offsets, middle);
        rayon::join(
            || recurse(offsets, a, middle, work),
            || recurse(offsets, b, end_chain, work),
        );
        return;
    }
    let mut rest = slices;
    for chain in first..end_chain {
        let (one, tail) = rest.split_at_chain(offsets, chain + 1);
        work(chain, one.into_work());
        rest = tail;
    }
}
