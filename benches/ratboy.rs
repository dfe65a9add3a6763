//! Collision benchmarks on real data: the TressFX Ratboy mohawk (2,228 strands × 32 vertices,
//! as strand groups 2 mm thick) against its body mesh (25,814 triangles), at rest:
//!
//! - `ratboy/mohawk/build`, `…/refit`, `…/bvh_query`: building the hair hierarchy of the whole
//!   mohawk, refitting it, and querying it against the body's hierarchy ([`query_body`]);
//! - `ratboy/subset/brute_force`, `…/bvh_query`: every 16th strand against every triangle
//!   ([`query_body_brute_force`]) and through the hierarchies, for the speedup (the full brute
//!   force costs about 16× the subset's: it is linear in the segment count).
//!
//! The data is AMD's TressFX samples (`hair_core::samples`: `HAIRLOD_DATA`, or `../shared/data`
//! beside the workspace). Without it the bench measures nothing and says which file it looked
//! for. `cargo bench --bench ratboy`

#[path = "../tests/tressfx/mod.rs"]
mod tressfx;

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use hair_collide::{
    ChainVolume, CollisionBody, HairBvh, SegmentContacts, query_body, query_body_brute_force,
};
use tressfx::{data_dir, read_tfx4, read_tfxmesh};

/// Strand group radius for the mohawk chains [m] (a thin wisp around each strand).
const THICKNESS: f32 = 0.002;

/// The brute force runs on every `SUBSET_STRIDE`-th strand (140 strands, 4,340 segments).
const SUBSET_STRIDE: usize = 16;

/// The chain layout and nodes of every `stride`-th strand: `(offsets, kinds, nodes [m])`.
fn chains_of(
    vertices_per_strand: usize,
    positions: &[Vec3],
    stride: usize,
) -> (Vec<u32>, Vec<ChainVolume>, Vec<Vec3>) {
    let strands: Vec<&[Vec3]> = positions
        .chunks_exact(vertices_per_strand)
        .step_by(stride)
        .collect();
    let offsets = (0..=strands.len())
        .map(|c| (c * vertices_per_strand) as u32)
        .collect();
    let kinds = vec![
        ChainVolume::StrandGroup {
            thickness: THICKNESS
        };
        strands.len()
    ];
    (offsets, kinds, strands.concat())
}

fn ratboy(c: &mut Criterion) {
    let dir = match data_dir() {
        Ok(dir) => dir,
        Err(error) => {
            eprintln!("ratboy benches skipped: {error}");
            return;
        }
    };
    let mesh = read_tfxmesh(&dir.join("ratboy_body.tfxmesh")).expect("readable mesh");
    let (vertices_per_strand, positions) =
        read_tfx4(&dir.join("ratboy_mohawk.tfx")).expect("readable groom");
    let body = CollisionBody::from_mesh(&mesh).expect("valid mesh");
    let mut contacts = SegmentContacts::new();

    let mut group = c.benchmark_group("ratboy/mohawk");
    let (offsets, kinds, nodes) = chains_of(vertices_per_strand, &positions, 1);
    let mut hair = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid hair");
    group.throughput(Throughput::Elements(hair.segment_count() as u64));
    group.bench_function("build", |b| {
        b.iter(|| HairBvh::build(&offsets, &kinds, black_box(&nodes), &[]).expect("valid hair"))
    });
    group.bench_function("refit", |b| {
        b.iter(|| hair.refit(black_box(&nodes), &[]).expect("same layout"))
    });
    group.bench_function("bvh_query", |b| {
        b.iter(|| query_body(black_box(&hair), &body, &mut contacts))
    });
    group.finish();
    query_body(&hair, &body, &mut contacts);
    eprintln!(
        "full mohawk: {} segments x {} triangles; {} colliding segments, {} pairs",
        hair.segment_count(),
        body.triangle_count(),
        contacts.segment_count(),
        contacts.pair_count()
    );

    let mut group = c.benchmark_group("ratboy/subset");
    group.sample_size(10);
    let (offsets, kinds, nodes) = chains_of(vertices_per_strand, &positions, SUBSET_STRIDE);
    let subset = HairBvh::build(&offsets, &kinds, &nodes, &[]).expect("valid hair");
    group.throughput(Throughput::Elements(subset.segment_count() as u64));
    group.bench_function("brute_force", |b| {
        b.iter(|| query_body_brute_force(black_box(&subset), &body, &mut contacts))
    });
    group.bench_function("bvh_query", |b| {
        b.iter(|| query_body(black_box(&subset), &body, &mut contacts))
    });
    group.finish();
}

criterion_group!(benches, ratboy);
criterion_main!(benches);
