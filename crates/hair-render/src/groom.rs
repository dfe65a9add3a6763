//! A groom's static render data (strands, clusters, patches on the groom's chain numbering), and
//! the upload of all of it in one call.

use glam::{Vec2, Vec3};
use hair_core::{Groom, Level};

use crate::error::Result;
use crate::inputs::StrandSet;
use crate::renderer::Renderer;
use crate::strand_shapes::StrandShapes;
use crate::surfaces::{ClusterSet, PatchSet};

/// The static render data of a [`Groom`], owned, with chains numbered as in
/// `groom.skeletons` (patches first, then clusters, then strand groups; see
/// [`Groom::level_chains`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GroomGeometry {
    /// Chain of each strand (a strand-group chain).
    pub strand_chain: Vec<u32>,
    /// Root offset of each strand in its group's node frames [m].
    pub strand_root_offsets: Vec<Vec2>,
    /// Shade of each strand in 0..1.
    pub strand_shades: Vec<f32>,
    /// Length of each strand as a fraction of its chain's (empty: all 1).
    pub strand_lengths: Vec<f32>,
    /// Scale of each strand's offset at the tip (empty: all 1).
    pub strand_tip_scales: Vec<f32>,
    /// Residual profile of each strand (empty: none; see [`hair_core::StrandSet::profile_of`]).
    pub strand_profiles: Vec<u32>,
    /// The residual profiles [m] (see [`hair_core::StrandSet::profiles`]).
    pub profiles: Vec<Vec3>,
    /// Chain of each cluster.
    pub cluster_chain: Vec<u32>,
    /// Root radius of each cluster's control circle [m].
    pub cluster_root_radii: Vec<f32>,
    /// Tip radius of each cluster's control circle [m].
    pub cluster_tip_radii: Vec<f32>,
    /// Chain of each patch.
    pub patch_chain: Vec<u32>,
    /// Width of each patch [m].
    pub patch_widths: Vec<f32>,
}

impl GroomGeometry {
    /// Collects the groom's strands, clusters and patches.
    pub fn new(groom: &Groom) -> GroomGeometry {
        let group_chains = groom.level_chains(Level::StrandGroup);
        let mut strand_chain = Vec::with_capacity(groom.strands.strand_count());
        for group in 0..groom.strands.group_count() {
            let chain = (group_chains.start + group) as u32;
            strand_chain.extend(groom.strands.strands(group).map(|_| chain));
        }
        GroomGeometry {
            strand_chain,
            strand_root_offsets: groom.strands.root_offsets.clone(),
            strand_shades: groom.strands.shades.clone(),
            strand_lengths: groom.strands.lengths.clone(),
            strand_tip_scales: groom.strands.tip_scales.clone(),
            strand_profiles: groom.strands.profile_of.clone(),
            profiles: groom.strands.profiles.clone(),
            cluster_chain: groom
                .level_chains(Level::Cluster)
                .map(|c| c as u32)
                .collect(),
            cluster_root_radii: groom.cluster_root_radii.clone(),
            cluster_tip_radii: groom.cluster_tip_radii.clone(),
            patch_chain: groom.level_chains(Level::Patch).map(|c| c as u32).collect(),
            patch_widths: groom.patch_widths.clone(),
        }
    }

    /// The strands as a [`StrandSet`].
    pub fn strands(&self) -> StrandSet<'_> {
        StrandSet {
            strand_chain: &self.strand_chain,
            strand_root_offsets: &self.strand_root_offsets,
            strand_shades: &self.strand_shades,
        }
    }

    /// The strands' lengths, tip scales and residual profiles as [`StrandShapes`].
    pub fn strand_shapes(&self) -> StrandShapes<'_> {
        StrandShapes {
            strand_lengths: &self.strand_lengths,
            strand_tip_scales: &self.strand_tip_scales,
            strand_profiles: &self.strand_profiles,
            profiles: &self.profiles,
        }
    }

    /// The clusters as a [`ClusterSet`].
    pub fn clusters(&self) -> ClusterSet<'_> {
        ClusterSet {
            cluster_chain: &self.cluster_chain,
            cluster_root_radii: &self.cluster_root_radii,
            cluster_tip_radii: &self.cluster_tip_radii,
        }
    }

    /// The patches as a [`PatchSet`].
    pub fn patches(&self) -> PatchSet<'_> {
        PatchSet {
            patch_chain: &self.patch_chain,
            patch_widths: &self.patch_widths,
        }
    }
}

impl Renderer {
    /// Uploads every strand, cluster and patch of `groom` (static data, once per groom). Which of
    /// them are drawn in a frame depends only on which chains have nodes in it (see
    /// [`crate::ActiveSkeletons`]).
    pub fn upload_groom(&mut self, groom: &Groom) -> Result<()> {
        let geometry = GroomGeometry::new(groom);
        self.upload_strands_with_shapes(&geometry.strands(), &geometry.strand_shapes())?;
        self.upload_clusters(&geometry.clusters())?;
        self.upload_patches(&geometry.patches())
    }
}
