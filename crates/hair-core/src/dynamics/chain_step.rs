//! One chain's step with the one-chain integrators (semi-implicit Euler, linear-implicit),
//! halving on failure, and the check every chain's new state passes (finite, no energy blow-up).

use glam::Vec3;

use crate::dynamics::environment::Environment;
use crate::dynamics::error::{ChainFailure, FailedQuantity};
use crate::dynamics::head_motion::angular_velocity;
use crate::dynamics::integrators::{
    ChainArrays, ChainConstants, Substep, linear_implicit, semi_implicit_euler,
};
use crate::dynamics::params::{FailurePolicy, IntegratorKind, SimulationSettings};
use crate::dynamics::root_motion::RootPoses;

/// Steps one chain through all its substeps with the semi-implicit Euler or linear-implicit
/// integrator, halving on failure where allowed; returns the failure that remains (the chain
/// restored to its start) and the halvings used beyond the adaptive substeps' `doublings`, which
/// the step starts from.
#[allow(clippy::too_many_arguments)]
pub(crate) fn step_chain(
    chain: usize,
    constants: &ChainConstants,
    mut arrays: ChainArrays,
    backup_positions: &mut [Vec3],
    backup_velocities: &mut [Vec3],
    settings: &SimulationSettings,
    params: &crate::dynamics::params::DynamicsParams,
    environment: &Environment,
    roots: &RootPoses,
    time: f64,
    doublings: u32,
) -> (Option<ChainFailure>, u32) {
    backup_positions.copy_from_slice(arrays.positions);
    backup_velocities.copy_from_slice(arrays.velocities);
    // The wind at the nodes, sampled once per step at its start.
    for (wind, position) in arrays.wind.iter_mut().zip(&*arrays.positions) {
        *wind = environment.wind.velocity_at(*position, time);
    }
    let max_halvings = match settings.on_failure {
        FailurePolicy::Error => 0,
        FailurePolicy::HalveSubstep { max_halvings } => max_halvings,
    };
    // The adaptive substeps' doublings come first; the failure policy's halvings follow them.
    let mut halvings = doublings;
    loop {
        let substeps = (settings.substeps as usize) << halvings;
        let h = settings.time_step / substeps as f32;
        let mut solved = true;
        for k in 0..substeps {
            let pose = |index: usize| roots.pose(chain, halvings, index).0;
            let head_start = pose(k);
            let head_end = pose(k + 1);
            let step = Substep {
                h,
                head_start,
                head_end,
                head_spin: angular_velocity(head_start.rotation, head_end.rotation, h),
                gravity: environment.gravity,
                params,
                roots: settings.roots,
            };
            match settings.integrator {
                IntegratorKind::LinearImplicit => {
                    if !linear_implicit(constants, &mut arrays, &step) {
                        solved = false;
                        break;
                    }
                }
                IntegratorKind::SemiImplicitEuler => {
                    semi_implicit_euler(constants, &mut arrays, &step)
                }
                // Never here: the lane kernels step these (`lane_step`); a failure, not a
                // wrong step, if it ever were.
                IntegratorKind::PositionBased | IntegratorKind::Xpbd => {
                    solved = false;
                    break;
                }
            }
        }
        let quantity = if solved {
            check_chain(
                constants.masses,
                arrays.positions,
                arrays.velocities,
                settings.max_speed,
            )
        } else {
            Some((FailedQuantity::NonFiniteVelocity, None))
        };
        let Some((quantity, node)) = quantity else {
            return (None, halvings - doublings);
        };
        arrays.positions.copy_from_slice(backup_positions);
        arrays.velocities.copy_from_slice(backup_velocities);
        if halvings - doublings < max_halvings {
            halvings += 1;
            continue;
        }
        return (
            Some(ChainFailure {
                integrator: settings.integrator,
                time,
                substep: h,
                halvings,
                chain,
                node,
                quantity,
            }),
            halvings - doublings,
        );
    }
}

/// The kinetic energy per unit mass `½·Σ m|v|² / Σ m` [J/kg] of nodes of masses `masses` [kg]
/// moving at `velocities` [m/s] (0 for no mass).
pub fn kinetic_energy_per_mass(masses: &[f32], velocities: &[Vec3]) -> f32 {
    let mut kinetic = 0.0f32;
    let mut mass = 0.0f32;
    for (m, v) in masses.iter().zip(velocities) {
        kinetic += 0.5 * m * v.length_squared();
        mass += m;
    }
    kinetic / mass.max(f32::MIN_POSITIVE)
}

/// The failure of one chain's state, if any: the first non-finite position or velocity, or an
/// energy blow-up (`½·Σ m|v|² / Σ m > ½·max_speed²`).
fn check_chain(
    masses: &[f32],
    positions: &[Vec3],
    velocities: &[Vec3],
    max_speed: f32,
) -> Option<(FailedQuantity, Option<usize>)> {
    if let Some(node) = positions.iter().position(|p| !p.is_finite()) {
        return Some((FailedQuantity::NonFinitePosition, Some(node)));
    }
    if let Some(node) = velocities.iter().position(|v| !v.is_finite()) {
        return Some((FailedQuantity::NonFiniteVelocity, Some(node)));
    }
    let energy_per_mass = kinetic_energy_per_mass(masses, velocities);
    let limit = 0.5 * max_speed * max_speed;
    if energy_per_mass.is_nan() || energy_per_mass > limit {
        return Some((
            FailedQuantity::EnergyBlowUp {
                energy_per_mass,
                limit,
            },
            None,
        ));
    }
    None
}
