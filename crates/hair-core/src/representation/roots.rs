//! Where a groom's strands are drawn from: each strand's root on its strand group's skeleton
//! ([`drawn_strand_root`]), for every strand of a groom at once. A body that stretches carries
//! each root on its own triangle, which the skeleton's rest offsets do not follow; what a strand
//! is drawn from is what it must be moved from.

use glam::Vec3;

use super::drawn::{ChainStart, drawn_strand_root};
use super::geometry::check_node_arrays;
use crate::error::{HairError, Result};
use crate::frame::Frame;
use crate::groom::Groom;
use crate::level::Level;

/// Calls `visit(strand, root)` with the drawn root [m] of every strand of `groom` whose strand
/// group's chain `chain_start(chain)` gives (by the groom's chain number); strands of chains it
/// gives `None` for (not drawn) are skipped. Strands in the groom's order.
pub fn for_each_strand_root(
    groom: &Groom,
    chain_start: impl Fn(usize) -> Option<ChainStart>,
    mut visit: impl FnMut(usize, Vec3),
) {
    let group_chains = groom.level_chains(Level::StrandGroup);
    let strands = &groom.strands;
    for (group, chain) in group_chains.enumerate() {
        let Some(start) = chain_start(chain) else {
            continue;
        };
        for strand in strands.strands(group) {
            let root = drawn_strand_root(
                &start,
                strands.root_offsets[strand],
                strands.profile(strand),
            );
            visit(strand, root);
        }
    }
}

/// Every strand's drawn root [m] on skeleton node positions and frames given for every node of
/// the groom (all chains, as [`super::geometry::strand_polylines`] takes them), in the groom's
/// strand order: the first point of each polyline that takes.
///
/// Errors: node arrays shorter than the groom's nodes, a strand-group chain of fewer than two
/// nodes.
pub fn strand_roots(
    groom: &Groom,
    node_positions: &[Vec3],
    node_frames: &[Frame],
) -> Result<Vec<Vec3>> {
    check_node_arrays(groom, node_positions, node_frames)?;
    for chain in groom.level_chains(Level::StrandGroup) {
        let nodes = groom.skeletons.nodes(chain).len();
        if nodes < 2 {
            return Err(HairError::invalid(
                "strand-group skeleton nodes",
                nodes,
                "at least 2 nodes per chain",
            ));
        }
    }
    let mut roots = vec![Vec3::ZERO; groom.strands.strand_count()];
    for_each_strand_root(
        groom,
        |chain| {
            let first = groom.skeletons.nodes(chain).start;
            Some(ChainStart {
                first: node_positions[first],
                second: node_positions[first + 1],
                normal: node_frames[first].normal,
                binormal: node_frames[first].binormal,
            })
        },
        |strand, root| roots[strand] = root,
    );
    Ok(roots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groom::GroomParams;
    use crate::head::{Head, HeadParams};
    use crate::representation::geometry::strand_polylines;
    use crate::{PROFILE_SAMPLES, RigidTransform};

    #[test]
    fn each_root_is_the_first_point_its_polyline_draws() {
        // Curly strands spread around their groups, half of them with a residual profile that
        // does not start at 0: the root reads the offset, the frame and r(0). The reference is
        // `strand_polylines`, which evaluates the whole B-spline (C(0) = first node, dC/du(0)
        // along the first segment); the two differ by f32 rounding of points a decimetre from
        // the origin, a few 10⁻⁸ m.
        let head = Head::procedural(&HeadParams::default()).unwrap();
        let params = GroomParams {
            section_count: 4,
            strands_per_group: 6,
            ..GroomParams::paper_curly()
        };
        let mut groom = Groom::generate(&params, &head).unwrap();
        let strands = groom.strands.strand_count();
        groom.strands.profiles = (0..PROFILE_SAMPLES)
            .map(|j| Vec3::new(0.002, -0.001, 0.0005) * (1.0 + j as f32 / 8.0))
            .collect();
        groom.strands.profile_of = (0..strands)
            .map(|s| if s % 2 == 0 { 0 } else { crate::NO_PROFILE })
            .collect();
        let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
        let roots = strand_roots(&groom, &positions, &frames).unwrap();
        let lines = strand_polylines(&groom, &positions, &frames, 4).unwrap();
        assert_eq!(roots.len(), lines.curve_count());
        for (strand, root) in roots.iter().enumerate() {
            let first = lines.points[lines.offsets[strand] as usize];
            assert!(
                root.distance(first) < 1e-6,
                "strand {strand}: {root} against {first}"
            );
        }
        let mut moved = 0.0f32;
        for (group, chain) in groom.level_chains(Level::StrandGroup).enumerate() {
            let node = positions[groom.skeletons.nodes(chain).start];
            for strand in groom.strands.strands(group) {
                moved = moved.max(roots[strand].distance(node));
            }
        }
        // The roots are not the chains' nodes: offsets and residuals moved them.
        assert!(moved > 1e-3, "{moved}");
        // Too few nodes is refused, not read past.
        assert!(strand_roots(&groom, &positions[..3], &frames).is_err());
    }
}
