//! Criterion benches of the model: building the paper-curly groom, and evaluating every strand's
//! NURBS points once (37,765 strands).

use criterion::{Criterion, criterion_group, criterion_main};
use hairlod::core::representation::geometry::{evaluate_strands, strand_sampler};
use hairlod::{Frame, Groom, GroomParams, Head, HeadParams, Level, RigidTransform, Scene};
use std::hint::black_box;

fn build_groom(c: &mut Criterion) {
    let head = Head::procedural(&HeadParams::default()).expect("default head");
    let params = GroomParams::paper_curly();
    c.bench_function("build paper-curly groom", |b| {
        b.iter(|| Groom::generate(black_box(&params), &head).expect("groom"))
    });
}

fn evaluate_all_strands(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;
    let head = RigidTransform::IDENTITY;
    let positions = groom.skeletons.rest_positions(&head);
    let mut frames = vec![Frame::default(); positions.len()];
    let nodes = groom
        .skeletons
        .chain_node_count(groom.level_chains(Level::StrandGroup).start);
    let samples_per_segment = 4;
    let sampler = strand_sampler(nodes, samples_per_segment).expect("sampler");
    let mut points = vec![glam::Vec3::ZERO; groom.strands.strand_count() * sampler.sample_count()];
    let mut group = c.benchmark_group("paper-curly strands");
    group.sample_size(30);
    group.bench_function("node frames + evaluate all strand NURBS points", |b| {
        b.iter(|| {
            groom
                .skeletons
                .node_frames_into(&head, &positions, &mut frames);
            evaluate_strands(groom, &positions, &frames, &sampler, &mut points).expect("strands");
            black_box(&points);
        })
    });
    group.bench_function("evaluate all strand NURBS points", |b| {
        b.iter(|| {
            evaluate_strands(groom, &positions, &frames, &sampler, &mut points).expect("strands");
            black_box(&points);
        })
    });
    group.finish();
}

criterion_group!(benches, build_groom, evaluate_all_strands);
criterion_main!(benches);
