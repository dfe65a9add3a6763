//! Warming a renderer up: a software rasterizer (llvmpipe, lavapipe) compiles each pipeline's
//! shaders for the state it is drawn in at its first draw, which takes a good part of a second.
//! [`Renderer::warm_up`] draws every kind of hair once, small, so that the first frame a caller
//! times (the first mode of a benchmark) does not pay for what every later frame reuses.

use glam::Vec3;
use hair_core::{Groom, Level};

use crate::active::ActiveSkeletons;
use crate::camera::Camera;
use crate::error::Result;
use crate::renderer::Renderer;
use crate::settings::{FrameSettings, ShadingMode};

/// Side of the warm-up frames [pixels] (the shaders' variants do not depend on the size).
const WARM_UP_SIZE: (u32, u32) = (160, 90);

impl Renderer {
    /// Draws `groom`'s rest pose (with the uploaded head) at each level, shaded with
    /// self-shadowing, colour-coded, and fading (the dissolve pipelines), into small frames
    /// that are thrown away. `groom` must be the uploaded one. Returns the frames drawn.
    pub fn warm_up(&mut self, groom: &Groom) -> Result<usize> {
        let camera = Camera::orbit(
            Vec3::new(0.0, -0.01, 0.0),
            0.8,
            0.5,
            0.15,
            35f32.to_radians(),
        );
        let (width, height) = WARM_UP_SIZE;
        let shaded = FrameSettings::new(width, height, camera);
        let coded = FrameSettings {
            mode: ShadingMode::LevelColors,
            ..shaded
        };
        let mut active = ActiveSkeletons::new();
        let mut frames = 0;
        for level in [Level::StrandGroup, Level::Cluster, Level::Patch] {
            active.gather_rest_pose(groom, level)?;
            for settings in [&shaded, &coded] {
                self.render(&active.frame(), settings)?;
                frames += 1;
            }
            active.set_coverage(0.5);
            self.render(&active.frame(), &shaded)?;
            frames += 1;
        }
        Ok(frames)
    }
}
