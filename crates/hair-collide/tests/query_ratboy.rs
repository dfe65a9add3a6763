//! Real data: the TressFX Ratboy mohawk (2,228 strands × 32 vertices) against its body mesh
//! (25,814 triangles). BVH query == brute force exactly; refit after moving == fresh build.
//!
//! The data lives in `../shared/data/tressfx` beside the workspace; the tests say so and pass
//! when it is absent (it is not part of this repository). The brute force runs on a subset of
//! strands (every 32nd) to keep the test short; the BVH query on all of them is timed by the
//! ignored `ratboy_query_timing` test:
//! `cargo test --release -p hair-collide --test query_ratboy -- --ignored --nocapture`.

mod support;

use std::time::Instant;

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

fn load() -> Option<Ratboy> {
    let Some(dir) = data_dir() else {
        eprintln!("skipped: ../shared/data/tressfx not found");
        return None;
    };
    let mesh = read_tfxmesh(&dir.join("ratboy_body.tfxmesh")).expect("readable mesh");
    assert_eq!(
        (mesh.positions.len(), mesh.triangles.len()),
        (12_909, 25_814)
    );
    let (vertices_per_strand, positions) =
        read_tfx4(&dir.join("ratboy_mohawk.tfx")).expect("readable groom");
    assert_eq!((vertices_per_strand, positions.len()), (32, 2_228 * 32));
    let body = CollisionBody::from_mesh(&mesh).expect("valid mesh");
    Some(Ratboy {
        body,
        vertices_per_strand,
        positions,
    })
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
fn ratboy_mohawk_bvh_equals_brute_force() {
    let Some(mut ratboy) = load() else { return };
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

    // Nod the head 0.2 rad about the neck instead.
    let rotation = Quat::from_rotation_x(0.2);
    let pivot = Vec3::new(0.0, 0.3, 0.0);
    ratboy
        .body
        .set_pose(rotation, pivot - rotation * pivot)
        .expect("finite");
    query_body(&hair, &ratboy.body, &mut fast);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
}

#[test]
fn ratboy_lone_strands_bvh_equals_brute_force() {
    let Some(ratboy) = load() else { return };
    let (offsets, kinds, nodes) = hair_of(&ratboy, SUBSET_STRIDE, 0.0);
    let hair = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let (mut fast, mut brute) = (SegmentContacts::new(), SegmentContacts::new());
    query_body(&hair, &ratboy.body, &mut fast);
    query_body_brute_force(&hair, &ratboy.body, &mut brute);
    assert_eq!(fast, brute);
}

/// Median of `runs` timings of `f` [ms].
fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[runs / 2]
}

#[test]
#[ignore = "timing report, run with --release --ignored --nocapture"]
fn ratboy_query_timing() {
    let Some(ratboy) = load() else { return };
    let (offsets, kinds, nodes) = hair_of(&ratboy, 1, THICKNESS);
    let mut hair = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let mut contacts = SegmentContacts::new();
    let build = median_ms(5, || {
        HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    });
    let refit = median_ms(11, || hair.refit(&nodes, &[]).expect("valid"));
    let query = median_ms(11, || query_body(&hair, &ratboy.body, &mut contacts));
    eprintln!(
        "full mohawk: {} segments x {} triangles; {} colliding segments, {} pairs",
        hair.segment_count(),
        ratboy.body.triangle_count(),
        contacts.segment_count(),
        contacts.pair_count()
    );
    eprintln!("build {build:.2} ms, refit {refit:.2} ms, BVH query {query:.2} ms");
    // Brute force on 1/16 of the strands (the full set would take 16x as long).
    let (offsets, kinds, nodes) = hair_of(&ratboy, 16, THICKNESS);
    let subset = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid");
    let brute = median_ms(3, || {
        query_body_brute_force(&subset, &ratboy.body, &mut contacts)
    });
    let fast = median_ms(11, || query_body(&subset, &ratboy.body, &mut contacts));
    eprintln!(
        "1/16 subset ({} segments): brute force {brute:.1} ms, BVH {fast:.3} ms, speedup {:.0}x",
        subset.segment_count(),
        brute / fast
    );
}
