//! The renderer's inputs: per-frame skeleton nodes and static per-strand data, flat and
//! struct-of-arrays, with validation and their GPU layouts.

use glam::{Vec2, Vec3};

use crate::error::{Result, invalid};

/// Skeleton state for one frame: node chains with an orthonormal frame per node.
///
/// Chain `c` owns nodes `chain_offsets[c]..chain_offsets[c + 1]`. The node frame is
/// (normal, binormal, tangent = normal × binormal); strands, clusters and patches place their
/// control points in its (normal, binormal) plane.
#[derive(Debug, Clone, Copy)]
pub struct SkeletonFrame<'a> {
    /// Chain start indices into the node arrays, `chain_count + 1` entries, from 0 to the node count,
    /// non-decreasing. May be empty when there are no chains.
    pub chain_offsets: &'a [u32],
    /// Node positions [m], one per node, chain-major.
    pub node_positions: &'a [Vec3],
    /// Unit node normals, one per node.
    pub node_normals: &'a [Vec3],
    /// Unit node binormals, one per node, orthogonal to the normals.
    pub node_binormals: &'a [Vec3],
    /// Coverage of each chain in `[0, 1]` for dissolving between levels of detail: a strand is
    /// drawn when a hash of its index is below its chain's coverage, a cluster or patch covers that
    /// fraction of its pixels (screen-door). Empty means every chain at 1 (fully drawn).
    pub chain_coverage: &'a [f32],
    /// Chains whose cluster or patch gives way to another surface coming in at `1 − coverage`
    /// (a cross-fade between two surface levels): such a surface keeps exactly the screen-door
    /// pixels the incoming one drops, so that where both cover, every pixel shows one of them
    /// and none shows both. Strands ignore it. Empty means none.
    pub chain_gives_way: &'a [bool],
    /// The level each chain's motion is simulated at, where it is not the level drawn (strands
    /// drawn on skeletons rebuilt from clusters or a patch): the colour-coded view
    /// ([`crate::ShadingMode::LevelColors`]) shows that level's colour. `None`, or empty for
    /// every chain: the chain's own level.
    pub chain_simulated_at: &'a [Option<hair_core::Level>],
}

impl SkeletonFrame<'_> {
    /// Number of chains.
    pub fn chain_count(&self) -> usize {
        self.chain_offsets.len().saturating_sub(1)
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.node_positions.len()
    }

    /// Checks the array sizes, the offsets and that every value is finite.
    pub fn validate(&self) -> Result<()> {
        let nodes = self.node_positions.len();
        if self.node_normals.len() != nodes || self.node_binormals.len() != nodes {
            return Err(invalid(format!(
                "node arrays differ in length: {nodes} positions, {} normals, {} binormals",
                self.node_normals.len(),
                self.node_binormals.len()
            )));
        }
        if !self.chain_coverage.is_empty() {
            if self.chain_coverage.len() != self.chain_count() {
                return Err(invalid(format!(
                    "{} chain coverages for {} chains (give one per chain, or none)",
                    self.chain_coverage.len(),
                    self.chain_count()
                )));
            }
            if let Some(bad) = self
                .chain_coverage
                .iter()
                .position(|c| !(0.0..=1.0).contains(c))
            {
                return Err(invalid(format!(
                    "chain {bad} has coverage {} (allowed: 0..=1)",
                    self.chain_coverage[bad]
                )));
            }
        }
        if !self.chain_gives_way.is_empty() && self.chain_gives_way.len() != self.chain_count() {
            return Err(invalid(format!(
                "{} chain give-way flags for {} chains (give one per chain, or none)",
                self.chain_gives_way.len(),
                self.chain_count()
            )));
        }
        if !self.chain_simulated_at.is_empty()
            && self.chain_simulated_at.len() != self.chain_count()
        {
            return Err(invalid(format!(
                "{} chain simulation levels for {} chains (give one per chain, or none)",
                self.chain_simulated_at.len(),
                self.chain_count()
            )));
        }
        if u32::try_from(nodes).is_err() {
            return Err(invalid(format!("{nodes} nodes exceed the u32 index range")));
        }
        match (self.chain_offsets.first(), self.chain_offsets.last()) {
            (None, _) if nodes > 0 => {
                return Err(invalid(format!(
                    "{nodes} nodes but no chain offsets (expected chain_count + 1 entries)"
                )));
            }
            (Some(&first), Some(&last)) if first != 0 || last as usize != nodes => {
                return Err(invalid(format!(
                    "chain offsets must run from 0 to the node count {nodes}, got {first}..{last}"
                )));
            }
            _ => {}
        }
        if let Some(chain) = self.chain_offsets.windows(2).position(|w| w[1] < w[0]) {
            return Err(invalid(format!(
                "chain offsets decrease at chain {chain}: {} then {}",
                self.chain_offsets[chain],
                self.chain_offsets[chain + 1]
            )));
        }
        for (name, values) in [
            ("position", self.node_positions),
            ("normal", self.node_normals),
            ("binormal", self.node_binormals),
        ] {
            if let Some(node) = values.iter().position(|v| !v.is_finite()) {
                return Err(invalid(format!(
                    "node {node} has a non-finite {name}: {}",
                    values[node]
                )));
            }
        }
        Ok(())
    }

    /// The control points of a strand that follows `chain` at `root_offset` [m] in the node frames:
    /// `position[k] + offset.x · normal[k] + offset.y · binormal[k]`. Empty for an unknown chain.
    pub fn strand_control_points(&self, chain: usize, root_offset: Vec2) -> Vec<Vec3> {
        let (Some(&start), Some(&end)) = (
            self.chain_offsets.get(chain),
            self.chain_offsets.get(chain + 1),
        ) else {
            return Vec::new();
        };
        (start as usize..end as usize)
            .filter_map(|k| {
                Some(
                    *self.node_positions.get(k)?
                        + *self.node_normals.get(k)? * root_offset.x
                        + *self.node_binormals.get(k)? * root_offset.y,
                )
            })
            .collect()
    }
}

/// Static per-strand data, uploaded once.
#[derive(Debug, Clone, Copy)]
pub struct StrandSet<'a> {
    /// The chain each strand follows, one per strand.
    pub strand_chain: &'a [u32],
    /// Offset of each strand from its chain in the node frame's (normal, binormal) plane [m].
    pub strand_root_offsets: &'a [Vec2],
    /// Shade of each strand in 0..1: 0 picks the dark end of the hair colour range, 1 the light end.
    pub strand_shades: &'a [f32],
}

impl StrandSet<'_> {
    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.strand_chain.len()
    }

    /// Checks the array sizes and values (finite offsets, shades in 0..1).
    pub fn validate(&self) -> Result<()> {
        let strands = self.strand_chain.len();
        if self.strand_root_offsets.len() != strands || self.strand_shades.len() != strands {
            return Err(invalid(format!(
                "strand arrays differ in length: {strands} chains, {} root offsets, {} shades",
                self.strand_root_offsets.len(),
                self.strand_shades.len()
            )));
        }
        if u32::try_from(strands).is_err() {
            return Err(invalid(format!("{strands} strands exceed the u32 range")));
        }
        if let Some(strand) = self.strand_root_offsets.iter().position(|o| !o.is_finite()) {
            return Err(invalid(format!(
                "strand {strand} has a non-finite root offset {}",
                self.strand_root_offsets[strand]
            )));
        }
        if let Some(strand) = self
            .strand_shades
            .iter()
            .position(|s| !(0.0..=1.0).contains(s))
        {
            return Err(invalid(format!(
                "strand {strand} has shade {}, expected a value in 0..1",
                self.strand_shades[strand]
            )));
        }
        Ok(())
    }
}

/// One node as the shaders read it (`Node` in `common.wgsl`), 48 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuNode {
    pub position: [f32; 4],
    pub normal: [f32; 4],
    pub binormal: [f32; 4],
}

/// One strand as the shaders read it (`Strand` in `strand_items.wgsl`), 32 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuStrand {
    pub chain: u32,
    pub shade: f32,
    pub root_offset: [f32; 2],
    /// Fraction of the chain the strand runs, `(0, 1]`.
    pub length: f32,
    /// Scale of the offset at the tip, `0..=1`.
    pub tip_scale: f32,
    /// Rank in `(0, 1)` within its chain: drawn while below the chain's coverage (set at upload,
    /// see `ChainOrder::with_dissolve_ranks`).
    pub dissolve_rank: f32,
    /// First entry of the strand's residual profile in the profile buffer, in units of
    /// [`hair_core::PROFILE_SAMPLES`] entries ([`hair_core::NO_PROFILE`]: none).
    pub profile: u32,
}

/// Packs a (validated) frame's nodes into `out`, reusing its allocation.
pub(crate) fn pack_nodes(frame: &SkeletonFrame<'_>, out: &mut Vec<GpuNode>) {
    out.clear();
    out.extend(
        frame
            .node_positions
            .iter()
            .zip(frame.node_normals)
            .zip(frame.node_binormals)
            .map(|((p, n), b)| GpuNode {
                position: p.extend(1.0).to_array(),
                normal: n.extend(0.0).to_array(),
                binormal: b.extend(0.0).to_array(),
            }),
    );
}

/// Packs a (validated) strand set with its (validated) shapes.
pub(crate) fn pack_strands(
    strands: &StrandSet<'_>,
    shapes: &crate::strand_shapes::StrandShapes<'_>,
) -> Vec<GpuStrand> {
    strands
        .strand_chain
        .iter()
        .zip(strands.strand_root_offsets)
        .zip(strands.strand_shades)
        .enumerate()
        .map(|(strand, ((&chain, offset), &shade))| GpuStrand {
            chain,
            shade,
            root_offset: offset.to_array(),
            length: shapes.length(strand),
            tip_scale: shapes.tip_scale(strand),
            dissolve_rank: 0.0,
            profile: shapes.profile(strand),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame<'a>(offsets: &'a [u32], positions: &'a [Vec3], axes: &'a [Vec3]) -> SkeletonFrame<'a> {
        SkeletonFrame {
            chain_offsets: offsets,
            node_positions: positions,
            node_normals: axes,
            node_binormals: axes,
            chain_coverage: &[],
            chain_gives_way: &[],
            chain_simulated_at: &[],
        }
    }

    #[test]
    fn well_formed_frames_pass() {
        let positions = [Vec3::ZERO, Vec3::Y, Vec3::X];
        let axes = [Vec3::X; 3];
        assert!(frame(&[0, 2, 3], &positions, &axes).validate().is_ok());
        assert!(frame(&[], &[], &[]).validate().is_ok());
        assert_eq!(frame(&[0, 2, 3], &positions, &axes).chain_count(), 2);
    }

    #[test]
    fn malformed_frames_are_rejected_with_reasons() {
        let positions = [Vec3::ZERO, Vec3::Y, Vec3::X];
        let axes = [Vec3::X; 3];
        let message = |f: SkeletonFrame<'_>| f.validate().unwrap_err().to_string();
        assert!(message(frame(&[0, 2, 3], &positions, &axes[..2])).contains("differ"));
        assert!(message(frame(&[0, 2, 4], &positions, &axes)).contains("node count 3"));
        assert!(message(frame(&[0, 3, 2, 3], &positions, &axes)).contains("decrease"));
        assert!(message(frame(&[], &positions, &axes)).contains("no chain offsets"));
        let nan = [Vec3::ZERO, Vec3::NAN, Vec3::X];
        assert!(message(frame(&[0, 3], &nan, &axes)).contains("node 1"));
    }

    #[test]
    fn strand_sets_are_checked() {
        let good = StrandSet {
            strand_chain: &[0, 1],
            strand_root_offsets: &[Vec2::ZERO, Vec2::ONE],
            strand_shades: &[0.0, 1.0],
        };
        assert!(good.validate().is_ok());
        let short = StrandSet {
            strand_shades: &[0.5],
            ..good
        };
        assert!(short.validate().unwrap_err().to_string().contains("differ"));
        let dark = StrandSet {
            strand_shades: &[0.5, f32::NAN],
            ..good
        };
        assert!(dark.validate().unwrap_err().to_string().contains("shade"));
    }

    #[test]
    fn control_points_sit_in_the_node_frame() {
        let positions = [Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0)];
        let normals = [Vec3::X; 2];
        let binormals = [Vec3::Z; 2];
        let f = SkeletonFrame {
            chain_offsets: &[0, 2],
            node_positions: &positions,
            node_normals: &normals,
            node_binormals: &binormals,
            chain_coverage: &[],
            chain_gives_way: &[],
            chain_simulated_at: &[],
        };
        let points = f.strand_control_points(0, Vec2::new(0.1, 0.2));
        assert_eq!(
            points,
            vec![Vec3::new(0.1, 0.0, 0.2), Vec3::new(0.1, -1.0, 0.2)]
        );
        assert!(f.strand_control_points(5, Vec2::ZERO).is_empty());
    }
}
