//! Collision benchmarks on the paper's groom (paper-curly: 91 sections, 37,765 strands) on the
//! procedural head (12,096 triangles), at rest, per level:
//!
//! - `query/<level>/bvh`: hair hierarchy against head hierarchy ([`query_body`]);
//! - `query/<level>/distance_field`: each segment volume culled by the head's distance field,
//!   the rest against the head hierarchy ([`query_body_near`]; the same contacts);
//! - `query/<level>/brute_force_subset`: every segment of every 8th chain against every triangle
//!   ([`query_body_brute_force`]); the full brute force costs about 8× this (it is linear in the
//!   segment count), which the note in `docs/collision.md` uses for the speedup;
//! - `hair_hair/<level>`: the hair–hair repulsion query and forces ([`add_repulsion_forces`]);
//! - `solver/<level>/<broad phase>`: one collision stage around a step (`before_step` +
//!   `after_step`: volumes (and, for the hierarchies, refit), query, response, friction,
//!   projection), the dynamics excluded, with each [`BroadPhase`];
//! - `distance_field/build`: the head's field at the default 2 mm cells ([`DistanceField::of`]),
//!   built once per mesh.
//!
//! `cargo bench -p hair-collide --bench collide`

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use hair_collide::{
    BroadPhase, CollisionBody, CollisionChain, CollisionSettings, CollisionSolver, DistanceField,
    HairHairSettings, SegmentContacts, add_repulsion_forces, distance_field, groom_level_chains,
    query_body, query_body_brute_force, query_body_near,
};
use hair_core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, IntegratorKind, Simulation, SimulationSettings,
    SimulationState,
};
use hair_core::{Level, Scene};

/// Brute force runs on every `SUBSET`-th chain.
const SUBSET: usize = 8;

struct Fixture {
    simulation: Simulation,
    state: SimulationState,
    environment: Environment,
    head: CollisionBody,
}

fn solver_for(
    fixture: &mut Fixture,
    chains: &[CollisionChain],
    broad_phase: BroadPhase,
) -> CollisionSolver {
    let mut solver = CollisionSolver::new(CollisionSettings {
        broad_phase,
        ..CollisionSettings::default()
    })
    .unwrap();
    solver.set_chains(&fixture.simulation, chains).unwrap();
    solver
        .before_step(
            std::slice::from_mut(&mut fixture.head),
            &fixture.simulation,
            &mut fixture.state,
            &fixture.environment,
        )
        .unwrap();
    solver
}

fn benches(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").unwrap();
    let groom = &scene.groom;
    let model = DynamicsModel::new(
        groom.skeletons.clone(),
        DynamicsParams::for_style(&groom.params.style),
    )
    .unwrap();
    let simulation = Simulation::new(
        model,
        SimulationSettings::recommended(IntegratorKind::PositionBased),
    )
    .unwrap();
    let environment = Environment::default();
    let state = simulation.rest_state(&environment, 0.0);
    let mut fixture = Fixture {
        simulation,
        state,
        environment,
        head: CollisionBody::from_mesh(&scene.head.mesh).unwrap(),
    };
    let mut group = c.benchmark_group("collide");
    group.sample_size(10);
    group.bench_function("distance_field/build", |b| {
        b.iter(|| DistanceField::of(&fixture.head, distance_field::DEFAULT_CELL))
    });
    for level in Level::ALL {
        let chains = groom_level_chains(groom, level);
        let subset: Vec<CollisionChain> = chains.iter().copied().step_by(SUBSET).collect();
        let full = solver_for(&mut fixture, &chains, BroadPhase::Hierarchies);
        let part = solver_for(&mut fixture, &subset, BroadPhase::Hierarchies);
        let mut contacts = SegmentContacts::new();
        let name = level.name();
        group.bench_function(format!("query/{name}/bvh"), |b| {
            b.iter(|| query_body(full.hierarchy().unwrap(), &fixture.head, &mut contacts))
        });
        group.bench_function(format!("query/{name}/distance_field"), |b| {
            let volumes = full.hierarchy().unwrap().volumes();
            b.iter(|| query_body_near(volumes, &fixture.head, &mut contacts))
        });
        group.bench_function(format!("query/{name}/volumes"), |b| {
            let volumes = full.hierarchy().unwrap().volumes();
            b.iter(|| hair_collide::query_body_volumes(volumes, &fixture.head, &mut contacts))
        });
        group.bench_function(format!("query/{name}/bvh_subset"), |b| {
            b.iter(|| query_body(part.hierarchy().unwrap(), &fixture.head, &mut contacts))
        });
        group.bench_function(format!("query/{name}/brute_force_subset"), |b| {
            b.iter(|| {
                query_body_brute_force(part.hierarchy().unwrap(), &fixture.head, &mut contacts)
            })
        });
        let hair = full.hierarchy().unwrap();
        let sections: Vec<u32> = chains.iter().map(|c| c.section).collect();
        let node_count = *hair.chain_offsets().last().unwrap() as usize;
        let masses = vec![1.0e-5; node_count];
        let mut forces = vec![Vec3::ZERO; node_count];
        let settings = HairHairSettings::default();
        group.bench_function(format!("hair_hair/{name}"), |b| {
            b.iter(|| {
                forces.fill(Vec3::ZERO);
                add_repulsion_forces(hair, &sections, &masses, &settings, &mut forces).unwrap()
            })
        });
        for broad_phase in BroadPhase::ALL {
            let mut solver = solver_for(&mut fixture, &chains, broad_phase);
            let phase = broad_phase.name();
            group.bench_function(format!("solver/{name}/{phase}"), |b| {
                b.iter(|| {
                    let f = &mut fixture;
                    solver
                        .before_step(
                            std::slice::from_mut(&mut f.head),
                            &f.simulation,
                            &mut f.state,
                            &f.environment,
                        )
                        .unwrap();
                    solver
                        .after_step(
                            std::slice::from_mut(&mut f.head),
                            &f.simulation,
                            &mut f.state,
                            &f.environment,
                        )
                        .unwrap()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(collide, benches);
criterion_main!(collide);
