//! Which simulated chains collide and with what volume: [`CollisionChain`] per active skeleton,
//! built from a groom for one level or for a per-section choice of levels.
//!
//! A layout is the list of active chains. The collision solver rebuilds its hierarchy only when
//! the layout changes (a section changes level) and refits it otherwise.

use hair_core::{Groom, Level};

use crate::bvh::ChainVolume;
use crate::error::{CollideError, Result};

/// The volume parameters of one chain, after its representation (§5.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChainShape {
    /// A strand group: an LSS of radius `thickness` \[m\] per segment (0 for a lone strand).
    StrandGroup {
        /// The group's radius \[m\] (`Groom::strand_group_radii`).
        thickness: f32,
    },
    /// A cluster: control circles of radius interpolated from `root_radius` to `tip_radius` \[m\]
    /// (§3.4); an LSS per segment encloses its 8 control points.
    Cluster {
        /// Control-circle radius at the root \[m\].
        root_radius: f32,
        /// Control-circle radius at the tip \[m\].
        tip_radius: f32,
    },
    /// A patch of width `width` \[m\] (§3.3); an RSS per segment encloses its 4 control points.
    Patch {
        /// Patch width \[m\].
        width: f32,
    },
}

impl ChainShape {
    /// The hierarchy's volume kind for this shape.
    pub fn volume(&self) -> ChainVolume {
        match *self {
            ChainShape::StrandGroup { thickness } => ChainVolume::StrandGroup { thickness },
            ChainShape::Cluster { .. } => ChainVolume::Cluster,
            ChainShape::Patch { .. } => ChainVolume::Patch,
        }
    }

    /// Checks that every size is finite and `>= 0`; `index` names the chain in the error.
    pub fn validate(&self, index: usize) -> Result<()> {
        let sizes: &[(&'static str, f32)] = match self {
            ChainShape::StrandGroup { thickness } => &[("thickness", *thickness)],
            ChainShape::Cluster {
                root_radius,
                tip_radius,
            } => &[("root_radius", *root_radius), ("tip_radius", *tip_radius)],
            ChainShape::Patch { width } => &[("width", *width)],
        };
        for &(name, value) in sizes {
            if !value.is_finite() {
                return Err(CollideError::NonFinite { what: name, index });
            }
            if value < 0.0 {
                return Err(CollideError::InvalidParameter {
                    name,
                    value: format!("{value} (chain {index})"),
                    allowed: "a finite number >= 0 m",
                });
            }
        }
        Ok(())
    }
}

/// One active chain of the simulation and how it collides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionChain {
    /// The chain's index in the simulated [`hair_core::SkeletonRest`] (the dynamics model).
    pub chain: u32,
    /// The section it belongs to: hair–hair repulsion skips pairs of the same section.
    pub section: u32,
    /// Its volume parameters.
    pub shape: ChainShape,
}

/// The collision chain of groom chain `chain`, for a simulation whose model is
/// `groom.skeletons` itself (chain ids are the groom's). `None` when `chain` is out of range.
pub fn groom_chain(groom: &Groom, chain: usize) -> Option<CollisionChain> {
    if chain >= groom.skeletons.chain_count() {
        return None;
    }
    let (section, level, _) = groom.chain_owner(chain);
    let local = chain - groom.level_chains(level).start;
    let shape = match level {
        Level::Patch => ChainShape::Patch {
            width: *groom.patch_widths.get(local)?,
        },
        Level::Cluster => ChainShape::Cluster {
            root_radius: *groom.cluster_root_radii.get(local)?,
            tip_radius: *groom.cluster_tip_radii.get(local)?,
        },
        Level::StrandGroup => ChainShape::StrandGroup {
            thickness: *groom.strand_group_radii.get(local)?,
        },
    };
    Some(CollisionChain {
        chain: chain as u32,
        section: section as u32,
        shape,
    })
}

/// Every chain of `level` (all sections at the same level), groom chain ids.
pub fn groom_level_chains(groom: &Groom, level: Level) -> Vec<CollisionChain> {
    groom
        .level_chains(level)
        .filter_map(|chain| groom_chain(groom, chain))
        .collect()
}

/// The active chains when section `s` is at `levels[s]`, section after section; writes into
/// `chains` (reusing its memory). Errors when `levels` does not have one entry per section.
pub fn groom_active_chains(
    groom: &Groom,
    levels: &[Level],
    chains: &mut Vec<CollisionChain>,
) -> Result<()> {
    if levels.len() != groom.section_count() {
        return Err(CollideError::SizeMismatch {
            what: "section levels",
            actual: levels.len(),
            expected: groom.section_count(),
        });
    }
    chains.clear();
    for (section, &level) in levels.iter().enumerate() {
        chains.extend(
            groom
                .section_chains(section, level)
                .filter_map(|chain| groom_chain(groom, chain)),
        );
    }
    Ok(())
}
