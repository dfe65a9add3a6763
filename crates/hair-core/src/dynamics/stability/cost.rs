//! The stability sweep's cost measurement: every integrator's wall time per node and substep on
//! many copies of the curly test chain, on one thread.

use crate::dynamics::error::DynamicsError;
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::params::SimulationSettings;
use crate::dynamics::simulation::Simulation;
use crate::dynamics::stability::report::StepCost;
use crate::dynamics::stability::{Scenario, SweepConfig, TestChain};
use crate::skeleton::SkeletonRest;

/// Chains in the cost measurement.
const COST_CHAINS: usize = 256;

/// Measures every integrator's cost at every substep count of the study: 256 copies of the curly
/// test chain in a 3 rad/s head shake and a 3 m/s wind, 0.1 s of 60 Hz frames after a 0.05 s
/// warm-up, on one thread, the best of three runs (wall time, so a busy machine reads slower).
pub(super) fn measure_costs(config: &SweepConfig) -> Result<Vec<StepCost>, DynamicsError> {
    let chain = TestChain::Curly;
    let single = chain.rest();
    let mut rest = SkeletonRest::default();
    for _ in 0..COST_CHAINS {
        rest.push_chain_from(&single, 0)?;
    }
    let scenario = Scenario {
        label: String::new(),
        stiffness_per_mass: None,
        wind_speed: 3.0,
        shake_speed: 3.0,
    };
    let environment = scenario.environment();
    let model = DynamicsModel::new(rest, scenario.params(&chain.style()))?;
    let nodes = model.node_count();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|_| DynamicsError::invalid("thread pool", 1, "a pool of one thread"))?;
    let frames = (0.1 / config.frame_step).round().max(1.0) as usize;
    let warm_up = (0.05 / config.frame_step).round().max(1.0) as usize;
    let mut costs = Vec::new();
    for &integrator in &config.integrators {
        for &substeps in &config.frame_substeps {
            let settings = SimulationSettings::new(integrator, config.frame_step, substeps);
            let mut simulation = Simulation::new(model.clone(), settings)?;
            let seconds = pool.install(|| -> Result<f64, DynamicsError> {
                let mut best = f64::INFINITY;
                for _ in 0..3 {
                    let mut state = simulation.rest_state(&environment, 0.0);
                    simulation.run(&mut state, &environment, warm_up)?;
                    let started = std::time::Instant::now();
                    simulation.run(&mut state, &environment, frames)?;
                    best = best.min(started.elapsed().as_secs_f64());
                }
                Ok(best)
            });
            // An integrator that fails in this mild scene has no cost to report.
            let Ok(seconds) = seconds else { continue };
            let node_substeps = (nodes * frames * substeps as usize) as f64;
            let per_node_substep = seconds / node_substeps;
            let substeps_per_second = substeps as f64 / config.frame_step as f64;
            costs.push(StepCost {
                integrator,
                substeps,
                nanoseconds_per_node_substep: (per_node_substep * 1e9) as f32,
                microseconds_per_node_second: (per_node_substep * substeps_per_second * 1e6) as f32,
            });
        }
    }
    Ok(costs)
}
