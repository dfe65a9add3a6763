//! Criterion benches of the skeleton dynamics: one 60 Hz step (the recommended substeps) of each
//! integrator on the paper-curly groom, with its 455 strand-group skeletons and with all 37,765
//! strands simulated as skeletons of their own. Throughput is in vertex-steps (nodes × substeps).
//!
//! Each step is measured twice: in wall time, and in the CPU time of all the process's threads
//! (the sum over `/proc/self/task/*/schedstat`; groups named `cpu-time …`), the measure least
//! disturbed by other work on a shared machine. The CPU-time groups are Linux only: elsewhere the
//! bench says so and skips them.
//!
//! A third group, `32 nodes one substep`, is the XPBD issue's measure: one substep (1/480 s) of
//! all paper-curly strands with skeletons of 32 nodes (the groom rebuilt with a finer smoothness
//! setting), bending and lengths, for XPBD and the other integrators.
//!
//! `cargo bench --bench dynamics` (add `-- position-based` for one integrator).

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use hairlod::core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, STANDARD_GRAVITY,
    Simulation, SimulationSettings, WindField, level_skeletons, strand_skeletons,
};
use hairlod::{GroomParams, HairStyle, HeadParams, Level, Scene, SkeletonRest};
use std::hint::black_box;

/// CPU time [ns] of all threads of this process so far (Linux `schedstat`), if readable.
fn process_cpu_nanoseconds() -> Option<u64> {
    let mut nanoseconds = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let stat = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        nanoseconds += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(nanoseconds)
}

/// Criterion measurement: CPU time of all the process's threads [ns].
struct ProcessCpuTime;

impl Measurement for ProcessCpuTime {
    type Intermediate = u64;
    type Value = u64;

    fn start(&self) -> u64 {
        process_cpu_nanoseconds().expect("/proc/self/task/*/schedstat is readable")
    }

    fn end(&self, start: u64) -> u64 {
        self.start().saturating_sub(start)
    }

    fn add(&self, v1: &u64, v2: &u64) -> u64 {
        v1 + v2
    }

    fn zero(&self) -> u64 {
        0
    }

    fn to_f64(&self, value: &u64) -> f64 {
        *value as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuTimeFormatter
    }
}

/// Formats CPU nanoseconds as CPU time, and throughputs as elements per CPU-second.
struct CpuTimeFormatter;

impl ValueFormatter for CpuTimeFormatter {
    fn scale_values(&self, typical_nanoseconds: f64, values: &mut [f64]) -> &'static str {
        let (factor, unit) = if typical_nanoseconds < 1e3 {
            (1.0, "ns CPU")
        } else if typical_nanoseconds < 1e6 {
            (1e-3, "µs CPU")
        } else if typical_nanoseconds < 1e9 {
            (1e-6, "ms CPU")
        } else {
            (1e-9, "s CPU")
        };
        for value in values {
            *value *= factor;
        }
        unit
    }

    fn scale_throughputs(
        &self,
        _typical_nanoseconds: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let elements = match *throughput {
            Throughput::Elements(elements) | Throughput::ElementsAndBytes { elements, .. } => {
                elements
            }
            Throughput::Bytes(bytes) | Throughput::BytesDecimal(bytes) => bytes,
            Throughput::Bits(bits) => bits,
        };
        // Millions per CPU-second: the dynamics' steps run at tens to hundreds of millions.
        for value in values {
            *value = elements as f64 * 1e9 / *value / 1e6;
        }
        "M/CPU-s"
    }

    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

/// A head shake of 3 rad/s in a 3 m/s gusting side wind, with gravity.
fn environment() -> Environment {
    Environment {
        head: HeadMotion::shake(0.5, 3.0),
        wind: WindField::gusting(Vec3::X * 3.0, 1.0, 0.8, 0.3, 1),
        gravity: STANDARD_GRAVITY,
    }
}

/// Benches one `Simulation::step` of every integrator, with `settings` per integrator, on `rest`.
///
/// Every iteration steps from the same state (the rest shape after three warm-up steps, so the
/// hair is moving), so the measure is one step's cost whatever the iteration count. A setting
/// that cannot make the warm-up or that step (an integrator unstable there) is reported and left
/// out rather than benched: the step is deterministic, so the trial step shows whether every
/// iteration will succeed.
fn bench_model<M: Measurement>(
    c: &mut Criterion<M>,
    name: &str,
    rest: &SkeletonRest,
    params: DynamicsParams,
    settings: impl Fn(IntegratorKind) -> SimulationSettings,
) {
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    let environment = environment();
    for integrator in IntegratorKind::ALL {
        let model = DynamicsModel::new(rest.clone(), params).expect("model");
        let settings = settings(integrator);
        let nodes = model.node_count() as u64;
        let mut simulation = Simulation::new(model, settings).expect("simulation");
        let mut warm = simulation.rest_state(&environment, 0.0);
        // Start from moving hair, not from the rest shape.
        let trial = simulation
            .run(&mut warm, &environment, 3)
            .and_then(|_| simulation.step(&mut warm.clone(), &environment));
        if let Err(error) = trial {
            eprintln!("{name}/step/{}: left out, {error}", integrator.name());
            continue;
        }
        group.throughput(Throughput::Elements(nodes * u64::from(settings.substeps)));
        group.bench_function(BenchmarkId::new("step", integrator.name()), |b| {
            b.iter_batched_ref(
                || warm.clone(),
                |state| {
                    simulation
                        .step(black_box(state), &environment)
                        .expect("the same step as the trial's, which succeeded")
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn dynamics(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;
    let params = DynamicsParams::for_style(&groom.params.style);
    let groups = level_skeletons(groom, Level::StrandGroup).expect("strand groups");
    bench_model(
        c,
        "paper-curly 455 strand groups",
        &groups,
        params,
        SimulationSettings::recommended,
    );
    let strands = strand_skeletons(groom).expect("strands");
    bench_model(
        c,
        "paper-curly 37765 strands",
        &strands,
        params,
        SimulationSettings::recommended,
    );
}

/// Nodes per skeleton in the `32 nodes one substep` group.
const NODES_PER_SKELETON: usize = 32;

/// The paper-curly groom with skeletons of [`NODES_PER_SKELETON`] nodes: the smoothness setting
/// (the longest segment) searched by bisection until the curly chains have that many nodes.
fn paper_curly_with_32_nodes() -> Scene {
    let base = GroomParams::paper_curly();
    let (mut low, mut high) = (1e-3f32, base.style.smoothness);
    for _ in 0..40 {
        let smoothness = 0.5 * (low + high);
        let mut params = base.clone();
        params.style = HairStyle {
            smoothness,
            ..base.style
        };
        let scene = Scene::new(&HeadParams::default(), &params).expect("paper-curly groom");
        let skeletons = level_skeletons(&scene.groom, Level::StrandGroup).expect("skeletons");
        let nodes = skeletons.nodes(0).len();
        if nodes == NODES_PER_SKELETON {
            return scene;
        }
        // Finer smoothness, more nodes.
        if nodes < NODES_PER_SKELETON {
            high = smoothness;
        } else {
            low = smoothness;
        }
    }
    panic!("no smoothness gives {NODES_PER_SKELETON} nodes per skeleton");
}

/// One substep of 1/480 s on all paper-curly strands at 32 nodes, for every integrator.
fn one_substep_32_nodes(c: &mut Criterion) {
    let scene = paper_curly_with_32_nodes();
    let groom = &scene.groom;
    let params = DynamicsParams::for_style(&groom.params.style);
    let strands = strand_skeletons(groom).expect("strands");
    bench_model(
        c,
        "paper-curly 37765 strands 32 nodes one substep",
        &strands,
        params,
        |integrator| SimulationSettings::new(integrator, 1.0 / 480.0, 1),
    );
}

fn dynamics_cpu_time(c: &mut Criterion<ProcessCpuTime>) {
    if process_cpu_nanoseconds().is_none() {
        eprintln!("/proc/self/task/*/schedstat is not readable (Linux only); no CPU time measured");
        return;
    }
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;
    let params = DynamicsParams::for_style(&groom.params.style);
    let groups = level_skeletons(groom, Level::StrandGroup).expect("strand groups");
    bench_model(
        c,
        "cpu-time paper-curly 455 strand groups",
        &groups,
        params,
        SimulationSettings::recommended,
    );
    let strands = strand_skeletons(groom).expect("strands");
    bench_model(
        c,
        "cpu-time paper-curly 37765 strands",
        &strands,
        params,
        SimulationSettings::recommended,
    );
}

criterion_group!(benches, dynamics, one_substep_32_nodes);
criterion_group! {
    name = cpu_time;
    config = Criterion::default().with_measurement(ProcessCpuTime);
    targets = dynamics_cpu_time
}
criterion_main!(benches, cpu_time);
