//! The map a deforming body's moving field reads its rest field through (`moving_field.rs`): an
//! affine map fitted to the deformation where it fits better than the rigid one, so that a squash
//! and stretch (an affine deformation) leaves only what is not affine (a jaw's drop) as the
//! deviation that loosens every certified bound.
//!
//! **The fit.** The affine map `x ≈ A X + t` that best maps the rest vertices `X` onto the current
//! ones `x` in least squares is `A = (Σ x X̃ᵀ)(Σ X̃ X̃ᵀ)⁻¹` with `X̃` the rest vertices less their
//! mean, and `t = x̄ − A X̄`: the first factor is the cross-covariance the rigid fit already sums,
//! the second the rest spread's inverse, found once.
//!
//! **The bound through it.** Every current vertex lies within `δ` of `A X + t`, and so does every
//! point of every current triangle (a convex combination of its vertices'), so the distance from
//! `p` to the current surface is at least its distance to the mapped rest surface less `δ`. An
//! affine map brings no two points closer than `σ` times their distance, `σ` its smallest singular
//! value, so that distance is at least `σ` times the rest field's distance at `A⁻¹(p − t)`; with
//! `det A > 0` the map keeps inside inside, and where the bound is positive the straight morph
//! from the mapped rest surface to the current one never crosses `p`: the sign holds.

use glam::{DMat3, DVec3, Mat3, Vec3};

/// How the moving field reads the rest field: current ≈ `map` · rest + `translation` \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FieldMap {
    /// The linear part.
    pub(crate) map: Mat3,
    /// Its inverse.
    pub(crate) inverse: Mat3,
    /// The translation \[m\].
    pub(crate) translation: Vec3,
    /// A lower bound on the map's smallest singular value: no two points come closer than this
    /// times their distance (1 for a rotation).
    pub(crate) shrink: f32,
    /// How far \[m\] any current vertex lies from its rest place so mapped, at most.
    pub(crate) deviation: f32,
}

/// Relative allowance for the rounding of the smallest singular value and of the mapped points.
const ROUNDING: f32 = 1e-5;

impl FieldMap {
    /// The rigid map `rotation` · rest + `translation`, every vertex within `deviation` \[m\].
    pub(crate) fn rigid(rotation: Mat3, translation: Vec3, deviation: f32) -> Self {
        FieldMap {
            map: rotation,
            inverse: rotation.transpose(),
            translation,
            shrink: 1.0,
            deviation,
        }
    }

    /// The affine map `map` · rest + `translation` \[m\] with every vertex within `deviation`
    /// \[m\] of it; `None` where it is not finite, turns inside out, or squeezes a direction
    /// below half its length (a fit that far from a motion is not read through).
    pub(crate) fn affine(map: Mat3, translation: Vec3, deviation: f32) -> Option<Self> {
        if !(map.is_finite() && translation.is_finite() && deviation.is_finite()) {
            return None;
        }
        if map.determinant() <= 0.0 {
            return None;
        }
        let shrink = smallest_singular_value(map.as_dmat3()) as f32 * (1.0 - ROUNDING);
        let inverse = map.inverse();
        (shrink >= 0.5 && inverse.is_finite()).then_some(FieldMap {
            map,
            inverse,
            translation,
            shrink,
            // The mapped points' rounding at a head's scale.
            deviation: deviation + 1e-6,
        })
    }

    /// `p` \[m\] (current body frame) brought back to the rest frame.
    #[inline]
    pub(crate) fn back(&self, p: Vec3) -> Vec3 {
        self.inverse * (p - self.translation)
    }

    /// The certified distance \[m\] at a current point whose rest image has the certified
    /// rest distance `rest_bound` \[m\]: at least this far from the current surface (see the
    /// module documentation); not positive where nothing is certified.
    #[inline]
    pub(crate) fn bound(&self, rest_bound: f32) -> f32 {
        rest_bound * self.shrink - self.deviation
    }
}

/// The smallest singular value of `a`: the square root of the smallest eigenvalue of `aᵀa`,
/// found by the closed form for a symmetric 3 × 3 matrix (Smith 1961).
fn smallest_singular_value(a: DMat3) -> f64 {
    let m = a.transpose() * a;
    let [c0, c1, c2] = [m.x_axis, m.y_axis, m.z_axis];
    let off = c1.x * c1.x + c2.x * c2.x + c2.y * c2.y;
    let diagonal = DVec3::new(c0.x, c1.y, c2.z);
    let smallest = if off <= f64::EPSILON * diagonal.length_squared() {
        diagonal.min_element()
    } else {
        let q = (diagonal.x + diagonal.y + diagonal.z) / 3.0;
        let spread = (diagonal - DVec3::splat(q)).length_squared() + 2.0 * off;
        let p = (spread / 6.0).sqrt();
        let b = (m - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
        let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos()
    };
    smallest.max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    /// Against the singular values of maps built from them: `R₁ diag(s) R₂` has singular
    /// values `s`; and the shrink bounds `|A u|/|u|` from below over many directions.
    #[test]
    fn the_smallest_singular_value_is_the_maps_least_stretch() {
        for (k, s) in [
            [1.0, 1.0, 1.0],
            [0.97, 1.06, 0.97],
            [1.2, 0.8, 1.0],
            [0.6, 0.61, 2.0],
            [1.0, 1.0, 0.9999],
        ]
        .into_iter()
        .enumerate()
        {
            let turn = Quat::from_euler(glam::EulerRot::XYZ, 0.3 * k as f32, -0.7, 1.1);
            let other = Quat::from_rotation_y(0.4 + k as f32);
            let a = Mat3::from_quat(turn)
                * Mat3::from_diagonal(Vec3::from_array(s))
                * Mat3::from_quat(other);
            let least = s.iter().copied().fold(f32::INFINITY, f32::min);
            let found = smallest_singular_value(a.as_dmat3()) as f32;
            assert!((found - least).abs() <= 1e-5, "{s:?}: {found}");
            let map = FieldMap::affine(a, Vec3::ZERO, 0.0).unwrap();
            for i in 0..500 {
                let t = i as f32 * 0.618;
                let u = Vec3::new(t.sin(), (1.7 * t).cos(), (0.3 * t).sin() - 0.2);
                assert!((a * u).length() >= map.shrink * u.length());
            }
        }
        // A reflection, a collapse and a map that is not finite are not read through.
        assert!(
            FieldMap::affine(
                Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0)),
                Vec3::ZERO,
                0.0
            )
            .is_none()
        );
        assert!(
            FieldMap::affine(
                Mat3::from_diagonal(Vec3::new(1.0, 0.3, 1.0)),
                Vec3::ZERO,
                0.0
            )
            .is_none()
        );
        assert!(FieldMap::affine(Mat3::IDENTITY * f32::NAN, Vec3::ZERO, 0.0).is_none());
    }
}
