//! The deforming heads of a run played back from a cache: a record holds the skeletons, the
//! head poses and the time, not the bodies, so each character's body is sampled again at the
//! record's time from the scene it was simulated on, and its strands are shifted onto the roots
//! it carries, as the run in memory draws them
//! ([`Pipeline::strand_root_shifts`](crate::pipeline::Pipeline::strand_root_shifts)).

use std::sync::Arc;

use glam::Vec3;
use hair_core::{RigidTransform, Scene, TriangleMesh};
use hair_render::ActiveSkeletons;

use crate::pipeline::{
    BodyRide, CharacterModel, Result, ShiftedCharacter, body_meshes, strand_root_shifts,
};

/// Every character's scene and, for a deforming head, where its groom rides it, in the shot's
/// order.
#[derive(Debug, Clone, Default)]
pub(crate) struct CachedBodies {
    characters: Vec<(Arc<Scene>, Option<BodyRide>)>,
}

impl CachedBodies {
    /// The bodies of `characters` (the models the cache was simulated from, in its order); a
    /// deforming head's strands are attached to its rest mesh here, once.
    pub(crate) fn of(characters: &[CharacterModel]) -> Result<CachedBodies> {
        let characters = characters
            .iter()
            .map(|c| Ok((c.scene.clone(), BodyRide::of(&c.scene, None)?)))
            .collect::<Result<_>>()?;
        Ok(CachedBodies { characters })
    }

    /// Each character's body mesh at `time` [s] (`None` for a rigid head); empty when every
    /// head is rigid.
    pub(crate) fn meshes(&self, time: f64) -> Vec<Option<TriangleMesh>> {
        if self.characters.iter().all(|(_, ride)| ride.is_none()) {
            return Vec::new();
        }
        body_meshes(
            self.characters
                .iter()
                .map(|(scene, _)| (scene.body_motion.as_ref(), time)),
        )
    }

    /// The strand root shifts of the skeletons `active` holds at `time` [s] with the heads at
    /// `heads` (the record's poses, in the shot's order); left empty where no head deforms.
    pub(crate) fn strand_root_shifts(
        &self,
        heads: &[RigidTransform],
        time: f64,
        active: &ActiveSkeletons,
        shifts: &mut Vec<Vec3>,
    ) {
        let characters = self
            .characters
            .iter()
            .enumerate()
            .map(|(k, (scene, ride))| ShiftedCharacter {
                groom: &scene.groom,
                ride: ride.as_ref(),
                head: heads.get(k).copied().unwrap_or_default(),
                time,
            });
        strand_root_shifts(characters, active, shifts);
    }
}
