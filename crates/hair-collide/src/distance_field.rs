//! A body's distance field: a grid over the body (in its own frame) of certified bounds on the
//! distance to its surface, so that a collision query can tell in a few lookups that a point or
//! a segment volume is clear of the body, and spend the exact triangle tests only on hair near
//! the surface.
//!
//! **What a grid vertex holds.** Vertices within `T` of the surface (the *seeds*, a shell a few
//! cells thick: `T` is two cells, and at least [`EXACT_REACH`] plus a cell diagonal, so that
//! every point within [`EXACT_REACH`] of the surface lies in a cell of exact corners, where
//! [`DistanceField::sample`] interpolates the distance and its gradient) hold the exact distance,
//! from the same closest-point search the projection uses, computed a z-slice per task.
//! Every other vertex `w` holds the lower bound `T + e(w) − h√3`, where `e(w)` is the exact
//! Euclidean distance from `w` to the nearest seed (the Felzenszwalb–Huttenlocher transform,
//! linear in the vertex count) and `h` the cell size. Why it holds: every point `x` within
//! `t = T − h√3/2` of the surface has a grid vertex within `h√3/2`, at distance at most `T` from
//! the surface, so a seed; the set within `t` therefore lies within `h√3/2` of the seeds, and
//! `d(w) = t + dist(w, {d ≤ t}) ≥ t + e(w) − h√3/2`.
//!
//! **Signs.** On a closed mesh (where the pseudonormal sign is inside/outside) a seed carries its
//! exact sign, and every other vertex the sign of its neighbours: a grid edge (length `h < T`)
//! from a vertex farther than `T` from the surface cannot cross it, so the sign spreads from the
//! seeds through the grid unchanged. On an open mesh the sign is "in front of or behind the
//! nearest face", which jumps away from the surface, so the field keeps distances only.
//!
//! **A point's bound.** The distance is 1-Lipschitz, so each corner `v` of the point's cell gives
//! `d(p) ≥ |s_v| − |p − v|` (with the corner's sign where positive); the field returns the best
//! of the eight, less a rounding allowance. Outside the grid, the distance to the body's bounds
//! is the bound. Every answer is a certificate, never an estimate: a collision query that skips
//! what the field clears finds exactly what the exhaustive query finds.

use std::collections::VecDeque;

use glam::Vec3;
use rayon::prelude::*;

use crate::field_bricks::ExactBricks;
use crate::geometry::Triangle;
use crate::volume::SweptSphere;

/// Default cell size \[m\] of a body's field (2 mm: a strand segment near the scalp costs a few
/// lookups, and a 30 cm head about 3 M vertices).
pub const DEFAULT_CELL: f32 = 2.0e-3;

/// At most this many grid vertices per field (16 MB of `f32`); a larger body gets larger cells.
pub const MAX_VERTICES: usize = 1 << 22;

/// The grid reaches this fraction of the body's largest extent beyond its bounds.
const PADDING: f32 = 0.25;

/// Seeds are the vertices within this many cells of the surface, and at least within
/// [`EXACT_REACH`].
const SEED_CELLS: f32 = 2.0;

/// Every point within this distance \[m\] of the surface lies in a cell whose eight corners
/// hold exact distances (the seeds reach this plus a cell diagonal), where
/// [`DistanceField::sample`] interpolates them: a segment volume of up to this radius touching
/// the body has its touching core there (strand groups and clusters of the presets are 2–6 mm).
pub const EXACT_REACH: f32 = 0.008;

/// Rounding allowance \[m\] of a bound: the f32 rounding of distances and of the head transform
/// at 1 m (as [`crate::solver::PENETRATION_TOLERANCE`]'s budget, a hundredth of it).
const ROUNDING: f32 = 1.0e-6;

/// A grid of certified distance bounds around a body, in the body's own frame (see the module
/// documentation). Built once per mesh and shared by every copy of the body.
#[derive(Debug, Clone)]
pub struct DistanceField {
    /// Position \[m\] of vertex `(0, 0, 0)`.
    origin: Vec3,
    /// Cell size \[m\].
    cell: f32,
    /// `1 / cell` \[1/m\].
    inverse_cell: f32,
    /// Vertices along x, y, z (each at least 2).
    dims: [usize; 3],
    /// Per vertex, x fastest: a signed (closed mesh) or unsigned (open mesh) bound \[m\], exact
    /// on the seeds.
    values: Vec<f32>,
    /// Whether the values carry inside/outside signs.
    signed: bool,
    /// The body's bounds \[m\]: every point outside them is outside the body.
    bounds: (Vec3, Vec3),
    /// Grid vertices within `seed_reach` of the surface, whose values are exact.
    seeds: usize,
    /// The cells whose eight corners are seeds (their values exact), which
    /// [`DistanceField::sample`] interpolates, stored apart in bricks.
    bricks: ExactBricks,
    /// Every point within this distance \[m\] of the surface lies in an exact cell.
    exact_reach: f32,
}

impl DistanceField {
    /// The field of the surface made of `triangles`, whose exact signed distance at a point
    /// \[m\] and closest triangle `closest` gives (`None` where it cannot), with cells of at
    /// least `cell` \[m\]; signed when `closed`; every point within `exact_reach` \[m\] of
    /// the surface (at least [`EXACT_REACH`]) in an exact cell. [`DistanceField::of`] builds it
    /// from a body.
    pub fn of_surface(
        triangles: &[Triangle],
        closed: bool,
        closest: impl Fn(Vec3) -> Option<(f32, u32)> + Sync,
        cell: f32,
        exact_reach: f32,
    ) -> Self {
        let exact_reach = if exact_reach.is_finite() {
            exact_reach.max(EXACT_REACH)
        } else {
            EXACT_REACH
        };
        let (mut low, mut high) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for triangle in triangles {
            for v in triangle.vertices {
                low = low.min(v);
                high = high.max(v);
            }
        }
        let signed = closed;
        let extent = (high - low).max(Vec3::ZERO);
        // Cells: at least `cell`, and few enough vertices with the padding of 2 seed reaches.
        let mut h = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            DEFAULT_CELL
        };
        // Hair hangs around a body: the grid reaches a quarter of its size beyond it (and at
        // least past the seeds), where the bound is sharp; beyond, the bounds' distance is.
        let pad_for = |h: f32| {
            let reach = (SEED_CELLS * h).max(exact_reach + h * 3.0f32.sqrt());
            (2.0 * (reach + h)).max(PADDING * extent.max_element())
        };
        let dims_for = |h: f32| {
            let pad = pad_for(h);
            [0, 1, 2].map(|k| ((extent[k] + 2.0 * pad) / h).ceil() as usize + 1)
        };
        while dims_for(h).iter().product::<usize>() > MAX_VERTICES {
            h *= 1.25;
        }
        let dims = dims_for(h);
        let origin = low - Vec3::splat(pad_for(h));
        let reach = (SEED_CELLS * h).max(exact_reach + h * 3.0f32.sqrt());
        let count = dims[0] * dims[1] * dims[2];
        let index = |i: usize, j: usize, k: usize| i + dims[0] * (j + dims[1] * k);
        let position =
            |i: usize, j: usize, k: usize| origin + Vec3::new(i as f32, j as f32, k as f32) * h;

        // Candidates: vertices within `reach` of a triangle's bounds.
        let mut candidate = vec![false; count];
        for triangle in triangles {
            let [a, b, c] = triangle.vertices;
            let lo = ((a.min(b).min(c) - Vec3::splat(reach) - origin) / h).floor();
            let hi = ((a.max(b).max(c) + Vec3::splat(reach) - origin) / h).ceil();
            let clamp = |x: f32, k: usize| (x.max(0.0) as usize).min(dims[k] - 1);
            for kz in clamp(lo.z, 2)..=clamp(hi.z, 2) {
                for jy in clamp(lo.y, 1)..=clamp(hi.y, 1) {
                    for ix in clamp(lo.x, 0)..=clamp(hi.x, 0) {
                        candidate[index(ix, jy, kz)] = true;
                    }
                }
            }
        }
        // Seeds: candidates within `reach`, with their exact (signed) distance; one z-slice of
        // the grid per task (each vertex's search is independent, so the field is the same
        // whatever the thread count).
        let slice = dims[0] * dims[1];
        let mut values = vec![f32::NAN; count];
        let mut is_seed = vec![false; count];
        let mut closest_triangles = vec![u32::MAX; count];
        values
            .par_chunks_mut(slice)
            .zip(is_seed.par_chunks_mut(slice))
            .zip(closest_triangles.par_chunks_mut(slice))
            .enumerate()
            .for_each(|(kz, ((values, is_seed), closest_triangles))| {
                for jy in 0..dims[1] {
                    for ix in 0..dims[0] {
                        let at = ix + dims[0] * jy;
                        if !candidate[at + slice * kz] {
                            continue;
                        }
                        let Some((distance, triangle)) = closest(position(ix, jy, kz)) else {
                            continue;
                        };
                        if distance.abs() <= reach {
                            values[at] = if signed { distance } else { distance.abs() };
                            is_seed[at] = true;
                            closest_triangles[at] = triangle;
                        }
                    }
                }
            });
        let seeds = is_seed.iter().filter(|&&s| s).count();
        drop(candidate);
        // Everything else: `reach + e(w) − h√3`, at least `reach`.
        let spread = squared_distances_to_seeds(&is_seed, dims);
        let diagonal = h * 3.0f32.sqrt();
        for (at, value) in values.iter_mut().enumerate() {
            if !is_seed[at] {
                *value = reach.max(reach + spread[at].sqrt() * h - diagonal);
            }
        }
        if signed {
            spread_signs(&mut values, &is_seed, dims);
        }
        let bricks = ExactBricks::new(&values, &closest_triangles, &is_seed, dims);
        DistanceField {
            origin,
            cell: h,
            inverse_cell: 1.0 / h,
            dims,
            values,
            signed,
            bounds: (low, high),
            seeds,
            bricks,
            exact_reach,
        }
    }

    /// The grid's box \[m\] (body frame): `(low corner, high corner)`. Beyond it a bound is the
    /// distance to the body's bounds.
    pub fn grid_bounds(&self) -> (Vec3, Vec3) {
        let size = Vec3::new(
            (self.dims[0] - 1) as f32,
            (self.dims[1] - 1) as f32,
            (self.dims[2] - 1) as f32,
        ) * self.cell;
        (self.origin, self.origin + size)
    }

    /// Cell size \[m\].
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Grid vertices along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Grid vertices within two cells of the surface (their values are exact distances).
    pub fn seed_count(&self) -> usize {
        self.seeds
    }

    /// Whether the field tells inside from outside (the body is closed).
    pub fn is_signed(&self) -> bool {
        self.signed
    }

    /// Bytes the grid holds.
    pub fn memory_bytes(&self) -> usize {
        self.values.len() * std::mem::size_of::<f32>() + self.bricks.memory_bytes()
    }

    /// The value of vertex `(i, j, k)` and its position \[m\].
    fn vertex(&self, i: usize, j: usize, k: usize) -> (f32, Vec3) {
        let at = i + self.dims[0] * (j + self.dims[1] * k);
        (self.values[at], self.vertex_position(i, j, k))
    }

    /// Where grid vertex `(i, j, k)` lies \[m\].
    #[inline]
    fn vertex_position(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.origin + Vec3::new(i as f32, j as f32, k as f32) * self.cell
    }

    /// A certified bound at `p` \[m\] (body frame): `(bound, sign)` with the unsigned distance
    /// from `p` to the surface at least `bound` (0 when nothing is certified), and, on a signed
    /// field, `sign` +1 outside or −1 inside where `bound > 0` (on an unsigned field, or where
    /// `bound` is 0, `sign` is 0). Inside the grid the bound is within `2h√3` of the distance;
    /// beyond it, the distance to the body's bounds. Non-finite points certify nothing.
    pub fn bound(&self, p: Vec3) -> (f32, f32) {
        if !p.is_finite() {
            return (0.0, 0.0);
        }
        // Outside a closed body's bounds is outside it; an open body has no outside.
        let bounds_sign = if self.signed { 1.0 } else { 0.0 };
        let (low, high) = self.bounds;
        let outside_bounds = p.clamp(low, high).distance(p) - ROUNDING;
        let (grid_low, grid_high) = self.grid_bounds();
        if p.clamp(grid_low, grid_high) != p {
            return if outside_bounds > 0.0 {
                (outside_bounds, bounds_sign)
            } else {
                (0.0, 0.0)
            };
        }
        let t = (p - self.origin) / self.cell;
        let cell = [0, 1, 2].map(|k| (t[k].floor().max(0.0) as usize).min(self.dims[k] - 2));
        let (mut best, mut sign) = (0.0f32, 0.0f32);
        // An exact cell's corners are read from its brick (the same values, in a few cache
        // lines), any other's from the whole grid.
        let in_brick = self.bricks.corners(cell[0], cell[1], cell[2]);
        for corner in 0..8 {
            let [x, y, z] = [corner & 1, (corner >> 1) & 1, corner >> 2];
            let (value, at) = match in_brick {
                Some(c) => (
                    c[2 * y + x][z],
                    self.vertex_position(cell[0] + x, cell[1] + y, cell[2] + z),
                ),
                None => self.vertex(cell[0] + x, cell[1] + y, cell[2] + z),
            };
            let certified = value.abs() - at.distance(p) - ROUNDING;
            if certified > best {
                best = certified;
                sign = if self.signed { value.signum() } else { 0.0 };
            }
        }
        if outside_bounds > best {
            (best, sign) = (outside_bounds, bounds_sign);
        }
        (best, sign)
    }

    /// The signed distance \[m\] to the surface at `p` (body frame) and its gradient, both of
    /// the trilinear interpolation of `p`'s cell, whose eight corners hold exact signed
    /// distances; positive outside. `None` where a corner is not exact (`p` farther than about
    /// [`EXACT_REACH`] from the surface), beyond the grid, on an unsigned field, or at a
    /// non-finite point. The interpolation's error on a smooth surface of curvature radius `R`
    /// is of order `h²/R` (a few µm at 2 mm cells on a head), larger near creases.
    pub fn sample(&self, p: Vec3) -> Option<(f32, Vec3)> {
        if !self.signed || !p.is_finite() {
            return None;
        }
        let t = (p - self.origin) * self.inverse_cell;
        if t.min_element() < 0.0 {
            return None;
        }
        // Truncation is the floor of these non-negative coordinates (and saturates at the top).
        let [i, j, k] = [t.x as usize, t.y as usize, t.z as usize];
        let base = Vec3::new(i as f32, j as f32, k as f32);
        // (Dims are at least 2; a far point's index saturates, so no `+ 1` here.)
        if i >= self.dims[0] - 1 || j >= self.dims[1] - 1 || k >= self.dims[2] - 1 {
            return None;
        }
        let f = t - base;
        let c = self.bricks.corners(i, j, k)?;
        // c[y·2 + x][z]: interpolate along x, then y, then z.
        let lerp = |a: f32, b: f32, w: f32| a + (b - a) * w;
        let along_x = |y: usize, z: usize| lerp(c[2 * y][z], c[2 * y + 1][z], f.x);
        let dx = |y: usize, z: usize| c[2 * y + 1][z] - c[2 * y][z];
        let (c00, c10, c01, c11) = (along_x(0, 0), along_x(1, 0), along_x(0, 1), along_x(1, 1));
        let (c0, c1) = (lerp(c00, c10, f.y), lerp(c01, c11, f.y));
        let distance = lerp(c0, c1, f.z);
        let gradient = Vec3::new(
            lerp(
                lerp(dx(0, 0), dx(1, 0), f.y),
                lerp(dx(0, 1), dx(1, 1), f.y),
                f.z,
            ),
            lerp(c10 - c00, c11 - c01, f.z),
            c1 - c0,
        ) * self.inverse_cell;
        Some((distance, gradient))
    }

    /// The closest triangle of the grid vertex nearest `p` \[m\] (body frame) among the
    /// corners of its cell, where that cell is exact (as [`sample`](Self::sample) answers);
    /// `None` elsewhere. Within a cell (a few millimetres) of the triangle closest to `p`
    /// itself: a starting point for whoever needs the surface near `p`.
    pub fn nearby_triangle(&self, p: Vec3) -> Option<u32> {
        if !p.is_finite() {
            return None;
        }
        let t = (p - self.origin) * self.inverse_cell;
        if t.min_element() < 0.0 {
            return None;
        }
        let [i, j, k] = [t.x as usize, t.y as usize, t.z as usize];
        if i >= self.dims[0] - 1 || j >= self.dims[1] - 1 || k >= self.dims[2] - 1 {
            return None;
        }
        let f = t - Vec3::new(i as f32, j as f32, k as f32);
        self.bricks.nearest_triangle([i, j, k], f.to_array())
    }

    /// How close to the surface \[m\] every point samples exactly: a point where
    /// [`sample`](Self::sample) answers `None` inside the grid is farther than this from the
    /// surface ([`EXACT_REACH`], less the rounding allowance).
    pub fn exact_reach(&self) -> f32 {
        self.exact_reach - ROUNDING
    }

    /// Whether `p` \[m\] (body frame) is certified outside the body by more than `margin` \[m\]:
    /// `Some(clearance)` with the distance to the surface at least `clearance > margin`, `None`
    /// when the field cannot say (near the surface, inside, or an unsigned field).
    pub fn outside_clearance(&self, p: Vec3, margin: f32) -> Option<f32> {
        let (bound, sign) = self.bound(p);
        (sign > 0.0 && bound > margin).then_some(bound)
    }

    /// Whether `volume` (body frame) is certified to touch no triangle of the body: its core is
    /// farther from the surface than its radius plus `slack` \[m\]. The core is covered by sample
    /// points, each standing for the part of the core within `δ` of it (a point, sub-segments of
    /// at most a cell, sub-rectangles of at most a cell a side), and is clear where every
    /// sample's bound exceeds `δ + radius + slack`.
    pub fn clears(&self, volume: &SweptSphere, slack: f32) -> bool {
        let need = volume.radius() + slack;
        let clear = |p: Vec3, cover: f32| self.bound(p).0 > cover + need;
        match volume {
            SweptSphere::Point(v) => clear(v.center, 0.0),
            SweptSphere::Line(v) => {
                let axis = v.end - v.start;
                let length = axis.length();
                if clear(v.start + axis * 0.5, 0.5 * length) {
                    return true;
                }
                let n = (length / self.cell).ceil().max(1.0);
                let cover = 0.5 * length / n;
                let count = n as usize;
                (0..count).all(|k| clear(v.start + axis * ((k as f32 + 0.5) / n), cover))
            }
            SweptSphere::Rectangle(v) => {
                let r = &v.rectangle;
                let [e0, e1] = r.half_extents;
                if clear(r.center, (e0 * e0 + e1 * e1).sqrt()) {
                    return true;
                }
                let n0 = (2.0 * e0 / self.cell).ceil().max(1.0);
                let n1 = (2.0 * e1 / self.cell).ceil().max(1.0);
                let (s0, s1) = (2.0 * e0 / n0, 2.0 * e1 / n1);
                let cover = 0.5 * (s0 * s0 + s1 * s1).sqrt();
                let corner = r.center - r.axes[0] * e0 - r.axes[1] * e1;
                (0..n1 as usize).all(|b| {
                    (0..n0 as usize).all(|a| {
                        let p = corner
                            + r.axes[0] * (s0 * (a as f32 + 0.5))
                            + r.axes[1] * (s1 * (b as f32 + 0.5));
                        clear(p, cover)
                    })
                })
            }
        }
    }
}

/// Per vertex, the squared distance (in cells²) to the nearest seed: the exact Euclidean
/// distance transform of Felzenszwalb and Huttenlocher ("Distance transforms of sampled
/// functions", 2012), one lower-envelope pass per axis. Infinite everywhere without a seed.
fn squared_distances_to_seeds(is_seed: &[bool], dims: [usize; 3]) -> Vec<f32> {
    let mut field: Vec<f32> = is_seed
        .iter()
        .map(|&s| if s { 0.0 } else { f32::INFINITY })
        .collect();
    let longest = dims.iter().copied().max().unwrap_or(0);
    let mut line = vec![0.0f32; longest];
    let mut out = vec![0.0f32; longest];
    let mut hull = vec![0usize; longest];
    let mut breaks = vec![0.0f32; longest + 1];
    let strides = [1, dims[0], dims[0] * dims[1]];
    for axis in 0..3 {
        let n = dims[axis];
        let stride = strides[axis];
        let (a, b) = match axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        for u in 0..dims[a] {
            for w in 0..dims[b] {
                let start = u * strides[a] + w * strides[b];
                for (q, slot) in line[..n].iter_mut().enumerate() {
                    *slot = field[start + q * stride];
                }
                lower_envelope(
                    &line[..n],
                    &mut out[..n],
                    &mut hull[..n],
                    &mut breaks[..n + 1],
                );
                for (q, value) in out[..n].iter().enumerate() {
                    field[start + q * stride] = *value;
                }
            }
        }
    }
    field
}

/// `out[q] = min_p (f[p] + (q − p)²)`: the lower envelope of parabolas rooted at the finite
/// samples of `f` (all infinite: all infinite).
fn lower_envelope(f: &[f32], out: &mut [f32], hull: &mut [usize], breaks: &mut [f32]) {
    let Some(first) = f.iter().position(|v| v.is_finite()) else {
        out.fill(f32::INFINITY);
        return;
    };
    // Abscissa where the parabolas rooted at p and q (p < q) cross.
    let cross = |p: usize, q: usize| {
        let (p2, q2) = ((p * p) as f32, (q * q) as f32);
        ((f[q] + q2) - (f[p] + p2)) / (2.0 * (q as f32 - p as f32))
    };
    let mut k = 0;
    hull[0] = first;
    breaks[0] = f32::NEG_INFINITY;
    breaks[1] = f32::INFINITY;
    for (q, value) in f.iter().enumerate().skip(first + 1) {
        if !value.is_finite() {
            continue;
        }
        let mut s = cross(hull[k], q);
        while s <= breaks[k] {
            k -= 1;
            s = cross(hull[k], q);
        }
        k += 1;
        hull[k] = q;
        breaks[k] = s;
        breaks[k + 1] = f32::INFINITY;
    }
    let mut j = 0;
    for (q, slot) in out.iter_mut().enumerate() {
        while breaks[j + 1] < q as f32 {
            j += 1;
        }
        let d = q as f32 - hull[j] as f32;
        *slot = d * d + f[hull[j]];
    }
}

/// Gives every non-seed vertex the sign of the seeds it is connected to through non-seed
/// vertices (breadth first from the seeds, six neighbours): the values' magnitudes stay.
fn spread_signs(values: &mut [f32], is_seed: &[bool], dims: [usize; 3]) {
    let mut known = is_seed.to_vec();
    let mut queue: VecDeque<usize> = (0..values.len()).filter(|&v| is_seed[v]).collect();
    let strides = [1, dims[0], dims[0] * dims[1]];
    while let Some(at) = queue.pop_front() {
        let sign = values[at].signum();
        let coordinates = [
            at % dims[0],
            (at / dims[0]) % dims[1],
            at / (dims[0] * dims[1]),
        ];
        for axis in 0..3 {
            let c = coordinates[axis];
            let neighbours = [
                (c > 0).then(|| at - strides[axis]),
                (c + 1 < dims[axis]).then(|| at + strides[axis]),
            ];
            for next in neighbours.into_iter().flatten() {
                if !known[next] {
                    known[next] = true;
                    values[next] = values[next].abs() * sign;
                    queue.push_back(next);
                }
            }
        }
    }
}
