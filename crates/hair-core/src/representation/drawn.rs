//! How a strand is drawn along its skeleton's curve, the one definition that the CPU polylines
//! ([`super::geometry::strand_polylines`]) and the renderer's `strands.wgsl` both follow: where its
//! run ends, its tapered root offset, and its residual profile.
//!
//! A strand of length fraction `l`, root offset `o`, tip scale `s` and residual profile `r(v)` is,
//! at skeleton-curve parameter `u ∈ [0, l]`,
//!
//! `P(u) = C(u) + σ(u)·(o.x·N(u) + o.y·B(u)) + r.x·N̂(u) + r.y·B̂(u) + r.z·T̂(u)`,
//!
//! with `σ(u) = 1 + (s − 1)·u`, `r = r(u / l)`, `C`, `N`, `B` the B-splines of the chain's nodes,
//! normals and binormals, `T̂ = C′/|C′|`, and `(N̂, B̂, T̂)` the orthonormal frame of
//! [`ChainPoint::residual_basis`]. The curve is tessellated into equal parameter steps;
//! the strand takes the steps up to `l` and ends exactly at `u = l`, its last point interpolated
//! between the two tessellation points around it.

use glam::{Mat3, Vec2, Vec3};

/// A skeleton curve's point and frame curves at one parameter.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChainPoint {
    /// `C(u)` [m].
    pub position: Vec3,
    /// `N(u)`, the B-spline of the node normals (nearly unit).
    pub normal: Vec3,
    /// `B(u)`, the B-spline of the node binormals (nearly unit).
    pub binormal: Vec3,
    /// `dC/du` [m per unit parameter].
    pub derivative: Vec3,
}

impl ChainPoint {
    /// The linear blend `self + (other − self)·t` of every field.
    pub fn lerp(&self, other: &ChainPoint, t: f32) -> ChainPoint {
        ChainPoint {
            position: self.position.lerp(other.position, t),
            normal: self.normal.lerp(other.normal, t),
            binormal: self.binormal.lerp(other.binormal, t),
            derivative: self.derivative.lerp(other.derivative, t),
        }
    }

    /// The unit tangent `T̂` (+Y where the curve does not move: `|dC/du|² ≤ 10⁻²⁴`, or NaN).
    /// `strands.wgsl`'s `residual_frame` follows the same rule, test for test.
    pub fn unit_tangent(&self) -> Vec3 {
        let d = self.derivative;
        if d.length_squared() > 1e-24 {
            d.normalize()
        } else {
            Vec3::Y
        }
    }

    /// The orthonormal basis `(N̂, B̂, T̂)` (columns) that residuals are measured in: the unit
    /// tangent `T̂`, the normal curve made perpendicular to it, `N̂ = (N − (N·T̂)·T̂)/|…|`, and
    /// `B̂ = T̂ × N̂`. Where `N` runs along the tangent, `N̂` comes from `B × T̂` instead, and from
    /// any perpendicular where that fails too. Orthonormal, so a residual is never larger than
    /// the offset it stands for. (The node frames' own interpolated frame twists more between
    /// nodes than this one turns: 2.6 times the ponytail's rest error.)
    pub fn residual_basis(&self) -> Mat3 {
        let t = self.unit_tangent();
        // |N| and |B| are about 1: a part under 10⁻⁶ is rounding, not a direction.
        let usable = |v: Vec3| (v.length_squared() > 1e-12).then(|| v.normalize());
        let n = usable(self.normal - self.normal.dot(t) * t)
            .or_else(|| usable(self.binormal.cross(t)))
            .unwrap_or_else(|| any_perpendicular(t));
        Mat3::from_cols(n, t.cross(n), t)
    }

    /// The point a strand at root offset `root_offset` [m] and tip scale `tip_scale` has at
    /// parameter `u` before its residual: `C + σ(u)·(o.x·N + o.y·B)`, `σ(u) = 1 + (s − 1)·u`.
    pub fn offset_point(&self, u: f32, root_offset: Vec2, tip_scale: f32) -> Vec3 {
        let o = (1.0 + (tip_scale - 1.0) * u) * root_offset;
        self.position + o.x * self.normal + o.y * self.binormal
    }
}

/// Index of the last point of a strand of length fraction `length` on a curve tessellated into
/// `segments` steps: `max(1, ⌈l·segments⌉)`, at most `segments` (a step within 10⁻⁴ of `l`
/// counts as reaching it).
pub fn strand_last_point(length: f32, segments: usize) -> usize {
    let steps = (length * segments as f32 - 1e-4).ceil();
    (steps.max(1.0) as usize).min(segments.max(1))
}

/// The curve parameter of a strand's point `point`: `min(point / segments, length)`.
pub fn strand_point_parameter(point: usize, segments: usize, length: f32) -> f32 {
    (point as f32 / segments.max(1) as f32).min(length)
}

/// The chain point at parameter `u` from its tessellation `samples` (at `u_k = k / (n − 1)`):
/// linear between the two samples around `u` (exact at a sample).
pub fn chain_point_at(samples: &[ChainPoint], u: f32) -> ChainPoint {
    let segments = samples.len().saturating_sub(1);
    if segments == 0 {
        return samples.first().copied().unwrap_or_default();
    }
    let s = u.clamp(0.0, 1.0) * segments as f32;
    let k = (s.floor() as usize).min(segments - 1);
    samples[k].lerp(&samples[k + 1], s - k as f32)
}

/// The residual of `profile` at fraction `v ∈ [0, 1]` of the strand's run: linear between its
/// entries (at `v_j = j / (n − 1)`).
pub fn profile_residual(profile: &[Vec3], v: f32) -> Vec3 {
    let steps = profile.len().saturating_sub(1);
    if steps == 0 {
        return profile.first().copied().unwrap_or(Vec3::ZERO);
    }
    let s = v.clamp(0.0, 1.0) * steps as f32;
    let j = (s.floor() as usize).min(steps - 1);
    profile[j].lerp(profile[j + 1], s - j as f32)
}

/// A unit vector perpendicular to the unit vector `t` (Frisvad's construction, as glam's
/// `any_orthonormal_vector`, but with `t.z = −0` taken as positive, as the shader takes it).
fn any_perpendicular(t: Vec3) -> Vec3 {
    let sign = if t.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + t.z);
    Vec3::new(t.x * t.y * a, sign + t.y * t.y * a, -t.y)
}

/// The shortest length fraction a residual profile is stretched over (as in the shader): a
/// strand shorter than this reads its profile as if it were this long.
pub const MIN_PROFILE_LENGTH: f32 = 1e-6;

/// The point of a strand drawn at curve parameter `u` of `chain` (see the module): `length` is
/// its length fraction, `profile` its residual profile, if any.
pub fn drawn_strand_point(
    chain: &ChainPoint,
    u: f32,
    length: f32,
    root_offset: Vec2,
    tip_scale: f32,
    profile: Option<&[Vec3]>,
) -> Vec3 {
    let point = chain.offset_point(u, root_offset, tip_scale);
    match profile {
        Some(profile) => {
            let r = profile_residual(profile, u / length.max(MIN_PROFILE_LENGTH));
            point + chain.residual_basis() * r
        }
        None => point,
    }
}

/// The start of a skeleton chain as its strands' roots read it: a clamped B-spline starts at
/// its first control point, so at `u = 0` the curve is the first node, its normal and binormal
/// curves the first node's, and its tangent runs towards the second node.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChainStart {
    /// The first node [m].
    pub first: Vec3,
    /// The second node [m].
    pub second: Vec3,
    /// The first node's normal (unit).
    pub normal: Vec3,
    /// The first node's binormal (unit).
    pub binormal: Vec3,
}

impl ChainStart {
    /// The chain point at `u = 0`, its derivative `second − first` (the true `dC/du` is that
    /// times a positive factor of the knots; only its direction is read at the root).
    pub fn chain_point(&self) -> ChainPoint {
        ChainPoint {
            position: self.first,
            normal: self.normal,
            binormal: self.binormal,
            derivative: self.second - self.first,
        }
    }
}

/// The root (`u = 0`) of a strand drawn on the chain starting at `start`, with root offset
/// `root_offset` [m] and residual `profile`: `P(0) = C(0) + o.x·N(0) + o.y·B(0) + (N̂, B̂, T̂)·r(0)`
/// (the tip scale and the length do not reach the root). The point [`drawn_strand_point`] and
/// `strands.wgsl` draw at `u = 0`.
pub fn drawn_strand_root(start: &ChainStart, root_offset: Vec2, profile: Option<&[Vec3]>) -> Vec3 {
    drawn_strand_point(&start.chain_point(), 0.0, 1.0, root_offset, 1.0, profile)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_perpendicular_is_a_unit_normal_of_every_direction() {
        // Frisvad's construction fails only at t = −z with the sign of +z: the branch on the
        // sign of t.z keeps `sign + t.z` away from 0 (|sign + t.z| ≥ 1).
        let directions = [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 0.0, -0.0),
            Vec3::new(0.3, -0.4, -0.0).normalize(),
            Vec3::new(0.0, 1e-4, -1.0).normalize(),
            Vec3::new(-0.6, 0.0, 0.8),
        ];
        for t in directions {
            let n = any_perpendicular(t);
            assert!((n.length() - 1.0).abs() < 1e-6, "{t} gives {n}");
            assert!(n.dot(t).abs() < 1e-6, "{t} gives {n}");
        }
    }

    #[test]
    fn a_motionless_or_nan_chain_point_still_has_an_orthonormal_basis() {
        // The shader's rule: |dC/du|² ≤ 10⁻²⁴ or NaN gives T̂ = +Y; a NaN normal falls back to
        // B × T̂.
        let still = ChainPoint {
            position: Vec3::ZERO,
            normal: Vec3::new(f32::NAN, 0.0, 0.0),
            binormal: Vec3::Z,
            derivative: Vec3::splat(1e-13),
        };
        assert_eq!(still.unit_tangent(), Vec3::Y);
        let basis = still.residual_basis();
        assert!(basis.is_finite());
        assert!((basis.transpose() * basis - Mat3::IDENTITY).abs_diff_eq(Mat3::ZERO, 1e-6));
        assert_eq!(basis.z_axis, Vec3::Y);
    }

    fn skewed() -> ChainPoint {
        ChainPoint {
            position: Vec3::new(0.1, 0.2, 0.3),
            normal: Vec3::new(0.9, 0.1, 0.0),
            binormal: Vec3::new(0.05, 0.0, 1.1),
            derivative: Vec3::new(0.2, -3.0, 0.1),
        }
    }

    #[test]
    fn the_residual_basis_is_orthonormal_even_where_the_frame_is_not() {
        let mut chain = skewed();
        // A skewed normal, one along the tangent, none at all.
        for normal in [chain.normal, chain.derivative, Vec3::ZERO] {
            chain.normal = normal;
            let basis = chain.residual_basis();
            let gram = basis.transpose() * basis;
            assert!(gram.abs_diff_eq(Mat3::IDENTITY, 1e-5), "{normal}: {gram}");
            assert!((basis.z_axis - chain.unit_tangent()).length() < 1e-6);
            assert!(basis.determinant() > 0.0);
        }
    }

    #[test]
    fn a_run_ends_exactly_at_its_length() {
        // l = 0.5 on 8 steps: points 0..=4, the last at u = 0.5 exactly.
        assert_eq!(strand_last_point(0.5, 8), 4);
        assert_eq!(strand_point_parameter(4, 8, 0.5), 0.5);
        // l = 0.55: ⌈4.4⌉ = 5 points after the root, the last clamped to u = 0.55.
        assert_eq!(strand_last_point(0.55, 8), 5);
        assert_eq!(strand_point_parameter(5, 8, 0.55), 0.55);
        assert_eq!(strand_point_parameter(3, 8, 0.55), 0.375);
        // Full and tiny lengths.
        assert_eq!(strand_last_point(1.0, 8), 8);
        assert_eq!(strand_last_point(1e-6, 8), 1);
    }

    #[test]
    fn interpolation_is_exact_at_samples_and_linear_between() {
        let samples: Vec<ChainPoint> = (0..5)
            .map(|k| ChainPoint {
                position: Vec3::new(k as f32, (k * k) as f32, 0.0),
                ..skewed()
            })
            .collect();
        for (k, sample) in samples.iter().enumerate() {
            let at = chain_point_at(&samples, k as f32 / 4.0);
            assert!((at.position - sample.position).length() < 1e-5);
        }
        // Halfway between samples 1 (1, 1) and 2 (2, 4): (1.5, 2.5).
        let mid = chain_point_at(&samples, 0.375);
        assert!((mid.position - Vec3::new(1.5, 2.5, 0.0)).length() < 1e-5);
        let profile = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 2.0, 0.0)];
        assert!((profile_residual(&profile, 0.75) - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
        assert_eq!(profile_residual(&profile, 1.5), profile[2]);
    }

    #[test]
    fn a_drawn_point_is_the_tapered_offset_plus_the_residual() {
        let chain = ChainPoint {
            position: Vec3::ZERO,
            normal: Vec3::X,
            binormal: Vec3::Z,
            derivative: Vec3::new(0.0, -2.0, 0.0),
        };
        // u = 0.5, tip scale 0: σ = 0.5, offset (0.02, 0.04) → 0.01·N + 0.02·B. T̂ = −Y, N̂ = X,
        // B̂ = T̂ × N̂ = −Y × X = Z, so the residual (0.001, 0.002, 0.003) adds (0.001, −0.003, 0.002).
        let profile = vec![Vec3::new(0.001, 0.002, 0.003); 4];
        let p = drawn_strand_point(&chain, 0.5, 1.0, Vec2::new(0.02, 0.04), 0.0, Some(&profile));
        assert!((p - Vec3::new(0.011, -0.003, 0.022)).length() < 1e-7, "{p}");
        let plain = drawn_strand_point(&chain, 0.5, 1.0, Vec2::new(0.02, 0.04), 0.0, None);
        assert!(
            (plain - Vec3::new(0.01, 0.0, 0.02)).length() < 1e-7,
            "{plain}"
        );
    }
}
