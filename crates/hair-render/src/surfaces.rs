//! Static data of clusters (§3.4) and patches (§3.3): the chain each follows and its radii or
//! width, validated and packed for the GPU (uploaded once, like strands).

use crate::error::{Result, invalid};

/// Static per-cluster data: a cluster is a closed tube around its chain, 4 control points per node
/// on a circle whose radius goes linearly from root to tip (periodic cubic around, the chain's
/// clamped B-spline along).
#[derive(Debug, Clone, Copy)]
pub struct ClusterSet<'a> {
    /// The chain each cluster follows, one per cluster.
    pub cluster_chain: &'a [u32],
    /// Control-circle radius at the root [m], one per cluster, ≥ 0.
    pub cluster_root_radii: &'a [f32],
    /// Control-circle radius at the tip [m], one per cluster, ≥ 0.
    pub cluster_tip_radii: &'a [f32],
}

/// Static per-patch data: a patch is a strip along its chain, 2 control points per node at half
/// the width either side along the node binormal (linear across, the chain's B-spline along).
#[derive(Debug, Clone, Copy)]
pub struct PatchSet<'a> {
    /// The chain each patch follows, one per patch.
    pub patch_chain: &'a [u32],
    /// Width of each patch [m], ≥ 0.
    pub patch_widths: &'a [f32],
}

fn check_lengths(what: &str, chains: usize, others: &[(&str, usize)]) -> Result<()> {
    if u32::try_from(chains).is_err() {
        return Err(invalid(format!("{chains} {what} exceed the u32 range")));
    }
    for &(name, len) in others {
        if len != chains {
            return Err(invalid(format!(
                "{what} arrays differ in length: {chains} chains, {len} {name}"
            )));
        }
    }
    Ok(())
}

fn check_sizes(what: &str, name: &str, values: &[f32]) -> Result<()> {
    if let Some(index) = values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(invalid(format!(
            "{what} {index} has {name} {} m, expected a finite value ≥ 0",
            values[index]
        )));
    }
    Ok(())
}

impl ClusterSet<'_> {
    /// Number of clusters.
    pub fn cluster_count(&self) -> usize {
        self.cluster_chain.len()
    }

    /// Checks the array sizes and that radii are finite and ≥ 0.
    pub fn validate(&self) -> Result<()> {
        check_lengths(
            "cluster",
            self.cluster_chain.len(),
            &[
                ("root radii", self.cluster_root_radii.len()),
                ("tip radii", self.cluster_tip_radii.len()),
            ],
        )?;
        check_sizes("cluster", "root radius", self.cluster_root_radii)?;
        check_sizes("cluster", "tip radius", self.cluster_tip_radii)
    }
}

impl PatchSet<'_> {
    /// Number of patches.
    pub fn patch_count(&self) -> usize {
        self.patch_chain.len()
    }

    /// Checks the array sizes and that widths are finite and ≥ 0.
    pub fn validate(&self) -> Result<()> {
        check_lengths(
            "patch",
            self.patch_chain.len(),
            &[("widths", self.patch_widths.len())],
        )?;
        check_sizes("patch", "width", self.patch_widths)
    }
}

/// One cluster or patch as the shaders read it (`Surface` in `surfaces.wgsl`), 16 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuSurface {
    pub chain: u32,
    /// Offset scale at the root [m]: the radius of a cluster, half the width of a patch.
    pub root_scale: f32,
    /// Offset scale at the tip [m].
    pub tip_scale: f32,
    /// Texture seed (the surface's index in its set).
    pub seed: u32,
}

/// Packs a (validated) cluster set, in input order.
pub(crate) fn pack_clusters(clusters: &ClusterSet<'_>) -> Vec<GpuSurface> {
    (0..clusters.cluster_count())
        .map(|i| GpuSurface {
            chain: clusters.cluster_chain[i],
            root_scale: clusters.cluster_root_radii[i],
            tip_scale: clusters.cluster_tip_radii[i],
            seed: i as u32,
        })
        .collect()
}

/// Radius of a cluster's ring curve as a fraction of its control-circle radius: the periodic
/// uniform cubic B-spline through the 4 control points at radius `r` (`surfaces.wgsl`) stays
/// between `0.648 r` (mid-span) and `2/3 r` (at a control point's parameter).
pub const RING_RADIUS_FACTOR: f32 = 2.0 / 3.0;

/// The largest ring radius [m] of the clusters on each chain (index = chain), 0 for chains
/// without clusters: what the tessellation around a tube follows.
pub(crate) fn chain_ring_radii(clusters: &ClusterSet<'_>) -> Vec<f32> {
    let chains = clusters
        .cluster_chain
        .iter()
        .map(|&c| c as usize + 1)
        .max()
        .unwrap_or(0);
    let mut radii = vec![0.0f32; chains];
    for i in 0..clusters.cluster_count() {
        let radius = clusters.cluster_root_radii[i].max(clusters.cluster_tip_radii[i]);
        let chain = clusters.cluster_chain[i] as usize;
        radii[chain] = radii[chain].max(RING_RADIUS_FACTOR * radius);
    }
    radii
}

/// Packs a (validated) patch set, in input order.
pub(crate) fn pack_patches(patches: &PatchSet<'_>) -> Vec<GpuSurface> {
    (0..patches.patch_count())
        .map(|i| GpuSurface {
            chain: patches.patch_chain[i],
            root_scale: 0.5 * patches.patch_widths[i],
            tip_scale: 0.5 * patches.patch_widths[i],
            seed: i as u32 ^ 0x9e37_79b9,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_radii_take_the_largest_cluster_per_chain() {
        let radii = chain_ring_radii(&ClusterSet {
            cluster_chain: &[2, 0, 2],
            cluster_root_radii: &[0.003, 0.006, 0.009],
            cluster_tip_radii: &[0.012, 0.001, 0.0],
        });
        let expected = [0.006, 0.0, 0.012].map(|r| RING_RADIUS_FACTOR * r);
        assert_eq!(radii, expected.to_vec());
    }

    #[test]
    fn sets_are_checked_with_reasons() {
        let good = ClusterSet {
            cluster_chain: &[0, 1],
            cluster_root_radii: &[0.01, 0.01],
            cluster_tip_radii: &[0.005, 0.0],
        };
        assert!(good.validate().is_ok());
        let short = ClusterSet {
            cluster_tip_radii: &[0.005],
            ..good
        };
        assert!(
            short
                .validate()
                .unwrap_err()
                .to_string()
                .contains("tip radii")
        );
        let negative = ClusterSet {
            cluster_root_radii: &[0.01, -1.0],
            ..good
        };
        let message = negative.validate().unwrap_err().to_string();
        assert!(message.contains("cluster 1") && message.contains("root radius"));
        let patches = PatchSet {
            patch_chain: &[3],
            patch_widths: &[f32::NAN],
        };
        assert!(
            patches
                .validate()
                .unwrap_err()
                .to_string()
                .contains("patch 0")
        );
        let packed = pack_patches(&PatchSet {
            patch_chain: &[3],
            patch_widths: &[0.04],
        });
        assert_eq!((packed[0].chain, packed[0].root_scale), (3, 0.02));
    }
}
