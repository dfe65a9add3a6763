//! [`DrawStyle`]: how a pipeline's or a crowd's frames are drawn beyond the camera, the image size
//! and the shading mode, kept by [`PipelineRenderer`](super::PipelineRenderer) and
//! [`CrowdRenderer`](crate::CrowdRenderer) and turned into each frame's settings in one place.

use hair_core::Camera;
use hair_render::{
    ClusterGeometry, FrameSettings, HairShading, LineCoverage, LineShading, ShadingMode,
};

/// Where strand lines are shaded, the hair's reflectance model, the lines' pixel coverage and
/// how cluster tubes are drawn; the renderer's defaults otherwise.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DrawStyle {
    /// Strand lines shaded at their curve points (the default) or per fragment.
    pub line_shading: LineShading,
    /// Kajiya-Kay (the default) or Marschner.
    pub hair_shading: HairShading,
    /// Strand lines covering whole pixels (the default) or their width's share.
    pub line_coverage: LineCoverage,
    /// Cluster tubes drawn as view-facing stand-ins (the default) or tessellated.
    pub cluster_geometry: ClusterGeometry,
}

impl DrawStyle {
    /// The settings of a `width`×`height` [pixels] frame through `camera` in `mode`, in this
    /// style.
    pub fn frame_settings(
        &self,
        width: u32,
        height: u32,
        camera: &Camera,
        mode: ShadingMode,
    ) -> FrameSettings {
        let mut settings = FrameSettings::new(width, height, *camera);
        settings.mode = mode;
        settings.line_shading = self.line_shading;
        settings.hair.shading = self.hair_shading;
        settings.line_coverage = self.line_coverage;
        settings.cluster_geometry = self.cluster_geometry;
        settings
    }
}
