//! The per-frame node buffer of a groom's *active* skeletons: chains of the levels in use carry
//! their nodes and frames, every other chain is empty (and draws nothing).

use glam::Vec3;
use hair_core::{Frame, Groom, Level, RigidTransform};

use crate::error::{Result, invalid};
use crate::inputs::SkeletonFrame;

/// Node positions and frames of the active skeletons, on the groom's chain numbering, reused from
/// frame to frame (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct ActiveSkeletons {
    chain_offsets: Vec<u32>,
    node_positions: Vec<Vec3>,
    node_normals: Vec<Vec3>,
    node_binormals: Vec<Vec3>,
    chain_coverage: Vec<f32>,
    chain_gives_way: Vec<bool>,
    chain_simulated_at: Vec<Option<Level>>,
}

impl ActiveSkeletons {
    /// An empty buffer.
    pub fn new() -> ActiveSkeletons {
        ActiveSkeletons::default()
    }

    /// A buffer holding a copy of `frame` (a frame written out and read back, for example a
    /// simulation cache's record), checked first ([`SkeletonFrame::validate`]): arrays of
    /// matching lengths, offsets from 0 to the node count, finite values, coverages in `0..=1`.
    /// Empty per-chain arrays stand for their defaults (coverage 1, no give-way, the chain's own
    /// level).
    pub fn from_frame(frame: &SkeletonFrame<'_>) -> Result<ActiveSkeletons> {
        frame.validate()?;
        let chains = frame.chain_count();
        Ok(ActiveSkeletons {
            chain_offsets: frame.chain_offsets.to_vec(),
            node_positions: frame.node_positions.to_vec(),
            node_normals: frame.node_normals.to_vec(),
            node_binormals: frame.node_binormals.to_vec(),
            chain_coverage: if frame.chain_coverage.is_empty() {
                vec![1.0; chains]
            } else {
                frame.chain_coverage.to_vec()
            },
            chain_gives_way: if frame.chain_gives_way.is_empty() {
                vec![false; chains]
            } else {
                frame.chain_gives_way.to_vec()
            },
            chain_simulated_at: if frame.chain_simulated_at.is_empty() {
                vec![None; chains]
            } else {
                frame.chain_simulated_at.to_vec()
            },
        })
    }

    /// Removes every chain.
    pub fn clear(&mut self) {
        self.chain_offsets.clear();
        self.node_positions.clear();
        self.node_normals.clear();
        self.node_binormals.clear();
        self.chain_coverage.clear();
        self.chain_gives_way.clear();
        self.chain_simulated_at.clear();
    }

    /// Appends an active chain: node positions [m] and their frames, one per node.
    pub fn push_chain(&mut self, node_positions: &[Vec3], node_frames: &[Frame]) -> Result<()> {
        self.push_chain_with_coverage(node_positions, node_frames, 1.0)
    }

    /// Appends an active chain drawn with `coverage` in `[0, 1]` (see
    /// [`SkeletonFrame::chain_coverage`]): a level fading in or out during a transition.
    pub fn push_chain_with_coverage(
        &mut self,
        node_positions: &[Vec3],
        node_frames: &[Frame],
        coverage: f32,
    ) -> Result<()> {
        self.push_fading_chain(node_positions, node_frames, coverage, false)
    }

    /// Appends an active chain whose cluster or patch, drawn with `coverage` in `[0, 1]`, gives
    /// way to another surface level coming in at `1 − coverage`: it keeps the screen-door pixels
    /// that one drops (see [`SkeletonFrame::chain_gives_way`]).
    pub fn push_chain_giving_way(
        &mut self,
        node_positions: &[Vec3],
        node_frames: &[Frame],
        coverage: f32,
    ) -> Result<()> {
        self.push_fading_chain(node_positions, node_frames, coverage, true)
    }

    fn push_fading_chain(
        &mut self,
        node_positions: &[Vec3],
        node_frames: &[Frame],
        coverage: f32,
        gives_way: bool,
    ) -> Result<()> {
        if !(0.0..=1.0).contains(&coverage) {
            return Err(invalid(format!(
                "chain {} has coverage {coverage} (allowed: 0..=1)",
                self.chain_count()
            )));
        }
        if node_positions.len() != node_frames.len() {
            return Err(invalid(format!(
                "chain {} has {} node positions but {} node frames",
                self.chain_count(),
                node_positions.len(),
                node_frames.len()
            )));
        }
        if self.chain_offsets.is_empty() {
            self.chain_offsets.push(0);
        }
        self.node_positions.extend_from_slice(node_positions);
        self.node_normals
            .extend(node_frames.iter().map(|frame| frame.normal));
        self.node_binormals
            .extend(node_frames.iter().map(|frame| frame.binormal));
        self.chain_offsets.push(self.node_positions.len() as u32);
        self.chain_coverage.push(coverage);
        self.chain_gives_way.push(gives_way);
        self.chain_simulated_at.push(None);
        Ok(())
    }

    /// Appends an active chain drawn with `coverage` in `[0, 1]` whose motion is simulated at
    /// `simulated_at`, another level than its own (strands drawn on skeletons rebuilt from
    /// clusters or a patch; see [`SkeletonFrame::chain_simulated_at`]).
    pub fn push_rebuilt_chain(
        &mut self,
        node_positions: &[Vec3],
        node_frames: &[Frame],
        coverage: f32,
        simulated_at: Level,
    ) -> Result<()> {
        self.push_fading_chain(node_positions, node_frames, coverage, false)?;
        if let Some(last) = self.chain_simulated_at.last_mut() {
            *last = Some(simulated_at);
        }
        Ok(())
    }

    /// Appends an inactive chain (no nodes: nothing on it is drawn).
    pub fn push_inactive_chain(&mut self) {
        if self.chain_offsets.is_empty() {
            self.chain_offsets.push(0);
        }
        self.chain_offsets.push(self.node_positions.len() as u32);
        self.chain_coverage.push(0.0);
        self.chain_gives_way.push(false);
        self.chain_simulated_at.push(None);
    }

    /// Refills the buffer for `groom`: section `s` is drawn at `section_levels[s]`, so its chains
    /// at that level take their nodes from `node_positions` [m] and `node_frames` (one per node of
    /// `groom.skeletons`, every level, chain-major) and all its other chains are inactive.
    pub fn gather(
        &mut self,
        groom: &Groom,
        section_levels: &[Level],
        node_positions: &[Vec3],
        node_frames: &[Frame],
    ) -> Result<()> {
        let sections = groom.section_count();
        if section_levels.len() != sections {
            return Err(invalid(format!(
                "{} section levels for a groom of {sections} sections",
                section_levels.len()
            )));
        }
        let nodes = groom.skeletons.node_count();
        if node_positions.len() != nodes || node_frames.len() != nodes {
            return Err(invalid(format!(
                "the groom has {nodes} skeleton nodes but {} positions and {} frames were given",
                node_positions.len(),
                node_frames.len()
            )));
        }
        self.clear();
        for chain in 0..groom.skeletons.chain_count() {
            let (section, level, _) = groom.chain_owner(chain);
            if section_levels[section] == level {
                let range = groom.skeletons.nodes(chain);
                self.push_chain(&node_positions[range.clone()], &node_frames[range])?;
            } else {
                self.push_inactive_chain();
            }
        }
        Ok(())
    }

    /// [`ActiveSkeletons::gather`] with every section at `level`.
    pub fn gather_level(
        &mut self,
        groom: &Groom,
        level: Level,
        node_positions: &[Vec3],
        node_frames: &[Frame],
    ) -> Result<()> {
        let levels = vec![level; groom.section_count()];
        self.gather(groom, &levels, node_positions, node_frames)
    }

    /// [`ActiveSkeletons::gather_level`] with the groom in its rest pose, the head at the origin
    /// (a still frame: previews, benchmarks, tests).
    pub fn gather_rest_pose(&mut self, groom: &Groom, level: Level) -> Result<()> {
        let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
        self.gather_level(groom, level, &positions, &frames)
    }

    /// Sets every active chain's coverage to `coverage` (0..=1): the whole frame fading.
    pub(crate) fn set_coverage(&mut self, coverage: f32) {
        for (chain, value) in self.chain_coverage.iter_mut().enumerate() {
            if self.chain_offsets[chain + 1] > self.chain_offsets[chain] {
                *value = coverage;
            }
        }
    }

    /// Number of chains (active or not).
    pub fn chain_count(&self) -> usize {
        self.chain_offsets.len().saturating_sub(1)
    }

    /// Number of nodes of the active chains (what is uploaded per frame).
    pub fn node_count(&self) -> usize {
        self.node_positions.len()
    }

    /// The frame to hand to [`crate::Renderer::render`].
    pub fn frame(&self) -> SkeletonFrame<'_> {
        SkeletonFrame {
            chain_offsets: &self.chain_offsets,
            node_positions: &self.node_positions,
            node_normals: &self.node_normals,
            node_binormals: &self.node_binormals,
            chain_coverage: &self.chain_coverage,
            chain_gives_way: &self.chain_gives_way,
            chain_simulated_at: &self.chain_simulated_at,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_frame_copies_a_frame_and_refuses_a_broken_one() {
        let mut active = ActiveSkeletons::new();
        let positions = [Vec3::ZERO, Vec3::NEG_Y, Vec3::new(0.0, -2.0, 0.0)];
        let frames = vec![Frame::default(); 3];
        active
            .push_chain_giving_way(&positions, &frames, 0.25)
            .unwrap();
        active.push_inactive_chain();
        active
            .push_rebuilt_chain(&positions[..2], &frames[..2], 1.0, Level::Cluster)
            .unwrap();
        let copy = ActiveSkeletons::from_frame(&active.frame()).unwrap();
        assert_eq!(copy.frame().chain_offsets, active.frame().chain_offsets);
        assert_eq!(copy.frame().node_positions, active.frame().node_positions);
        assert_eq!(copy.frame().chain_coverage, &[0.25, 0.0, 1.0]);
        assert_eq!(copy.frame().chain_gives_way, &[true, false, false]);
        assert_eq!(
            copy.frame().chain_simulated_at,
            &[None, None, Some(Level::Cluster)]
        );
        // Offsets that end past the nodes are refused, naming them.
        let offsets = [0, 3, 3, 6];
        let broken = SkeletonFrame {
            chain_offsets: &offsets,
            ..active.frame()
        };
        let error = ActiveSkeletons::from_frame(&broken)
            .unwrap_err()
            .to_string();
        assert!(error.contains("chain offsets"), "{error}");
    }

    #[test]
    fn set_coverage_fades_only_active_chains() {
        let mut active = ActiveSkeletons::new();
        let positions = [Vec3::ZERO, Vec3::NEG_Y];
        let frames = vec![Frame::default(); 2];
        active.push_chain(&positions, &frames).unwrap();
        active.push_inactive_chain();
        active.push_chain(&positions, &frames).unwrap();
        active.set_coverage(0.5);
        assert_eq!(active.frame().chain_coverage, &[0.5, 0.0, 0.5]);
    }

    #[test]
    fn gather_keeps_only_the_chosen_level() {
        let scene = hair_core::Scene::new(
            &hair_core::HeadParams::default(),
            &hair_core::GroomParams {
                section_count: 3,
                strands_per_group: 2,
                ..hair_core::GroomParams::preset("straight").unwrap()
            },
        )
        .unwrap();
        let groom = &scene.groom;
        let head = hair_core::RigidTransform::IDENTITY;
        let (positions, frames) = groom.skeletons.rest_pose(&head);
        let mut active = ActiveSkeletons::new();
        let levels = [Level::Patch, Level::Cluster, Level::StrandGroup];
        active.gather(groom, &levels, &positions, &frames).unwrap();
        assert_eq!(active.chain_count(), 9 * 3);
        let per = groom.counts().nodes_per_skeleton;
        assert_eq!(active.node_count(), (1 + 3 + 5) * per);
        assert!(active.frame().validate().is_ok());
        let frame = active.frame();
        let nodes_of = |chain: usize| frame.chain_offsets[chain + 1] - frame.chain_offsets[chain];
        assert_eq!(nodes_of(0) as usize, per); // patch of section 0
        assert_eq!(nodes_of(1), 0); // patch of section 1
        assert_eq!(
            nodes_of(groom.section_chains(1, Level::Cluster).start) as usize,
            per
        );
        assert!(
            active
                .gather(groom, &levels[..2], &positions, &frames)
                .unwrap_err()
                .to_string()
                .contains("2 section levels")
        );
    }
}
