//! Command-line arguments that choose a groom: a preset plus optional overrides of its parameters.

use anyhow::{Context, Result};
use clap::Args;
use hairlod::core::head::HeadParams;
use hairlod::core::{GroomParams, Scene};

use crate::cli_args::choice;
use hairlod::core::GroomPreset;

/// A preset groom and overrides of its parameters (shared by the verbs that build a scene).
#[derive(Debug, Clone, Args)]
pub struct SceneArgs {
    /// Preset groom.
    #[arg(long, default_value = "paper-curly", value_parser = choice::<GroomPreset>())]
    pub preset: GroomPreset,
    /// Override: number of sections (each 1 patch = 3 clusters = 5 strand groups).
    #[arg(long, value_name = "N")]
    pub sections: Option<usize>,
    /// Override: strands per strand group.
    #[arg(long, value_name = "N")]
    pub strands_per_group: Option<usize>,
    /// Override: hair length [m].
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    pub hair_length: Option<f32>,
    /// Override: wave or curl factor θ0 [degrees, 0..90] (ignored by straight hair).
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true)]
    pub style_factor: Option<f32>,
    /// Override: wave amplitude or curl radius [m].
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    pub style_size: Option<f32>,
    /// Override: longest skeleton segment allowed [m] (smaller: more nodes, smoother hair).
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    pub smoothness: Option<f32>,
    /// Override: random seed of strand placement and shades.
    #[arg(long)]
    pub seed: Option<u64>,
}

impl SceneArgs {
    /// The groom parameters: the preset with the overrides applied (not yet validated).
    pub fn groom_params(&self) -> Result<GroomParams> {
        let mut params = GroomParams::from(self.preset);
        if let Some(sections) = self.sections {
            params.section_count = sections;
        }
        if let Some(strands) = self.strands_per_group {
            params.strands_per_group = strands;
        }
        if let Some(length) = self.hair_length {
            params.hair_length = length;
        }
        if let Some(factor) = self.style_factor {
            params.style.factor_degrees = factor;
        }
        if let Some(size) = self.style_size {
            params.style.size = size;
        }
        if let Some(smoothness) = self.smoothness {
            params.style.smoothness = smoothness;
        }
        if let Some(seed) = self.seed {
            params.seed = seed;
        }
        Ok(params)
    }

    /// Builds the scene: the default procedural head and the groom on it.
    pub fn build(&self) -> Result<Scene> {
        let params = self.groom_params()?;
        Scene::new(&HeadParams::default(), &params)
            .with_context(|| format!("could not build the `{}` groom", self.preset.name()))
    }
}
