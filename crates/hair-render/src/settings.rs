//! Per-frame render settings: image size, camera, light, hair material, strand style, tessellation
//! and the LOD colour-coding mode. Colours are linear RGB in 0..1.

use glam::Vec3;

use crate::camera::Camera;
use crate::error::{Result, invalid};
use crate::material::{HairMaterial, HairShading};
use crate::shadows::SelfShadowing;

/// How geometry is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadingMode {
    /// Kajiya-Kay hair shading and a Lambert-lit head.
    #[default]
    Shaded,
    /// Flat colour per level of detail (Fig. 6): strands, clusters and patches each in their
    /// [`LevelColors`] colour, the head flat in its code colour.
    LevelColors,
}

/// Flat colours of the LOD colour-coding mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelColors {
    /// Strand groups (finest level): yellow.
    pub strands: Vec3,
    /// Clusters: red.
    pub clusters: Vec3,
    /// Patches (coarsest level): blue.
    pub patches: Vec3,
    /// The head: neutral grey.
    pub head: Vec3,
}

impl Default for LevelColors {
    fn default() -> Self {
        LevelColors {
            strands: Vec3::new(1.0, 1.0, 0.0),
            clusters: Vec3::new(1.0, 0.0, 0.0),
            patches: Vec3::new(0.0, 0.0, 1.0),
            head: Vec3::splat(0.2),
        }
    }
}

/// The texture of clusters and patches (§6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SurfaceTexture {
    /// Hair: fine strands across the surface whose shades drift along the hair, each ending at
    /// its own length, fewer of them towards the silhouette; the coverage becomes MSAA samples
    /// (alpha-to-coverage), so tips and silhouettes break up like strands (with MSAA only).
    #[default]
    Hair,
    /// Stripes across the surface, constant along the hair, solid to the edges.
    Stripes,
}

hair_core::named_enum! {
    /// How cluster tubes (§3.4) are drawn.
    ///
    /// Seen from outside, a tube is its silhouette: a band `2ρ` wide along its axis, whose normal
    /// turns from one edge through the eye to the other. [`ClusterGeometry::Impostor`] draws that band
    /// (one strip, in the plane touching the tube's near side) and rebuilds the tube's normal per
    /// fragment, so it covers the pixels of the tube's front half with a fraction of its triangles:
    /// a CPU rasterizer spends a large share of a cluster frame per triangle (`docs/render.md`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum ClusterGeometry {
        /// The tube's view-facing silhouette, one strip across, shaded with the tube's normal and
        /// texture (the default). Where a tube points at the eye its stand-in narrows (a tube seen
        /// end-on shows its ring; the band folds along the axis's short projection).
        #[default]
        Impostor = "impostor",
        /// The tube tessellated around within [`Tessellation::max_chord_error_pixels`] of its ring,
        /// back faces culled.
        Tube = "tube",
    }
}

/// Strips across an impostor cluster ([`ClusterGeometry::Impostor`]): one, edge to edge.
pub const IMPOSTOR_BANDS: u32 = 1;

impl ClusterGeometry {
    /// Strips around (a tube) or across (an impostor) a cluster whose ring radius is
    /// `ring_radius` [m], `distance` [m] from a camera of focal length `focal_pixels`.
    pub fn bands(
        &self,
        tessellation: &Tessellation,
        ring_radius: f32,
        distance: f32,
        focal_pixels: f32,
    ) -> u32 {
        match self {
            ClusterGeometry::Impostor => IMPOSTOR_BANDS,
            ClusterGeometry::Tube => {
                tessellation.around_segments_for(ring_radius, distance, focal_pixels)
            }
        }
    }
}

/// How strands are drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StrandStyle {
    /// One-pixel lines.
    Lines,
    /// Camera-facing ribbons; strands whose ribbon would be at most one pixel wide are drawn as
    /// 1-pixel lines instead (the same coverage at a fraction of the cost).
    Ribbons {
        /// Hair width [m] (human hair: 50–100 µm).
        width: f32,
        /// Smallest on-screen width [pixels], so that distant strands do not vanish.
        min_width_pixels: f32,
    },
}

impl StrandStyle {
    /// The width [pixels] a strand is drawn at `distance` [m] through a focal length of
    /// `focal_pixels`: the ribbon's projected width, at least its minimum; `None` for lines
    /// (always one pixel, never widened).
    pub fn ribbon_pixels(&self, focal_pixels: f32, distance: f32) -> Option<f32> {
        match *self {
            StrandStyle::Lines => None,
            StrandStyle::Ribbons {
                width,
                min_width_pixels,
            } => Some((width * focal_pixels / distance.max(1e-6)).max(min_width_pixels)),
        }
    }
}

impl Default for StrandStyle {
    /// Ribbons 80 µm wide, at least 1 pixel.
    fn default() -> Self {
        StrandStyle::Ribbons {
            width: 80e-6,
            min_width_pixels: 1.0,
        }
    }
}

/// Where the Kajiya-Kay model is evaluated on strands drawn as 1-pixel lines (ribbons are always
/// shaded per fragment).
///
/// A line is one pixel wide, so shading varies only along it; evaluating the model at the curve
/// points and interpolating the colour (Gouraud) instead of interpolating the tangent and
/// evaluating per fragment (Phong) moves the work from the ~5 fragments a segment covers to its
/// end points. On a CPU rasteriser that halves the cost of a strand frame; the image differs only
/// where the highlight turns within one segment (`docs/render.md` gives the measured difference).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LineShading {
    /// Shade at the curve points, interpolate the colour along each segment (the default).
    #[default]
    PerVertex,
    /// Interpolate tangent and position along each segment and shade every fragment.
    PerFragment,
}

/// Tessellation: the number of segments along every strand, cluster and patch, and around every
/// cluster, follows the camera distance of its skeleton's root (§6: nearly continuous LOD within a
/// representation).
///
/// A chain whose root is `d` metres from the camera gets
/// `clamp(ceil(max_segments · full_detail_distance / d), min_segments, max_segments)` segments
/// along. Around a cluster tube whose ring has radius `R` pixels on screen (its radius times the
/// focal length over `d`), it gets the fewest segments `n` whose polygon stays within
/// `max_chord_error_pixels` `ε` of the ring, `n = ceil(π / acos(1 − ε/R))`, clamped to
/// `min_around_segments..=max_around_segments`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tessellation {
    /// Segments along the hair at `full_detail_distance` and closer.
    pub max_segments: u32,
    /// Segments along the hair however far away (≥ 1).
    pub min_segments: u32,
    /// Segments around a cluster tube at `full_detail_distance` and closer (the around settings
    /// apply to [`ClusterGeometry::Tube`]; an impostor is always one strip across).
    pub max_around_segments: u32,
    /// Segments around a cluster tube however far away (≥ 3).
    pub min_around_segments: u32,
    /// Distance [m] within which chains get the most segments.
    pub full_detail_distance: f32,
    /// Largest on-screen gap [pixels] between a cluster tube's polygon and its ring.
    pub max_chord_error_pixels: f32,
}

impl Default for Tessellation {
    /// 4 to 32 segments along (full detail within 1 m), 4 to 12 around within one pixel (see
    /// `docs/render.md`: against 0.5 px, a close-up all-clusters frame costs 8–33 % less at
    /// 0.45–2.4 m and its SSIM against all-strands is unchanged to 3 decimals).
    fn default() -> Self {
        Tessellation {
            max_segments: 32,
            min_segments: 4,
            max_around_segments: 12,
            min_around_segments: 4,
            full_detail_distance: 1.0,
            max_chord_error_pixels: 1.0,
        }
    }
}

/// The most segments a strand may be tessellated into.
pub const MAX_SEGMENTS_LIMIT: u32 = 1024;
/// The most segments around a cluster tube.
pub const MAX_AROUND_SEGMENTS_LIMIT: u32 = 64;

impl Tessellation {
    /// Segments along a chain whose root is `distance` [m] from the camera.
    pub fn segments_at(&self, distance: f32) -> u32 {
        scaled_count(
            self.max_segments,
            self.min_segments,
            self.full_detail_distance,
            distance,
        )
    }

    /// Segments around a cluster tube whose ring radius is `ring_radius` [m], `distance` [m] from
    /// a camera of focal length `focal_pixels` [pixels]: `ceil(π / acos(1 − ε/R))` for the ring's
    /// on-screen radius `R` [pixels] and `ε = max_chord_error_pixels`, clamped to
    /// `min_around_segments..=max_around_segments` (the least for a ring under `ε`, a non-finite
    /// or non-positive distance, or a zero radius).
    pub fn around_segments_for(&self, ring_radius: f32, distance: f32, focal_pixels: f32) -> u32 {
        let (min, max) = (
            self.min_around_segments.min(self.max_around_segments),
            self.max_around_segments,
        );
        let on_screen = ring_radius * focal_pixels / distance;
        if !(on_screen.is_finite() && on_screen > self.max_chord_error_pixels) {
            return min;
        }
        // The chord of an n-gon inscribed in a circle of radius R sits R(1 − cos(π/n)) inside it.
        let wanted = std::f32::consts::PI / (1.0 - self.max_chord_error_pixels / on_screen).acos();
        (wanted.ceil().min(max as f32) as u32).clamp(min, max)
    }
}

/// `clamp(ceil(max · full / distance), min, max)`; `min` for a non-finite distance.
fn scaled_count(max: u32, min: u32, full_detail_distance: f32, distance: f32) -> u32 {
    if !distance.is_finite() {
        return min.min(max);
    }
    let wanted = max as f32 * full_detail_distance / distance.max(1e-6);
    (wanted.ceil().min(max as f32) as u32).clamp(min.min(max), max)
}

/// A directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    /// Direction from the scene towards the light (normalised when used).
    pub direction: Vec3,
    /// Light colour and intensity.
    pub color: Vec3,
    /// Ambient light added everywhere.
    pub ambient: Vec3,
}

impl Default for DirectionalLight {
    /// White light from the upper front right, a little ambient.
    fn default() -> Self {
        DirectionalLight {
            direction: Vec3::new(0.5, 0.7, 1.0).normalize(),
            color: Vec3::ONE,
            ambient: Vec3::splat(0.08),
        }
    }
}

hair_core::named_enum! {
    /// How much of a pixel a strand drawn as a 1-pixel line covers.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum LineCoverage {
        /// The whole pixel: a sub-pixel strand is drawn as if a pixel wide.
        #[default]
        Pixel = "pixel",
        /// Its projected width's share `w·f/z` of each pixel (the ribbon width of
        /// [`StrandStyle::Ribbons`]), as that share of the pixel's MSAA samples, picked by a hash of
        /// the strand and the pixel so that overlapping strands cover different samples and add up
        /// (stochastic transparency, order-independent). Single-sampled, and on the GL backend
        /// (whose shader writer cannot set the sample mask in wgpu 30), the whole fragment is kept
        /// with that probability instead: the same mean, more noise.
        Width = "width",
    }
}

/// Everything a frame needs besides the geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameSettings {
    /// Image width [pixels].
    pub width: u32,
    /// Image height [pixels].
    pub height: u32,
    /// The camera.
    pub camera: Camera,
    /// The light.
    pub light: DirectionalLight,
    /// Background colour.
    pub background: Vec3,
    /// Shaded or colour-coded.
    pub mode: ShadingMode,
    /// Hair colours and shading coefficients.
    pub hair: HairMaterial,
    /// Head colour (Lambert-lit in [`ShadingMode::Shaded`]).
    pub head_color: Vec3,
    /// Lines or ribbons.
    pub strand_style: StrandStyle,
    /// Where strands drawn as lines are shaded.
    pub line_shading: LineShading,
    /// Segments per strand.
    pub tessellation: Tessellation,
    /// Colours of the colour-coding mode.
    pub level_colors: LevelColors,
    /// Self-shadowing of the hair (deep opacity maps).
    pub shadows: SelfShadowing,
    /// Texture of clusters and patches.
    pub surface_texture: SurfaceTexture,
    /// Cluster tubes drawn as view-facing stand-ins or tessellated.
    pub cluster_geometry: ClusterGeometry,
    /// How much of a pixel a strand line covers.
    pub line_coverage: LineCoverage,
    /// How many of a strand group's strands are drawn (all by default).
    pub strand_thinning: StrandThinning,
}

impl FrameSettings {
    /// A `width`×`height` [pixels] frame through `camera` with default light, materials and style.
    pub fn new(width: u32, height: u32, camera: Camera) -> FrameSettings {
        FrameSettings {
            width,
            height,
            camera,
            light: DirectionalLight::default(),
            background: Vec3::new(0.02, 0.02, 0.03),
            mode: ShadingMode::Shaded,
            hair: HairMaterial::default(),
            head_color: Vec3::new(0.6, 0.42, 0.33),
            strand_style: StrandStyle::default(),
            line_shading: LineShading::default(),
            tessellation: Tessellation::default(),
            level_colors: LevelColors::default(),
            shadows: SelfShadowing::default(),
            surface_texture: SurfaceTexture::default(),
            cluster_geometry: ClusterGeometry::default(),
            line_coverage: LineCoverage::default(),
            strand_thinning: StrandThinning::default(),
        }
    }

    /// Checks sizes, the camera and that every value is finite and in range.
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 {
            return Err(invalid(format!(
                "image size {}x{}: both sides must be at least 1 pixel",
                self.width, self.height
            )));
        }
        self.camera
            .validate()
            .map_err(|error| invalid(error.to_string()))?;
        self.strand_thinning.validate()?;
        let colors = [
            ("light direction", self.light.direction),
            ("light colour", self.light.color),
            ("ambient light", self.light.ambient),
            ("background", self.background),
            ("dark hair colour", self.hair.dark_color),
            ("light hair colour", self.hair.light_color),
            ("head colour", self.head_color),
            ("strand code colour", self.level_colors.strands),
            ("cluster code colour", self.level_colors.clusters),
            ("patch code colour", self.level_colors.patches),
            ("head code colour", self.level_colors.head),
        ];
        for (name, value) in colors {
            if !value.is_finite() {
                return Err(invalid(format!("{name} is not finite: {value}")));
            }
        }
        if self.light.direction.length_squared() < 1e-12 {
            return Err(invalid("light direction is zero"));
        }
        let coefficients = [
            ("diffuse", self.hair.diffuse),
            ("specular", self.hair.specular),
            ("specular exponent", self.hair.specular_exponent),
        ];
        for (name, value) in coefficients {
            if !(value.is_finite() && value >= 0.0) {
                return Err(invalid(format!(
                    "hair {name} coefficient {value} must be finite and ≥ 0"
                )));
            }
        }
        if let HairShading::Marschner(model) = self.hair.shading {
            model.validate().map_err(invalid)?;
        }
        if self.line_coverage == LineCoverage::Width
            && !matches!(self.strand_style, StrandStyle::Ribbons { width, .. } if width > 0.0)
        {
            return Err(invalid(
                "line coverage by width needs the hair width: strand style ribbons with a width > 0",
            ));
        }
        if let StrandStyle::Ribbons {
            width,
            min_width_pixels,
        } = self.strand_style
            && !(width.is_finite()
                && width >= 0.0
                && min_width_pixels.is_finite()
                && min_width_pixels >= 0.0)
        {
            return Err(invalid(format!(
                "ribbon width {width} m / {min_width_pixels} px must be finite and ≥ 0"
            )));
        }
        let t = self.tessellation;
        if t.min_segments == 0
            || t.min_segments > t.max_segments
            || t.max_segments > MAX_SEGMENTS_LIMIT
        {
            return Err(invalid(format!(
                "tessellation needs 1 ≤ min_segments ≤ max_segments ≤ {MAX_SEGMENTS_LIMIT} \
                 (got {}..{})",
                t.min_segments, t.max_segments
            )));
        }
        if t.min_around_segments < 3
            || t.min_around_segments > t.max_around_segments
            || t.max_around_segments > MAX_AROUND_SEGMENTS_LIMIT
        {
            return Err(invalid(format!(
                "tessellation needs 3 ≤ min_around_segments ≤ max_around_segments ≤ \
                 {MAX_AROUND_SEGMENTS_LIMIT} (got {}..{})",
                t.min_around_segments, t.max_around_segments
            )));
        }
        if !(t.max_chord_error_pixels.is_finite() && t.max_chord_error_pixels > 0.0) {
            return Err(invalid(format!(
                "tessellation chord error {} px must be finite and > 0",
                t.max_chord_error_pixels
            )));
        }
        self.shadows.validate()?;
        if !(t.full_detail_distance.is_finite() && t.full_detail_distance > 0.0) {
            return Err(invalid(format!(
                "full-detail distance {} m must be finite and > 0",
                t.full_detail_distance
            )));
        }
        Ok(())
    }
}

/// How many of a strand group's strands are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum StrandThinning {
    /// Every strand (the default, and what a reference render needs).
    #[default]
    Off,
    /// As many as `strands_per_pixel` times the group's projected width [pixels], at least one
    /// and at most all: a group `2r` wide [m] at distance `d` [m] through a focal length of
    /// `f` pixels draws `max(1, k·2r·f/d)` of its `n` strands.
    ByScreenWidth {
        /// Strands kept per pixel of the group's width (k above; 4 covers a group's pixels as
        /// fully as all its strands do, see `docs/render.md`).
        strands_per_pixel: f32,
        /// Widen each drawn strand so that the group covers what all its strands cover: a
        /// strand drawn `p` pixels wide standing for `1/φ` strands (φ the drawn fraction) is
        /// drawn `p/φ` wide, at most the group's own projected width (so that a group thinned to
        /// one strand draws one strand as wide as the group: an aggregated strand). Needs
        /// [`StrandStyle::Ribbons`]; lines keep their pixel.
        raise_widths: bool,
    },
}

impl StrandThinning {
    /// Checks that `strands_per_pixel` is finite and positive.
    pub fn validate(&self) -> Result<()> {
        match *self {
            StrandThinning::Off => Ok(()),
            StrandThinning::ByScreenWidth {
                strands_per_pixel, ..
            } => {
                if strands_per_pixel.is_finite() && strands_per_pixel > 0.0 {
                    Ok(())
                } else {
                    Err(invalid(format!(
                        "strand thinning's strands per pixel is {strands_per_pixel} (allowed: finite, > 0)"
                    )))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::marschner::Marschner;

    #[test]
    fn segment_count_falls_with_distance() {
        let t = Tessellation::default();
        assert_eq!(t.segments_at(0.5), 32);
        assert_eq!(t.segments_at(1.0), 32);
        assert_eq!(t.segments_at(2.0), 16);
        assert_eq!(t.segments_at(100.0), 4);
        assert_eq!(t.segments_at(f32::INFINITY), 4);
    }

    /// A ring of radius R pixels needs n = ceil(π / acos(1 − ε/R)) segments for a chord error
    /// of at most ε: R = 10 px, ε = 0.5 px gives π / acos(0.95) = 9.93, so 10; the n-gon's chord
    /// error R(1 − cos(π/n)) is then within ε and that of n − 1 is not.
    /// With the default ε = 1 px: R = 10 px gives π / acos(0.9) = 6.97, so 7; R = 5 px gives
    /// π / acos(0.8) = 4.88, so 5.
    #[test]
    fn segments_around_follow_the_projected_ring() {
        let default = Tessellation::default();
        assert_eq!(default.around_segments_for(0.005, 1.0, 2000.0), 7);
        assert_eq!(default.around_segments_for(0.005, 2.0, 2000.0), 5);
        let t = Tessellation {
            max_chord_error_pixels: 0.5,
            ..default
        };
        // 10 px: 5 mm at 1 m with a 2000 px focal length.
        let n = t.around_segments_for(0.005, 1.0, 2000.0);
        assert_eq!(n, 10);
        let chord = |n: u32| 10.0 * (1.0 - (std::f32::consts::PI / n as f32).cos());
        assert!(chord(n) <= 0.5 && chord(n - 1) > 0.5);
        // Twice as far: R = 5 px, π / acos(0.9) = 6.97, so 7.
        assert_eq!(t.around_segments_for(0.005, 2.0, 2000.0), 7);
        // Large on screen: capped; tiny, behind or degenerate: the least.
        assert_eq!(t.around_segments_for(0.05, 0.1, 2000.0), 12);
        assert_eq!(t.around_segments_for(0.005, 100.0, 2000.0), 4);
        assert_eq!(t.around_segments_for(0.0, 1.0, 2000.0), 4);
        assert_eq!(t.around_segments_for(0.005, f32::INFINITY, 2000.0), 4);
        assert_eq!(t.around_segments_for(0.005, 0.0, 2000.0), 4);
    }

    #[test]
    fn settings_are_validated() {
        let good = FrameSettings::new(64, 48, Camera::default());
        assert!(good.validate().is_ok());
        assert!(FrameSettings { width: 0, ..good }.validate().is_err());
        let mut bad = good;
        bad.light.direction = Vec3::ZERO;
        assert!(bad.validate().is_err());
        let mut bad = good;
        bad.tessellation.min_segments = 0;
        assert!(bad.validate().is_err());
        let mut bad = good;
        bad.tessellation.max_chord_error_pixels = 0.0;
        assert!(bad.validate().unwrap_err().to_string().contains("chord"));
        let mut bad = good;
        bad.tessellation.min_around_segments = 2;
        assert!(bad.validate().unwrap_err().to_string().contains("around"));
        let mut bad = good;
        bad.hair.shading = HairShading::Marschner(Marschner {
            width: -1.0,
            ..Marschner::default()
        });
        assert!(bad.validate().unwrap_err().to_string().contains("width"));
        let mut bad = good;
        bad.line_coverage = LineCoverage::Width;
        bad.strand_style = StrandStyle::Lines;
        assert!(bad.validate().unwrap_err().to_string().contains("coverage"));
        let mut bad = good;
        bad.hair.light_color = Vec3::NAN;
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("light hair colour")
        );
    }
}
