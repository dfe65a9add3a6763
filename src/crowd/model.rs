//! [`CrowdModel`]: the built characters of a crowd shot (each groom built, hung and measured once
//! however many characters wear it), from which each mode's [`Crowd`](super::Crowd) starts.

use std::sync::Arc;

use hair_collide::CollisionBody;
use hair_core::Scene;
use hair_core::lod::{LevelDeviation, level_deviations};

use crate::pipeline::{CharacterModel, PipelineError, Result};
use crate::shot::{Character, Shot};

/// One built character: its description, its scene (groom and head) and its sections' level
/// deviations [m].
#[derive(Debug, Clone)]
pub struct CrowdMember {
    /// What the shot says of it.
    pub character: Character,
    /// Its groom on the procedural head (head space), shared with the characters that wear the
    /// same groom (and with their models).
    pub scene: Arc<Scene>,
    /// Its sections' level deviations [m] ([`level_deviations`]), shared by characters with the
    /// same groom.
    pub deviations: Arc<Vec<LevelDeviation>>,
    /// Its head's collision body, built once per groom: a clone, which shares the mesh, its
    /// tree and pseudonormals with the other characters'.
    pub body: CollisionBody,
}

impl CrowdMember {
    /// Its model: its scene, its motion and the groom style's material.
    pub fn model(&self) -> CharacterModel {
        CharacterModel::new(self.scene.clone(), self.character.environment.clone())
    }
}

/// The built characters of a crowd shot.
#[derive(Debug, Clone)]
pub struct CrowdModel {
    /// The shot (camera, frames, settings; its characters are the members').
    pub shot: Shot,
    /// One per character, in the shot's order.
    pub members: Vec<CrowdMember>,
}

impl CrowdModel {
    /// Builds every character of `shot` ([`Shot::build_scene_with`]), each distinct groom once;
    /// errors for a shot without characters.
    pub fn build(shot: &Shot) -> Result<CrowdModel> {
        if !shot.is_crowd() {
            return Err(PipelineError::NoCharacters);
        }
        let mut built: Vec<(usize, CrowdMember)> = Vec::new();
        let mut members = Vec::with_capacity(shot.characters.len());
        for (k, character) in shot.characters.iter().enumerate() {
            let same = built
                .iter()
                .find(|(first, _)| shot.characters[*first].groom == character.groom);
            let member = match same {
                Some((_, first)) => CrowdMember {
                    character: character.clone(),
                    ..first.clone()
                },
                None => {
                    let scene = Arc::new(shot.build_scene_with(&character.groom)?);
                    // Grooms on one head share its collision body (mesh, tree, pseudonormals).
                    let body = match built
                        .iter()
                        .find(|(_, other)| other.scene.head.mesh == scene.head.mesh)
                    {
                        Some((_, other)) => other.body.clone(),
                        None => CollisionBody::from_mesh(&scene.head.mesh)?,
                    };
                    let member = CrowdMember {
                        character: character.clone(),
                        deviations: Arc::new(level_deviations(&scene.groom)?),
                        body,
                        scene,
                    };
                    built.push((k, member.clone()));
                    member
                }
            };
            members.push(member);
        }
        Ok(CrowdModel {
            shot: shot.clone(),
            members,
        })
    }

    /// Strands in the whole crowd.
    pub fn strand_count(&self) -> usize {
        self.members
            .iter()
            .map(|m| m.scene.groom.strands.strand_count())
            .sum()
    }
}
