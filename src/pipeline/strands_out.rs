//! Every strand of the groom at the current frame, as plain curves for export (cyHair `.hair`,
//! USD): sections simulated at a coarser level are handed over to strand groups first, as a
//! switch to strand level would (§4.2), so every frame has every strand.

use glam::Vec3;
use hair_core::Curves;
use hair_core::lod::{SectionStateRef, hand_over};
use hair_core::representation::geometry::strand_polylines;
use hair_core::skeleton::node_frames;
use hair_core::{Frame, Level};

use super::error::{PipelineError, Result};
use super::pipeline::Pipeline;

impl Pipeline {
    /// Every strand of the groom at the end of the last frame [m, world], root first (on a
    /// deforming body, each strand's root where the body carries it), with
    /// `samples_per_segment` (≥ 1) points per skeleton segment along each strand's B-spline.
    /// Strands are in the groom's order, so the curves of every frame of a run match one to one.
    pub fn strand_curves(&self, samples_per_segment: usize) -> Result<Curves> {
        let groom = &self.scene().groom;
        let skeletons = &groom.skeletons;
        let roots = self.chain_roots();
        let mut positions = vec![Vec3::ZERO; skeletons.node_count()];
        let mut frames = vec![Frame::default(); skeletons.node_count()];
        let mut velocities = Vec::new();
        for (section, &level) in self.section_levels().iter().enumerate() {
            let chains = groom.section_chains(section, Level::StrandGroup);
            let nodes =
                skeletons.offsets[chains.start] as usize..skeletons.offsets[chains.end] as usize;
            let block = self.block(level);
            let slot = block
                .slot(section)
                .ok_or_else(|| PipelineError::SectionNotAt { section, level })?;
            let from = block.nodes(slot);
            if level == Level::StrandGroup {
                positions[nodes.clone()].copy_from_slice(&block.state.node_positions[from]);
            } else {
                velocities.resize(nodes.len(), Vec3::ZERO);
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
                    &roots,
                )?;
            }
            for chain in chains {
                let chain_nodes = skeletons.nodes(chain);
                node_frames(
                    &skeletons.world_root_frame(chain, &roots.pose(chain)),
                    &positions[chain_nodes.clone()],
                    &mut frames[chain_nodes],
                );
            }
        }
        let mut lines = strand_polylines(groom, &positions, &frames, samples_per_segment)?;
        if let Some(ride) = self.ride() {
            ride.place_strand_roots(roots.head(), self.time(), &mut lines.points, &lines.offsets);
        }
        Ok(Curves {
            points: lines.points,
            offsets: lines.offsets,
            ..Curves::default()
        })
    }
}
