//! Real data: the TressFX Ratboy mohawk (2,228 strands × 32 vertices) against its body mesh
//! (25,814 triangles). BVH query == brute force exactly; refit after moving == fresh build.
//!
//! The data is AMD's TressFX samples (`hair_core::samples`: `HAIRLOD_DATA`, or `../shared/data`
//! beside the workspace; not part of this repository): the tests are ignored by default,
//! `.ci/run` runs them, and without the data they fail naming the file. The brute force
//! runs on a subset of strands (every 32nd) to keep the test short; the BVH query on all of them
//! is timed by the criterion bench `cargo bench -p hair-collide --bench ratboy`.

mod support;

use glam::{Quat, Vec3};
use hair_collide::{
    ChainVolume, CollisionBody, HairBvh, SegmentContacts, query_body, query_body_brute_force,
};
use support::tressfx::{data_dir, read_tfx4, read_tfxmesh};

/// Brute force runs on every `SUBSET_STRIDE`-th strand (70 strands, 2,170 segments: 56 M exact
/// tests per brute-force query).
const SUBSET_STRIDE: usize = 32;

/// Strand group radius for the mohawk chains [m] (a thin wisp around each strand).
const THICKNESS: f32 = 0.002;

struct Ratboy {
    body: CollisionBody,
    vertices_per_strand: usize,
    positions: Vec<Vec3>,
}

fn load() -> Ratboy {
    let dir = data_dir().unwrap_or_else(|error| panic!("{error}"));
    let mesh = read_tfxmesh(&dir.join("ratboy_body.tfxmesh")).expect("readable mesh");
    assert_eq!(
        (mesh.positions.len(), mesh.triangles.len()),
        (12_909, 25_814)
    );
    let (vertices_per_strand, positions) =
        read_tfx4(&dir.join("ratboy_mohawk.tfx")).expect("readable groom");
    assert_eq!((vertices_per_strand, positions.len()), (32, 2_228 * 32));
    let body = CollisionBody::from_mesh(&mesh).expect("valid mesh");
    Ratboy {
        body,
        vertices_per_strand,
        positions,
    }
}

/// The chains of every `stride`-th strand as strand groups.
fn hair_of(
    ratboy: &Ratboy,
    stride: usize,
    thickness: f32,
) -> (Vec<u32>, Vec<ChainVolume>, Vec<Vec3>) {
    let v = ratboy.vertices_per_strand;
    let strands: Vec<&[Vec3]> = ratboy.positions.chunks_exact(v).step_by(stride).collect();
    let offsets = (0..=strands.len()).map(|c| (c * v) as u32).collect();
    let kinds = vec![ChainVolume::StrandGroup { thickness }; strands.len()];
    (offsets, kinds, strands.concat())
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn ratboy_mohawk_bvh_equals_brute_force() {
    let ratboy = load();
    let (offsets, kinds, mut nodes) = hair_of(&ratboy, SUBSET_STRIDE, THICKNESS);
    let mut hair = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let (mut fast, mut brute) = (SegmentContacts::new(), SegmentContacts::new());
    query_body(&hair, &ratboy.body, &mut fast);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
    // The roots lie on the scalp: many strands touch the body.
    assert!(
        fast.segment_count() >= 100,
        "{} colliding segments",
        fast.segment_count()
    );

    // Push the mohawk 1 cm down into the head and sideways, refit, compare with a fresh build.
    for p in &mut nodes {
        *p += Vec3::new(0.004, -0.01, 0.0);
    }
    hair.refit(&nodes, &[]).expect("same layout");
    let fresh = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let mut from_fresh = SegmentContacts::new();
    query_body(&hair, &ratboy.body, &mut fast);
    query_body(&fresh, &ratboy.body, &mut from_fresh);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
    assert_eq!(fast, from_fresh);

    // Nod the head 0.2 rad about the neck instead: seen from the head (the query's frame), the
    // hair turns the other way.
    let rotation = Quat::from_rotation_x(0.2);
    let pivot = Vec3::new(0.0, 0.3, 0.0);
    let translation = pivot - rotation * pivot;
    let seen: Vec<Vec3> = nodes
        .iter()
        .map(|&p| rotation.inverse() * (p - translation))
        .collect();
    let hair = HairBvh::build(&offsets, &kinds, &seen, &[]).expect("valid");
    query_body(&hair, &ratboy.body, &mut fast);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn ratboy_lone_strands_bvh_equals_brute_force() {
    let ratboy = load();
    let (offsets, kinds, nodes) = hair_of(&ratboy, SUBSET_STRIDE, 0.0);
    let hair = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let (mut fast, mut brute) = (SegmentContacts::new(), SegmentContacts::new());
    query_body(&hair, &ratboy.body, &mut fast);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
}
