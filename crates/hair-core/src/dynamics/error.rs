//! Errors of the skeleton dynamics: bad settings, mismatched state, and detected instabilities.

use std::fmt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::dynamics::integrator_kind::IntegratorKind;
use crate::error::HairError;

/// What went wrong in the chain that failed a step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum FailedQuantity {
    /// A node position became NaN or infinite.
    NonFinitePosition,
    /// A node velocity became NaN or infinite.
    NonFiniteVelocity,
    /// The chain's kinetic energy per unit mass `½·Σm|v|²/Σm` [J/kg] exceeded the limit
    /// `½·max_speed²` of the settings: an energy blow-up.
    EnergyBlowUp {
        /// The chain's kinetic energy per unit mass [J/kg].
        energy_per_mass: f32,
        /// The limit [J/kg].
        limit: f32,
    },
}

impl fmt::Display for FailedQuantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FailedQuantity::NonFinitePosition => write!(f, "a node position is not finite"),
            FailedQuantity::NonFiniteVelocity => write!(f, "a node velocity is not finite"),
            FailedQuantity::EnergyBlowUp {
                energy_per_mass,
                limit,
            } => write!(
                f,
                "energy blow-up: kinetic energy per unit mass {energy_per_mass:.4e} J/kg above the \
                 limit {limit:.4e} J/kg"
            ),
        }
    }
}

/// Where and how one chain failed (the first failing chain is reported).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ChainFailure {
    /// The integrator that was running.
    pub integrator: IntegratorKind,
    /// Simulation time at the start of the failing step [s].
    pub time: f64,
    /// The substep that failed [s] (after any halvings).
    pub substep: f32,
    /// Halvings of the substep already tried for this chain.
    pub halvings: u32,
    /// Index of the failing chain.
    pub chain: usize,
    /// The first offending node, as an index into the chain (0 = root), where one node is to blame.
    pub node: Option<usize>,
    /// What failed.
    pub quantity: FailedQuantity,
}

/// Errors of [`Simulation`](crate::dynamics::Simulation) and its settings.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DynamicsError {
    /// A step became unstable (a non-finite value or an energy blow-up) and no retry was allowed or
    /// every allowed halving of the substep failed too. The state was restored to its value before
    /// the step.
    #[error(
        "the {} integrator became unstable at t = {:.4} s with substep {:.3e} s (after {} halvings) \
         on chain {}{}: {}",
        .0.integrator.name(),
        .0.time,
        .0.substep,
        .0.halvings,
        .0.chain,
        .0.node.map(|n| format!(", node {n}")).unwrap_or_default(),
        .0.quantity
    )]
    Unstable(ChainFailure),
    /// A setting or parameter is outside its allowed range.
    #[error("invalid dynamics setting {name}: {value} (allowed: {allowed})")]
    InvalidSetting {
        /// The setting, as written in code (`time_step`, `substeps`).
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The allowed range in words, with units.
        allowed: &'static str,
    },
    /// The state does not belong to the simulation's model.
    #[error("state mismatch: {what} has {actual} entries, the model needs {expected}")]
    StateMismatch {
        /// Which array.
        what: &'static str,
        /// Entries given.
        actual: usize,
        /// Entries required.
        expected: usize,
    },
    /// The position-based and XPBD integrators step chains of at most
    /// [`MAX_CHAIN_NODES`](crate::dynamics::MAX_CHAIN_NODES) nodes (their scratch lives on the
    /// stack); a model with a longer chain asks for one of the other integrators, or for fewer
    /// nodes per chain (the fit's `max_nodes`).
    #[error(
        "chain {chain} has {nodes} nodes; the {} integrator steps chains of at most {limit} nodes \
         (fit with max_nodes <= {limit}, or use the semi-implicit Euler or linear-implicit \
         integrator)",
        .integrator.name()
    )]
    ChainTooLong {
        /// The first chain over the limit.
        chain: usize,
        /// Its node count.
        nodes: usize,
        /// The most nodes the integrator takes.
        limit: usize,
        /// The integrator asked for.
        integrator: IntegratorKind,
    },
    /// Sag-free initialisation found a shape the springs cannot hold under gravity.
    #[error(
        "sag-free initialisation: chain {chain} would need its spring at node {node} turned by \
         {turn:.2} rad (more than {max_turn} rad) to hold its rest shape under gravity: the hair \
         is too soft for this shape"
    )]
    TooSoftToHold {
        /// The chain.
        chain: usize,
        /// The node (within the chain) whose spring cannot hold.
        node: usize,
        /// The turn of its natural direction the balance asked for [rad].
        turn: f32,
        /// The largest turn allowed [rad].
        max_turn: f32,
    },
    /// Building the model failed.
    #[error(transparent)]
    Model(#[from] HairError),
}

impl DynamicsError {
    /// Shorthand for [`DynamicsError::InvalidSetting`].
    pub fn invalid(name: &'static str, value: impl fmt::Display, allowed: &'static str) -> Self {
        DynamicsError::InvalidSetting {
            name,
            value: value.to_string(),
            allowed,
        }
    }

    /// The failure details when this is an instability.
    pub fn failure(&self) -> Option<&ChainFailure> {
        match self {
            DynamicsError::Unstable(failure) => Some(failure),
            _ => None,
        }
    }
}

/// Checks that `value` is finite and `> 0`.
pub(crate) fn positive(name: &'static str, value: f32) -> Result<f32, DynamicsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(DynamicsError::invalid(name, value, "a finite number > 0"))
    }
}

/// Checks that `value` is finite and `>= 0`.
pub(crate) fn non_negative(name: &'static str, value: f32) -> Result<f32, DynamicsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(DynamicsError::invalid(name, value, "a finite number >= 0"))
    }
}
