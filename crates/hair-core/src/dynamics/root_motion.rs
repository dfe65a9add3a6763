//! Roots that ride a deforming body: a [`DeformingBody`] is a mesh sampled in time in the body's
//! own space (the head's, which the head motion then places in the world), and each chain's root
//! rides one of its triangles ([`SurfaceAttachment`]). The triangle carries the root by a rigid
//! transform ([`DeformingBody::carry`]): its point moves with the barycentric point and its
//! frame turns with the triangle, so a chain's root position, root frame and rest directions
//! follow the skin; the head motion is applied after it. Rigid motion is the special case where
//! every triangle is carried by the same transform.

use std::sync::Arc;

use glam::{Mat3, Quat, Vec3};

use crate::dynamics::error::DynamicsError;
use crate::dynamics::head_motion::HeadMotion;
use crate::mesh_sequence::MeshSequence;
use crate::transform::RigidTransform;

/// Where a chain's root rides: one triangle of the body (its index in the body's triangles) and
/// the barycentric point on it (non-negative, sum 1) nearest the root at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceAttachment {
    /// The triangle's index.
    pub triangle: u32,
    /// Barycentric coordinates of the point on it.
    pub barycentric: Vec3,
}

/// A body that deforms over time, in its own space [m, s]: a [`MeshSequence`] whose first sample
/// is the rest shape the roots were attached on. Before the first sample the body is at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct DeformingBody {
    sequence: Arc<MeshSequence>,
}

impl DeformingBody {
    /// The body of `sequence`.
    pub fn new(sequence: Arc<MeshSequence>) -> Self {
        DeformingBody { sequence }
    }

    /// Its samples.
    pub fn sequence(&self) -> &MeshSequence {
        &self.sequence
    }

    /// The rigid transform [body space] that carries what rides `attachment` from rest to time
    /// `time` [s]: the rotation takes the triangle's rest frame (first edge, the in-plane
    /// perpendicular, the normal) to its frame at `time`, and the translation takes the rest
    /// barycentric point to the point at `time`. The identity at or before the first sample; a
    /// triangle of zero area (at rest or at `time`) is carried without turning. Panics when the
    /// attachment's triangle is out of range.
    pub fn carry(&self, attachment: &SurfaceAttachment, time: f64) -> RigidTransform {
        self.carry_between(attachment, self.sequence.bracket(time))
    }

    /// [`DeformingBody::carry`] at the time between the samples `(s0, s1, weight)` that
    /// [`MeshSequence::bracket`] gives for it: many attachments carried to one time look the
    /// samples up once. Panics when the attachment's triangle or a sample is out of range.
    pub fn carry_between(
        &self,
        attachment: &SurfaceAttachment,
        (s0, s1, weight): (usize, usize, f32),
    ) -> RigidTransform {
        if s1 == 0 {
            return RigidTransform::IDENTITY;
        }
        let rest = self.triangle_at(attachment, (0, 0, 0.0));
        let now = self.triangle_at(attachment, (s0, s1, weight));
        let point = |p: [Vec3; 3]| barycentric_point(p, attachment.barycentric);
        let rotation = match (triangle_frame(rest), triangle_frame(now)) {
            (Some(from), Some(to)) => Quat::from_mat3(&(to * from.transpose())).normalize(),
            _ => Quat::IDENTITY,
        };
        RigidTransform {
            rotation,
            translation: point(now) - rotation * point(rest),
        }
    }
}

impl DeformingBody {
    /// The offset of `point` [m, body space] from `attachment`'s point on the rest sample, in
    /// the triangle's rest frame: `F_restᵀ·(point − p_rest)`, what
    /// [`DeformingBody::carry_offset`] takes. `None` where the rest triangle has no frame (zero
    /// area). Panics when the attachment's triangle is out of range.
    pub fn rest_offset(&self, attachment: &SurfaceAttachment, point: Vec3) -> Option<Vec3> {
        let rest = self.triangle_at(attachment, (0, 0, 0.0));
        let frame = triangle_frame(rest)?;
        Some(frame.transpose() * (point - barycentric_point(rest, attachment.barycentric)))
    }

    /// Where the point whose rest offset is `offset` ([`DeformingBody::rest_offset`]) rides
    /// `attachment` to at the time between the samples `bracket` ([`MeshSequence::bracket`]):
    /// `p_now + F_now·offset`, where [`DeformingBody::carry_between`] takes it (its rotation is
    /// `F_now·F_restᵀ`) up to rounding, without building the rotation: many points carried to
    /// one time cost a third as much. `None` at or before the first sample and where the
    /// triangle has no frame now; [`DeformingBody::carry_between`] carries those.
    pub fn carry_offset(
        &self,
        attachment: &SurfaceAttachment,
        offset: Vec3,
        bracket: (usize, usize, f32),
    ) -> Option<Vec3> {
        if bracket.1 == 0 {
            return None;
        }
        let now = self.triangle_at(attachment, bracket);
        let frame = triangle_frame(now)?;
        Some(barycentric_point(now, attachment.barycentric) + frame * offset)
    }

    /// The vertices of `attachment`'s triangle at the time between the samples `(s0, s1, w)`.
    fn triangle_at(
        &self,
        attachment: &SurfaceAttachment,
        (s0, s1, weight): (usize, usize, f32),
    ) -> [Vec3; 3] {
        let sequence = &*self.sequence;
        let vertices = sequence.triangles()[attachment.triangle as usize].map(|v| v as usize);
        let (a, b) = (sequence.sample_positions(s0), sequence.sample_positions(s1));
        vertices.map(|v| a[v].lerp(b[v], weight))
    }
}

/// The point of barycentric coordinates `w` on the triangle `p`.
fn barycentric_point(p: [Vec3; 3], w: Vec3) -> Vec3 {
    p[0] * w.x + p[1] * w.y + p[2] * w.z
}

/// What carries a simulation's roots besides the head: a deforming body and, for each chain of
/// the simulation's model, the point of the body its root rides
/// ([`Simulation::set_root_carrier`](crate::dynamics::Simulation::set_root_carrier)).
#[derive(Debug, Clone, PartialEq)]
pub struct RootCarrier {
    /// The body.
    pub body: Arc<DeformingBody>,
    /// Where each chain's root rides, one per chain of the model.
    pub attachments: Vec<SurfaceAttachment>,
}

impl RootCarrier {
    /// Checks that there is one attachment per chain (`chains`) and that each names a triangle
    /// of the body.
    pub fn validate(&self, chains: usize) -> Result<(), DynamicsError> {
        if self.attachments.len() != chains {
            return Err(DynamicsError::StateMismatch {
                what: "root attachments",
                actual: self.attachments.len(),
                expected: chains,
            });
        }
        let triangles = self.body.sequence().triangles().len();
        if let Some(bad) = self
            .attachments
            .iter()
            .find(|a| a.triangle as usize >= triangles || !a.barycentric.is_finite())
        {
            return Err(DynamicsError::InvalidSetting {
                name: "root attachment",
                value: format!("triangle {} at {}", bad.triangle, bad.barycentric),
                allowed: "a triangle of the deforming body, finite barycentric coordinates",
            });
        }
        Ok(())
    }

    /// Chain `chain`'s root pose at `time` [s]: the head's pose after the body's carry.
    #[inline]
    pub fn pose(&self, chain: usize, head: &HeadMotion, time: f64) -> RigidTransform {
        head.transform_at(time)
            .after(&self.body.carry(&self.attachments[chain], time))
    }
}

/// Where each of a groom's skeleton chains has its root at one moment: on the rigid head, or
/// carried by a deforming body and then by the head. What reads the state at one time and needs
/// the roots (the hand-over between levels, the strands' frames) asks it per chain.
#[derive(Debug, Clone, Copy)]
pub struct ChainRoots<'a> {
    head: RigidTransform,
    carried: Option<(&'a DeformingBody, &'a [SurfaceAttachment], f64)>,
}

impl<'a> ChainRoots<'a> {
    /// Every root on the head posed by `head`.
    pub fn rigid(head: RigidTransform) -> Self {
        Self {
            head,
            carried: None,
        }
    }

    /// Chain `c`'s root carried by `body` at `time` [s] from its `attachments[c]` (one per
    /// chain of the groom), then by `head` (the head's pose at `time`).
    pub fn carried(
        head: RigidTransform,
        body: &'a DeformingBody,
        attachments: &'a [SurfaceAttachment],
        time: f64,
    ) -> Self {
        Self {
            head,
            carried: Some((body, attachments, time)),
        }
    }

    /// The head's pose.
    pub fn head(&self) -> &RigidTransform {
        &self.head
    }

    /// The pose that takes chain `chain`'s rest root (head space) to where it is. Panics when a
    /// carried `chain` has no attachment.
    #[inline]
    pub fn pose(&self, chain: usize) -> RigidTransform {
        match self.carried {
            None => self.head,
            Some((body, attachments, time)) => {
                self.head.after(&body.carry(&attachments[chain], time))
            }
        }
    }
}

/// The roots' poses over one step, as the kernels read them: the head's at the substep
/// boundaries, shared by every chain, or with a [`RootCarrier`] each chain's own.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RootPoses<'a> {
    /// Head poses at the substep boundaries (`substeps + 1`).
    pub head: &'a [RigidTransform],
    /// Their rotations as matrices.
    pub head_rotations: &'a [Mat3],
    /// With a carrier: each chain's poses at the substep boundaries, chain after chain
    /// (`substeps + 1` each).
    pub chains: &'a [RigidTransform],
    /// Their rotations as matrices.
    pub chain_rotations: &'a [Mat3],
    /// The carrier, if any.
    pub carrier: Option<&'a RootCarrier>,
    /// The head's motion (for the boundaries of halved substeps).
    pub head_motion: &'a HeadMotion,
    /// Time at the start of the step [s].
    pub time: f64,
    /// The step's length [s] and its substeps before halving.
    pub time_step: f32,
    pub substeps: u32,
}

impl RootPoses<'_> {
    /// Whether every chain shares the head's pose (no carrier).
    #[inline]
    pub(crate) fn shared(&self) -> bool {
        self.carrier.is_none()
    }

    /// Chain `chain`'s root pose and its rotation matrix at substep boundary `k` of the step split
    /// into `substeps << halvings` substeps: the precomputed ones without halvings, else sampled
    /// at `time + k·h` as those were.
    #[inline]
    pub(crate) fn pose(&self, chain: usize, halvings: u32, k: usize) -> (RigidTransform, Mat3) {
        if halvings == 0 {
            return match self.carrier {
                None => (self.head[k], self.head_rotations[k]),
                Some(_) => {
                    let index = chain * self.head.len() + k;
                    (self.chains[index], self.chain_rotations[index])
                }
            };
        }
        let substeps = (self.substeps as usize) << halvings;
        let h = self.time_step / substeps as f32;
        let time = self.time + k as f64 * h as f64;
        let head = self.head_motion.transform_at(time);
        let pose = match self.carrier {
            None => head,
            Some(carrier) => head.after(&carrier.body.carry(&carrier.attachments[chain], time)),
        };
        (pose, Mat3::from_quat(pose.rotation))
    }
}

/// A triangle's orthonormal frame as matrix columns: the first edge's direction, the in-plane
/// direction perpendicular to it, the unit normal (counter-clockwise). `None` for zero area.
/// What a root riding the triangle turns with, and what a deforming body's moving field turns
/// its gradients with (`hair_collide`).
pub fn triangle_frame([a, b, c]: [Vec3; 3]) -> Option<Mat3> {
    let edge = (b - a).try_normalize()?;
    let normal = (b - a).cross(c - a).try_normalize()?;
    Some(Mat3::from_cols(edge, normal.cross(edge), normal))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit right triangle and a second one beside it, moved through three samples by
    /// `motion(sample)` applied to every vertex.
    fn body(motion: impl Fn(usize, Vec3) -> Vec3) -> DeformingBody {
        let rest = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Z * -1.0,
            Vec3::new(1.0, 0.0, -1.0),
        ];
        let samples = (0..3)
            .map(|s| rest.iter().map(|&p| motion(s, p)).collect())
            .collect();
        let sequence =
            MeshSequence::new(vec![[0, 1, 2], [1, 3, 2]], vec![0.0, 0.5, 1.0], samples).unwrap();
        DeformingBody::new(Arc::new(sequence))
    }

    const ON_FIRST: SurfaceAttachment = SurfaceAttachment {
        triangle: 0,
        barycentric: Vec3::new(0.2, 0.3, 0.5),
    };

    #[test]
    fn a_rigid_motion_of_the_samples_is_carried_exactly() {
        let pose = |s: usize| {
            RigidTransform::new(
                Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 0.4 * s as f32),
                Vec3::new(0.1, -0.2, 0.05) * s as f32,
            )
        };
        let body = body(|s, p| pose(s).transform_point(p));
        for (time, sample) in [(0.5, 1), (1.0, 2), (3.0, 2)] {
            let carried = body.carry(&ON_FIRST, time);
            let expected = pose(sample);
            assert!(carried.rotation.angle_between(expected.rotation) < 1e-5);
            // Any point rides the same transform: the root above the triangle too.
            let root = Vec3::new(0.3, 0.02, -0.4);
            let error = carried.transform_point(root) - expected.transform_point(root);
            assert!(error.length() < 1e-5, "{error}");
        }
        assert_eq!(body.carry(&ON_FIRST, 0.0), RigidTransform::IDENTITY);
        assert_eq!(body.carry(&ON_FIRST, -1.0), RigidTransform::IDENTITY);
    }

    #[test]
    fn a_stretch_moves_the_barycentric_point_and_a_shear_turns_only_what_the_triangle_turns() {
        // Stretch along x by 1 + s: the point follows its barycentric combination, the frame
        // does not turn (the first edge stays along x, the normal along y).
        let stretched = body(|s, p| Vec3::new(p.x * (1.0 + s as f32), p.y, p.z));
        let carried = stretched.carry(&ON_FIRST, 1.0);
        assert!(carried.rotation.angle_between(Quat::IDENTITY) < 1e-6);
        // The rest point (0.3, 0, −0.5) at stretch 3 lies at (0.9, 0, −0.5).
        let point = Vec3::new(0.3, 0.0, -0.5);
        assert!((carried.transform_point(point) - Vec3::new(0.9, 0.0, -0.5)).length() < 1e-6);
        // Between samples the vertices are interpolated: stretch 1.5 at t = 0.25.
        let halfway = stretched.carry(&ON_FIRST, 0.25).transform_point(point);
        assert!((halfway - Vec3::new(0.45, 0.0, -0.5)).length() < 1e-6);
        // Lift the far vertex of the first triangle (z = −1) by 0.5·s: it tilts about the
        // first edge (x) by atan(0.5·s), its normal now (0, cos, sin)·... turned by that angle.
        let tilted = body(|s, p: Vec3| p + Vec3::Y * (0.5 * s as f32) * (-p.z) * (1.0 - p.x));
        let carried = tilted.carry(&ON_FIRST, 1.0);
        let angle = 1f32.atan();
        let expected = Quat::from_axis_angle(Vec3::X, angle);
        assert!(carried.rotation.angle_between(expected) < 1e-5);
    }

    #[test]
    fn a_carried_offset_lands_where_the_carry_takes_its_point() {
        // A stretch, a tilt and a turn at once, at sample times and between them, for points on,
        // above and beside both triangles: `carry_offset` is the carry without its rotation
        // (F_now·F_restᵀ·(x − p_rest) = F_now·offset), equal up to f32 rounding of unit-size
        // values (the carry's quaternion round trip adds a few 10⁻⁷).
        let body = body(|s, p: Vec3| {
            let s = s as f32;
            let turned =
                Quat::from_rotation_y(0.3 * s) * Vec3::new(p.x * (1.0 + 0.2 * s), p.y, p.z);
            turned + Vec3::Y * (0.25 * s) * (-p.z) * (1.0 - p.x)
        });
        let attachments = [
            ON_FIRST,
            SurfaceAttachment {
                triangle: 1,
                barycentric: Vec3::new(0.6, 0.1, 0.3),
            },
        ];
        for attachment in &attachments {
            for point in [
                Vec3::new(0.3, 0.0, -0.5),
                Vec3::new(0.1, 0.05, -0.2),
                Vec3::new(1.2, -0.1, 0.3),
            ] {
                let offset = body.rest_offset(attachment, point).unwrap();
                for time in [0.25, 0.5, 0.8, 1.0, 2.0] {
                    let bracket = body.sequence().bracket(time);
                    let expected = body
                        .carry_between(attachment, bracket)
                        .transform_point(point);
                    let carried = body.carry_offset(attachment, offset, bracket).unwrap();
                    assert!(
                        (carried - expected).length() < 2e-6,
                        "{time}: {carried} against {expected}"
                    );
                }
                // At rest the carry is the identity, which `carry_offset` leaves to it.
                assert_eq!(
                    body.carry_offset(attachment, offset, body.sequence().bracket(0.0)),
                    None
                );
            }
        }
    }
}
