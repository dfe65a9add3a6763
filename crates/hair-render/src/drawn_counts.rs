//! What the last frame drew, counted from its strand batches after thinning and dissolves
//! ([`crate::Renderer::last_drawn`]): what the drawing cost follows, beside the nodes simulated.

use crate::batches::Batch;

/// Strands and strand segments drawn in one frame's camera pass.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DrawnCounts {
    /// Strands drawn: every strand of a whole chain, a thinned or dissolving chain's drawn share.
    pub strands: usize,
    /// Their segments (each strand tessellated as its chain is at its distance).
    pub strand_segments: usize,
}

impl DrawnCounts {
    /// The counts of a frame's strand batches (each batch's strands times their segments).
    pub(crate) fn of_strand_batches(batches: &[Batch]) -> DrawnCounts {
        batches
            .iter()
            .fold(DrawnCounts::default(), |counts, batch| {
                let strands = batch.items.len();
                DrawnCounts {
                    strands: counts.strands + strands,
                    strand_segments: counts.strand_segments
                        + strands * batch.along_segments as usize,
                }
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_sum_each_batch_strands_and_segments() {
        let batch = |items: std::ops::Range<u32>, along_segments| Batch {
            items,
            along_segments,
            around_segments: 1,
            thin: true,
            dissolving: false,
        };
        // 10 strands of 32 segments and 5 of 4: 15 strands, 340 segments.
        let counts = DrawnCounts::of_strand_batches(&[batch(0..10, 32), batch(10..15, 4)]);
        assert_eq!(
            counts,
            DrawnCounts {
                strands: 15,
                strand_segments: 340
            }
        );
        assert_eq!(DrawnCounts::of_strand_batches(&[]), DrawnCounts::default());
    }
}
