//! hairlod: hair simulation with automatic levels of detail.
pub use hair_core as core;
