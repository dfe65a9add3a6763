//! The gather stage of a frame: what each section draws and where, from the state, never
//! written. The skeletons to draw ([`append_drawn`]): each level as itself, with each level's
//! dissolve coverage while a section blends, or every level as strands on strand-group
//! skeletons rebuilt from the level simulated ([`DrawnAs::Strands`], [`StrandFollow`]); and what
//! they cost to draw ([`drawn_work`], [`section_work`]).

use glam::Vec3;
use hair_core::dynamics::{ChainRoots, follow_the_leader};
use hair_core::lod::{FollowScratch, SectionWork, StrandFollow};
use hair_core::skeleton::node_frames;
use hair_core::{Frame, Groom, Level};
use hair_render::ActiveSkeletons;

use super::error::Result;
use super::levels::SectionLevels;
use super::settings::DrawnAs;
use super::state::PipelineState;

/// The gather stage's scratch, reused from frame to frame (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub(crate) struct DrawScratch {
    /// Node frames of one chain.
    frames: Vec<Frame>,
    /// One section's strand-group nodes to draw, section-local ([`DrawnAs::Strands`]).
    strands: Vec<Vec3>,
    /// The strand-group nodes rebuilt from the level a blending section leaves.
    leaving: Vec<Vec3>,
    /// How the strand groups follow the coarser levels (built at the first frame drawn as
    /// strands).
    follow: Option<StrandFollow>,
    /// The rebuild's own scratch.
    rebuild: FollowScratch,
}

/// What the gather stage reads: the groom, the state, where the roots are and the time shown.
#[derive(Clone, Copy)]
pub(super) struct Gathered<'a> {
    pub(super) groom: &'a Groom,
    pub(super) state: &'a PipelineState,
    /// Where each chain's root is carried (by the head, or by a deforming body and the head)
    /// at the state's time.
    pub(super) roots: ChainRoots<'a>,
    /// The time shown [s].
    pub(super) display_time: f64,
    pub(super) drawn_as: DrawnAs,
}

/// Appends to `active` the skeletons to draw, on the groom's chain numbering after the chains
/// already there: each level as itself ([`DrawnAs::Level`], [`append_levels`]) or every
/// level as strands ([`DrawnAs::Strands`], [`append_strands`]).
pub(super) fn append_drawn(
    gathered: Gathered<'_>,
    scratch: &mut DrawScratch,
    active: &mut ActiveSkeletons,
) -> Result<()> {
    match gathered.drawn_as {
        DrawnAs::Level => append_levels(gathered, &mut scratch.frames, active),
        DrawnAs::Strands => append_strands(gathered, scratch, active),
    }
}

/// Each visible section's chains at its level (and at its previous level while it blends), with
/// node frames from the simulated positions and each chain's carried root frame; every other
/// chain inactive.
/// `frames_scratch` is reused.
fn append_levels(
    gathered: Gathered<'_>,
    frames_scratch: &mut Vec<Frame>,
    active: &mut ActiveSkeletons,
) -> Result<()> {
    let Gathered {
        groom,
        state,
        roots,
        display_time,
        ..
    } = gathered;
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
        let local = nodes_in_section(groom, section, level, chain);
        let start = block.nodes(slot).start;
        let positions = &block.state.node_positions[start + local.start..start + local.end];
        chain_frames(groom, chain, &roots, positions, frames_scratch);
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

/// The node range of chain `chain` inside its section's nodes at `level` (the section's chains
/// one after the other).
fn nodes_in_section(
    groom: &Groom,
    section: usize,
    level: Level,
    chain: usize,
) -> std::ops::Range<usize> {
    let before: usize = (groom.section_chains(section, level).start..chain)
        .map(|c| groom.skeletons.chain_node_count(c))
        .sum();
    before..before + groom.skeletons.chain_node_count(chain)
}

/// Fills `frames` with the node frames of chain `chain` at `positions`, its root frame carried
/// where `roots` has it.
fn chain_frames(
    groom: &Groom,
    chain: usize,
    roots: &ChainRoots<'_>,
    positions: &[Vec3],
    frames: &mut Vec<Frame>,
) {
    frames.clear();
    frames.resize(positions.len(), Frame::default());
    node_frames(
        &groom.skeletons.world_root_frame(chain, &roots.pose(chain)),
        positions,
        frames,
    );
}

/// Every visible section's strand groups, on skeletons rebuilt from the level the section is
/// simulated at ([`StrandFollow::rebuild`]; its own strand-group skeletons when it is simulated as
/// strand groups). While a section blends between two levels, its strands are drawn on the
/// skeletons of both rebuilt and blended by the blend's weight (lengths restored by
/// follow-the-leader), so the strands move from one simulation to the other without a jump; a
/// section coming into view or leaving it dissolves in or out as a whole. Cluster and patch
/// chains are inactive. Each strand-group chain is marked with the level its section is
/// simulated at, for the colour-coded view.
fn append_strands(
    gathered: Gathered<'_>,
    scratch: &mut DrawScratch,
    active: &mut ActiveSkeletons,
) -> Result<()> {
    let Gathered {
        groom,
        state,
        roots,
        display_time,
        ..
    } = gathered;
    let levels = &state.levels;
    if scratch.follow.is_none() {
        scratch.follow = Some(StrandFollow::new(groom));
    }
    // Whether the section of the strand-group chains being pushed has nodes to draw.
    let mut section_drawn = false;
    for chain in 0..groom.skeletons.chain_count() {
        let (section, level, child) = groom.chain_owner(chain);
        let shown = levels.shown_weight(section, display_time);
        if level != Level::StrandGroup || shown <= 0.0 {
            active.push_inactive_chain();
            continue;
        }
        if child == 0 {
            section_drawn = section_strands(gathered, section, scratch)?;
        }
        if !section_drawn {
            active.push_inactive_chain();
            continue;
        }
        let positions = &scratch.strands[nodes_in_section(groom, section, level, chain)];
        chain_frames(groom, chain, &roots, positions, &mut scratch.frames);
        // The colour-coded view shows the level the strands' motion comes from.
        match levels.current()[section] {
            Level::StrandGroup => {
                active.push_chain_with_coverage(positions, &scratch.frames, shown)?;
            }
            simulated => {
                active.push_rebuilt_chain(positions, &scratch.frames, shown, simulated)?;
            }
        }
    }
    Ok(())
}

/// Fills `scratch.strands` with section `section`'s strand-group nodes to draw
/// ([`append_strands`]); `false` when no level simulates the section (nothing to draw).
fn section_strands(
    gathered: Gathered<'_>,
    section: usize,
    scratch: &mut DrawScratch,
) -> Result<bool> {
    let Gathered {
        groom,
        state,
        display_time,
        ..
    } = gathered;
    let levels = &state.levels;
    let chains = groom.section_chains(section, Level::StrandGroup);
    let nodes: usize = chains
        .clone()
        .map(|chain| groom.skeletons.chain_node_count(chain))
        .sum();
    scratch.strands.resize(nodes, Vec3::ZERO);
    let current = levels.current()[section];
    let DrawScratch {
        strands,
        leaving,
        follow,
        rebuild,
        ..
    } = scratch;
    let Some(follow) = follow.as_ref() else {
        return Ok(false);
    };
    if !rebuilt_strands(gathered, follow, section, current, strands, rebuild)? {
        return Ok(false);
    }
    let Some(previous) = levels.previous(section) else {
        return Ok(true);
    };
    let weight = levels.blend_weight(section, display_time);
    if weight >= 1.0 {
        return Ok(true);
    }
    leaving.resize(nodes, Vec3::ZERO);
    if !rebuilt_strands(gathered, follow, section, previous, leaving, rebuild)? {
        return Ok(true);
    }
    for (arriving, leaving) in strands.iter_mut().zip(leaving.iter()) {
        *arriving = leaving.lerp(*arriving, weight);
    }
    let mut start = 0;
    for chain in chains {
        let count = groom.skeletons.chain_node_count(chain);
        follow_the_leader(
            &mut strands[start..start + count],
            &groom.skeletons.segment_rest_lengths[groom.skeletons.nodes(chain)],
        );
        start += count;
    }
    Ok(true)
}

/// Writes into `out` section `section`'s strand-group nodes as simulated at `level`: copied at
/// the strand-group level, rebuilt by `follow` from a coarser one; `false` when the level does
/// not simulate the section.
fn rebuilt_strands(
    gathered: Gathered<'_>,
    follow: &StrandFollow,
    section: usize,
    level: Level,
    out: &mut [Vec3],
    rebuild: &mut FollowScratch,
) -> Result<bool> {
    let block = &gathered.state.blocks[level];
    let Some(slot) = block.slot(section) else {
        return Ok(false);
    };
    let simulated = &block.state.node_positions[block.nodes(slot)];
    follow.rebuild(
        gathered.groom,
        section,
        level,
        simulated,
        &gathered.roots,
        out,
        rebuild,
    )?;
    Ok(true)
}

/// Segments drawn and pixels covered at each level by the sections shown at `display_time` [s]
/// (strand groups count each of their strands drawn: a dissolving strand level draws only its
/// coverage's share of them; a dissolving surface is drawn whole and screen-doored, and not at
/// all once its coverage is 0, as a surface that gave way is in the second half of its blend).
/// Drawn as strands ([`DrawnAs::Strands`]), every shown section draws its strand groups, at
/// the strand-group level whatever it simulates. `section_pixels` are the pixels each section
/// covers this frame.
pub(super) fn drawn_work(
    levels: &SectionLevels,
    drawn_as: DrawnAs,
    section_work: &[SectionWork],
    section_pixels: &[f64],
    display_time: f64,
) -> ([usize; 3], [f64; 3]) {
    let (mut segments, mut pixels) = ([0; 3], [0.0; 3]);
    let strands = Level::StrandGroup as usize;
    for (section, work) in section_work.iter().enumerate() {
        let shown = levels.shown_weight(section, display_time);
        if shown <= 0.0 {
            continue;
        }
        if drawn_as == DrawnAs::Strands {
            segments[strands] += (work.drawn_segments[strands] as f32 * shown).round() as usize;
            pixels[strands] += section_pixels[section];
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
