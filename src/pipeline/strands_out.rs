//! Every strand of the groom at the current frame, as plain curves for export (cyHair `.hair`,
//! USD): sections simulated at a coarser level are handed over to strand groups first, as a
//! switch to strand level would (§4.2), so every frame has every strand.

use glam::Vec3;
use hair_core::formats::Curves;
use hair_core::lod::{SectionStateRef, hand_over};
use hair_core::representation::geometry::strand_polylines;
use hair_core::skeleton::node_frames;
use hair_core::{Frame, Level};

use super::error::{PipelineError, Result};
use super::pipeline::Pipeline;

impl Pipeline {
    /// Every strand of the groom at the end of the last frame [m, world], root first, with
    /// `samples_per_segment` (≥ 1) points per skeleton segment along each strand's B-spline.
    /// Strands are in the groom's order, so the curves of every frame of a run match one to one.
    pub fn strand_curves(&self, samples_per_segment: usize) -> Result<Curves> {
        let groom = &self.scene().groom;
        let skeletons = &groom.skeletons;
        let head = self.head_pose();
        let mut positions = vec![Vec3::ZERO; skeletons.node_count()];
        let mut frames = vec![Frame::default(); skeletons.node_count()];
        for section in 0..groom.section_count() {
            let chains = groom.section_chains(section, Level::StrandGroup);
            let nodes =
                skeletons.offsets[chains.start] as usize..skeletons.offsets[chains.end] as usize;
            let (level, block) = Level::ALL
                .into_iter()
                .map(|level| (level, self.block(level)))
                .find(|(_, block)| block.slot(section).is_some())
                .ok_or_else(|| {
                    PipelineError::State(format!("section {section} is simulated at no level"))
                })?;
            let from = block.nodes(block.slot(section).expect("found above"));
            if level == Level::StrandGroup {
                positions[nodes.clone()].copy_from_slice(&block.state.node_positions[from]);
            } else {
                let mut velocities = vec![Vec3::ZERO; nodes.len()];
                hand_over(
                    groom,
                    section,
                    level,
                    SectionStateRef {
                        positions: &block.state.node_positions[from.clone()],
                        velocities: &block.state.node_velocities[from],
                    },
                    Level::StrandGroup,
                    &mut positions[nodes.clone()],
                    &mut velocities,
                    &head,
                )?;
            }
            for chain in chains {
                let chain_nodes = skeletons.nodes(chain);
                node_frames(
                    &skeletons.world_root_frame(chain, &head),
                    &positions[chain_nodes.clone()],
                    &mut frames[chain_nodes],
                );
            }
        }
        let lines = strand_polylines(groom, &positions, &frames, samples_per_segment)?;
        Ok(Curves {
            points: lines.points,
            offsets: lines.offsets,
            ..Curves::default()
        })
    }
}
