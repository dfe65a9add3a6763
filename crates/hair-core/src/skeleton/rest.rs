//! The static model of many skeleton chains, stored flat with an offsets array.

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::skeleton::chain::{ChainAngles, build_chain, node_frames};
use crate::transform::RigidTransform;

/// Rest lengths, rest angles and root attachments of many chains (the *model* part of skeletons).
///
/// Chain `c` owns nodes `offsets[c]..offsets[c + 1]`. Roots are given in head space: the head's rigid
/// transform carries them into the world.
#[derive(Debug, Clone, PartialEq)]
pub struct SkeletonRest {
    /// Node ranges: `chain_count + 1` entries, starting at 0, non-decreasing.
    pub offsets: Vec<u32>,
    /// Rest length of the segment ending at each node [m], one per node; 0 at roots.
    pub segment_rest_lengths: Vec<f32>,
    /// Rest polar angle θ0 of each node [rad], one per node; 0 at roots.
    pub rest_polar_angles: Vec<f32>,
    /// Rest azimuth φ0 of each node [rad], one per node; 0 at roots.
    pub rest_azimuth_angles: Vec<f32>,
    /// Natural polar angle of each node's angular spring [rad], one per node; 0 at roots: the
    /// direction the spring pulls its segment towards. Equal to the rest angle unless sag-free
    /// initialisation ([`crate::dynamics::sag_free`]) turned it so that the rest shape is a static
    /// equilibrium under gravity.
    pub natural_polar_angles: Vec<f32>,
    /// Natural azimuth of each node's angular spring [rad], one per node; 0 at roots (see
    /// [`SkeletonRest::natural_polar_angles`]).
    pub natural_azimuth_angles: Vec<f32>,
    /// Root position of each chain in head space [m], one per chain.
    pub root_positions: Vec<Vec3>,
    /// Root frame of each chain in head space, one per chain (tangent: the growth direction; normal:
    /// away from the scalp).
    pub root_frames: Vec<Frame>,
}

impl Default for SkeletonRest {
    fn default() -> Self {
        SkeletonRest {
            offsets: vec![0],
            segment_rest_lengths: Vec::new(),
            rest_polar_angles: Vec::new(),
            rest_azimuth_angles: Vec::new(),
            natural_polar_angles: Vec::new(),
            natural_azimuth_angles: Vec::new(),
            root_positions: Vec::new(),
            root_frames: Vec::new(),
        }
    }
}

impl SkeletonRest {
    /// Number of chains.
    pub fn chain_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of nodes over all chains.
    pub fn node_count(&self) -> usize {
        *self.offsets.last().unwrap_or(&0) as usize
    }

    /// The node index range of chain `chain`.
    pub fn nodes(&self, chain: usize) -> Range<usize> {
        self.offsets[chain] as usize..self.offsets[chain + 1] as usize
    }

    /// Number of nodes of chain `chain`.
    pub fn chain_node_count(&self, chain: usize) -> usize {
        self.nodes(chain).len()
    }

    /// Appends a copy of chain `chain` of `source` (root, root frame, segment lengths, rest and
    /// natural angles) and returns its index here.
    pub fn push_chain_from(&mut self, source: &SkeletonRest, chain: usize) -> Result<usize> {
        let nodes = source.nodes(chain);
        let angles = ChainAngles {
            segment_lengths: source.segment_rest_lengths[nodes.clone()].to_vec(),
            polar_angles: source.rest_polar_angles[nodes.clone()].to_vec(),
            azimuth_angles: source.rest_azimuth_angles[nodes.clone()].to_vec(),
        };
        let index = self.push_chain(
            source.root_positions[chain],
            source.root_frames[chain],
            &angles,
        )?;
        let start = self.offsets[index] as usize;
        let count = nodes.len();
        self.natural_polar_angles[start..start + count]
            .copy_from_slice(&source.natural_polar_angles[nodes.clone()]);
        self.natural_azimuth_angles[start..start + count]
            .copy_from_slice(&source.natural_azimuth_angles[nodes]);
        Ok(index)
    }

    /// Replaces the rest angles of chain `chain` (its shape at rest), one entry per node [rad]
    /// (the root's is ignored and stored as 0); its springs' natural angles stay. Fails, changing
    /// nothing, on a size mismatch or a non-finite angle.
    pub fn set_rest_angles(&mut self, chain: usize, polar: &[f32], azimuth: &[f32]) -> Result<()> {
        let nodes = self.checked_angles(chain, "rest angles", polar, azimuth)?;
        set_angles(
            &mut self.rest_polar_angles,
            &mut self.rest_azimuth_angles,
            nodes,
            polar,
            azimuth,
        );
        Ok(())
    }

    /// Replaces the natural angles of chain `chain`'s springs, one entry per node [rad] (the
    /// root's is ignored and stored as 0); its rest shape stays. Fails, changing nothing, on a
    /// size mismatch or a non-finite angle.
    pub fn set_natural_angles(
        &mut self,
        chain: usize,
        polar: &[f32],
        azimuth: &[f32],
    ) -> Result<()> {
        let nodes = self.checked_angles(chain, "natural angles", polar, azimuth)?;
        set_angles(
            &mut self.natural_polar_angles,
            &mut self.natural_azimuth_angles,
            nodes,
            polar,
            azimuth,
        );
        Ok(())
    }

    /// The node range of `chain` when `polar` and `azimuth` have one finite angle per node after
    /// the root; `what` names them in the error.
    fn checked_angles(
        &self,
        chain: usize,
        what: &'static str,
        polar: &[f32],
        azimuth: &[f32],
    ) -> Result<Range<usize>> {
        let nodes = self.nodes(chain);
        for values in [polar, azimuth] {
            if values.len() != nodes.len() {
                return Err(HairError::SizeMismatch {
                    what,
                    actual: values.len(),
                    expected: nodes.len(),
                });
            }
            if let Some(bad) = values.iter().skip(1).find(|v| !v.is_finite()) {
                return Err(HairError::invalid(what, bad, "finite angles [rad]"));
            }
        }
        Ok(nodes)
    }

    /// Appends a chain and returns its index. `angles` has one entry per node, at least 2 nodes,
    /// positive finite segment lengths (after the root) and finite angles.
    pub fn push_chain(
        &mut self,
        root_position: Vec3,
        root_frame: Frame,
        angles: &ChainAngles,
    ) -> Result<usize> {
        let node_count = angles.node_count();
        if node_count < 2 {
            return Err(HairError::invalid(
                "node count",
                node_count,
                "at least 2 nodes per chain",
            ));
        }
        if angles.polar_angles.len() != node_count || angles.azimuth_angles.len() != node_count {
            return Err(HairError::SizeMismatch {
                what: "rest angles",
                actual: angles.polar_angles.len().min(angles.azimuth_angles.len()),
                expected: node_count,
            });
        }
        if !root_position.is_finite() {
            return Err(HairError::invalid(
                "root position",
                root_position,
                "finite coordinates [m]",
            ));
        }
        for i in 1..node_count {
            let length = angles.segment_lengths[i];
            if !(length.is_finite() && length > 0.0) {
                return Err(HairError::invalid(
                    "segment length",
                    length,
                    "a finite number > 0 m",
                ));
            }
            if !(angles.polar_angles[i].is_finite() && angles.azimuth_angles[i].is_finite()) {
                return Err(HairError::invalid(
                    "rest angle",
                    format!("({}, {})", angles.polar_angles[i], angles.azimuth_angles[i]),
                    "finite angles [rad]",
                ));
            }
        }
        let start = self.node_count();
        let end = u32::try_from(start + node_count)
            .map_err(|_| HairError::invalid("node count", start + node_count, "< 2^32 nodes"))?;
        // Store 0 at the root, whatever the caller put there.
        self.segment_rest_lengths.push(0.0);
        self.rest_polar_angles.push(0.0);
        self.rest_azimuth_angles.push(0.0);
        self.segment_rest_lengths
            .extend_from_slice(&angles.segment_lengths[1..]);
        self.rest_polar_angles
            .extend_from_slice(&angles.polar_angles[1..]);
        self.rest_azimuth_angles
            .extend_from_slice(&angles.azimuth_angles[1..]);
        // Springs pull towards the rest shape until sag-free initialisation says otherwise.
        self.natural_polar_angles.push(0.0);
        self.natural_azimuth_angles.push(0.0);
        self.natural_polar_angles
            .extend_from_slice(&angles.polar_angles[1..]);
        self.natural_azimuth_angles
            .extend_from_slice(&angles.azimuth_angles[1..]);
        self.root_positions.push(root_position);
        self.root_frames.push(root_frame);
        self.offsets.push(end);
        Ok(self.chain_count() - 1)
    }

    /// Rest length of chain `chain` [m].
    pub fn chain_length(&self, chain: usize) -> f32 {
        self.segment_rest_lengths[self.nodes(chain)].iter().sum()
    }

    /// Writes the rest positions of chain `chain` [m], with the head at `head`, into `positions`
    /// (length: the chain's node count).
    pub fn rest_positions_of(&self, chain: usize, head: &RigidTransform, positions: &mut [Vec3]) {
        let nodes = self.nodes(chain);
        // Sizes come from this struct's own invariants, so this cannot fail.
        let _ = build_chain(
            head.transform_point(self.root_positions[chain]),
            &head.transform_frame(&self.root_frames[chain]),
            &self.segment_rest_lengths[nodes.clone()],
            &self.rest_polar_angles[nodes.clone()],
            &self.rest_azimuth_angles[nodes],
            positions,
        );
    }

    /// Rest positions of every node [m] with the head at `head`, chain-major (in parallel over
    /// chains; the result does not depend on the thread count).
    pub fn rest_positions(&self, head: &RigidTransform) -> Vec<Vec3> {
        let mut positions = vec![Vec3::ZERO; self.node_count()];
        self.for_each_chain_mut(&mut positions, |chain, slice| {
            self.rest_positions_of(chain, head, slice)
        });
        positions
    }

    /// Rest positions [m] and node frames of every node with the head at `head`, chain-major.
    pub fn rest_pose(&self, head: &RigidTransform) -> (Vec<Vec3>, Vec<Frame>) {
        let positions = self.rest_positions(head);
        let mut frames = vec![Frame::default(); positions.len()];
        self.node_frames_into(head, &positions, &mut frames);
        (positions, frames)
    }

    /// Computes the frame at every node of every chain from `positions` (one per node, chain-major)
    /// with the head at `head` (which carries the root frames), in parallel over chains; see
    /// [`node_frames`]. `frames` has one entry per node.
    pub fn node_frames_into(
        &self,
        head: &RigidTransform,
        positions: &[Vec3],
        frames: &mut [Frame],
    ) {
        self.for_each_chain_mut(frames, |chain, chain_frames| {
            let root = self.world_root_frame(chain, head);
            node_frames(&root, &positions[self.nodes(chain)], chain_frames);
        });
    }

    /// Splits a per-node array into its chains and calls `work(chain, slice)` for each, in parallel.
    pub fn for_each_chain_mut<T: Send>(
        &self,
        per_node: &mut [T],
        work: impl Fn(usize, &mut [T]) + Sync + Send,
    ) {
        debug_assert_eq!(per_node.len(), self.node_count());
        let mut slices = Vec::with_capacity(self.chain_count());
        let mut rest = per_node;
        for chain in 0..self.chain_count() {
            let (chain_slice, tail) = rest.split_at_mut(self.chain_node_count(chain));
            slices.push((chain, chain_slice));
            rest = tail;
        }
        slices
            .into_par_iter()
            .for_each(|(chain, slice)| work(chain, slice));
    }

    /// The root frame of chain `chain` in the world, with the head at `head`.
    pub fn world_root_frame(&self, chain: usize, head: &RigidTransform) -> Frame {
        head.transform_frame(&self.root_frames[chain])
    }
}

/// Writes one chain's angles (`nodes` of the per-node arrays), 0 at its root.
fn set_angles(
    polar_out: &mut [f32],
    azimuth_out: &mut [f32],
    nodes: Range<usize>,
    polar: &[f32],
    azimuth: &[f32],
) {
    polar_out[nodes.clone()].copy_from_slice(polar);
    azimuth_out[nodes.clone()].copy_from_slice(azimuth);
    polar_out[nodes.start] = 0.0;
    azimuth_out[nodes.start] = 0.0;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::chain::measure_chain;
    use glam::Quat;

    fn angles(n: usize, polar: f32) -> ChainAngles {
        ChainAngles {
            segment_lengths: (0..n).map(|i| if i == 0 { 0.0 } else { 0.02 }).collect(),
            polar_angles: (0..n).map(|i| if i == 0 { 0.0 } else { polar }).collect(),
            azimuth_angles: (0..n)
                .map(|i| (i % 4) as f32 * std::f32::consts::FRAC_PI_2)
                .collect(),
        }
    }

    #[test]
    fn offsets_index_the_flat_arrays() {
        let mut rest = SkeletonRest::default();
        rest.push_chain(Vec3::ZERO, Frame::default(), &angles(5, 0.3))
            .unwrap();
        rest.push_chain(Vec3::X, Frame::default(), &angles(3, 0.0))
            .unwrap();
        assert_eq!(rest.offsets, vec![0, 5, 8]);
        assert_eq!(rest.chain_count(), 2);
        assert_eq!(rest.node_count(), 8);
        assert_eq!(rest.nodes(1), 5..8);
        assert!((rest.chain_length(0) - 0.08).abs() < 1e-6);
        assert_eq!(rest.segment_rest_lengths[5], 0.0);
    }

    #[test]
    fn moved_head_carries_the_rest_shape_rigidly() {
        let mut rest = SkeletonRest::default();
        rest.push_chain(Vec3::new(0.0, 0.1, 0.0), Frame::default(), &angles(9, 0.5))
            .unwrap();
        let head = RigidTransform::new(Quat::from_rotation_y(0.7), Vec3::new(0.3, -0.2, 0.1));
        let at_rest = rest.rest_positions(&RigidTransform::IDENTITY);
        let moved = rest.rest_positions(&head);
        for (a, b) in at_rest.iter().zip(&moved) {
            assert!((head.transform_point(*a) - *b).length() < 1e-5);
        }
        // The measured angles in the moved root frame are the rest angles (rigid invariance).
        let measured = measure_chain(&rest.world_root_frame(0, &head), &moved).unwrap();
        for i in 1..9 {
            assert!((measured.polar_angles[i] - 0.5).abs() < 1e-4);
        }
    }

    #[test]
    fn bad_chains_are_rejected_with_names() {
        let mut rest = SkeletonRest::default();
        let mut bad = angles(4, 0.2);
        bad.segment_lengths[2] = -0.01;
        let error = rest
            .push_chain(Vec3::ZERO, Frame::default(), &bad)
            .unwrap_err();
        assert!(error.to_string().contains("segment length"));
        assert!(
            rest.push_chain(Vec3::ZERO, Frame::default(), &angles(1, 0.0))
                .is_err()
        );
        let mut nan = angles(4, 0.2);
        nan.polar_angles[3] = f32::NAN;
        assert!(rest.push_chain(Vec3::ZERO, Frame::default(), &nan).is_err());
        assert_eq!(rest.chain_count(), 0);
    }
}
