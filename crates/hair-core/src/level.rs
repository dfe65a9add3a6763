//! The three levels of detail of a section (§4.2): patch, clusters, strand groups.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::HairError;

/// A level of detail, ordered from coarsest to finest (`Patch < Cluster < StrandGroup`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Level {
    /// One skeleton with a ruled NURBS strip (§3.3).
    Patch,
    /// Three skeletons, each a generalized cylinder (§3.4).
    Cluster,
    /// Five skeletons, each carrying many NURBS strands (§3.5).
    StrandGroup,
}

impl Level {
    /// All levels, coarsest first.
    pub const ALL: [Level; 3] = [Level::Patch, Level::Cluster, Level::StrandGroup];

    /// The chains of every skeleton at this level in the level-major layout of `sections`
    /// sections (all patches, then all clusters, then all strand groups, each level
    /// section-major): `0..S`, `S..4S` or `4S..9S`.
    pub fn chains(self, sections: usize) -> std::ops::Range<usize> {
        let s = sections;
        match self {
            Level::Patch => 0..s,
            Level::Cluster => s..4 * s,
            Level::StrandGroup => 4 * s..9 * s,
        }
    }

    /// The chains of section `section` at this level in the same layout (1, 3 or 5 consecutive
    /// chains).
    pub fn section_chains(self, sections: usize, section: usize) -> std::ops::Range<usize> {
        let per = self.skeletons_per_section();
        let start = self.chains(sections).start + per * section;
        start..start + per
    }

    /// Skeletons a section has at this level: 1, 3 or 5.
    pub fn skeletons_per_section(self) -> usize {
        match self {
            Level::Patch => 1,
            Level::Cluster => 3,
            Level::StrandGroup => 5,
        }
    }

    /// The name used on the command line: `patches`, `clusters`, `strands`.
    pub fn name(self) -> &'static str {
        match self {
            Level::Patch => "patches",
            Level::Cluster => "clusters",
            Level::StrandGroup => "strands",
        }
    }

    /// The next finer level, if any.
    pub fn finer(self) -> Option<Level> {
        match self {
            Level::Patch => Some(Level::Cluster),
            Level::Cluster => Some(Level::StrandGroup),
            Level::StrandGroup => None,
        }
    }

    /// The next coarser level, if any.
    pub fn coarser(self) -> Option<Level> {
        match self {
            Level::Patch => None,
            Level::Cluster => Some(Level::Patch),
            Level::StrandGroup => Some(Level::Cluster),
        }
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Level {
    type Err = HairError;

    /// Parses `patches`/`patch`, `clusters`/`cluster`, `strands`/`strand-groups`/`strand-group`.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim().to_ascii_lowercase().as_str() {
            "patch" | "patches" => Ok(Level::Patch),
            "cluster" | "clusters" => Ok(Level::Cluster),
            "strand" | "strands" | "strand-group" | "strand-groups" => Ok(Level::StrandGroup),
            _ => Err(HairError::UnknownName {
                kind: "level",
                name: text.to_string(),
                known: "patches, clusters, strands".to_string(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_parse_order_and_count() {
        assert_eq!("strands".parse::<Level>().unwrap(), Level::StrandGroup);
        assert_eq!("Clusters".parse::<Level>().unwrap(), Level::Cluster);
        assert!(
            "voxels"
                .parse::<Level>()
                .unwrap_err()
                .to_string()
                .contains("patches, clusters, strands")
        );
        assert!(Level::Patch < Level::Cluster && Level::Cluster < Level::StrandGroup);
        let skeletons: Vec<usize> = Level::ALL
            .iter()
            .map(|l| l.skeletons_per_section())
            .collect();
        assert_eq!(skeletons, vec![1, 3, 5]);
        for level in Level::ALL {
            assert_eq!(level.name().parse::<Level>().unwrap(), level);
        }
    }
}
