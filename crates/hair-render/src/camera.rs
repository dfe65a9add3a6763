//! The camera: the same look-at perspective camera (right-handed, +Y up, depth 0..1) the level of
//! detail selection uses, re-exported from `hair-core` so a frame is chosen and drawn through one
//! camera.

pub use hair_core::Camera;
