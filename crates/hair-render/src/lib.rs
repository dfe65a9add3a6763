//! `hair-render`: the headless wgpu renderer of hairlod (§6 of *Simplified Representations for
//! Modeling Hair*).
//!
//! # What it does
//!
//! - **Device** ([`device`]): any adapter, a real GPU first, falling back to Mesa's CPU drivers
//!   (lavapipe on Vulkan, llvmpipe through EGL on GL). `HAIRLOD_BACKEND=vulkan|gl|auto` or
//!   [`DeviceOptions::backend`] picks the backend; [`AdapterReport`] says what was found, and when
//!   nothing is, the error says what to install.
//! - **Geometry on the GPU**: per frame only the skeleton nodes ([`SkeletonFrame`]: chain offsets,
//!   node positions and frames) are uploaded; the per-strand data ([`StrandSet`]: chain, root offset
//!   in the node frame, shade) is uploaded once. The vertex shader pulls nodes from storage buffers,
//!   builds the strand's control points `p_k + o.x·n_k + o.y·b_k` and evaluates its clamped uniform
//!   cubic B-spline ([`bspline`] is the CPU reference), tessellated into a number of segments that
//!   falls with camera distance ([`Tessellation`]). Strands are camera-facing ribbons or lines.
//! - **Shading**: Kajiya-Kay in the Heidrich-Seidel form from the curve tangent only (diffuse
//!   ∝ sin(T, L), specular ∝ (sin(T, L)·sin(T, V) − (T·L)(T·V))^p), or Marschner's R, TT and TRT
//!   lobes ([`HairShading`], [`Marschner`]), per-strand shade within a hair colour range
//!   ([`HairMaterial`]); sub-pixel strand lines can cover their width's share of a pixel
//!   ([`LineCoverage`]); the head ([`hair_core::TriangleMesh`]) is Lambert-lit and
//!   hides hair behind it by depth. 4× MSAA by default.
//! - **Clusters and patches** ([`ClusterSet`], [`PatchSet`]): closed tubes (4 control points per
//!   node, periodic cubic around) and ruled strips (2 per node, linear across), evaluated in the
//!   vertex shader from the same node buffers; a tube is drawn as its view-facing silhouette with
//!   the tube's normal rebuilt per fragment ([`ClusterGeometry::Impostor`], the default) or
//!   tessellated around ([`ClusterGeometry::Tube`]); shaded with Kajiya-Kay along the hair on a procedural
//!   hair texture in the hair colour range ([`SurfaceTexture`]: shades drifting along the hair,
//!   strands of their own lengths, a thinning silhouette by alpha-to-coverage).
//! - **Self-shadowing** ([`SelfShadowing`], [`shadows`]): deep opacity maps drawn from the active
//!   strands, clusters and patches; hair and head receive.
//! - **Strand shapes** ([`StrandShapes`]): per-strand lengths and tip scales (strands gathering
//!   towards their skeleton on the way to the tip). [`Renderer::upload_groom`] uploads all three levels
//!   of a groom; [`ActiveSkeletons`] builds the per-frame node buffer of the active skeletons
//!   (chains without nodes draw nothing).
//! - **Tessellation** per chain from its root's camera distance, drawn in instanced batches of
//!   equal tessellation (no collapsed vertices); strand curves are evaluated once per chain sample
//!   in a compute pass and shared by the chain's strands.
//! - **LOD colour coding** ([`ShadingMode::LevelColors`], Fig. 6): strands flat yellow, clusters
//!   red, patches blue, the head flat grey; [`Renderer::render_side_by_side`] gives shaded |
//!   colour-coded.
//! - **Output** ([`output`]): atomic PNG writes, sortable frame names, side-by-side and contact
//!   sheets.
//!
//! # Example
//!
//! ```no_run
//! use glam::{Vec2, Vec3};
//! use hair_render::{Camera, FrameSettings, Renderer, RendererOptions, SkeletonFrame, StrandSet};
//!
//! # fn main() -> Result<(), hair_render::RenderError> {
//! let mut renderer = Renderer::new(&RendererOptions::from_env()?)?;
//! println!("rendering on {}", renderer.adapter_report());
//! // One chain of three nodes hanging down, one strand on it.
//! let positions = [Vec3::ZERO, Vec3::new(0.0, -0.1, 0.0), Vec3::new(0.0, -0.2, 0.0)];
//! let normals = [Vec3::X; 3];
//! let binormals = [Vec3::Z; 3];
//! renderer.upload_strands(&StrandSet {
//!     strand_chain: &[0],
//!     strand_root_offsets: &[Vec2::ZERO],
//!     strand_shades: &[0.5],
//! })?;
//! let frame = SkeletonFrame {
//!     chain_offsets: &[0, 3],
//!     node_positions: &positions,
//!     node_normals: &normals,
//!     node_binormals: &binormals,
//!     chain_coverage: &[],
//!     chain_gives_way: &[],
//!     chain_simulated_at: &[],
//! };
//! let image = renderer.render(&frame, &FrameSettings::new(320, 240, Camera::default()))?;
//! hair_render::output::write_png_atomic(&image, std::path::Path::new("frame_00000.png"))?;
//! # Ok(())
//! # }
//! ```
//!
//! See `docs/render.md` for the shading, the CLI and measured figures.

pub mod active;
pub mod bspline;
pub mod camera;
pub mod device;
pub mod drawn_counts;
pub mod error;
pub mod groom;
pub mod inputs;
pub mod marschner;
mod material;
pub mod output;
pub mod renderer;
pub mod settings;
pub mod shadows;
pub mod strand_shapes;
pub mod surfaces;
pub mod target;
pub mod thinning;
pub mod timings;

mod batches;
mod buffers;
mod chain_curves;
mod evaluate;
mod head;
mod items;
mod main_pass;
mod pipelines;
mod readback;
mod scene_inputs;
mod scopes;
mod shadow_maps;
mod shadow_pass;
mod shadow_pipelines;
mod uniforms;
mod warm_up;

pub use active::ActiveSkeletons;
pub use groom::GroomGeometry;
pub use surfaces::{ClusterSet, PatchSet};

pub use camera::Camera;
pub use device::{
    AdapterReport, BACKEND_ENV_VAR, BackendChoice, DeviceOptions, GpuContext, acquire_device,
    acquire_device_for_surface,
};
pub use drawn_counts::DrawnCounts;
pub use error::{RenderError, Result};
pub use inputs::{SkeletonFrame, StrandSet};
pub use marschner::Marschner;
pub use material::{HairMaterial, HairShading, ShadingModel};
pub use renderer::{Renderer, RendererOptions};
pub use settings::StrandThinning;
pub use settings::{
    ClusterGeometry, DirectionalLight, FrameSettings, IMPOSTOR_BANDS, LevelColors, LineCoverage,
    LineShading, ShadingMode, StrandStyle, SurfaceTexture, Tessellation,
};
pub use shadows::SelfShadowing;
pub use strand_shapes::StrandShapes;
pub use target::RenderTarget;
pub use timings::RenderTimings;
/// The wgpu this renderer is built on (its device, queue and textures), for callers that draw
/// beside it, such as an interactive viewer.
pub use wgpu;
