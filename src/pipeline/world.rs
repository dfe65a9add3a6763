//! The world a frame advances (DESIGN "One frame"): the characters, each one's model (its scene:
//! groom and head; its environment: head motion, wind, gravity; its skeletons' material) and its
//! state ([`PipelineState`]: the level blocks, the sections' levels and choices, time), with the
//! settings every character runs with. A world holds nothing of the working memory that steps
//! it: that is a [`WorldPipeline`](super::world_pipeline::WorldPipeline)'s, which advances every
//! character of the world through the stage modules in one pass (like rapier's
//! `PhysicsPipeline::step`, which is handed the world's sets). A lone character
//! ([`Pipeline`](super::Pipeline)) is a world of one; a crowd ([`Crowd`](crate::crowd::Crowd))
//! is a world of many.

use std::sync::Arc;

use hair_core::dynamics::{DynamicsParams, Environment};
use hair_core::lod::SectionChoice;
use hair_core::{Level, RigidTransform, Scene, TriangleMesh};

use super::block::LevelBlock;
use super::settings::PipelineSettings;
use super::state::PipelineState;

/// What a character is made of, fixed for the run (its fingerprint is what a checkpoint must
/// match): the scene, the environment it moves in and its skeletons' material.
#[derive(Debug, Clone)]
pub struct CharacterModel {
    /// The groom on its head (head space), shared with the characters that wear the same groom.
    pub(crate) scene: Arc<Scene>,
    /// Head motion (which places the head in the world), wind and gravity.
    pub(crate) environment: Environment,
    /// Mass, stiffness, damping and drag of its skeletons.
    pub(crate) params: DynamicsParams,
}

impl CharacterModel {
    /// A character wearing `scene`, moved by `environment`, its skeletons of the groom style's
    /// material ([`DynamicsParams::for_style`]).
    pub fn new(scene: Arc<Scene>, environment: Environment) -> Self {
        let params = DynamicsParams::for_style(&scene.groom.params.style);
        CharacterModel {
            scene,
            environment,
            params,
        }
    }

    /// The scene: groom and head.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The environment: head motion, wind, gravity.
    pub fn environment(&self) -> &Environment {
        &self.environment
    }

    /// The skeletons' material (mass, stiffness, damping, drag).
    pub fn params(&self) -> &DynamicsParams {
        &self.params
    }

    /// The fingerprint of this model run with `settings`: the groom (parameters and skeleton
    /// rest data), the head mesh, the environment and the settings, hashed (FNV-1a, 64 bits) to
    /// 16 hex digits.
    pub fn fingerprint(&self, settings: &PipelineSettings) -> String {
        super::fingerprint::model_fingerprint(
            &self.scene,
            &self.environment,
            settings,
            &self.params,
        )
    }
}

/// One character of a world: its model and its state.
#[derive(Debug, Clone)]
pub struct Character {
    pub(crate) model: CharacterModel,
    pub(crate) state: PipelineState,
}

impl Character {
    /// Its model: scene, environment, material.
    pub fn model(&self) -> &CharacterModel {
        &self.model
    }

    /// Its state as the world holds it between frames (the collision stage's velocity memory is
    /// the working memory's until a checkpoint takes it:
    /// [`Pipeline::state`](super::Pipeline::state)).
    pub fn state(&self) -> &PipelineState {
        &self.state
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// The current level of every section.
    pub fn section_levels(&self) -> &[Level] {
        self.state.levels.current()
    }

    /// The last choice of every section (level, visibility, reason).
    pub fn choices(&self) -> &[SectionChoice] {
        &self.state.choices
    }

    /// The block of `level`: the sections simulated at it and their state.
    pub fn block(&self, level: Level) -> &LevelBlock {
        &self.state.blocks[level]
    }

    /// The head's pose at the time the skeletons are at (the end of the last frame stepped).
    pub fn head_pose(&self) -> RigidTransform {
        self.model.environment.head.transform_at(self.state.time)
    }

    /// Its body's mesh [m, head space, with vertex normals] at the time the skeletons are at,
    /// where its head deforms ([`Scene::body_motion`]); `None` for a rigid head.
    pub fn body_mesh(&self) -> Option<TriangleMesh> {
        let motion = self.model.scene.body_motion.as_ref()?;
        Some(motion.mesh_at(self.state.time))
    }
}

/// Every character a frame advances, and the settings they all run with.
#[derive(Debug, Clone)]
pub struct World {
    pub(crate) settings: PipelineSettings,
    pub(crate) characters: Vec<Character>,
}

impl World {
    /// The settings every character runs with.
    pub fn settings(&self) -> &PipelineSettings {
        &self.settings
    }

    /// The characters, in the order they were added (a crowd's: the shot's).
    pub fn characters(&self) -> &[Character] {
        &self.characters
    }

    /// The fingerprint of the world run with its settings, which a checkpoint must match to
    /// resume: a lone character's model fingerprint ([`CharacterModel::fingerprint`]), or for
    /// several characters FNV-1a over their count and their model fingerprints in order (so a
    /// crowd's checkpoint resumes only the same characters in the same order and places).
    pub fn fingerprint(&self) -> String {
        let prints: Vec<String> = self
            .characters
            .iter()
            .map(|c| c.model.fingerprint(&self.settings))
            .collect();
        if let [one] = prints.as_slice() {
            return one.clone();
        }
        let mut hash = super::fingerprint::Fnv1a::new();
        hash.write(format!("world of {}", prints.len()).as_bytes());
        for print in &prints {
            hash.write(print.as_bytes());
        }
        hash.hex()
    }
}
