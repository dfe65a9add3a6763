//! A scene: the procedural head and a groom on it, built from parameters or a named preset; and
//! the head's deformation over time, where it deforms.

use std::sync::Arc;

use crate::error::HairError;
use crate::error::Result;
use crate::groom::{Groom, GroomParams};
use crate::head::{Head, HeadParams};
use crate::mesh_sequence::MeshSequence;

/// A head and its groom (the static model of everything hairlod simulates and draws).
#[derive(Debug, Clone)]
pub struct Scene {
    /// The head: collision body and drawn mesh; hair roots sit on its scalp.
    pub head: Head,
    /// The hair on it.
    pub groom: Groom,
    /// How the head (the body) deforms over time, in head space: a mesh sequence on the head
    /// mesh's triangles whose first sample is the head mesh ([`Scene::set_body_motion`]). The
    /// roots ride its triangles, collision follows it and it is drawn deformed; `None`: the head
    /// is rigid (moved only by the head motion).
    pub body_motion: Option<Arc<MeshSequence>>,
}

impl Scene {
    /// Builds the procedural head from `head_params` and generates `groom_params` on it.
    pub fn new(head_params: &HeadParams, groom_params: &GroomParams) -> Result<Scene> {
        let head = Head::procedural(head_params)?;
        let groom = Groom::generate(groom_params, &head)?;
        Ok(Scene {
            head,
            groom,
            body_motion: None,
        })
    }

    /// Makes `motion` the head's deformation; `None` makes the head rigid again. Fails unless
    /// its triangles are the head mesh's and its first sample is the head mesh's positions
    /// (the rest shape the roots were attached on).
    pub fn set_body_motion(&mut self, motion: Option<Arc<MeshSequence>>) -> Result<()> {
        if let Some(motion) = &motion {
            let mesh = &self.head.mesh;
            if motion.triangles() != mesh.triangles.as_slice() {
                return Err(HairError::invalid(
                    "body motion",
                    format!("{} triangles", motion.triangles().len()),
                    "the head mesh's triangles, in its order",
                ));
            }
            if motion.sample_positions(0) != mesh.positions.as_slice() {
                return Err(HairError::invalid(
                    "body motion",
                    "a first sample that is not the head mesh",
                    "the head mesh's positions as its first sample (the rest shape)",
                ));
            }
        }
        self.body_motion = motion;
        Ok(())
    }

    /// The preset groom called `name` on the default head (see
    /// [`PRESET_NAMES`](crate::groom::PRESET_NAMES)).
    pub fn preset(name: &str) -> Result<Scene> {
        Scene::new(&HeadParams::default(), &GroomParams::preset(name)?)
    }
}
