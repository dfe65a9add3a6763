//! What a run's simulation cost per level: nodes simulated, dynamics and collision time, and
//! their cost per node, from the frames' reports. `bench` prints it beside the paper tables and
//! writes it into their JSON, so that a claim "the cost follows the model" can be read off one
//! table: at a level whose nodes shrink fivefold, the time should shrink about as much.

use serde::Serialize;

use crate::run::ModeRun;

/// One level's (or the whole run's) simulation cost, means per frame over the run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LevelCost {
    /// Skeleton nodes simulated at the level, mean per frame.
    pub nodes: f64,
    /// Dynamics time (the integrator's step) [ms per frame].
    pub dynamics_ms: f64,
    /// Collision time (contacts, response, friction, positional guarantee) [ms per frame].
    pub collision_ms: f64,
    /// Dynamics and collision together per node simulated [ns]; 0 where no node was.
    pub ns_per_node: f64,
}

impl LevelCost {
    fn of(frames: usize, nodes: f64, dynamics: f64, collision: f64) -> LevelCost {
        let n = frames.max(1) as f64;
        let nodes = nodes / n;
        let (dynamics, collision) = (dynamics / n, collision / n);
        LevelCost {
            nodes,
            dynamics_ms: dynamics * 1e3,
            collision_ms: collision * 1e3,
            ns_per_node: if nodes > 0.0 {
                (dynamics + collision) / nodes * 1e9
            } else {
                0.0
            },
        }
    }

    /// Dynamics plus collision [ms per frame].
    pub fn total_ms(&self) -> f64 {
        self.dynamics_ms + self.collision_ms
    }
}

/// A run's simulation cost: per level (patches, clusters, strand groups, as [`Level`] indexes
/// them) and in all.
#[derive(Debug, Clone, Serialize)]
pub struct SimulationCosts {
    /// The run's mode (`LODs`, `Strands`, …).
    pub mode: String,
    /// Per level: patches, clusters, strand groups.
    pub levels: [LevelCost; 3],
    /// Every level together.
    pub all: LevelCost,
}

impl SimulationCosts {
    /// The costs of `run`, from its frames' per-level figures.
    pub fn of(run: &ModeRun) -> SimulationCosts {
        // Per level: summed nodes, dynamics [s] and collision [s] over the frames.
        let mut sums = [[0.0f64; 3]; 3];
        for frame in &run.frames {
            for (l, sum) in sums.iter_mut().enumerate() {
                sum[0] += frame.level_nodes[l] as f64;
                sum[1] += frame.level_dynamics[l];
                sum[2] += frame.level_collision[l];
            }
        }
        let frames = run.frames.len();
        let cost = |[nodes, dynamics, collision]: [f64; 3]| {
            LevelCost::of(frames, nodes, dynamics, collision)
        };
        let mut all = [0.0; 3];
        for sum in &sums {
            for (total, value) in all.iter_mut().zip(sum) {
                *total += value;
            }
        }
        SimulationCosts {
            mode: run.mode.to_string(),
            levels: sums.map(cost),
            all: cost(all),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{FrameReport, RunMode};
    use hair_core::Level;

    #[test]
    fn costs_are_means_per_frame_and_per_node() {
        // Two frames: strand groups 1,000 then 3,000 nodes at 2 + 1 ms and 4 + 1 ms, patches
        // 500 nodes at 1 ms of dynamics in the second frame only.
        let mut a = FrameReport::default();
        a.level_nodes[Level::StrandGroup as usize] = 1000;
        a.level_dynamics[Level::StrandGroup as usize] = 2e-3;
        a.level_collision[Level::StrandGroup as usize] = 1e-3;
        let mut b = FrameReport::default();
        b.level_nodes[Level::StrandGroup as usize] = 3000;
        b.level_dynamics[Level::StrandGroup as usize] = 4e-3;
        b.level_collision[Level::StrandGroup as usize] = 1e-3;
        b.level_nodes[Level::Patch as usize] = 500;
        b.level_dynamics[Level::Patch as usize] = 1e-3;
        let run = ModeRun::new(RunMode::Lods, vec![a, b]);
        let costs = SimulationCosts::of(&run);
        let strands = costs.levels[Level::StrandGroup as usize];
        // Means: 2,000 nodes, 3 ms dynamics, 1 ms collision; 4 ms / 2,000 nodes = 2,000 ns.
        assert!((strands.nodes - 2000.0).abs() < 1e-9);
        assert!((strands.dynamics_ms - 3.0).abs() < 1e-9);
        assert!((strands.collision_ms - 1.0).abs() < 1e-9);
        assert!((strands.ns_per_node - 2000.0).abs() < 1e-6);
        let patches = costs.levels[Level::Patch as usize];
        // 250 nodes and 0.5 ms per frame: 2,000 ns per node.
        assert!((patches.ns_per_node - 2000.0).abs() < 1e-6);
        assert_eq!(costs.levels[Level::Cluster as usize].ns_per_node, 0.0);
        // All: 2,250 nodes, 4.5 ms in all: 2,000 ns per node.
        assert!((costs.all.nodes - 2250.0).abs() < 1e-9);
        assert!((costs.all.total_ms() - 4.5).abs() < 1e-9);
        assert!((costs.all.ns_per_node - 2000.0).abs() < 1e-6);
    }
}
