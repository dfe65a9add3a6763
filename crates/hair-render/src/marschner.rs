//! Marschner hair shading (Marschner, Jensen, Cammarano, Worley, Hanrahan 2003, "Light scattering
//! from human hair fibers"): the three single-scattering lobes of a dielectric cylinder, R
//! (reflection off the surface), TT (transmission through the fibre) and TRT (one internal
//! reflection), each a longitudinal Gaussian times an azimuthal term. This is the CPU reference of
//! `marschner_scatter` in `shaders/bspline.wgsl`, step for step.
//!
//! With `T` the hair tangent, `L` the direction towards the light and `V` towards the eye:
//!
//! - longitudinal angles `sin θ_i = T·L`, `sin θ_r = T·V`, half angle `θ_h = (θ_i + θ_r)/2`,
//!   difference angle `θ_d = (θ_r − θ_i)/2`;
//! - azimuth `φ` between the projections of `L` and `V` onto the normal plane of `T`;
//! - `M_p(θ_h) = g(β_p, θ_h − α_p)`, `g(β, x) = exp(−x²/2β²)/(β√(2π))`, with the paper's shifts
//!   and widths `α_R`, `α_TT = −α_R/2`, `α_TRT = −3α_R/2`, `β_TT = β_R/2`, `β_TRT = 2β_R`;
//! - `N_R = ¼·cos(φ/2)·F(cos θ_d·cos(φ/2))`, the mirror reflection off a cylinder (it integrates
//!   to `F` over the circle);
//! - `N_TT = (1 − F(cos θ_d))²·A^(1/cos θ_d)·v(κ_TT, φ − π)`, forward scattering through the fibre;
//! - `N_TRT = (1 − F(cos θ_d))²·F(cos θ_d)·A^(2/cos θ_d)·v(κ_TRT, φ)`, back towards the light,
//!   coloured twice;
//! - `v(κ, x) = exp(κ(cos x − 1))·√(κ/2π)`, a von Mises lobe normalised for large `κ`;
//! - `F(c) = F₀ + (1 − F₀)(1 − c)⁵` (Schlick), `F₀ = ((η − 1)/(η + 1))²`;
//! - `A` the transmittance of one pass through the fibre: the hair's base colour;
//! - `S = Σ_p M_p·N_p / cos²θ_d`, and the light a fibre sends to the eye is `E·S·cos θ_i`.
//!
//! Simplifications against the paper, for a real-time shader: the azimuthal terms are lobes
//! (von Mises) at the paper's directions instead of the exact refraction paths with their
//! caustics (no glints), and the absorption path length is taken at the fibre's centre.

use glam::Vec3;

/// Concentration of the TT lobe about the forward direction `φ = π` (about ±30° wide).
pub const KAPPA_TT: f32 = 4.0;

/// Concentration of the TRT lobe about the backward direction `φ = 0` (about ±20° wide).
pub const KAPPA_TRT: f32 = 8.0;

/// Parameters of the Marschner model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marschner {
    /// Longitudinal shift `α_R` of the R lobe [rad]: the cuticle scales tilt the highlight
    /// towards the root; the paper measures −10° to −5°.
    pub shift: f32,
    /// Longitudinal width `β_R` of the R lobe [rad]: the paper measures 5° to 10°.
    pub width: f32,
    /// Refractive index of the fibre (keratin: 1.55).
    pub refractive_index: f32,
}

impl Default for Marschner {
    /// The middle of the paper's measured ranges: `α_R` = −7.5°, `β_R` = 7.5°, `η` = 1.55.
    fn default() -> Self {
        Marschner {
            shift: (-7.5f32).to_radians(),
            width: 7.5f32.to_radians(),
            refractive_index: 1.55,
        }
    }
}

impl Marschner {
    /// `S·cos θ_i` per colour channel: the radiance a fibre sends towards `to_eye` per unit
    /// irradiance from `to_light` (normal to the light), with `absorption` the transmittance of
    /// one pass through the fibre (the hair's base colour, 0..1 per channel). `tangent`,
    /// `to_light` and `to_eye` are unit vectors.
    pub fn scatter(&self, tangent: Vec3, to_light: Vec3, to_eye: Vec3, absorption: Vec3) -> Vec3 {
        let sin_i = tangent.dot(to_light).clamp(-1.0, 1.0);
        let sin_r = tangent.dot(to_eye).clamp(-1.0, 1.0);
        let theta_i = sin_i.asin();
        let theta_r = sin_r.asin();
        let theta_h = 0.5 * (theta_i + theta_r);
        let cos_d = (0.5 * (theta_r - theta_i)).cos().max(1e-3);
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let light_normal = to_light - sin_i * tangent;
        let eye_normal = to_eye - sin_r * tangent;
        let norms = (light_normal.length_squared() * eye_normal.length_squared()).sqrt();
        let cos_phi = if norms > 1e-12 {
            (light_normal.dot(eye_normal) / norms).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let cos_half_phi = (0.5 + 0.5 * cos_phi).max(0.0).sqrt();

        let f0 = ((self.refractive_index - 1.0) / (self.refractive_index + 1.0)).powi(2);
        let fresnel = |c: f32| f0 + (1.0 - f0) * (1.0 - c.clamp(0.0, 1.0)).powi(5);
        let m_r = gaussian(self.width, theta_h - self.shift);
        let m_tt = gaussian(0.5 * self.width, theta_h + 0.5 * self.shift);
        let m_trt = gaussian(2.0 * self.width, theta_h + 1.5 * self.shift);

        let n_r = 0.25 * cos_half_phi * fresnel(cos_d * cos_half_phi);
        let f = fresnel(cos_d);
        // At least 1e-6, as in the shader (WGSL's pow is undefined at 0).
        let a = absorption.clamp(Vec3::splat(1e-6), Vec3::ONE);
        let n_tt = (1.0 - f) * (1.0 - f) * von_mises(KAPPA_TT, -cos_phi);
        let n_trt = (1.0 - f) * (1.0 - f) * f * von_mises(KAPPA_TRT, cos_phi);
        let scatter = Vec3::splat(m_r * n_r)
            + m_tt * n_tt * a.powf(1.0 / cos_d)
            + m_trt * n_trt * a.powf(2.0 / cos_d);
        scatter * (cos_i / (cos_d * cos_d))
    }

    /// Checks that every parameter is finite and physical, naming the first one that is not.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.shift.is_finite() && self.shift.abs() < std::f32::consts::FRAC_PI_4) {
            return Err(format!(
                "Marschner shift {} rad must be finite and within ±π/4",
                self.shift
            ));
        }
        if !(self.width.is_finite() && self.width > 1e-3 && self.width < 1.0) {
            return Err(format!(
                "Marschner width {} rad must be in 0.001..1",
                self.width
            ));
        }
        if !(self.refractive_index.is_finite()
            && self.refractive_index > 1.0
            && self.refractive_index < 4.0)
        {
            return Err(format!(
                "Marschner refractive index {} must be in 1..4",
                self.refractive_index
            ));
        }
        Ok(())
    }
}

/// The unit Gaussian `g(β, x) = exp(−x²/2β²)/(β√(2π))` [1/rad].
fn gaussian(width: f32, x: f32) -> f32 {
    (-x * x / (2.0 * width * width)).exp() / (width * (2.0 * std::f32::consts::PI).sqrt())
}

/// The von Mises lobe `exp(κ(c − 1))·√(κ/2π)` at `c = cos x` [1/rad].
fn von_mises(kappa: f32, cos_x: f32) -> f32 {
    (kappa * (cos_x - 1.0)).exp() * (kappa / (2.0 * std::f32::consts::PI)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// Integrates `f(φ)` over the circle by the midpoint rule.
    fn over_circle(f: impl Fn(f32) -> f32) -> f32 {
        let n = 20_000;
        (0..n)
            .map(|k| f(-PI + (k as f32 + 0.5) * 2.0 * PI / n as f32) * 2.0 * PI / n as f32)
            .sum()
    }

    /// `N_R` integrates to the Fresnel factor at `θ_d = 0`, `¼∫cos(φ/2)·F dφ`: with F constant
    /// that is `¼·4·F = F`; here F varies with `cos(φ/2)`, so compare with that integral directly.
    /// The lobes: `∫ v(κ, φ) dφ = 2π·I₀(κ)·e^(−κ)·√(κ/2π) = I₀(κ)e^(−κ)√(2πκ)`, which tends
    /// to 1 as κ grows (`1 + 1/8κ + 9/128κ² + …`): 1.0378 at κ = 4, 1.0169 at κ = 8 (the
    /// series of I₀ summed to convergence).
    #[test]
    fn lobes_are_normalised() {
        let lobe_tt = over_circle(|phi| von_mises(KAPPA_TT, (phi - PI).cos()));
        let lobe_trt = over_circle(|phi| von_mises(KAPPA_TRT, phi.cos()));
        assert!((lobe_tt - 1.0378).abs() < 1e-3, "{lobe_tt}");
        assert!((lobe_trt - 1.0169).abs() < 1e-3, "{lobe_trt}");
        let g = |w: f32| over_circle(|x| gaussian(w, x));
        assert!((g(0.13) - 1.0).abs() < 1e-4);
    }

    /// Without absorption (A = 0) only R is left, and it peaks where the half angle meets the
    /// shift: with the light and the eye in one plane with the tangent, on the same side
    /// (φ = 0), `θ_h = α_R` when `θ_r = 2α_R − θ_i`.
    #[test]
    fn the_reflection_peaks_at_the_shifted_half_angle() {
        let model = Marschner::default();
        let tangent = Vec3::Y;
        let theta_i = 0.3f32;
        let to_light = Vec3::new(theta_i.cos(), theta_i.sin(), 0.0);
        let value = |theta_r: f32| {
            model
                .scatter(
                    tangent,
                    to_light,
                    Vec3::new(theta_r.cos(), theta_r.sin(), 0.0),
                    Vec3::ZERO,
                )
                .x
        };
        // θ_r ± 0.15 moves θ_h by 0.075 = 0.57 β_R: the Gaussian falls to 0.85 while
        // 1/cos²θ_d changes by under 8 %.
        let peak = 2.0 * model.shift - theta_i;
        assert!(value(peak) > value(peak + 0.15) && value(peak) > value(peak - 0.15));
        assert!(value(peak) > 5.0 * value(peak + 0.6));
    }

    /// Seen from behind the fibre, against the light (φ = π), TT carries the colour:
    /// `A^(1/cos θ_d)` with `θ_d = 0` is A itself, so the channels keep A's ratios where R
    /// (colourless) is small.
    #[test]
    fn transmission_is_coloured_forward_and_absent_backward() {
        let model = Marschner::default();
        let absorption = Vec3::new(0.8, 0.4, 0.1);
        let to_light = Vec3::X;
        let forward = model.scatter(Vec3::Y, to_light, -Vec3::X, absorption);
        let backward = model.scatter(Vec3::Y, to_light, Vec3::X, Vec3::ZERO);
        assert!(forward.x > forward.y && forward.y > forward.z);
        assert!(
            forward.x > 10.0 * backward.x,
            "{forward} against {backward}"
        );
        assert!(model.scatter(Vec3::Y, to_light, -Vec3::X, Vec3::ZERO).x < 0.01 * forward.x);
    }

    #[test]
    fn parameters_are_validated() {
        assert!(Marschner::default().validate().is_ok());
        let bad = Marschner {
            width: 0.0,
            ..Marschner::default()
        };
        assert!(bad.validate().unwrap_err().contains("width"));
        let bad = Marschner {
            refractive_index: f32::NAN,
            ..Marschner::default()
        };
        assert!(bad.validate().unwrap_err().contains("refractive index"));
    }
}
