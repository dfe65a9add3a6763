//! Wind: an air velocity field in space and time (constant, gusting, or a scripted blast).
//!
//! Wind acts on the hair through air drag: a node of mass `m` and velocity `v` feels
//! `m·γ·(w(x, t) − v)` with `γ` the drag rate of [`DynamicsParams`](crate::dynamics::DynamicsParams).

use glam::Vec3;

use crate::dynamics::lanes::{LANES, LaneVec3, Lanes};
use crate::random::SplitMix64;

/// Number of travelling waves summed in a gusting field.
pub const GUST_WAVE_COUNT: usize = 8;

/// One travelling wave of a gust field: `amplitude·direction·sin(k·x − ω·t + phase)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GustWave {
    /// Direction of the velocity it adds (unit).
    pub direction: Vec3,
    /// Velocity amplitude [m/s].
    pub amplitude: f32,
    /// Wave vector [rad/m].
    pub wave_vector: Vec3,
    /// Angular frequency [rad/s].
    pub angular_frequency: f32,
    /// Phase [rad].
    pub phase: f32,
}

/// An air velocity field [m/s] over space [m] and time [s].
#[derive(Debug, Clone, PartialEq, Default)]
pub enum WindField {
    /// Still air.
    #[default]
    Calm,
    /// The same velocity everywhere, always [m/s].
    Constant(Vec3),
    /// A mean velocity plus seeded, smooth gusts varying in time and space: a sum of
    /// [`GUST_WAVE_COUNT`] travelling waves with random directions, wave vectors, frequencies and
    /// phases (a random-phase spectral field). Build it with [`WindField::gusting`].
    Gusting {
        /// Mean velocity [m/s].
        mean: Vec3,
        /// The waves (boxed: they are large next to the other variants).
        waves: Box<[GustWave; GUST_WAVE_COUNT]>,
    },
    /// A scripted blast: speed rises linearly from 0 to `peak_speed` over `rise` seconds from
    /// `start`, holds for `hold` seconds and falls back to 0 over `fall` seconds. The blast front
    /// travels along `direction` at `front_speed` [m/s] from the plane through the origin
    /// perpendicular to it, so points downstream feel it later.
    Blast {
        /// Direction of the blast (unit).
        direction: Vec3,
        /// Peak speed [m/s].
        peak_speed: f32,
        /// When the front leaves the origin's plane [s].
        start: f32,
        /// Rise time [s].
        rise: f32,
        /// Hold time [s].
        hold: f32,
        /// Fall time [s].
        fall: f32,
        /// Speed of the blast front [m/s].
        front_speed: f32,
    },
}

impl WindField {
    /// A gusting field: `mean` velocity [m/s] plus gusts of RMS speed about `gust_speed` [m/s] per
    /// component direction, with time scale `gust_period` [s] and length scale `gust_length` [m];
    /// equal seeds give equal fields.
    pub fn gusting(
        mean: Vec3,
        gust_speed: f32,
        gust_period: f32,
        gust_length: f32,
        seed: u64,
    ) -> Self {
        let mut rng = SplitMix64::new(seed);
        let per_wave = gust_speed * (2.0 / GUST_WAVE_COUNT as f32).sqrt();
        let unit = |rng: &mut SplitMix64| loop {
            let v = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let length_squared = v.length_squared();
            if (0.01..=1.0).contains(&length_squared) {
                return v / length_squared.sqrt();
            }
        };
        let waves = Box::new(std::array::from_fn(|_| {
            let direction = unit(&mut rng);
            let wave_direction = unit(&mut rng);
            let wavelength = gust_length * rng.range(0.5, 2.0);
            let period = gust_period * rng.range(0.5, 2.0);
            GustWave {
                direction,
                amplitude: per_wave,
                wave_vector: wave_direction * (std::f32::consts::TAU / wavelength.max(1e-6)),
                angular_frequency: std::f32::consts::TAU / period.max(1e-6),
                phase: rng.range(0.0, std::f32::consts::TAU),
            }
        }));
        WindField::Gusting { mean, waves }
    }

    /// A blast along `direction` with the given peak speed [m/s], start, rise, hold and fall times
    /// [s], arriving everywhere at once (infinite front speed).
    pub fn blast(
        direction: Vec3,
        peak_speed: f32,
        start: f32,
        rise: f32,
        hold: f32,
        fall: f32,
    ) -> Self {
        WindField::Blast {
            direction: direction.normalize_or_zero(),
            peak_speed,
            start,
            rise,
            hold,
            fall,
            front_speed: f32::INFINITY,
        }
    }

    /// The air velocity [m/s] at `position` [m] and time `time` [s].
    #[inline]
    pub fn velocity_at(&self, position: Vec3, time: f64) -> Vec3 {
        match self {
            WindField::Calm => Vec3::ZERO,
            WindField::Constant(velocity) => *velocity,
            WindField::Gusting { mean, waves } => {
                let t = time as f32;
                let mut velocity = *mean;
                for wave in waves.iter() {
                    let argument =
                        wave.wave_vector.dot(position) - wave.angular_frequency * t + wave.phase;
                    velocity += wave.direction * (wave.amplitude * wave_sin(argument));
                }
                velocity
            }
            WindField::Blast {
                direction,
                peak_speed,
                start,
                rise,
                hold,
                fall,
                front_speed,
            } => {
                let delay = if front_speed.is_finite() {
                    direction.dot(position) / front_speed
                } else {
                    0.0
                };
                let local = time as f32 - start - delay;
                *direction * (peak_speed * trapezoid(local, *rise, *hold, *fall))
            }
        }
    }

    /// An upper bound of the wind speed anywhere, ever [m/s].
    pub fn max_speed(&self) -> f32 {
        match self {
            WindField::Calm => 0.0,
            WindField::Constant(velocity) => velocity.length(),
            WindField::Gusting { mean, waves } => {
                mean.length() + waves.iter().map(|w| w.amplitude.abs()).sum::<f32>()
            }
            WindField::Blast { peak_speed, .. } => peak_speed.abs(),
        }
    }
}

/// `sin x` [x in rad] without a library call for `|x| < 1e6`: `x = n·π + r` with `|r| ≤ π/2`
/// (two-part π), then the Taylor polynomial of degree 11 (error < 6e-8 before f32 rounding) and
/// the sign of `n`. Library `sin` beyond. Several times faster than `f32::sin`, and
/// vectorisable, which matters because gusts need eight per node and step.
#[inline]
pub fn wave_sin(x: f32) -> f32 {
    if x.abs() < WAVE_SIN_RANGE {
        wave_sin_core(x)
    } else {
        x.sin()
    }
}

/// Inputs up to this magnitude take the polynomial in [`wave_sin`].
const WAVE_SIN_RANGE: f32 = 1.0e6;

/// The branch-free polynomial part of [`wave_sin`] (valid for `|x| <` [`WAVE_SIN_RANGE`]).
#[inline(always)]
fn wave_sin_core(x: f32) -> f32 {
    // Round to nearest (even) by the 1.5·2²³ trick: exact for |v| < 2²², no library call.
    const ROUND: f32 = 12_582_912.0;
    let n = (x * std::f32::consts::FRAC_1_PI + ROUND) - ROUND;
    // π = PI_HIGH + PI_LOW, PI_HIGH with few mantissa bits so that n·PI_HIGH is exact.
    const PI_HIGH: f32 = 3.140_625;
    const PI_LOW: f32 = 9.676_536e-4;
    let r = (x - n * PI_HIGH) - n * PI_LOW;
    let r2 = r * r;
    let p = -1.0 / 39_916_800.0f32;
    let p = p * r2 + 1.0 / 362_880.0;
    let p = p * r2 - 1.0 / 5_040.0;
    let p = p * r2 + 1.0 / 120.0;
    let p = p * r2 - 1.0 / 6.0;
    let sine = r + r * r2 * p;
    // (−1)ⁿ: n − 2·round(n/2) is 0 for even n and ±1 for odd n.
    let half = (n * 0.5 + ROUND) - ROUND;
    let odd = n - 2.0 * half;
    sine * (1.0 - 2.0 * odd * odd)
}

impl WindField {
    /// [`WindField::velocity_at`] of every lane of `positions` [m] at `time` [s], lane-parallel
    /// for gusts (the same numbers as the one-point version).
    #[inline(always)]
    pub(crate) fn velocity_at_lanes(&self, positions: &LaneVec3, time: f64) -> LaneVec3 {
        let WindField::Gusting { mean, waves } = self else {
            let mut out = LaneVec3::default();
            for lane in 0..LANES {
                out.set(lane, self.velocity_at(positions.get(lane), time));
            }
            return out;
        };
        let t = time as f32;
        let mut velocity = LaneVec3 {
            x: Lanes::splat(mean.x),
            y: Lanes::splat(mean.y),
            z: Lanes::splat(mean.z),
        };
        for wave in waves.iter() {
            let k = wave.wave_vector;
            let argument = (positions.x * Lanes::splat(k.x)
                + positions.y * Lanes::splat(k.y)
                + positions.z * Lanes::splat(k.z)
                - Lanes::splat(wave.angular_frequency * t))
                + Lanes::splat(wave.phase);
            let mut sine = argument.map(wave_sin_core);
            // One test for all lanes, then the library only where it is needed: a per-lane `if`
            // around `sin` lets the vectoriser call it for every lane and blend (a quarter of
            // the position-based step, measured).
            let out_of_range =
                Lanes::splat(1.0) - Lanes::splat(WAVE_SIN_RANGE).greater(argument.abs());
            if out_of_range.any() {
                for (sine, &argument) in sine.0.iter_mut().zip(&argument.0) {
                    if argument.abs() >= WAVE_SIN_RANGE || argument.is_nan() {
                        *sine = argument.sin();
                    }
                }
            }
            let amplitude = sine * Lanes::splat(wave.amplitude);
            velocity.x = velocity.x + Lanes::splat(wave.direction.x) * amplitude;
            velocity.y = velocity.y + Lanes::splat(wave.direction.y) * amplitude;
            velocity.z = velocity.z + Lanes::splat(wave.direction.z) * amplitude;
        }
        velocity
    }
}

/// A trapezoid pulse: 0 before 0, rising to 1 over `rise`, 1 for `hold`, falling to 0 over `fall`.
fn trapezoid(t: f32, rise: f32, hold: f32, fall: f32) -> f32 {
    if t <= 0.0 {
        0.0
    } else if t < rise {
        t / rise
    } else if t <= rise + hold {
        1.0
    } else if t < rise + hold + fall {
        1.0 - (t - rise - hold) / fall
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gusts_are_seeded_smooth_and_vary_in_space_and_time() {
        let a = WindField::gusting(Vec3::X, 2.0, 1.0, 0.5, 7);
        let b = WindField::gusting(Vec3::X, 2.0, 1.0, 0.5, 7);
        let c = WindField::gusting(Vec3::X, 2.0, 1.0, 0.5, 8);
        let p = Vec3::new(0.1, 0.2, 0.3);
        assert_eq!(a.velocity_at(p, 0.4), b.velocity_at(p, 0.4));
        assert_ne!(a.velocity_at(p, 0.4), c.velocity_at(p, 0.4));
        assert_ne!(a.velocity_at(p, 0.4), a.velocity_at(p, 0.9));
        assert_ne!(a.velocity_at(p, 0.4), a.velocity_at(p + Vec3::Y * 0.3, 0.4));
        // Smooth: |dw/dt| ≤ Σ A·ω ≤ 8·A·2π/(0.5 s); a 1 ms step changes w by less than that × 1 ms.
        let bound: f32 = 8.0 * 2.0 * 0.5f32.sqrt() * std::f32::consts::TAU / 0.5 * 1e-3;
        let jump = (a.velocity_at(p, 0.401) - a.velocity_at(p, 0.4)).length();
        assert!(jump <= bound, "{jump} > {bound}");
        assert!(a.velocity_at(p, 3.0).length() <= a.max_speed());
    }

    #[test]
    fn wave_sine_matches_the_library() {
        // Reference: f64 sin. Bound: the polynomial's 6e-8 plus f32 rounding of the reduced
        // argument, |x|·ε ≈ 1.2e-7·|x| (the input itself is only known to that).
        for k in -200_000..=200_000 {
            let x = k as f32 * 1.37e-3;
            let exact = (x as f64).sin() as f32;
            let bound = 1.5e-7 + 1.2e-7 * x.abs();
            assert!((wave_sin(x) - exact).abs() <= bound, "{x}: {}", wave_sin(x));
        }
        assert_eq!(wave_sin(2.0e7), 2.0e7f32.sin());
    }

    #[test]
    fn blast_follows_its_script() {
        let wind = WindField::blast(Vec3::Z, 10.0, 1.0, 0.5, 1.0, 0.5);
        assert_eq!(wind.velocity_at(Vec3::ZERO, 0.5), Vec3::ZERO);
        assert!((wind.velocity_at(Vec3::ZERO, 1.25).z - 5.0).abs() < 1e-5);
        assert!((wind.velocity_at(Vec3::ZERO, 2.0).z - 10.0).abs() < 1e-5);
        assert!((wind.velocity_at(Vec3::ZERO, 2.75).z - 5.0).abs() < 1e-4);
        assert_eq!(wind.velocity_at(Vec3::ZERO, 4.0), Vec3::ZERO);
    }
}
