//! Rigid transforms: the head's pose, which carries the hair roots (rotation then translation).

use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::frame::Frame;

/// A rigid transform `x ↦ rotation · x + translation` [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidTransform {
    /// Unit rotation quaternion.
    pub rotation: Quat,
    /// Translation [m].
    pub translation: Vec3,
}

impl Default for RigidTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl RigidTransform {
    /// The identity transform.
    pub const IDENTITY: RigidTransform = RigidTransform {
        rotation: Quat::IDENTITY,
        translation: Vec3::ZERO,
    };

    /// A transform from a rotation and a translation [m].
    pub fn new(rotation: Quat, translation: Vec3) -> Self {
        RigidTransform {
            rotation,
            translation,
        }
    }

    /// Maps a point [m].
    pub fn transform_point(&self, point: Vec3) -> Vec3 {
        self.rotation * point + self.translation
    }

    /// Maps a direction (rotation only).
    pub fn transform_vector(&self, vector: Vec3) -> Vec3 {
        self.rotation * vector
    }

    /// Maps a frame (rotation only).
    pub fn transform_frame(&self, frame: &Frame) -> Frame {
        frame.rotate(self.rotation)
    }

    /// `self` after `inner`: the transform `x ↦ self(inner(x))`.
    pub fn after(&self, inner: &RigidTransform) -> Self {
        RigidTransform {
            rotation: (self.rotation * inner.rotation).normalize(),
            translation: self.rotation * inner.translation + self.translation,
        }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Self {
        let rotation = self.rotation.inverse();
        RigidTransform {
            rotation,
            translation: -(rotation * self.translation),
        }
    }
}
