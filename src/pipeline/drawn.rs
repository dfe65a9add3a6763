//! The gather stage of a frame: what each section draws and where, from the state, never
//! written. The skeletons to draw ([`append_drawn`]), with each level's dissolve coverage while a
//! section blends, and what they cost to draw ([`drawn_work`], [`section_work`]).

use hair_core::lod::SectionWork;
use hair_core::skeleton::node_frames;
use hair_core::{Frame, Groom, Level, RigidTransform};
use hair_render::ActiveSkeletons;

use super::error::Result;
use super::levels::SectionLevels;
use super::state::PipelineState;

/// Appends to `active` the skeletons to draw at `display_time` [s], on `groom`'s chain
/// numbering after the chains already there: each visible section's chains at its level (and at
/// its previous level while it blends), with node frames from the simulated positions and the
/// head at `head`; every other chain inactive. `frames_scratch` is reused.
pub(super) fn append_drawn(
    groom: &Groom,
    state: &PipelineState,
    head: &RigidTransform,
    display_time: f64,
    frames_scratch: &mut Vec<Frame>,
    active: &mut ActiveSkeletons,
) -> Result<()> {
    let levels = &state.levels;
    for chain in 0..groom.skeletons.chain_count() {
        let (section, level, _) = groom.chain_owner(chain);
        let shown = levels.shown_weight(section, display_time);
        let drawn = shown > 0.0 && levels.drawn(section).any(|drawn| drawn == level);
        let block = &state.blocks[level];
        let located = block.slot(section).filter(|_| drawn);
        let Some(slot) = located else {
            active.push_inactive_chain();
            continue;
        };
        // The chain's nodes inside the section's node range of the block.
        let section_chains = groom.section_chains(section, level);
        let before: usize = (section_chains.start..chain)
            .map(|c| groom.skeletons.chain_node_count(c))
            .sum();
        let count = groom.skeletons.chain_node_count(chain);
        let start = block.nodes(slot).start + before;
        let positions = &block.state.node_positions[start..start + count];
        frames_scratch.clear();
        frames_scratch.resize(count, Frame::default());
        let root_frame = groom.skeletons.world_root_frame(chain, head);
        node_frames(&root_frame, positions, frames_scratch);
        // While blending, the new level dissolves in over the first half of the blend while
        // the old one dissolves out over the whole blend: no frame shows less hair than
        // either level, and the switch frame itself changes little. Between two surfaces
        // the old one gives way on the complementary pixels over the first half. A section
        // coming into view or leaving it dissolves in or out as a whole.
        let coverage = levels.coverage(section, level, display_time);
        if levels.gives_way(section, level) {
            active.push_chain_giving_way(positions, frames_scratch, coverage)?;
        } else {
            active.push_chain_with_coverage(positions, frames_scratch, coverage)?;
        }
    }
    Ok(())
}

/// Segments drawn and pixels covered at each level by the sections shown at `display_time` [s]
/// (strand groups count each of their strands drawn: a dissolving strand level draws only its
/// coverage's share of them; a dissolving surface is drawn whole and screen-doored, and not at
/// all once its coverage is 0, as a surface that gave way is in the second half of its blend).
/// `section_pixels` are the pixels each section covers this frame.
pub(super) fn drawn_work(
    levels: &SectionLevels,
    section_work: &[SectionWork],
    section_pixels: &[f64],
    display_time: f64,
) -> ([usize; 3], [f64; 3]) {
    let (mut segments, mut pixels) = ([0; 3], [0.0; 3]);
    for (section, work) in section_work.iter().enumerate() {
        if levels.shown_weight(section, display_time) <= 0.0 {
            continue;
        }
        for level in levels.drawn(section) {
            let coverage = levels.coverage(section, level, display_time);
            if coverage <= 0.0 {
                continue;
            }
            let whole = work.drawn_segments[level as usize];
            segments[level as usize] += if level == Level::StrandGroup {
                (whole as f32 * coverage).round() as usize
            } else {
                whole
            };
            pixels[level as usize] += section_pixels[section];
        }
    }
    (segments, pixels)
}

/// What each section of `groom` simulates and draws at each level: its skeleton nodes, and its
/// skeleton segments drawn (a strand group's once per strand).
pub(super) fn section_work(groom: &Groom) -> Vec<SectionWork> {
    let first_group = groom.level_chains(Level::StrandGroup).start;
    (0..groom.section_count())
        .map(|section| {
            let mut work = SectionWork::default();
            for level in Level::ALL {
                for chain in groom.section_chains(section, level) {
                    let nodes = groom.skeletons.chain_node_count(chain);
                    let copies = if level == Level::StrandGroup {
                        groom.strands.strands(chain - first_group).len()
                    } else {
                        1
                    };
                    work.nodes[level as usize] += nodes;
                    work.drawn_segments[level as usize] += nodes.saturating_sub(1) * copies;
                }
            }
            work
        })
        .collect()
}
