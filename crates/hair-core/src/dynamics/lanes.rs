//! Lane-wise f32 arithmetic for stepping [`LANES`] chains at once: [`Lanes`] (one number per
//! chain) and [`LaneVec3`] (one vector per chain), written as fixed-size loops that the compiler
//! turns into SIMD instructions. Every operation is the IEEE operation of each lane (no fused
//! multiply-add), so results do not depend on the instruction set the code was compiled for.

// Lane loops index several arrays by lane on purpose: that is the form the vectoriser reads.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use glam::Vec3;

/// Chains stepped together.
pub(crate) const LANES: usize = 8;

/// One f32 per lane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C, align(32))]
pub(crate) struct Lanes(pub [f32; LANES]);

macro_rules! lane_binary {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(self, other: Lanes) -> Lanes {
                let mut out = [0.0; LANES];
                for l in 0..LANES {
                    out[l] = self.0[l] $op other.0[l];
                }
                Lanes(out)
            }
        }
    };
}

lane_binary!(Add, add, +);
lane_binary!(Sub, sub, -);
lane_binary!(Mul, mul, *);
lane_binary!(Div, div, /);

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        self.map(|x| -x)
    }
}

impl Lanes {
    /// Every lane `value`.
    #[inline(always)]
    pub fn splat(value: f32) -> Lanes {
        Lanes([value; LANES])
    }

    /// `f` of every lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Lanes {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = f(self.0[l]);
        }
        Lanes(out)
    }

    /// `f` of every pair of lanes.
    #[inline(always)]
    pub fn zip(self, other: Lanes, f: impl Fn(f32, f32) -> f32) -> Lanes {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = f(self.0[l], other.0[l]);
        }
        Lanes(out)
    }

    /// 0 in every lane holding a finite number, NaN in the others (`x − x`).
    #[inline(always)]
    pub fn nan_unless_finite(self) -> Lanes {
        self.zip(self, |a, b| a - b)
    }

    /// Square root of every lane.
    #[inline(always)]
    pub fn sqrt(self) -> Lanes {
        self.map(f32::sqrt)
    }

    /// Lane-wise maximum (the other operand where one is NaN, as `f32::max`).
    #[inline(always)]
    pub fn max(self, other: Lanes) -> Lanes {
        self.zip(other, |a, b| if a > b { a } else { b })
    }

    /// Lane-wise absolute value.
    #[inline(always)]
    pub fn abs(self) -> Lanes {
        self.map(f32::abs)
    }

    /// `if mask > 0 { a } else { b }` per lane, with `mask` a lane-wise condition as 1.0 / 0.0.
    #[inline(always)]
    pub fn select(mask: Lanes, a: Lanes, b: Lanes) -> Lanes {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = if mask.0[l] > 0.0 { a.0[l] } else { b.0[l] };
        }
        Lanes(out)
    }

    /// 1.0 where `self > other`, else 0.0.
    #[inline(always)]
    pub fn greater(self, other: Lanes) -> Lanes {
        self.zip(other, |a, b| if a > b { 1.0 } else { 0.0 })
    }

    /// Whether any lane of a lane-wise condition (1.0 / 0.0) holds: an OR of the bits, which
    /// the compiler reduces in vector registers.
    #[inline(always)]
    pub fn any(self) -> bool {
        self.0.iter().fold(0u32, |any, &x| any | x.to_bits()) != 0
    }

    /// The bend angle `α = atan2(sin, cos)` [rad] of two unit vectors from `sin = |a × b| ≥ 0` and
    /// `cos = a·b`, and the factor `α / sin α` (→ 1 as α → 0), without library calls and with one
    /// division except where some lane bends back by more than 135°.
    ///
    /// The ratio `t` of the smaller to the larger of `sin`, `|cos|` goes into an odd polynomial
    /// for `atan t` on `[0, 1]` (degree 15, error < 4e-8 rad before f32 rounding; evaluated in
    /// Estrin's scheme for a short dependency chain), then the octant: the angle is within 2e-7
    /// rad of `f32::atan2`. Below 45° `α/sin α = P(t²)/cos` (`t = tan α`), from 45° to 135° it is
    /// `α/max`, beyond it `α/sin` (or `1 + α²/6` where `sin ≤ 1e-3`).
    #[inline(always)]
    #[allow(clippy::excessive_precision)] // the fitted coefficients, as printed
    pub fn bend_angle_and_factor(sin: Lanes, cos: Lanes) -> (Lanes, Lanes) {
        let zero = Lanes::splat(0.0);
        let magnitude = cos.abs();
        let swap = sin.greater(magnitude);
        let numerator = Lanes::select(swap, magnitude, sin);
        let denominator = Lanes::select(swap, sin, magnitude);
        let inverse = Lanes::select(
            denominator.greater(zero),
            Lanes::splat(1.0) / denominator,
            zero,
        );
        let t = numerator * inverse;
        let s = t * t;
        // atan t ≈ t·P(t²) on [0, 1] (weighted least-squares fit, |error| < 4e-8 in exact
        // arithmetic), P = Σ c_k s^k in pairs.
        let c = |value: f32| Lanes::splat(value);
        let s2 = s * s;
        let s4 = s2 * s2;
        let low = (c(0.999_999_33) + c(-0.333_298_43) * s)
            + (c(0.199_463_69) + c(-0.139_076_88) * s) * s2;
        let high = (c(0.096_398_89) + c(-0.055_882_04) * s)
            + (c(0.021_842_73) + c(-0.004_049_165_6) * s) * s2;
        let p = low + high * s4;
        let along = t * p;
        let angle = Lanes::select(swap, c(std::f32::consts::FRAC_PI_2) - along, along);
        let backward = zero.greater(cos);
        let angle = Lanes::select(backward, c(std::f32::consts::PI) - angle, angle);
        let mut factor = Lanes::select(swap, angle * inverse, p * inverse);
        let far = Lanes::select(swap, zero, backward);
        if far.any() {
            let beyond = Lanes::select(
                sin.greater(c(1e-3)),
                angle / sin,
                c(1.0) + angle * angle * c(1.0 / 6.0),
            );
            factor = Lanes::select(far, beyond, factor);
        }
        (angle, factor)
    }
}

/// One 3-vector per lane, stored by component.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct LaneVec3 {
    pub x: Lanes,
    pub y: Lanes,
    pub z: Lanes,
}

impl LaneVec3 {
    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> LaneVec3 {
        LaneVec3 {
            x: Lanes::splat(v.x),
            y: Lanes::splat(v.y),
            z: Lanes::splat(v.z),
        }
    }

    /// Lane `lane` as a [`Vec3`].
    #[inline(always)]
    pub fn get(&self, lane: usize) -> Vec3 {
        Vec3::new(self.x.0[lane], self.y.0[lane], self.z.0[lane])
    }

    /// Sets lane `lane`.
    #[inline(always)]
    pub fn set(&mut self, lane: usize, v: Vec3) {
        self.x.0[lane] = v.x;
        self.y.0[lane] = v.y;
        self.z.0[lane] = v.z;
    }

    /// Dot product per lane.
    #[inline(always)]
    pub fn dot(self, o: LaneVec3) -> Lanes {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product per lane.
    #[inline(always)]
    pub fn cross(self, o: LaneVec3) -> LaneVec3 {
        LaneVec3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// Squared length per lane.
    #[inline(always)]
    pub fn length_squared(self) -> Lanes {
        self.dot(self)
    }

    /// Scales every lane's vector by that lane's number.
    #[inline(always)]
    pub fn scale(self, s: Lanes) -> LaneVec3 {
        LaneVec3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// Per lane `if mask > 0 { a } else { b }`.
    #[inline(always)]
    pub fn select(mask: Lanes, a: LaneVec3, b: LaneVec3) -> LaneVec3 {
        LaneVec3 {
            x: Lanes::select(mask, a.x, b.x),
            y: Lanes::select(mask, a.y, b.y),
            z: Lanes::select(mask, a.z, b.z),
        }
    }
}

impl Add for LaneVec3 {
    type Output = LaneVec3;
    #[inline(always)]
    fn add(self, o: LaneVec3) -> LaneVec3 {
        LaneVec3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for LaneVec3 {
    type Output = LaneVec3;
    #[inline(always)]
    fn sub(self, o: LaneVec3) -> LaneVec3 {
        LaneVec3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Neg for LaneVec3 {
    type Output = LaneVec3;
    #[inline(always)]
    fn neg(self) -> LaneVec3 {
        LaneVec3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl AddAssign for LaneVec3 {
    #[inline(always)]
    fn add_assign(&mut self, o: LaneVec3) {
        *self = *self + o;
    }
}

impl SubAssign for LaneVec3 {
    #[inline(always)]
    fn sub_assign(&mut self, o: LaneVec3) {
        *self = *self - o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bend_angle_and_factor_match_the_library() {
        // Reference: f64 atan2 and α/sin α on y ≥ 0 over every octant. Angle bound 2e-7 rad (the
        // polynomial's 4e-8 error plus f32 rounding of its evaluation) plus a few ulp of π
        // (octant reflections); factor bound 1e-6 relative (P(0) = 1 − 7e-7, the fit's weight)
        // plus the angle's error over sin α.
        let mut worst_angle = 0.0f64;
        let mut worst_factor = 0.0f64;
        for k in 0..=20_000 {
            let exact = std::f64::consts::PI * k as f64 / 20_000.0;
            let (y, x) = (exact.sin().abs() as f32, exact.cos() as f32);
            let (angle, factor) = Lanes::bend_angle_and_factor(Lanes::splat(y), Lanes::splat(x));
            let reference = (y as f64).atan2(x as f64);
            worst_angle = worst_angle.max((angle.0[0] as f64 - reference).abs());
            if y > 1e-3 {
                let expected = reference / y as f64;
                let bound = 1e-6 * expected + 2.5e-7 / y as f64;
                let error = (factor.0[0] as f64 - expected).abs();
                worst_factor = worst_factor.max(error / bound);
            } else if x > 0.0 {
                assert!((factor.0[0] - 1.0).abs() < 1e-6, "{y} {x}: {}", factor.0[0]);
            }
        }
        assert!(
            worst_angle < 2e-7 + 4.0 * f64::from(f32::EPSILON) * std::f64::consts::PI,
            "{worst_angle}"
        );
        assert!(worst_factor <= 1.0, "{worst_factor}");
        let (angle, factor) = Lanes::bend_angle_and_factor(Lanes::splat(0.0), Lanes::splat(1.0));
        assert_eq!(angle.0[0], 0.0);
        assert!((factor.0[0] - 1.0).abs() < 1e-6);
    }
}
