//! The TressFX Ratboy mohawk (2,228 strands × 32 vertices) against its body mesh (25,814
//! triangles), read through `hair_formats` and collided through `hair_collide` (here, beside the
//! other cross-crate tests, so that hair-collide never depends on the file readers):
//!
//! - the mohawk's roots attached to its body: every root's attachment is at most as far as its
//!   nearest body vertex (the closest surface point can only be nearer), the roots lie on the
//!   body's surface (the data's README: median 6 mm from a vertex), and the attachment points ride
//!   the body when it moves;
//! - BVH query == brute force exactly; refit after moving == fresh build. The brute force runs on
//!   a subset of strands (every 32nd) to keep the test short; the BVH query on all of them is
//!   timed by the criterion bench `cargo bench --bench ratboy`.
//!
//! The data is AMD's TressFX samples (`hair_core::samples`: `HAIRLOD_DATA`, or `../shared/data`
//! beside the workspace; not part of this repository): the tests are ignored by default,
//! `.ci/run` runs them, and without the data they fail naming the file.

mod tressfx;

use glam::{Quat, Vec3};
use hair_collide::{
    ChainVolume, CollisionBody, HairBvh, SegmentContacts, attach_roots, query_body,
    query_body_brute_force,
};
use tressfx::{data_dir, read_tfx4, read_tfxmesh};

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_roots_attach_to_the_ratboy_body() {
    let dir = data_dir().unwrap_or_else(|error| panic!("{error}"));
    let mesh = read_tfxmesh(&dir.join("ratboy_body.tfxmesh")).unwrap();
    let (vertices_per_strand, positions) = read_tfx4(&dir.join("ratboy_mohawk.tfx")).unwrap();
    let roots: Vec<Vec3> = positions
        .iter()
        .step_by(vertices_per_strand)
        .copied()
        .collect();
    assert_eq!(roots.len(), 2228);
    let body = CollisionBody::from_mesh(&mesh).unwrap();
    let (attachments, report) = attach_roots(&body, &roots).unwrap();
    // Brute force: the distance from each root to its nearest vertex bounds its attachment's.
    let mut nearest_vertex: Vec<f32> = roots
        .iter()
        .map(|root| {
            mesh.positions
                .iter()
                .map(|v| v.distance(*root))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    for ((root, attachment), bound) in roots.iter().zip(&attachments).zip(&nearest_vertex) {
        let distance = attachment.point_on(&mesh).distance(*root);
        assert!(distance <= bound + 1e-6, "{root}: {distance} > {bound}");
        assert!((distance - attachment.signed_distance.abs()).abs() < 1e-5);
    }
    nearest_vertex.sort_by(f32::total_cmp);
    let vertex_median = nearest_vertex[nearest_vertex.len() / 2];
    eprintln!(
        "mohawk roots to the body: {report:?}; to the nearest vertex: median {vertex_median} m"
    );
    assert!(report.median <= vertex_median);
    // The roots were placed on the body's surface (measured: median 0.2 µm, largest 0.7 mm),
    // not merely near its vertices (median 5.9 mm): every one within a millimetre.
    assert!(report.median < 1e-4 && report.max < 1e-3, "{report:?}");

    // Move the body rigidly: the attachment points move with it.
    let (rotation, shift) = (Quat::from_rotation_x(0.4), Vec3::new(0.0, 0.1, -0.05));
    let mut moved = mesh.clone();
    for p in &mut moved.positions {
        *p = rotation * *p + shift;
    }
    for attachment in &attachments {
        let expected = rotation * attachment.point_on(&mesh) + shift;
        assert!(attachment.point_on(&moved).distance(expected) < 1e-5);
    }
}

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
