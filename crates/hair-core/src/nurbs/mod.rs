//! NURBS geometry (§3.1): knot vectors, B-spline basis functions, rational curves and tensor-product surfaces, and a precomputed sampler for many strands.
//!
//! The D-NURBS of the paper are ordinary NURBS whose control points `pᵢ(t)` and weights `wᵢ(t)`
//! change with time; this module holds the geometry only, evaluated at one instant:
//!
//! ```text
//! c(u) = Σᵢ Nᵢ,ₚ(u) wᵢ pᵢ / Σᵢ Nᵢ,ₚ(u) wᵢ
//! ```
//!
//! where `Nᵢ,ₚ` are the B-spline basis functions of degree `p` (order `p + 1`; the paper's `B_{i,k}`
//! has order `k`) over a [`KnotVector`].
//!
//! Conventions:
//! - positions are in metres, parameters `u`, `v` are dimensionless, so derivatives `dC/du` are in
//!   metres per unit parameter (not unit vectors);
//! - every parameter domain is `[0, 1]` for the uniform constructors; evaluation clamps a parameter
//!   into the domain of an open (clamped) direction and wraps it for a periodic (closed) one;
//! - a periodic direction with `n` control points uses the knot vector of an "unrolled" curve of
//!   `n + p` control points whose control point `j` is `P[j mod n]`, so the curve is closed and
//!   `C^(p-1)` everywhere;
//! - surface control grids are stored u-fastest: point `(i, j)` is at index `i + count_u * j`;
//! - evaluation never allocates; constructors validate their input and return
//!   [`HairError`](crate::HairError) naming the bad parameter.
//!
//! For tens of thousands of strands sharing one knot vector, precompute the basis once with
//! [`CurveSampler`] and evaluate each strand as a weighted sum of its control points.

pub mod basis;
mod curve;
mod knots;
mod sampler;
mod surface;
mod tessellation;
#[cfg(test)]
mod test_support;

pub use curve::NurbsCurve;
pub use knots::KnotVector;
pub use sampler::CurveSampler;
pub use surface::NurbsSurface;

/// The degree used when none is asked for: cubic, `C²` across simple knots.
pub const DEFAULT_DEGREE: usize = 3;

/// The highest degree accepted (evaluation keeps `MAX_DEGREE + 1` basis values on the stack).
pub const MAX_DEGREE: usize = 9;
