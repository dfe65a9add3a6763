//! The pipeline's working memory for one level: the integrator and its scratch, the collision
//! stage and the collision bodies it poses. Rebuilt from the model and the level's block whenever
//! the block's sections change; nothing of it is state (a checkpoint holds none of it).

use hair_collide::{
    BroadPhase, CollisionBody, CollisionChain, CollisionSettings, CollisionSolver, groom_chain,
};
use hair_core::dynamics::{DynamicsModel, DynamicsParams, Simulation};
use hair_core::{Groom, Level, PerLevel, SkeletonRest};

use super::block::LevelBlock;
use super::body_motion::BodyRide;
use super::error::Result;
use super::settings::PipelineSettings;

/// The working memory of every level, and the collision chains' scratch.
pub(crate) struct Workspace {
    pub(crate) levels: PerLevel<LevelWork>,
    chains: Vec<CollisionChain>,
}

impl Workspace {
    /// Every level's working memory ([`LevelWork::new`]).
    pub(crate) fn new(
        body: Option<&CollisionBody>,
        broad_phase: BroadPhase,
        ride: Option<&BodyRide>,
    ) -> Result<Workspace> {
        let level = || -> Result<LevelWork> {
            let mut work = LevelWork::new(body, broad_phase)?;
            work.ride = ride.cloned();
            Ok(work)
        };
        Ok(Workspace {
            levels: PerLevel {
                patch: level()?,
                cluster: level()?,
                strand_group: level()?,
            },
            chains: Vec::new(),
        })
    }

    /// Points every level's collision stage at its block's chains.
    pub(crate) fn refresh_collision_chains(
        &mut self,
        groom: &Groom,
        blocks: &PerLevel<LevelBlock>,
    ) -> Result<()> {
        for level in Level::ALL {
            self.levels[level].refresh_collision_chains(groom, &blocks[level], &mut self.chains)?;
        }
        Ok(())
    }
}

/// The solvers of one level's block: the integrator and its scratch (`None` while no section is
/// at the level), the collision stage (`None` with collision off) and its own copy of the
/// collision bodies (copies share the mesh and tree and differ only in pose, so the levels'
/// blocks step side by side).
pub(crate) struct LevelWork {
    pub(crate) simulation: Option<Simulation>,
    pub(crate) solver: Option<CollisionSolver>,
    pub(crate) bodies: Vec<CollisionBody>,
    /// Where the groom rides a deforming head: the simulation's roots are carried by it.
    pub(crate) ride: Option<BodyRide>,
}

impl LevelWork {
    /// Working memory with no integrator yet, a collision stage when `body` is given (collision
    /// on) posing its own copy of it and finding the hair near it by `broad_phase`.
    pub(crate) fn new(body: Option<&CollisionBody>, broad_phase: BroadPhase) -> Result<LevelWork> {
        Ok(LevelWork {
            simulation: None,
            solver: body
                .map(|_| {
                    CollisionSolver::new(CollisionSettings {
                        broad_phase,
                        ..CollisionSettings::default()
                    })
                })
                .transpose()?,
            bodies: body.into_iter().cloned().collect(),
            ride: None,
        })
    }

    /// Builds the integrator for the chains of `block` (none when it is empty).
    pub(crate) fn rebuild_simulation(
        &mut self,
        groom: &Groom,
        block: &LevelBlock,
        params: DynamicsParams,
        settings: &PipelineSettings,
    ) -> Result<()> {
        self.simulation = if block.sections.is_empty() {
            None
        } else {
            let mut rest = SkeletonRest::default();
            for &chain in &block.chains {
                rest.push_chain_from(&groom.skeletons, chain)?;
            }
            let mut simulation =
                Simulation::new(DynamicsModel::new(rest, params)?, settings.dynamics)?;
            if let Some(ride) = &self.ride {
                simulation.set_root_carrier(Some(ride.carrier(&block.chains)))?;
            }
            Some(simulation)
        };
        Ok(())
    }

    /// Points the collision stage at the block's chains (rebuilding its hierarchies), with
    /// `chains` as scratch; nothing with collision off or an empty block.
    pub(crate) fn refresh_collision_chains(
        &mut self,
        groom: &Groom,
        block: &LevelBlock,
        chains: &mut Vec<CollisionChain>,
    ) -> Result<()> {
        let (Some(solver), Some(simulation)) = (self.solver.as_mut(), self.simulation.as_ref())
        else {
            return Ok(());
        };
        chains.clear();
        for (model_chain, &chain) in block.chains.iter().enumerate() {
            if let Some(mut collision) = groom_chain(groom, chain) {
                collision.chain = model_chain as u32;
                chains.push(collision);
            }
        }
        solver.set_chains(simulation, chains)?;
        Ok(())
    }
}
