//! Self-shadowing with deep opacity maps (Yuksel & Keyser 2008): the settings, the light's
//! orthographic view fitted around the active hair, and the two light-space textures.
//!
//! Per frame, before the camera pass, the active hair (strands, clusters and patches, whatever
//! level each section is at) is drawn twice from the light:
//!
//! 1. **depth map**: the depth `z₀` of the hair nearest the light in each texel;
//! 2. **opacity map**: every fragment adds its optical depth `τ` to one of four layers (the
//!    channels of an `Rgba16Float` texel, additive blending) chosen by its distance `z − z₀`
//!    behind that first hair: layer `i` spans `[bᵢ, bᵢ₊₁)` with `b₀ = 0` and
//!    [`SelfShadowing::layer_ends`] `b₁..b₄` [m].
//!
//! A point at distance `d` behind `z₀` then receives `exp(−Ω(d))` of the light, where `Ω(d)` sums
//! the layers that end before `d` and the part `(d − bᵢ)/(bᵢ₊₁ − bᵢ)` of the layer it lies in
//! (the optical depth grows linearly within a layer). Optical depths are physical: a strand line
//! crossing a texel of side `s` covers `w/s` of it (`w` the hair width), times
//! [`SelfShadowing::strand_opacity`]; a cluster or patch fragment carries the optical depth of the
//! strands it stands for (see `shaders/shadows.wgsl`).

use glam::{Mat4, Vec3};

use crate::error::{Result, invalid};

/// Self-shadowing options of a frame ([`crate::FrameSettings::shadows`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfShadowing {
    /// Draw self-shadows (deep opacity maps) at all.
    pub enabled: bool,
    /// Side of the square depth and opacity maps [texels], 16..=4096: the most, with
    /// [`SelfShadowing::match_screen`].
    pub resolution: u32,
    /// Shrink the maps to the hair's size on screen: a map texel no smaller than about a screen
    /// pixel (see [`map_resolution`]). The optical depths are physical (per texel side), so the
    /// shadow keeps its darkness; only its detail follows the image's.
    pub match_screen: bool,
    /// Ends of the four opacity layers behind the first hair, `b₁ < b₂ < b₃ < b₄` [m]; beyond
    /// `b₄` a point receives the light left after all four layers.
    pub layer_ends: [f32; 4],
    /// Fraction of the light a strand stops where it lies across it, `0..=1` (hair fibres pass a
    /// good part of the light on, forward-scattered: the TT lobe of Marschner et al. 2003).
    pub strand_opacity: f32,
    /// Hair fibre width [m] used for the optical depth of strands and of the strands each cluster
    /// and patch stands for.
    pub hair_width: f32,
    /// The light passes draw every `along_stride`-th curve point of each strand and surface
    /// (≥ 1): a coarser tessellation for the shadow than for the image.
    pub along_stride: u32,
}

impl Default for SelfShadowing {
    /// On, 512² maps at most (matched to the hair's screen size), layers ending 4, 12, 28 and 60 mm behind the first hair, strands stopping
    /// 40 % of the light they cover, 80 µm fibres, every 4th curve point.
    fn default() -> Self {
        SelfShadowing {
            enabled: true,
            resolution: 512,
            match_screen: true,
            layer_ends: [0.004, 0.012, 0.028, 0.060],
            strand_opacity: 0.4,
            hair_width: 80e-6,
            along_stride: 4,
        }
    }
}

impl SelfShadowing {
    /// Self-shadowing switched off.
    pub fn off() -> SelfShadowing {
        SelfShadowing {
            enabled: false,
            ..SelfShadowing::default()
        }
    }

    /// Checks that every value is finite and in range.
    pub fn validate(&self) -> Result<()> {
        if !(16..=4096).contains(&self.resolution) {
            return Err(invalid(format!(
                "shadow map resolution {} must be 16..=4096 texels",
                self.resolution
            )));
        }
        let ends = self.layer_ends;
        if !(ends.iter().all(|e| e.is_finite())
            && ends[0] > 0.0
            && ends.windows(2).all(|w| w[0] < w[1]))
        {
            return Err(invalid(format!(
                "shadow layer ends {ends:?} m must be finite, > 0 and increasing"
            )));
        }
        if !(self.strand_opacity.is_finite() && (0.0..=1.0).contains(&self.strand_opacity)) {
            return Err(invalid(format!(
                "strand opacity {} must be in 0..=1",
                self.strand_opacity
            )));
        }
        if !(self.hair_width.is_finite() && self.hair_width > 0.0) {
            return Err(invalid(format!(
                "shadow hair width {} m must be finite and > 0",
                self.hair_width
            )));
        }
        if self.along_stride == 0 {
            return Err(invalid("shadow along-stride must be at least 1"));
        }
        Ok(())
    }
}

/// Smallest map side with [`SelfShadowing::match_screen`] [texels].
pub const MIN_MATCHED_RESOLUTION: u32 = 64;

/// The side of the maps [texels] for hair inside a sphere that spans `screen_diameter` pixels
/// on screen: `shadows.resolution` without [`SelfShadowing::match_screen`], else the power of two
/// at or above the diameter (a texel at most about a screen pixel), within
/// [`MIN_MATCHED_RESOLUTION`]`..=resolution`. Powers of two keep the few map sizes a zoom passes
/// through reusable.
pub fn map_resolution(shadows: &SelfShadowing, screen_diameter: f32) -> u32 {
    let most = shadows.resolution;
    if !(shadows.match_screen && screen_diameter.is_finite() && screen_diameter > 0.0) {
        return most;
    }
    let wanted = (screen_diameter.ceil().min(most as f32) as u32).next_power_of_two();
    wanted.clamp(MIN_MATCHED_RESOLUTION.min(most), most)
}

/// The light's orthographic view of a sphere: `centre` and `radius` [m] bound the hair,
/// `towards_light` points from the scene to the light. Returns the view-projection (wgpu clip
/// space, depth 0 at the light side of the sphere and 1 at the far side) and its depth range [m]
/// (`2·radius`).
pub(crate) fn light_view_projection(centre: Vec3, radius: f32, towards_light: Vec3) -> (Mat4, f32) {
    let radius = radius.max(1e-4);
    let direction = towards_light.normalize_or(Vec3::Y);
    let up = if direction.y.abs() > 0.9 {
        Vec3::X
    } else {
        Vec3::Y
    };
    let eye = centre + direction * (2.0 * radius);
    let view = glam::camera::rh::view::look_at_mat4(eye, centre, up);
    let projection = glam::camera::rh::proj::directx::orthographic(
        -radius,
        radius,
        -radius,
        radius,
        radius,
        3.0 * radius,
    );
    (projection * view, 2.0 * radius)
}

/// A sphere around `points` [m] (the centre of their box, the farthest point), grown by `margin`
/// [m]; `None` without finite points.
pub(crate) fn bounding_sphere(
    points: impl Iterator<Item = Vec3> + Clone,
    margin: f32,
) -> Option<(Vec3, f32)> {
    let (min, max) =
        points
            .clone()
            .filter(|p| p.is_finite())
            .fold(None, |acc: Option<(Vec3, Vec3)>, p| match acc {
                None => Some((p, p)),
                Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
            })?;
    let centre = 0.5 * (min + max);
    let radius = points
        .filter(|p| p.is_finite())
        .map(|p| p.distance(centre))
        .fold(0.0f32, f32::max);
    Some((centre, radius + margin))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sphere's near pole (towards the light) maps to depth 0, its far pole to 1, its centre
    /// to the middle of the map, and a point on the rim across the light to the map's edge.
    #[test]
    fn light_view_covers_the_sphere() {
        let centre = Vec3::new(0.1, 1.6, -0.2);
        let light = Vec3::new(0.5, 0.7, 1.0).normalize();
        let (matrix, depth_range) = light_view_projection(centre, 0.3, light);
        assert!((depth_range - 0.6).abs() < 1e-6);
        let project = |p: Vec3| matrix.project_point3(p);
        let near = project(centre + light * 0.3);
        let far = project(centre - light * 0.3);
        let middle = project(centre);
        assert!(
            near.z.abs() < 1e-5 && (far.z - 1.0).abs() < 1e-5,
            "{near} {far}"
        );
        assert!(middle.x.abs() < 1e-5 && middle.y.abs() < 1e-5 && (middle.z - 0.5).abs() < 1e-5);
        let across = light.cross(Vec3::Y).normalize();
        let rim = project(centre + across * 0.3);
        assert!((rim.x.abs().max(rim.y.abs()) - 1.0).abs() < 1e-4, "{rim}");
    }

    #[test]
    fn bounding_sphere_holds_every_point() {
        let points = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let (centre, radius) = bounding_sphere(points.iter().copied(), 0.1).unwrap();
        for p in points {
            assert!(p.distance(centre) <= radius - 0.1 + 1e-6);
        }
        assert!(bounding_sphere([Vec3::NAN].into_iter(), 0.1).is_none());
    }

    /// A texel at most about a screen pixel, powers of two, within the bounds; the full
    /// resolution when not matching or when the hair's screen size is unknown.
    #[test]
    fn map_resolution_follows_the_screen_size() {
        let shadows = SelfShadowing::default();
        assert_eq!(map_resolution(&shadows, 1000.0), 512);
        assert_eq!(map_resolution(&shadows, 300.0), 512);
        assert_eq!(map_resolution(&shadows, 200.0), 256);
        assert_eq!(map_resolution(&shadows, 100.0), 128);
        assert_eq!(map_resolution(&shadows, 10.0), MIN_MATCHED_RESOLUTION);
        assert_eq!(map_resolution(&shadows, f32::INFINITY), 512);
        let fixed = SelfShadowing {
            match_screen: false,
            ..shadows
        };
        assert_eq!(map_resolution(&fixed, 10.0), 512);
        let small = SelfShadowing {
            resolution: 32,
            ..shadows
        };
        assert_eq!(map_resolution(&small, 10.0), 32);
    }

    #[test]
    fn settings_are_validated() {
        assert!(SelfShadowing::default().validate().is_ok());
        let bad = SelfShadowing {
            layer_ends: [0.01, 0.005, 0.02, 0.03],
            ..SelfShadowing::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("layer"));
        let bad = SelfShadowing {
            resolution: 8,
            ..SelfShadowing::default()
        };
        assert!(bad.validate().is_err());
        let bad = SelfShadowing {
            along_stride: 0,
            ..SelfShadowing::default()
        };
        assert!(bad.validate().is_err());
    }
}
