//! Tests of the hand-over between levels (§4.2): a split then a merge gives back the parent
//! exactly, the centre child is the parent, and wrong sizes are refused.

use glam::Vec3;

use super::tests::rest_section;
use super::*;
use crate::dynamics::ChainRoots;
use crate::level::Level;
use crate::scene::Scene;
use crate::transform::RigidTransform;

/// A posed, moving state of a section at `level`: its rest shape under a turned head, bent by a
/// smooth displacement growing along the chain, with made-up velocities.
fn moving_section(
    scene: &Scene,
    section: usize,
    level: Level,
    head: &RigidTransform,
) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut positions = rest_section(scene, section, level, head);
    let mut velocities = Vec::with_capacity(positions.len());
    for (k, p) in positions.iter_mut().enumerate() {
        *p += Vec3::new(0.01 * (k as f32 * 0.7).sin(), 0.0, 0.004 * k as f32);
        velocities.push(Vec3::new(0.1 * k as f32, -0.05, 0.02 * (k as f32).cos()));
    }
    (positions, velocities)
}

#[test]
fn split_then_merge_returns_the_parent_exactly_and_the_centre_child_is_the_parent() {
    let scene = Scene::preset("curly").unwrap();
    let groom = &scene.groom;
    let head = RigidTransform::new(glam::Quat::from_rotation_y(0.4), Vec3::new(0.0, 0.01, 0.0));
    let nodes = |section, level| -> usize {
        groom
            .section_chains(section, level)
            .map(|chain| groom.skeletons.chain_node_count(chain))
            .sum()
    };
    for section in [0, 7, groom.section_count() - 1] {
        for (parent, child) in [
            (Level::Patch, Level::Cluster),
            (Level::Cluster, Level::StrandGroup),
        ] {
            let (positions, velocities) = moving_section(&scene, section, parent, &head);
            let from = SectionStateRef {
                positions: &positions,
                velocities: &velocities,
            };
            let mut child_positions = vec![Vec3::ZERO; nodes(section, child)];
            let mut child_velocities = child_positions.clone();
            hand_over(
                groom,
                section,
                parent,
                from,
                child,
                &mut child_positions,
                &mut child_velocities,
                &ChainRoots::rigid(head),
            )
            .unwrap();
            // The centre child inherits the centre parent exactly (bitwise).
            let centre_offset = |level: Level| -> usize {
                let chains = groom.section_chains(section, level);
                (chains.start..groom.centre_chain(section, level))
                    .map(|chain| groom.skeletons.chain_node_count(chain))
                    .sum()
            };
            let n = groom
                .skeletons
                .chain_node_count(groom.centre_chain(section, child));
            let (pc, cc) = (centre_offset(parent), centre_offset(child));
            assert_eq!(child_positions[cc..cc + n], positions[pc..pc + n]);
            assert_eq!(child_velocities[cc..cc + n], velocities[pc..pc + n]);
            // Every child has its rest segment lengths (follow-the-leader is exact to rounding)
            // and its own root.
            let mut start = 0;
            for chain in groom.section_chains(section, child) {
                let range = groom.skeletons.nodes(chain);
                let chain_positions = &child_positions[start..start + range.len()];
                if start != cc {
                    let root = head.transform_point(groom.skeletons.root_positions[chain]);
                    assert!(chain_positions[0].distance(root) < 1e-6);
                    for (k, length) in groom.skeletons.segment_rest_lengths[range.clone()]
                        .iter()
                        .enumerate()
                        .skip(1)
                    {
                        let actual = chain_positions[k].distance(chain_positions[k - 1]);
                        assert!(
                            (actual - length).abs() < 1e-5 * length.max(1e-3),
                            "{actual} vs {length}"
                        );
                    }
                }
                assert!(chain_positions.iter().all(|p| p.is_finite()));
                start += range.len();
            }
            // Merging back: the centre parent is restored exactly.
            let back = SectionStateRef {
                positions: &child_positions,
                velocities: &child_velocities,
            };
            let mut parent_positions = vec![Vec3::ZERO; positions.len()];
            let mut parent_velocities = parent_positions.clone();
            hand_over(
                groom,
                section,
                child,
                back,
                parent,
                &mut parent_positions,
                &mut parent_velocities,
                &ChainRoots::rigid(head),
            )
            .unwrap();
            let m = groom
                .skeletons
                .chain_node_count(groom.centre_chain(section, parent));
            assert_eq!(parent_positions[pc..pc + m], positions[pc..pc + m]);
            assert_eq!(parent_velocities[pc..pc + m], velocities[pc..pc + m]);
            if parent == Level::Patch {
                // A patch has only the centre: split + merge is the identity.
                assert_eq!(parent_positions, positions);
                assert_eq!(parent_velocities, velocities);
            }
        }
    }
}

#[test]
fn hand_over_rejects_wrong_sizes() {
    let scene = Scene::preset("curly").unwrap();
    let positions = vec![Vec3::ZERO; 3];
    let from = SectionStateRef {
        positions: &positions,
        velocities: &positions,
    };
    let mut out = vec![Vec3::ZERO; 3];
    let mut out_v = out.clone();
    let error = hand_over(
        &scene.groom,
        0,
        Level::Patch,
        from,
        Level::Cluster,
        &mut out,
        &mut out_v,
        &ChainRoots::rigid(RigidTransform::IDENTITY),
    )
    .unwrap_err();
    assert!(error.to_string().contains("source positions"), "{error}");
}
