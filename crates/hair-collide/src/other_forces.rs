//! The non-collision forces friction opposes (§5.4): the external forces of the dynamics on a
//! node, gravity and air drag towards the wind, `m·g + m·γ·(w − v)`, as the integrators apply
//! them.
//!
//! The angular springs are left out on purpose. F_col is held constant over a whole step (up to
//! 16 substeps), and the springs vary much faster than that: the curly style's stiffest joint
//! rings at `ω = √(EI/λ)/l² ≈ 220 rad/s`, so `ω·Δt ≈ 3.7` at 60 Hz, and a step-lagged
//! `−μ·F_spring` arrives at an arbitrary phase of the oscillation and pumps energy into it
//! (measured: the position-based integrator blew up within 10 steps of a shaking head with the
//! springs included). Gravity, drag and wind vary slowly, so opposing them is safe.

use glam::Vec3;
use hair_core::dynamics::{DynamicsModel, Environment};

/// The external force \[N\] on model node `node` at `position` \[m\] moving at `velocity`
/// \[m/s\] at `time` \[s\]: `m·g + m·γ·(w − v)`.
pub(crate) fn external_force(
    model: &DynamicsModel,
    environment: &Environment,
    node: usize,
    position: Vec3,
    velocity: Vec3,
    time: f64,
) -> Vec3 {
    let m = model.node_masses[node];
    let wind = environment.wind.velocity_at(position, time);
    environment.gravity * m + (wind - velocity) * (m * model.params.air_drag_rate)
}
