//! Criterion benches of the skeleton dynamics: one 60 Hz step (the recommended substeps) of each
//! integrator on the paper-curly groom, with its 455 strand-group skeletons and with all 37,765
//! strands simulated as skeletons of their own. Throughput is in vertex-steps (nodes × substeps).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use hairlod::core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, STANDARD_GRAVITY,
    Simulation, SimulationSettings, WindField, level_skeletons, strand_skeletons,
};
use hairlod::{Level, Scene, SkeletonRest};
use std::hint::black_box;

/// A head shake of 3 rad/s in a 3 m/s gusting side wind, with gravity.
fn environment() -> Environment {
    Environment {
        head: HeadMotion::shake(0.5, 3.0),
        wind: WindField::gusting(Vec3::X * 3.0, 1.0, 0.8, 0.3, 1),
        gravity: STANDARD_GRAVITY,
    }
}

fn bench_model(c: &mut Criterion, name: &str, rest: &SkeletonRest, params: DynamicsParams) {
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    let environment = environment();
    for integrator in IntegratorKind::ALL {
        let model = DynamicsModel::new(rest.clone(), params).expect("model");
        let settings = SimulationSettings::recommended(integrator);
        let nodes = model.node_count() as u64;
        let mut simulation = Simulation::new(model, settings).expect("simulation");
        let mut state = simulation.rest_state(&environment, 0.0);
        // Start from moving hair, not from the rest shape.
        simulation
            .run(&mut state, &environment, 3)
            .expect("warm-up steps");
        group.throughput(Throughput::Elements(nodes * u64::from(settings.substeps)));
        group.bench_function(BenchmarkId::new("step", integrator.name()), |b| {
            b.iter(|| {
                simulation
                    .step(black_box(&mut state), &environment)
                    .expect("a stable step")
            })
        });
    }
    group.finish();
}

fn dynamics(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;
    let params = DynamicsParams::for_style(&groom.params.style);
    let groups = level_skeletons(groom, Level::StrandGroup).expect("strand groups");
    bench_model(c, "paper-curly 455 strand groups", &groups, params);
    let strands = strand_skeletons(groom).expect("strands");
    bench_model(c, "paper-curly 37765 strands", &strands, params);
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
