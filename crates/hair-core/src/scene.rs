//! A scene: the procedural head and a groom on it, built from parameters or a named preset.

use crate::error::Result;
use crate::groom::{Groom, GroomParams};
use crate::head::{Head, HeadParams};

/// A head and its groom (the static model of everything hairlod simulates and draws).
#[derive(Debug, Clone)]
pub struct Scene {
    /// The head: collision body and drawn mesh; hair roots sit on its scalp.
    pub head: Head,
    /// The hair on it.
    pub groom: Groom,
}

impl Scene {
    /// Builds the procedural head from `head_params` and generates `groom_params` on it.
    pub fn new(head_params: &HeadParams, groom_params: &GroomParams) -> Result<Scene> {
        let head = Head::procedural(head_params)?;
        let groom = Groom::generate(groom_params, &head)?;
        Ok(Scene { head, groom })
    }

    /// The preset groom called `name` on the default head (see
    /// [`PRESET_NAMES`](crate::groom::PRESET_NAMES)).
    pub fn preset(name: &str) -> Result<Scene> {
        Scene::new(&HeadParams::default(), &GroomParams::preset(name)?)
    }
}
