//! BVH query == brute-force query, exactly, on seeded random grooms of mixed representations
//! around a sphere head, before and after moving the hair (refit) and the head (set_pose);
//! refit == fresh build; bad input gives errors.

mod support;

use glam::{Quat, Vec3};
use hair_collide::{
    ChainVolume, CollideError, CollisionBody, HairBvh, SegmentContacts, query_body,
    query_body_brute_force, query_body_volumes,
};
use hair_core::mesh::MeshError;
use support::{Rng, uv_sphere};

const HEAD_CENTER: Vec3 = Vec3::new(0.0, 1.6, 0.0);
const HEAD_RADIUS: f32 = 0.1;

/// A random groom: chains rooted around the head surface (some inside, some outside), random
/// walks of 1–2 cm segments, mixed representations.
struct Groom {
    offsets: Vec<u32>,
    kinds: Vec<ChainVolume>,
    nodes: Vec<Vec3>,
}

impl Groom {
    fn random(rng: &mut Rng, chain_count: usize) -> Self {
        let mut offsets = vec![0u32];
        let mut kinds = Vec::new();
        let mut nodes = Vec::new();
        for _ in 0..chain_count {
            let node_count = match rng.below(20) {
                0 => 0,
                1 => 1,
                _ => 2 + rng.below(15),
            };
            let mut p = HEAD_CENTER + rng.direction() * HEAD_RADIUS * rng.range(0.9, 1.1);
            let mut direction = rng.direction();
            for _ in 0..node_count {
                nodes.push(p);
                direction = (direction + rng.direction() * 0.5).normalize();
                p += direction * rng.range(0.01, 0.02);
            }
            offsets.push(nodes.len() as u32);
            kinds.push(match rng.below(4) {
                0 => ChainVolume::StrandGroup { thickness: 0.0 },
                1 => ChainVolume::StrandGroup {
                    thickness: rng.range(0.0, 0.005),
                },
                2 => ChainVolume::Cluster,
                _ => ChainVolume::Patch,
            });
        }
        Groom {
            offsets,
            kinds,
            nodes,
        }
    }

    /// Control points for the clusters (4 per node, a circle of 4 mm around the node, twisted)
    /// and patches (2 per node, ±8 mm along a direction), chain after chain.
    fn control_points(&self, rng: &mut Rng) -> Vec<Vec3> {
        let mut controls = Vec::new();
        for (chain, kind) in self.kinds.iter().enumerate() {
            let nodes = &self.nodes[self.offsets[chain] as usize..self.offsets[chain + 1] as usize];
            for &node in nodes {
                let side = rng.direction();
                match kind {
                    ChainVolume::StrandGroup { .. } => {}
                    ChainVolume::Cluster => {
                        let other = side.any_orthonormal_vector();
                        let third = side.cross(other);
                        controls.extend([other, third, -other, -third].map(|d| node + d * 0.004));
                    }
                    ChainVolume::Patch => {
                        controls.extend([node - side * 0.008, node + side * 0.008])
                    }
                }
            }
        }
        controls
    }
}

fn both_queries(hair: &HairBvh, body: &CollisionBody) -> SegmentContacts {
    let mut fast = SegmentContacts::new();
    let mut brute = SegmentContacts::new();
    query_body(hair, body, &mut fast);
    query_body_brute_force(hair, body, &mut brute);
    assert_eq!(fast, brute, "BVH and brute force disagree");
    // Volume by volume through the body's tree, in chunks of 256 side by side.
    let mut volumes = SegmentContacts::new();
    query_body_volumes(hair.volumes(), body, &mut volumes);
    assert_eq!(
        volumes, brute,
        "the per-volume query and brute force disagree"
    );
    fast
}

#[test]
fn bvh_query_equals_brute_force_on_random_grooms() {
    // 528 triangles, ~200 chains of ~1,600 segments: the brute force runs 0.85 M exact tests
    // per query, 21 queries.
    let head = uv_sphere(HEAD_CENTER, HEAD_RADIUS, 12, 24);
    let mut body = CollisionBody::from_mesh(&head).expect("valid mesh");
    for seed in 1..=3u64 {
        let mut rng = Rng::new(seed);
        let mut groom = Groom::random(&mut rng, 200);
        let controls = groom.control_points(&mut rng);
        let mut hair = HairBvh::build(&groom.offsets, &groom.kinds, &groom.nodes, &controls)
            .expect("valid groom");
        let contacts = both_queries(&hair, &body);
        // The configuration is not trivial: many contacts, and many segments without any.
        assert!(
            contacts.pair_count() > 100,
            "seed {seed}: {} pairs",
            contacts.pair_count()
        );
        assert!(contacts.segment_count() < hair.segment_count() / 2);
        // Output is sorted and well formed.
        assert!(contacts.segments.windows(2).all(|w| w[0] < w[1]));
        for (_, triangles) in contacts.iter() {
            assert!(!triangles.is_empty() && triangles.windows(2).all(|w| w[0] < w[1]));
        }

        // Move the hair (jitter up to 5 mm and drift), then refit, and compare with a fresh build.
        for round in 0..2 {
            let drift = rng.vec3(0.02);
            for p in &mut groom.nodes {
                *p += drift + rng.vec3(0.005);
            }
            let controls = groom.control_points(&mut rng);
            hair.refit(&groom.nodes, &controls).expect("same layout");
            let fresh = HairBvh::build(&groom.offsets, &groom.kinds, &groom.nodes, &controls)
                .expect("valid");
            assert_eq!(hair.volumes(), fresh.volumes());
            let refitted = both_queries(&hair, &body);
            assert_eq!(
                refitted,
                both_queries(&fresh, &body),
                "seed {seed} round {round}"
            );

            // Move the head too: the query is in the head's frame, where the hair moves by the
            // inverse of the head's motion. Posing the body changes nothing there.
            let rotation = Quat::from_axis_angle(rng.direction(), rng.range(-0.3, 0.3));
            let pivot = HEAD_CENTER;
            let translation = pivot - rotation * pivot + rng.vec3(0.01);
            body.set_pose(rotation, translation).expect("finite pose");
            let seen = |p: Vec3| rotation.inverse() * (p - translation);
            let nodes: Vec<Vec3> = groom.nodes.iter().map(|&p| seen(p)).collect();
            let controls: Vec<Vec3> = controls.iter().map(|&p| seen(p)).collect();
            let moved =
                HairBvh::build(&groom.offsets, &groom.kinds, &nodes, &controls).expect("valid");
            let posed = both_queries(&moved, &body);
            body.set_pose(Quat::IDENTITY, Vec3::ZERO).expect("identity");
            assert_eq!(posed, both_queries(&moved, &body), "the pose is not read");
        }
    }
}

#[test]
fn lone_strand_crossing_the_surface_touches_it_and_one_outside_does_not() {
    let head = uv_sphere(HEAD_CENTER, HEAD_RADIUS, 16, 32);
    let body = CollisionBody::from_mesh(&head).expect("valid mesh");
    // Chain 0 goes from inside the head straight out through the top; chain 1 floats above.
    let nodes = [
        HEAD_CENTER + Vec3::Y * 0.05,
        HEAD_CENTER + Vec3::Y * 0.15,
        HEAD_CENTER + Vec3::Y * 0.3,
        HEAD_CENTER + Vec3::new(0.0, 0.4, 0.0),
    ];
    let kinds = [
        ChainVolume::StrandGroup { thickness: 0.0 },
        ChainVolume::StrandGroup { thickness: 0.0 },
    ];
    let hair = HairBvh::build(&[0, 2, 4], &kinds, &nodes, &[]).expect("valid");
    assert_eq!(hair.segment_count(), 2);
    let contacts = both_queries(&hair, &body);
    assert_eq!(contacts.segments, vec![0]);
    // The segment leaves through the pole: it touches the pole's fan of triangles.
    assert!(!contacts.triangles.is_empty());
    let normals: Vec<Vec3> = contacts
        .triangles
        .iter()
        .map(|&t| body.local_triangles()[t as usize].normal)
        .collect();
    let mean = normals.iter().sum::<Vec3>() / normals.len() as f32;
    assert!(mean.normalize().dot(Vec3::Y) > 0.95, "mean normal {mean}");
    // Thicker: the floating chain reaches down to the head when its radius covers the gap.
    let thick = [
        ChainVolume::StrandGroup { thickness: 0.0 },
        ChainVolume::StrandGroup { thickness: 0.21 },
    ];
    let hair = HairBvh::build(&[0, 2, 4], &thick, &nodes, &[]).expect("valid");
    assert_eq!(both_queries(&hair, &body).segments, vec![0, 1]);
}

#[test]
fn empty_and_tiny_hair() {
    let head = uv_sphere(HEAD_CENTER, HEAD_RADIUS, 8, 16);
    let body = CollisionBody::from_mesh(&head).expect("valid mesh");
    let empty = HairBvh::build(&[0], &[], &[], &[]).expect("no chains is fine");
    assert!(both_queries(&empty, &body).is_empty());
    // Chains of 0 and 1 nodes have no segments.
    let kinds = [
        ChainVolume::Cluster,
        ChainVolume::StrandGroup { thickness: 0.0 },
    ];
    let hair = HairBvh::build(&[0, 0, 1], &kinds, &[HEAD_CENTER], &[]).expect("valid");
    assert_eq!(hair.segment_count(), 0);
    assert!(both_queries(&hair, &body).is_empty());
    // One segment inside the head surface's reach.
    let kinds = [ChainVolume::StrandGroup { thickness: 0.0 }];
    let nodes = [HEAD_CENTER, HEAD_CENTER + Vec3::X * 0.2];
    let mut hair = HairBvh::build(&[0, 2], &kinds, &nodes, &[]).expect("valid");
    assert_eq!(both_queries(&hair, &body).segment_count(), 1);
    hair.refit(&[HEAD_CENTER + Vec3::Y, HEAD_CENTER + Vec3::Y * 2.0], &[])
        .expect("same layout");
    assert!(both_queries(&hair, &body).is_empty());
    assert_eq!(hair.segment_top_nodes(), &[0]);
}

#[test]
fn bad_input_gives_clear_errors() {
    let kinds = [ChainVolume::StrandGroup { thickness: 0.001 }];
    let nodes = [Vec3::ZERO, Vec3::Y];
    assert!(matches!(
        HairBvh::build(&[0, 3], &kinds, &nodes, &[]),
        Err(CollideError::InvalidOffsets { .. })
    ));
    assert!(matches!(
        HairBvh::build(&[], &[], &[], &[]),
        Err(CollideError::InvalidOffsets { .. })
    ));
    assert!(matches!(
        HairBvh::build(&[1, 2], &kinds, &nodes, &[]),
        Err(CollideError::InvalidOffsets { .. })
    ));
    assert!(matches!(
        HairBvh::build(&[0, 2, 1], &[kinds[0], kinds[0]], &nodes, &[]),
        Err(CollideError::InvalidOffsets { .. })
    ));
    assert!(matches!(
        HairBvh::build(&[0, 2], &[], &nodes, &[]),
        Err(CollideError::SizeMismatch {
            what: "chain_volumes",
            ..
        })
    ));
    assert!(matches!(
        HairBvh::build(&[0, 2], &[ChainVolume::Patch], &nodes, &[Vec3::ZERO; 3]),
        Err(CollideError::SizeMismatch {
            what: "control_points",
            actual: 3,
            expected: 4
        })
    ));
    assert!(matches!(
        HairBvh::build(
            &[0, 2],
            &[ChainVolume::StrandGroup { thickness: -1.0 }],
            &nodes,
            &[]
        ),
        Err(CollideError::InvalidParameter {
            name: "thickness",
            ..
        })
    ));
    assert!(matches!(
        HairBvh::build(
            &[0, 2],
            &[ChainVolume::StrandGroup {
                thickness: f32::NAN
            }],
            &nodes,
            &[]
        ),
        Err(CollideError::NonFinite {
            what: "thickness",
            ..
        })
    ));
    assert!(matches!(
        HairBvh::build(&[0, 2], &kinds, &[Vec3::ZERO, Vec3::NAN], &[]),
        Err(CollideError::NonFinite {
            what: "node_positions",
            index: 1
        })
    ));
    let mut hair = HairBvh::build(&[0, 2], &kinds, &nodes, &[]).expect("valid");
    let before = hair.volumes().to_vec();
    assert!(hair.refit(&[Vec3::ZERO], &[]).is_err());
    assert!(
        hair.refit(&[Vec3::ZERO, Vec3::splat(f32::INFINITY)], &[])
            .is_err()
    );
    assert_eq!(
        hair.volumes(),
        &before[..],
        "a failed refit leaves the volumes unchanged"
    );
    assert!(hair.has_layout(&[0, 2], &kinds));
    assert!(!hair.has_layout(&[0, 2], &[ChainVolume::Cluster]));
    let message = HairBvh::build(&[0, 2], &kinds, &[Vec3::ZERO, Vec3::NAN], &[])
        .unwrap_err()
        .to_string();
    assert_eq!(message, "non-finite node_positions at index 1");

    // Meshes.
    let mut mesh = uv_sphere(HEAD_CENTER, HEAD_RADIUS, 4, 8);
    mesh.triangles.push([0, 1, 10_000]);
    assert!(matches!(
        CollisionBody::from_mesh(&mesh),
        Err(CollideError::Mesh(MeshError::VertexOutOfRange {
            vertex: 10_000,
            ..
        }))
    ));
    let mut mesh = uv_sphere(HEAD_CENTER, HEAD_RADIUS, 4, 8);
    mesh.positions[3].x = f32::NAN;
    assert!(matches!(
        CollisionBody::from_mesh(&mesh),
        Err(CollideError::Mesh(MeshError::NonFinitePosition {
            vertex: 3,
            ..
        }))
    ));
    assert_eq!(
        CollisionBody::from_mesh(&hair_core::TriangleMesh::default()).unwrap_err(),
        CollideError::Mesh(MeshError::NoTriangles)
    );
    let flat = hair_core::TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    assert_eq!(
        CollisionBody::from_mesh(&flat).unwrap_err(),
        CollideError::Mesh(MeshError::Degenerate { triangle_count: 1 })
    );
    let mut body =
        CollisionBody::from_mesh(&uv_sphere(HEAD_CENTER, HEAD_RADIUS, 4, 8)).expect("valid");
    assert!(
        body.set_pose(Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0), Vec3::ZERO)
            .is_err()
    );
    assert!(
        body.set_pose(Quat::from_xyzw(0.0, 0.0, 0.0, 0.0), Vec3::ZERO)
            .is_err()
    );
    assert!(body.set_pose(Quat::IDENTITY, Vec3::NAN).is_err());
}
