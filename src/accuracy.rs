//! How far a configuration's frames are from the reference's: image, geometric and physical error
//! metrics (issue 7).
//!
//! The *reference* is the most accurate run of a scene ([`reference_settings`]: every section at
//! strand level, the linear-implicit integrator at 1/6000 s, collision on); any other
//! configuration is run on the same control inputs (camera, head motion, wind) and compared with
//! it frame by frame:
//!
//! - **image**: [`ssim`] (from the `image-compare` crate, on luma) and [`psnr`] (from the mean
//!   squared error over the RGB channels) of the rendered frame against the reference frame;
//! - **geometric**: [`geometric_error`], the mean and 95th-percentile screen-space distance
//!   [pixels] between corresponding hair samples (see [`strand_skeletons`] for the
//!   correspondence), over the samples the viewer sees of the reference
//!   ([`geometric_error_of_visible`], [`visible_samples`]: hair behind the head does not count);
//! - **physical**: [`segment_length_error`] (relative, max over every simulated segment) and
//!   [`penetration_depth`] [m] (max over every free simulated node) against a collision body.
//!
//! ```
//! use hairlod::accuracy::{geometric_error, sample_skeletons, strand_skeletons};
//! use hairlod::core::dynamics::Environment;
//! use hairlod::pipeline::{Pipeline, PipelineSettings, LodMode};
//! use hairlod::{Camera, Level, Scene};
//!
//! let settings = PipelineSettings { lod: LodMode::Fixed(Level::Patch), ..Default::default() };
//! let mut pipeline = Pipeline::new(Scene::preset("curly")?, Environment::default(), settings)?;
//! let camera = Camera::default();
//! pipeline.advance(&camera)?;
//! let groom = &pipeline.scene().groom;
//! let samples = sample_skeletons(groom, &strand_skeletons(&pipeline)?, 8);
//! // Compared with itself, a frame has no error.
//! let error = geometric_error(&camera, 160, 120, &samples, &samples);
//! assert_eq!(error.mean_pixels, 0.0);
//! # Ok::<(), hairlod::pipeline::PipelineError>(())
//! ```

use glam::Vec3;
use hair_collide::{BroadPhase, CollisionBody, LineOfSight};
use hair_core::dynamics::{IntegratorKind, SimulationSettings};
use hair_core::lod::{SectionStateRef, hand_over};
use hair_core::{Camera, Groom, Level};
use serde::{Deserialize, Serialize};

use crate::pipeline::{DrawnAs, LodMode, Pipeline, PipelineSettings, Result};

pub use crate::metrics::{ImageError, image_error, luma, psnr, ssim};

/// Substeps per 60 Hz frame of the reference run: 100, a step of 1/6000 s, the step at which the
/// stability map (`hairlod stability`, `docs/dynamics.md`) takes linear-implicit as converged.
pub const REFERENCE_SUBSTEPS: u32 = 100;

/// The reference configuration: every section at strand level, the linear-implicit integrator
/// (the widest stable region) at [`REFERENCE_SUBSTEPS`] per 60 Hz frame, collision on.
pub fn reference_settings() -> PipelineSettings {
    PipelineSettings {
        lod: LodMode::Fixed(Level::StrandGroup),
        drawn_as: DrawnAs::Level,
        dynamics: SimulationSettings::new(
            IntegratorKind::LinearImplicit,
            1.0 / 60.0,
            REFERENCE_SUBSTEPS,
        ),
        collision: true,
        broad_phase: BroadPhase::default(),
    }
}

/// Every section's five strand-group skeletons as the pipeline's current state puts them [m]:
/// chain-major in the groom's strand-group chain order (section by section, five chains each, the
/// groom's node count per chain), the layout of `groom.level_chains(Level::StrandGroup)`.
///
/// This is the correspondence of the geometric error: a section simulated at strand level gives
/// its own skeletons; a section simulated as clusters or a patch gives the skeletons its strands
/// would have, i.e. the state its level hands down to strand level ([`hand_over`], §4.2): the
/// centre strand group is the centre cluster or the patch skeleton exactly (all levels share the
/// section's root and the centre child inherits), the others are interpolated between clusters or
/// moved across the section from the outermost skeleton, then put on their own roots with their
/// rest segment lengths. So a coarse level is charged both for its dynamics and for the strand
/// positions it cannot represent.
pub fn strand_skeletons(pipeline: &Pipeline) -> Result<Vec<Vec3>> {
    let groom = &pipeline.scene().groom;
    let skeletons = &groom.skeletons;
    let chains = groom.level_chains(Level::StrandGroup);
    let first_node = skeletons.offsets[chains.start] as usize;
    let mut out = vec![Vec3::ZERO; skeletons.offsets[chains.end] as usize - first_node];
    let mut velocities = Vec::new();
    let roots = pipeline.chain_roots();
    for (section, &level) in pipeline.section_levels().iter().enumerate() {
        let target = groom.section_chains(section, Level::StrandGroup);
        let range = skeletons.offsets[target.start] as usize - first_node
            ..skeletons.offsets[target.end] as usize - first_node;
        let block = pipeline.block(level);
        let Some(slot) = block.slot(section) else {
            continue;
        };
        let nodes = block.nodes(slot);
        let positions = &block.state.node_positions[nodes.clone()];
        if level == Level::StrandGroup {
            out[range].copy_from_slice(positions);
            continue;
        }
        velocities.clear();
        velocities.resize(range.len(), Vec3::ZERO);
        hand_over(
            groom,
            section,
            level,
            SectionStateRef {
                positions,
                velocities: &block.state.node_velocities[nodes],
            },
            Level::StrandGroup,
            &mut out[range],
            &mut velocities,
            &roots,
        )?;
    }
    Ok(out)
}

/// Samples every strand-group skeleton of `skeletons` (the layout of [`strand_skeletons`]) at
/// `per_skeleton` equal arc-length fractions `k / (per_skeleton − 1)`, root to tip, of its
/// polyline [m]; chain-major. Equal fractions (rather than equal node indices) make the samples
/// of two configurations correspond even where a skeleton is stretched.
pub fn sample_skeletons(groom: &Groom, skeletons: &[Vec3], per_skeleton: usize) -> Vec<Vec3> {
    let rest = &groom.skeletons;
    let chains = groom.level_chains(Level::StrandGroup);
    let first_node = rest.offsets[chains.start] as usize;
    let mut samples = Vec::with_capacity(chains.len() * per_skeleton);
    let mut cumulative = Vec::new();
    for chain in chains {
        let nodes = rest.nodes(chain);
        let polyline = &skeletons[nodes.start - first_node..nodes.end - first_node];
        cumulative.clear();
        cumulative.push(0.0f32);
        for pair in polyline.windows(2) {
            let last = *cumulative.last().unwrap_or(&0.0);
            cumulative.push(last + pair[0].distance(pair[1]));
        }
        let total = *cumulative.last().unwrap_or(&0.0);
        for k in 0..per_skeleton {
            let fraction = if per_skeleton > 1 {
                k as f32 / (per_skeleton - 1) as f32
            } else {
                0.0
            };
            let s = fraction * total;
            // The segment holding arc length s.
            let i = cumulative
                .partition_point(|&c| c < s)
                .clamp(1, polyline.len().max(2) - 1);
            let point = if polyline.len() < 2 {
                polyline.first().copied().unwrap_or(Vec3::ZERO)
            } else {
                let (a, b) = (cumulative[i - 1], cumulative[i]);
                let t = if b > a { (s - a) / (b - a) } else { 0.0 };
                polyline[i - 1].lerp(polyline[i], t.clamp(0.0, 1.0))
            };
            samples.push(point);
        }
    }
    samples
}

/// Screen-space distance between corresponding hair samples of a configuration and the reference
/// in one frame [pixels].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct GeometricError {
    /// Mean distance [pixels].
    pub mean_pixels: f64,
    /// 95th percentile (nearest rank) of the distances [pixels].
    pub p95_pixels: f64,
    /// Largest distance [pixels].
    pub max_pixels: f64,
    /// Samples compared: those whose reference sample projects into the image (and whose
    /// configuration sample is in front of the camera).
    pub samples: usize,
}

/// The geometric error of `samples` against `reference` (same layout, e.g. from
/// [`sample_skeletons`]), both projected by `camera` into a `width`×`height` image. Only samples
/// the viewer can see count: those whose reference sample lands inside the image. A configuration
/// sample behind the camera while its reference is in view counts as the image diagonal (it is
/// off-screen, as wrong as a sample can be). All zero when no sample is in view.
pub fn geometric_error(
    camera: &Camera,
    width: u32,
    height: u32,
    reference: &[Vec3],
    samples: &[Vec3],
) -> GeometricError {
    geometric_error_where(camera, width, height, reference, samples, |_| true)
}

/// [`geometric_error`] over the samples a viewer sees of the reference: only samples whose
/// `visible` entry is true count (`visible` from [`visible_samples`] on the reference; entries
/// past its end count as hidden).
pub fn geometric_error_of_visible(
    camera: &Camera,
    width: u32,
    height: u32,
    reference: &[Vec3],
    samples: &[Vec3],
    visible: &[bool],
) -> GeometricError {
    geometric_error_where(camera, width, height, reference, samples, |i| {
        visible.get(i).copied().unwrap_or(false)
    })
}

/// How far in front of a body's surface a sample still counts as seen [m]: hair roots sit on the
/// scalp, and the head's tessellation may put the true surface up to about a millimetre away.
pub const SIGHT_MARGIN: f32 = 2e-3;

/// Which of `samples` [m] a viewer at `camera`'s position sees past the head (`sight`, posed
/// where the head is): see [`LineOfSight::is_visible`] with [`SIGHT_MARGIN`]. Hair hiding hair
/// is not counted as hidden (the strands are thin and the reference's own strands show through).
pub fn visible_samples(camera: &Camera, sight: &LineOfSight, samples: &[Vec3]) -> Vec<bool> {
    samples
        .iter()
        .map(|&p| sight.is_visible(camera.position, p, SIGHT_MARGIN))
        .collect()
}

/// The head of `pipeline`'s scene as a line-of-sight blocker, posed where the head is at the
/// pipeline's current time (for [`visible_samples`]).
pub fn head_sight(pipeline: &Pipeline) -> Result<LineOfSight> {
    let mut sight = LineOfSight::new(&pipeline.scene().head.mesh)?;
    let pose = pipeline.environment().head.transform_at(pipeline.time());
    sight.set_pose(pose.rotation, pose.translation)?;
    Ok(sight)
}

fn geometric_error_where(
    camera: &Camera,
    width: u32,
    height: u32,
    reference: &[Vec3],
    samples: &[Vec3],
    counts: impl Fn(usize) -> bool,
) -> GeometricError {
    let diagonal = f64::from(width).hypot(f64::from(height));
    let mut distances: Vec<f64> = reference
        .iter()
        .zip(samples)
        .enumerate()
        .filter(|(i, _)| counts(*i))
        .filter_map(|(_, (&r, &s))| {
            let r = camera.project_to_pixel(r, width, height)?;
            let inside =
                (0.0..=width as f32).contains(&r.x) && (0.0..=height as f32).contains(&r.y);
            if !inside {
                return None;
            }
            Some(match camera.project_to_pixel(s, width, height) {
                Some(s) => f64::from(r.distance(s)).min(diagonal),
                None => diagonal,
            })
        })
        .collect();
    if distances.is_empty() {
        return GeometricError::default();
    }
    distances.sort_by(f64::total_cmp);
    let n = distances.len();
    let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n) - 1;
    GeometricError {
        mean_pixels: distances.iter().sum::<f64>() / n as f64,
        p95_pixels: distances[rank],
        max_pixels: distances[n - 1],
        samples: n,
    }
}

/// Largest relative segment-length error `|l − l0| / l0` over every simulated segment of every
/// level block of `pipeline` (dimensionless; 0: every segment at its rest length).
pub fn segment_length_error(pipeline: &Pipeline) -> f32 {
    let mut worst = 0.0f32;
    for level in Level::ALL {
        let block = pipeline.block(level);
        let rest = &pipeline.scene().groom.skeletons;
        let positions = &block.state.node_positions;
        let mut first = 0;
        for &chain in &block.chains {
            let groom_nodes = rest.nodes(chain);
            for k in 1..groom_nodes.len() {
                let rest_length = rest.segment_rest_lengths[groom_nodes.start + k];
                if rest_length > 0.0 {
                    let length = positions[first + k].distance(positions[first + k - 1]);
                    worst = worst.max((length - rest_length).abs() / rest_length);
                }
            }
            first += groom_nodes.len();
        }
    }
    worst
}

/// Deepest penetration [m] of any free simulated node of `pipeline` into `body` (the depth of
/// the deepest node inside, 0 when none is inside). `body` must be posed where the pipeline's head
/// is (for a moving head: `body.set_pose` with the head transform at [`Pipeline::time`]).
///
/// Attached roots ([`RootMode::Attached`](hair_core::dynamics::RootMode)) are left out, as the
/// collision stage's guarantee leaves them out: they are not simulated but pinned to the scalp
/// where the groom put them, which for the built-in heads is the analytic surface, and the
/// tessellated mesh cuts under it by up to its sagitta (see [`root_penetration_depth`]).
pub fn penetration_depth(pipeline: &Pipeline, body: &CollisionBody) -> f32 {
    let attached = roots_attached(pipeline);
    deepest_inside(pipeline, body, |k| k > 0 || !attached)
}

/// Deepest penetration [m] of any attached root of `pipeline` into `body` (0 when roots are free
/// or none is inside): how far the groom's roots lie under the body's mesh.
pub fn root_penetration_depth(pipeline: &Pipeline, body: &CollisionBody) -> f32 {
    let attached = roots_attached(pipeline);
    deepest_inside(pipeline, body, |k| k == 0 && attached)
}

fn roots_attached(pipeline: &Pipeline) -> bool {
    pipeline.settings().dynamics.roots == hair_core::dynamics::RootMode::Attached
}

/// The deepest of the simulated nodes inside `body` whose index along its chain `counts`.
fn deepest_inside(
    pipeline: &Pipeline,
    body: &CollisionBody,
    counts: impl Fn(usize) -> bool,
) -> f32 {
    let rest = &pipeline.scene().groom.skeletons;
    let mut deepest = 0.0f32;
    for level in Level::ALL {
        let block = pipeline.block(level);
        let mut first = 0;
        for &chain in &block.chains {
            let count = rest.nodes(chain).len();
            let nodes = &block.state.node_positions[first..first + count];
            for (k, &p) in nodes.iter().enumerate() {
                if counts(k)
                    && let Some(distance) = body.signed_distance(p)
                {
                    deepest = deepest.max(-distance);
                }
            }
            first += count;
        }
    }
    deepest
}

/// The physical error of one frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PhysicalError {
    /// Largest relative segment-length error (see [`segment_length_error`]).
    pub segment_length: f32,
    /// Deepest penetration of a free node into the head [m] (see [`penetration_depth`]).
    pub penetration: f32,
    /// Deepest attached root under the head's mesh [m] (see [`root_penetration_depth`]).
    #[serde(default)]
    pub root_penetration: f32,
}

impl PhysicalError {
    /// The physical error of `pipeline`'s current state against `body`.
    pub fn of(pipeline: &Pipeline, body: &CollisionBody) -> Self {
        PhysicalError {
            segment_length: segment_length_error(pipeline),
            penetration: penetration_depth(pipeline, body),
            root_penetration: root_penetration_depth(pipeline, body),
        }
    }

    /// The worse of `self` and `other`, field by field (for the max over a run).
    pub fn max(self, other: PhysicalError) -> PhysicalError {
        PhysicalError {
            segment_length: self.segment_length.max(other.segment_length),
            penetration: self.penetration.max(other.penetration),
            root_penetration: self.root_penetration.max(other.root_penetration),
        }
    }
}

/// The head of `pipeline`'s scene as a collision body, posed where the head is at the pipeline's
/// current time (for [`penetration_depth`]).
pub fn head_body(pipeline: &Pipeline) -> Result<CollisionBody> {
    let mut body = CollisionBody::from_mesh(&pipeline.scene().head.mesh)?;
    pose_head_body(&mut body, pipeline)?;
    Ok(body)
}

/// Moves a body from [`head_body`] to where `pipeline`'s head is at its current time (for a run:
/// build the body once, pose it every frame).
pub fn pose_head_body(body: &mut CollisionBody, pipeline: &Pipeline) -> Result<()> {
    let pose = pipeline.environment().head.transform_at(pipeline.time());
    body.set_pose(pose.rotation, pose.translation)?;
    Ok(())
}
