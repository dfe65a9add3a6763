//! [`Environment`]: what drives a simulation from outside (head motion, wind, gravity).

use glam::Vec3;

use crate::dynamics::forces::STANDARD_GRAVITY;
use crate::dynamics::head_motion::HeadMotion;
use crate::dynamics::wind::WindField;

/// The control inputs of a simulation: head motion, wind and gravity.
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    /// The head's pose over time (carries attached roots).
    pub head: HeadMotion,
    /// The wind field.
    pub wind: WindField,
    /// Gravitational acceleration [m/s²].
    pub gravity: Vec3,
}

impl Default for Environment {
    /// A still head at the origin, calm air, standard gravity.
    fn default() -> Self {
        Environment {
            head: HeadMotion::default(),
            wind: WindField::Calm,
            gravity: STANDARD_GRAVITY,
        }
    }
}
