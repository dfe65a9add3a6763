//! [`PerLevel`]: one value for each level of detail, indexed by [`Level`] (in place of parallel
//! arrays indexed by `level as usize`).

use std::ops::{Index, IndexMut};

use serde::{Deserialize, Serialize};

use crate::level::Level;

/// One `T` per level of detail, indexed by [`Level`]; iterates coarsest first.
///
/// ```
/// use hair_core::{Level, PerLevel};
///
/// let mut counts = PerLevel::from_fn(|level| level.skeletons_per_section());
/// counts[Level::Cluster] += 1;
/// assert_eq!(counts.iter().map(|(_, n)| *n).collect::<Vec<_>>(), vec![1, 4, 5]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct PerLevel<T> {
    /// The patch level's value.
    pub patch: T,
    /// The cluster level's value.
    pub cluster: T,
    /// The strand-group level's value.
    pub strand_group: T,
}

impl<T> PerLevel<T> {
    /// The values `make(level)` for each level.
    pub fn from_fn(mut make: impl FnMut(Level) -> T) -> Self {
        PerLevel {
            patch: make(Level::Patch),
            cluster: make(Level::Cluster),
            strand_group: make(Level::StrandGroup),
        }
    }

    /// Each level with its value, coarsest first.
    pub fn iter(&self) -> impl Iterator<Item = (Level, &T)> {
        [
            (Level::Patch, &self.patch),
            (Level::Cluster, &self.cluster),
            (Level::StrandGroup, &self.strand_group),
        ]
        .into_iter()
    }

    /// Each level with its value, mutable, coarsest first.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = (Level, &mut T)> {
        [
            (Level::Patch, &mut self.patch),
            (Level::Cluster, &mut self.cluster),
            (Level::StrandGroup, &mut self.strand_group),
        ]
        .into_iter()
    }

    /// The values, coarsest first.
    pub fn values(&self) -> impl Iterator<Item = &T> {
        self.iter().map(|(_, value)| value)
    }

    /// A new `PerLevel` of `f(level, value)`.
    pub fn map<U>(self, mut f: impl FnMut(Level, T) -> U) -> PerLevel<U> {
        PerLevel {
            patch: f(Level::Patch, self.patch),
            cluster: f(Level::Cluster, self.cluster),
            strand_group: f(Level::StrandGroup, self.strand_group),
        }
    }

    /// The values as an array, coarsest first (patches, clusters, strand groups).
    pub fn into_array(self) -> [T; 3] {
        [self.patch, self.cluster, self.strand_group]
    }
}

impl<T> Index<Level> for PerLevel<T> {
    type Output = T;

    fn index(&self, level: Level) -> &T {
        match level {
            Level::Patch => &self.patch,
            Level::Cluster => &self.cluster,
            Level::StrandGroup => &self.strand_group,
        }
    }
}

impl<T> IndexMut<Level> for PerLevel<T> {
    fn index_mut(&mut self, level: Level) -> &mut T {
        match level {
            Level::Patch => &mut self.patch,
            Level::Cluster => &mut self.cluster,
            Level::StrandGroup => &mut self.strand_group,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indexing_follows_the_level_and_iteration_is_coarsest_first() {
        let mut names = PerLevel::from_fn(Level::name);
        assert_eq!(names[Level::StrandGroup], "strands");
        names[Level::Patch] = "strip";
        let order: Vec<Level> = names.iter().map(|(level, _)| level).collect();
        assert_eq!(order, Level::ALL.to_vec());
        assert_eq!(names.map(|_, n| n.len()).into_array(), [5, 8, 7]);
    }
}
