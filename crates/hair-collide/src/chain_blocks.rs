//! Work over the active chains side by side: the chains are split in halves, recursively, down to
//! blocks of a few dozen consecutive chains, each block run as one rayon task with its own parts
//! of the per-node (or per-segment, per-control-point) buffers. Blocks write disjoint parts, so
//! the result does not depend on the thread count, and nothing is allocated.

use std::ops::Range;

/// A buffer laid out chain after chain: chain `c`'s items start at `first(c)`, an absolute index
/// (`first` is monotonic; `first(chain count)` is the end). `items` starts at the first item of
/// the first chain of the block it is handed to.
pub(crate) struct ChainSlice<'a, T, F> {
    /// The items of the block's chains.
    pub items: &'a mut [T],
    /// Where each chain's items start.
    pub first: F,
}

/// Buffers that split between two runs of chains.
pub(crate) trait ChainData: Send + Sized {
    /// Splits the buffers of `chains` at chain `middle`: those of `chains.start..middle` and
    /// those of `middle..chains.end`.
    fn split(self, chains: &Range<usize>, middle: usize) -> (Self, Self);
}

impl<T: Send, F: Fn(usize) -> usize + Copy + Send> ChainData for ChainSlice<'_, T, F> {
    fn split(self, chains: &Range<usize>, middle: usize) -> (Self, Self) {
        let at = (self.first)(middle) - (self.first)(chains.start);
        let (left, right) = self.items.split_at_mut(at);
        (
            ChainSlice {
                items: left,
                first: self.first,
            },
            ChainSlice {
                items: right,
                first: self.first,
            },
        )
    }
}

impl<A: ChainData, B: ChainData> ChainData for (A, B) {
    fn split(self, chains: &Range<usize>, middle: usize) -> (Self, Self) {
        let (a_left, a_right) = self.0.split(chains, middle);
        let (b_left, b_right) = self.1.split(chains, middle);
        ((a_left, b_left), (a_right, b_right))
    }
}

/// Runs `task(block, data)` for blocks of at most `per_task` consecutive chains of `chains`, side
/// by side, each with the block's part of `data`.
pub(crate) fn for_chain_blocks<D: ChainData>(
    chains: Range<usize>,
    per_task: usize,
    data: D,
    task: &(impl Fn(Range<usize>, D) + Sync),
) {
    if chains.len() <= per_task.max(1) {
        task(chains, data);
        return;
    }
    let middle = chains.start + chains.len() / 2;
    let (left, right) = data.split(&chains, middle);
    rayon::join(
        || for_chain_blocks(chains.start..middle, per_task, left, task),
        || for_chain_blocks(middle..chains.end, per_task, right, task),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every item is written once, by the task of its own chain, whatever the block size: each
    /// chain `c` of length `c % 5` writes `c` into its items, and the block's part starts where
    /// its first chain's items do.
    #[test]
    fn blocks_hand_each_chain_its_own_items() {
        let lengths: Vec<usize> = (0..200).map(|c| c % 5).collect();
        let mut offsets = vec![0];
        for length in &lengths {
            offsets.push(offsets.last().unwrap() + length);
        }
        for per_task in [1, 3, 64, 1000] {
            let mut items = vec![usize::MAX; *offsets.last().unwrap()];
            let mut counts = vec![0usize; lengths.len()];
            let first = |c: usize| offsets[c];
            let data = (
                ChainSlice {
                    items: &mut items,
                    first,
                },
                ChainSlice {
                    items: &mut counts,
                    first: |c: usize| c,
                },
            );
            for_chain_blocks(
                0..lengths.len(),
                per_task,
                data,
                &|block, (items, counts)| {
                    let start = first(block.start);
                    for c in block.clone() {
                        items.items[first(c) - start..first(c + 1) - start].fill(c);
                        counts.items[c - block.start] += 1;
                    }
                },
            );
            for c in 0..lengths.len() {
                assert!(items[offsets[c]..offsets[c + 1]].iter().all(|&v| v == c));
                assert_eq!(counts[c], 1, "chain {c} run once (per_task {per_task})");
            }
        }
    }
}
