//! Section roots spread evenly over the scalp in rings around the crown.
//!
//! Placement: around the crown direction `c` (with a tangent basis `e1` pointing back, `e2 = c × e1`),
//! directions are `cos γ c + sin γ (cos ω e1 + sin ω e2)`. Along each of 360 meridians
//! (fixed ω) the arc length `s(γ)` along the surface from the crown is tabulated; ring `k` is the
//! curve `s = k h`. One root sits at the crown; each ring's parts inside the scalp (arcs) get roots
//! spaced evenly by arc length, in numbers proportional to their length (largest-remainder rounding
//! over all arcs gives exactly the requested count). The spacing `h` is solved so that the ideal
//! counts `Σ length / h` add up to the requested count, so roots are about `h` apart both along and
//! across the rings.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3};

use super::Head;
use super::scalp::{comb_direction, distance_to_polyline, height_above_hairline};
use super::shape::surface_point;
use crate::error::{HairError, Result};
use crate::frame::Frame;

/// Number of meridians (azimuth samples) around the crown.
const AZIMUTHS: usize = 360;
/// Number of steps along each meridian, out to `MAX_POLAR_ANGLE` from the crown.
const POLAR_STEPS: usize = 720;
/// How far from the crown direction the meridians are tabulated [rad] (150°: past every hairline).
const MAX_POLAR_ANGLE: f64 = 150.0 * PI / 180.0;
/// Largest number of roots [`Head::scalp_roots`] places.
pub const MAX_ROOT_COUNT: usize = 1_000_000;

/// A hair root on the scalp, with the frame a section grows from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalpRoot {
    /// Position on the head's surface [m].
    pub position: Vec3,
    /// Unit outward surface normal.
    pub normal: Vec3,
    /// Unit tangent direction the hair lies along from this root: away from the part line,
    /// downwards and slightly backwards; radially away from the crown behind it.
    pub comb_direction: Vec3,
    /// Unit tangent across the section's width: `comb_direction × normal`, which is the binormal of
    /// `Frame::from_tangent_and_normal(comb_direction, normal)` (see [`ScalpRoot::frame`]).
    pub across: Vec3,
    /// Distance from the crown [m]: arc length along the surface, along the curve of directions in
    /// the plane through the crown direction and this root's (the ring radius the root was placed
    /// on; equal to the geodesic distance on a sphere, close to it on this head).
    pub crown_distance: f32,
    /// Distance to the part line [m], see [`Head::part_distance`].
    pub part_distance: f32,
    /// Whether the root lies within `near_face_distance` of the front hairline (the hairline in
    /// front of the ears).
    pub near_face: bool,
}

impl ScalpRoot {
    /// The root frame with tangent `comb_direction`, normal `normal` and binormal `across`.
    pub fn frame(&self) -> Frame {
        Frame {
            normal: self.normal,
            binormal: self.across,
            tangent: self.comb_direction,
        }
    }
}

/// A sample on a ring: meridian index, polar angle [rad] and surface point [m].
#[derive(Debug, Clone, Copy)]
struct RingSample {
    meridian: usize,
    polar: f64,
    point: DVec3,
}

/// A maximal run of consecutive ring samples on the scalp, and its length [m].
#[derive(Debug, Clone)]
struct Arc {
    ring: usize,
    closed: bool,
    samples: Vec<RingSample>,
    length: f64,
}

/// The crown frame and the arc-length table of the meridians around it.
struct Planner<'a> {
    head: &'a Head,
    crown: DVec3,
    e1: DVec3,
    e2: DVec3,
    /// `arc[m * (POLAR_STEPS + 1) + k]`: arc length [m] from the crown to step k of meridian m.
    arc: Vec<f64>,
}

impl<'a> Planner<'a> {
    fn new(head: &'a Head) -> Planner<'a> {
        let crown = head.crown.as_dvec3().normalize();
        let back = DVec3::NEG_Z - crown * crown.dot(DVec3::NEG_Z);
        let e1 = back.try_normalize().unwrap_or(DVec3::X);
        let e2 = crown.cross(e1);
        let mut planner = Planner {
            head,
            crown,
            e1,
            e2,
            arc: Vec::with_capacity(AZIMUTHS * (POLAR_STEPS + 1)),
        };
        for m in 0..AZIMUTHS {
            let mut previous = head.crown.as_dvec3();
            let mut total = 0.0;
            planner.arc.push(0.0);
            for k in 1..=POLAR_STEPS {
                let polar = MAX_POLAR_ANGLE * k as f64 / POLAR_STEPS as f64;
                let point = surface_point(planner.direction(polar, Self::azimuth(m as f64))).0;
                total += point.distance(previous);
                planner.arc.push(total);
                previous = point;
            }
        }
        planner
    }

    fn azimuth(meridian: f64) -> f64 {
        TAU * meridian / AZIMUTHS as f64
    }

    fn direction(&self, polar: f64, azimuth: f64) -> DVec3 {
        let (sin_p, cos_p) = polar.sin_cos();
        let (sin_a, cos_a) = azimuth.sin_cos();
        self.crown * cos_p + (self.e1 * cos_a + self.e2 * sin_a) * sin_p
    }

    fn is_scalp(&self, point: DVec3) -> bool {
        height_above_hairline(&self.head.params, point) >= 0.0
    }

    /// The polar angle where meridian `m` has arc length `radius`, if the table reaches it.
    fn polar_at(&self, m: usize, radius: f64) -> Option<f64> {
        let table = &self.arc[m * (POLAR_STEPS + 1)..(m + 1) * (POLAR_STEPS + 1)];
        if radius > table[POLAR_STEPS] {
            return None;
        }
        let k = table
            .partition_point(|&s| s <= radius)
            .clamp(1, POLAR_STEPS);
        let (low, high) = (table[k - 1], table[k]);
        let fraction = if high > low {
            (radius - low) / (high - low)
        } else {
            0.0
        };
        Some(MAX_POLAR_ANGLE * (k as f64 - 1.0 + fraction) / POLAR_STEPS as f64)
    }

    /// The scalp arcs of ring `ring` (arc length `ring · spacing` from the crown).
    fn ring_arcs(&self, ring: usize, spacing: f64) -> Vec<Arc> {
        let radius = ring as f64 * spacing;
        let samples: Vec<Option<RingSample>> = (0..AZIMUTHS)
            .map(|m| {
                let polar = self.polar_at(m, radius)?;
                let point = surface_point(self.direction(polar, Self::azimuth(m as f64))).0;
                self.is_scalp(point).then_some(RingSample {
                    meridian: m,
                    polar,
                    point,
                })
            })
            .collect();
        let Some(start) = (0..AZIMUTHS).find(|&m| samples[m].is_none()) else {
            let mut closed: Vec<RingSample> = samples.into_iter().flatten().collect();
            closed.push(closed[0]);
            return vec![make_arc(ring, true, closed)];
        };
        let mut arcs = Vec::new();
        let mut run = Vec::new();
        for offset in 1..=AZIMUTHS {
            match samples[(start + offset) % AZIMUTHS] {
                Some(sample) => run.push(sample),
                None if !run.is_empty() => {
                    arcs.push(make_arc(ring, false, std::mem::take(&mut run)))
                }
                None => {}
            }
        }
        arcs
    }

    /// All scalp arcs for ring spacing `spacing` [m].
    fn arcs(&self, spacing: f64) -> Vec<Arc> {
        let farthest = (0..AZIMUTHS)
            .map(|m| self.arc[(m + 1) * (POLAR_STEPS + 1) - 1])
            .fold(0.0, f64::max);
        let rings = (farthest / spacing).floor() as usize;
        (1..=rings)
            .flat_map(|ring| self.ring_arcs(ring, spacing))
            .collect()
    }

    /// The point at arc length `target` along `arc` [m], on the scalp.
    fn point_on_arc(&self, arc: &Arc, target: f64) -> DVec3 {
        let samples = &arc.samples;
        let mut walked = 0.0;
        for pair in samples.windows(2) {
            let length = pair[0].point.distance(pair[1].point);
            if walked + length >= target && length > 0.0 {
                let t = ((target - walked) / length).clamp(0.0, 1.0);
                let next_meridian = pair[0].meridian as f64 + 1.0;
                let azimuth =
                    Self::azimuth(pair[0].meridian as f64 * (1.0 - t) + next_meridian * t);
                let polar = pair[0].polar + (pair[1].polar - pair[0].polar) * t;
                let point = surface_point(self.direction(polar, azimuth)).0;
                if self.is_scalp(point) {
                    return point;
                }
                return if t < 0.5 {
                    pair[0].point
                } else {
                    pair[1].point
                };
            }
            walked += length;
        }
        samples[samples.len() - 1].point
    }
}

fn make_arc(ring: usize, closed: bool, samples: Vec<RingSample>) -> Arc {
    let length = samples
        .windows(2)
        .map(|p| p[0].point.distance(p[1].point))
        .sum();
    Arc {
        ring,
        closed,
        samples,
        length,
    }
}

/// Splits `total` into integers proportional to `weights` (largest remainder, ties to the first).
fn apportion(weights: &[f64], total: usize) -> Vec<usize> {
    let sum: f64 = weights.iter().sum();
    if sum <= 0.0 {
        return vec![0; weights.len()];
    }
    let quotas: Vec<f64> = weights.iter().map(|w| w / sum * total as f64).collect();
    let mut counts: Vec<usize> = quotas.iter().map(|q| q.floor() as usize).collect();
    let mut order: Vec<usize> = (0..weights.len()).collect();
    order.sort_by(|&a, &b| {
        let (fa, fb) = (quotas[a] - quotas[a].floor(), quotas[b] - quotas[b].floor());
        fb.total_cmp(&fa).then(a.cmp(&b))
    });
    let placed: usize = counts.iter().sum();
    for &i in order.iter().take(total.saturating_sub(placed)) {
        counts[i] += 1;
    }
    counts
}

impl Head {
    /// Exactly `count` section roots spread evenly over the scalp, ordered by `crown_distance`
    /// (the crown first, the hairline last). Deterministic; see the module documentation for the
    /// placement (rings around the crown). Errors when `count` is 0 or above [`MAX_ROOT_COUNT`].
    pub fn scalp_roots(&self, count: usize) -> Result<Vec<ScalpRoot>> {
        if !(1..=MAX_ROOT_COUNT).contains(&count) {
            return Err(HairError::invalid(
                "root count",
                count,
                "an integer in 1..=1000000",
            ));
        }
        let planner = Planner::new(self);
        let wanted = (count - 1) as f64;
        // Ideal count for spacing h is about area / h²: start from the scalp area of a 0.1 m sphere's
        // cap and correct h by the square root of the count ratio.
        let mut spacing = (0.07 / count as f64).sqrt();
        let mut arcs = planner.arcs(spacing);
        for _ in 0..12 {
            let ideal: f64 = arcs.iter().map(|arc| arc.length).sum::<f64>() / spacing;
            if count == 1 || (ideal > 0.0 && (ideal - wanted).abs() <= 0.01 * wanted + 0.5) {
                break;
            }
            spacing *= if ideal > 0.0 {
                (ideal / wanted).sqrt()
            } else {
                0.5
            };
            arcs = planner.arcs(spacing);
        }
        // Small counts can jump past the scalp's edge: come back until a ring lies on the scalp.
        for _ in 0..40 {
            if count == 1 || arcs.iter().any(|arc| arc.length > 0.0) {
                break;
            }
            spacing *= 0.5;
            arcs = planner.arcs(spacing);
        }
        let lengths: Vec<f64> = arcs.iter().map(|arc| arc.length).collect();
        let counts = apportion(&lengths, count - 1);
        if counts.iter().sum::<usize>() != count - 1 {
            // Unreachable with validated parameters: the crown always has scalp around it.
            return Err(HairError::invalid(
                "root count",
                count,
                "a count the scalp can hold (no ring of scalp was found around the crown)",
            ));
        }

        let mut points = Vec::with_capacity(count);
        points.push((planner.head.crown.as_dvec3(), 0.0));
        for (arc, &n) in arcs.iter().zip(&counts) {
            let radius = arc.ring as f64 * spacing;
            let step = arc.length / n.max(1) as f64;
            let offset = if arc.closed && arc.ring % 2 == 0 {
                0.0
            } else {
                0.5
            };
            for i in 0..n {
                points.push((
                    planner.point_on_arc(arc, (i as f64 + offset) * step),
                    radius,
                ));
            }
        }
        Ok(points
            .into_iter()
            .map(|(point, radius)| self.root_at(point, radius as f32))
            .collect())
    }

    /// The root at surface point `point` [m] with crown distance `crown_distance` [m].
    fn root_at(&self, point: DVec3, crown_distance: f32) -> ScalpRoot {
        let (point, normal) = surface_point(point);
        let comb = comb_direction(&self.params, self.crown.as_dvec3(), point, normal);
        let across = comb.cross(normal).normalize_or_zero();
        let position = point.as_vec3();
        ScalpRoot {
            position,
            normal: normal.as_vec3(),
            comb_direction: comb.as_vec3(),
            across: across.as_vec3(),
            crown_distance,
            part_distance: self.part_distance(position),
            near_face: distance_to_polyline(position, &self.front_hairline)
                <= self.params.near_face_distance,
        }
    }
}
