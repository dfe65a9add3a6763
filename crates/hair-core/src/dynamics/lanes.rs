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

    /// `atan2(y, x)` for `y ≥ 0` (the bend angle of two unit vectors from `|a × b|` and `a·b`):
    /// a polynomial without library calls, absolute error below 2e-7 rad over `[0, π]`.
    #[inline(always)]
    pub fn atan2_upper(y: Lanes, x: Lanes) -> Lanes {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = atan2_upper(y.0[l], x.0[l]);
        }
        Lanes(out)
    }
}

/// `atan2(y, x)` for `y ≥ 0` without a library call: the ratio of the smaller to the larger
/// magnitude `t ∈ [0, 1]` into an odd polynomial for `atan t` on `[0, 1]` (degree 15, error
/// < 4e-8 rad before f32 rounding), then the octant.
#[inline(always)]
#[allow(clippy::excessive_precision)] // the fitted coefficients, as printed
pub(crate) fn atan2_upper(y: f32, x: f32) -> f32 {
    let ax = x.abs();
    let swap = y > ax;
    let (numerator, denominator) = if swap { (ax, y) } else { (y, ax) };
    let t = if denominator > 0.0 {
        numerator / denominator
    } else {
        0.0
    };
    let s = t * t;
    // atan t ≈ t·P(t²) on [0, 1] (weighted least-squares fit, |error| < 4e-8 in exact arithmetic).
    let p = -0.004_049_165_6_f32;
    let p = p * s + 0.021_842_73;
    let p = p * s - 0.055_882_04;
    let p = p * s + 0.096_398_89;
    let p = p * s - 0.139_076_88;
    let p = p * s + 0.199_463_69;
    let p = p * s - 0.333_298_43;
    let p = p * s + 0.999_999_33;
    let mut angle = t * p;
    if swap {
        angle = std::f32::consts::FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = std::f32::consts::PI - angle;
    }
    angle
}

/// One 3-vector per lane, stored by component.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct LaneVec3 {
    pub x: Lanes,
    pub y: Lanes,
    pub z: Lanes,
}

impl LaneVec3 {
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
    fn polynomial_atan2_matches_the_library() {
        // Reference: f32::atan2 on y ≥ 0 over every octant; bound 2e-7 rad (the polynomial's 4e-8
        // error plus f32 rounding of its evaluation) plus a few ulp of π (octant reflections).
        let mut worst = 0.0f32;
        for k in 0..=20_000 {
            let angle = std::f32::consts::PI * k as f32 / 20_000.0;
            for radius in [1e-3f32, 1.0, 7.5] {
                let (y, x) = (angle.sin().abs() * radius, angle.cos() * radius);
                worst = worst.max((atan2_upper(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(
            worst < 2e-7 + 4.0 * f32::EPSILON * std::f32::consts::PI,
            "{worst}"
        );
        assert_eq!(atan2_upper(0.0, 0.0), 0.0);
        assert_eq!(atan2_upper(0.0, 1.0), 0.0);
    }
}
