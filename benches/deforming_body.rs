//! Criterion benches of a deforming body's collision work per step (issue 53): the talking
//! procedural head of `scenes/talking-head.toml` at 80 × 128 bands (20,224 triangles, the
//! `talk` animation: jaw and squash), with the straight groom's strand groups at rest on
//! it, read through its rest field (field contacts, the default broad phase).
//!
//! - `body update`: the next instant of the body from the last (`deformed_reusing`, in the memory
//!   of the one before: the triangles, the tree refitted, the rigid fit), the instants walking
//!   through the 2 s animation at 60 Hz;
//! - `contacts + projection`: one step's collision stage on an instant (the moving field's
//!   contacts, `before_step`, then the exact projection, `after_step`), from the rest state each
//!   time.
//!
//! `cargo bench --bench deforming_body`. The frame loop's figures (`examples/deforming_body_cost`)
//! add the dynamics and the threads' waits; these are the stage's own.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use glam::Vec3;
use hairlod::SceneFile;
use hairlod::collide::{
    BroadPhase, CollisionBody, CollisionSettings, CollisionSolver, RestField, groom_level_chains,
};
use hairlod::core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, IntegratorKind, Simulation, SimulationSettings,
};
use hairlod::core::{MeshSequence, Scene};
use hairlod::{Level, Shot};
use std::hint::black_box;

/// Frames of the walk through the animation: 2 s at 60 Hz.
const FRAMES: usize = 120;
/// The step [s].
const STEP: f32 = 1.0 / 60.0;

/// The talking head at 20k triangles and its groom.
fn talking_head() -> Scene {
    let text =
        "[groom]\npreset = \"straight\"\n[body]\nanimation = \"talk\"\n[frames]\ncount = 120\n";
    let mut shot: Shot = SceneFile::parse(text)
        .and_then(|file| file.resolve())
        .expect("the talking head's scene");
    shot.head.latitude_bands = 80;
    shot.head.longitude_bands = 128;
    shot.build_scene().expect("the talking head")
}

/// The mesh at `time` [s] and its vertices' velocities over the step before it.
fn instant(sequence: &MeshSequence, time: f64) -> (Vec<Vec3>, Vec<Vec3>) {
    let (mut now, mut before) = (Vec::new(), Vec::new());
    sequence.positions_at(time, &mut now);
    sequence.positions_at(time - f64::from(STEP), &mut before);
    let velocities = now
        .iter()
        .zip(&before)
        .map(|(a, b)| (*a - *b) / STEP)
        .collect();
    (now, velocities)
}

fn deforming_body(c: &mut Criterion) {
    let scene = talking_head();
    let sequence = scene.body_motion.clone().expect("a deforming head");
    let still = vec![Vec3::ZERO; scene.head.mesh.positions.len()];
    let rest = CollisionBody::from_moving_mesh(&scene.head.mesh, still).expect("the rest body");
    let field = RestField::of(&rest);
    let first = rest.reading_rest_field(&field).expect("reads its field");
    let instants: Vec<(Vec<Vec3>, Vec<Vec3>)> = (0..FRAMES)
        .map(|k| instant(&sequence, k as f64 * f64::from(STEP)))
        .collect();
    let mut group = c.benchmark_group("deforming head, 20k triangles");
    group.sample_size(60);

    // The instants one after the other, each in the memory of the one before the last.
    let (mut last, mut spare) = (first.clone(), None);
    let mut frame = 0;
    group.bench_function("body update", |b| {
        b.iter(|| {
            frame = (frame + 1) % FRAMES;
            let (positions, velocities) = &instants[frame];
            let next = last
                .deformed_reusing(positions, velocities.clone(), spare.take())
                .expect("the next instant");
            spare = Some(std::mem::replace(&mut last, next));
            black_box(&last);
        })
    });

    // One step's collision on the instant half a second in.
    let groom = &scene.groom;
    let model = DynamicsModel::new(
        groom.skeletons.clone(),
        DynamicsParams::for_style(&groom.params.style),
    )
    .expect("the groom's dynamics");
    let simulation = Simulation::new(
        model,
        SimulationSettings::recommended(IntegratorKind::PositionBased),
    )
    .expect("the simulation");
    let environment = Environment::default();
    let state = simulation.rest_state(&environment, 0.0);
    let mut solver = CollisionSolver::new(CollisionSettings {
        broad_phase: BroadPhase::FieldContacts,
        ..CollisionSettings::default()
    })
    .expect("the solver");
    solver
        .set_chains(&simulation, &groom_level_chains(groom, Level::StrandGroup))
        .expect("the strands' chains");
    let (positions, velocities) = &instants[30];
    let mut bodies = vec![
        first
            .deformed(positions, velocities.clone())
            .expect("an instant"),
    ];
    group.bench_function("contacts + projection", |b| {
        b.iter_batched(
            || state.clone(),
            |mut state| {
                let contacts = solver
                    .before_step(&mut bodies, &simulation, &mut state, &environment)
                    .expect("contacts");
                let projection = solver
                    .after_step(&mut bodies, &simulation, &mut state, &environment)
                    .expect("projection");
                black_box((contacts, projection))
            },
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, deforming_body);
criterion_main!(benches);
