//! Fingerprints that are the same on every machine and Rust version: FNV-1a ([`Fnv1a`]), and
//! the fingerprint of a run's model that a checkpoint must match to resume
//! ([`model_fingerprint`]).

use hair_core::Scene;
use hair_core::dynamics::{DynamicsParams, Environment};

use super::settings::PipelineSettings;

/// FNV-1a, 64 bits: a fingerprint that is the same on every machine and Rust version (the
/// standard library's hasher promises neither).
pub(crate) struct Fnv1a(u64);

impl Fnv1a {
    /// The empty hash.
    pub(crate) fn new() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    /// Adds `bytes`.
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Adds the bits of `values`.
    pub(crate) fn write_f32s(&mut self, values: impl IntoIterator<Item = f32>) {
        for value in values {
            self.write(&value.to_bits().to_le_bytes());
        }
    }

    /// The hash.
    pub(crate) fn value(&self) -> u64 {
        self.0
    }

    /// The hash as 16 hexadecimal digits.
    pub(crate) fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

/// The fingerprint of a run's model: the groom (parameters and skeleton rest data: lengths,
/// rest and natural angles, roots), the head mesh, the environment, the settings and the
/// skeletons' material, hashed (FNV-1a, 64 bits) to 16 hex digits.
pub(super) fn model_fingerprint(
    scene: &Scene,
    environment: &Environment,
    settings: &PipelineSettings,
    params: &DynamicsParams,
) -> String {
    let mut hash = Fnv1a::new();
    let groom = &scene.groom;
    hash.write(
        format!(
            "{:?}|{:?}|{:?}|{:?}",
            groom.params, environment, settings, params
        )
        .as_bytes(),
    );
    let rest = &groom.skeletons;
    hash.write_f32s(rest.segment_rest_lengths.iter().copied());
    hash.write_f32s(rest.rest_polar_angles.iter().copied());
    hash.write_f32s(rest.rest_azimuth_angles.iter().copied());
    hash.write_f32s(rest.natural_polar_angles.iter().copied());
    hash.write_f32s(rest.natural_azimuth_angles.iter().copied());
    hash.write_f32s(rest.root_positions.iter().flat_map(|p| p.to_array()));
    hash.write_f32s(scene.head.mesh.positions.iter().flat_map(|p| p.to_array()));
    hash.write(&(groom.skeletons.node_count() as u64).to_le_bytes());
    hash.hex()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        // FNV-1a 64 of "" and "a" (Fowler, Noll, Vo reference values).
        assert_eq!(Fnv1a::new().hex(), "cbf29ce484222325");
        let mut hash = Fnv1a::new();
        hash.write(b"a");
        assert_eq!(hash.hex(), "af63dc4c8601ec8c");
    }
}
