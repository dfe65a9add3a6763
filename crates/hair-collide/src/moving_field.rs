//! A deforming body's distance field, moving with it (issues 51 and 53): the rest mesh's field
//! ([`DistanceField`], built once), read at each instant through the deformation, so that hair
//! collides with a talking, squashing head through a few field samples per segment, as it does
//! with a rigid one, instead of descending a refitted triangle tree.
//!
//! **A point's rest image.** A point `p` near the deformed surface is written in the frame of a
//! *carrier* triangle `t` (its current vertices `a, b, c` and unit normal `n`):
//! `p = a + u (b − a) + v (c − a) + h n`, and sent to the same coordinates over the rest
//! triangle: `q = A + u (B − A) + v (C − A) + h N`. The normal offset `h` is kept, so a point
//! above the inside of its carrier keeps its distance to the surface exactly; the in-plane
//! coordinates stretch with the triangle. The carrier is the closest triangle recorded at the
//! rest field's grid vertex nearest the image ([`DistanceField::nearby_triangle`]): a first
//! image comes from a map fitted to the whole deformation (below), then at most two
//! more through the carrier found, until the carrier no longer changes. The field's distance at
//! `q` is the sample's distance, and its gradient, turned from the rest triangle's frame to the
//! current one's, the sample's normal.
//!
//! **Its error.** Above the inside of the carrier the distance is exact up to the rest field's
//! own interpolation (`h²/R`, µm). Where the closest point lies on another triangle (over edges,
//! a neighbour of the carrier), the in-plane stretch `ε` of the triangles between them moves the
//! image by at most `ε` times the point's distance to the surface: 8 % stretch at 5 mm off the
//! surface is 0.4 mm. Contacts carry that error, as a rigid body's field contacts carry the
//! samples' (`field_contacts.rs`); the positional guarantee is the exact projection's, whatever
//! the field says.
//!
//! **Certified bounds.** Every vertex of the deformed mesh lies within `δ` of its rest position
//! moved by the fitted map `F` (`δ` is measured at each instant), and so does every point of
//! every triangle (a convex combination of its vertices'). So the distance from `p` to the
//! deformed surface is at least `σ` times the rest surface's distance at `F⁻¹ p` less `δ` (`σ`
//! the map's least stretch, 1 for a rigid one), and where that is positive the straight-line
//! morph from `F(rest)` to the deformed surface never crosses `p`: the rest field's sign holds.
//! This is what the projection skips clear nodes with, and what tells a point beyond the exact
//! shell without a tree search.
//!
//! **The fit.** The rigid fit is the rotation and translation that best map the rest vertices
//! onto the current ones in least squares (Kabsch): the rotation is the polar factor of the
//! cross-covariance of the centred positions, found by Higham's iteration
//! `R ← (R + R⁻ᵀ) / 2`. `F` is the affine least-squares fit where it keeps the vertices closer
//! than the rigid one does (`field_map.rs`): a squash and stretch is affine, so only what is not
//! (a jaw's drop) is left in `δ`. The talking head's worst `δ` is 18 mm rigid and 8.7 mm affine.
//! `F` only has to be a good first guess and a small `δ`; the bounds hold for any such map.

use std::sync::Arc;

use glam::{Mat3, Vec3};

use hair_core::dynamics::triangle_frame;

use crate::body::CollisionBody;
use crate::distance_field::{DEFAULT_CELL, DistanceField};
use crate::error::{CollideError, Result};
use crate::geometry::Triangle;
use crate::rest_field::{Deformation, MOVING_REACH, RestField, positions_of};

impl RestField {
    /// The rest field of `rest`, a body built from the deforming mesh at rest (its pose is not
    /// read): builds its distance field, exact within [`MOVING_REACH`] of the surface (about
    /// 1 s for a 20k-triangle head in a release build on two cores).
    pub fn of(rest: &CollisionBody) -> Self {
        let field = DistanceField::of_reaching(rest, DEFAULT_CELL, MOVING_REACH);
        let shape = &rest.shape;
        RestField::from_parts(
            shape.indices.clone(),
            shape.triangles.clone(),
            shape.pseudonormals.vertex_count,
            field,
        )
    }
}

/// An instant's field: its deformation and the body at that instant.
#[derive(Clone, Copy)]
pub(crate) struct MovedField<'a> {
    deformation: &'a Deformation,
    current: &'a [Triangle],
    body: &'a CollisionBody,
}

/// A point's place on its carrier triangle: `p = a + u (b − a) + v (c − a) + h n`.
#[derive(Debug, Clone, Copy)]
struct OnTriangle {
    u: f32,
    v: f32,
    h: f32,
}

/// `p` on `triangle` (see [`OnTriangle`]); `None` on a degenerate triangle.
fn on_triangle(triangle: &Triangle, p: Vec3) -> Option<OnTriangle> {
    let [a, b, c] = triangle.vertices;
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    // Degenerate (or not finite): no plane to measure in.
    if det.is_nan() || det <= f32::EPSILON * g11 * g22 {
        return None;
    }
    let (r1, r2) = (d.dot(e1), d.dot(e2));
    Some(OnTriangle {
        u: (g22 * r1 - g12 * r2) / det,
        v: (g11 * r2 - g12 * r1) / det,
        h: d.dot(triangle.normal),
    })
}

/// The point at `place` over `triangle`.
fn at_place(triangle: &Triangle, place: OnTriangle) -> Vec3 {
    let [a, b, c] = triangle.vertices;
    a + (b - a) * place.u + (c - a) * place.v + triangle.normal * place.h
}

/// A field sample through the deformation: the distance \[m\] (positive outside), its gradient
/// turned into the current frame, and the carrier triangle with the point's barycentric
/// weights on it (clamped into the triangle).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MovedSample {
    pub distance: f32,
    pub gradient: Vec3,
    pub triangle: u32,
    pub weights: Vec3,
}

impl<'a> MovedField<'a> {
    /// The field of `body`, an instant of `deformation`.
    pub(crate) fn new(deformation: &'a Deformation, body: &'a CollisionBody) -> Self {
        MovedField {
            deformation,
            current: &body.shape.triangles,
            body,
        }
    }

    fn rest(&self) -> &RestField {
        &self.deformation.rest
    }

    fn field(&self) -> &DistanceField {
        self.deformation.rest.field()
    }

    /// `p` \[m\] (current body frame) brought back to the rest frame by the fitted map.
    fn fitted_back(&self, p: Vec3) -> Vec3 {
        self.deformation.map.back(p)
    }

    /// The rest image of `p` through carrier `t`, with `p`'s place on it.
    fn image(&self, t: u32, p: Vec3) -> Option<(Vec3, OnTriangle)> {
        let place = on_triangle(self.current.get(t as usize)?, p)?;
        let rest = self.rest().triangles().get(t as usize)?;
        Some((at_place(rest, place), place))
    }

    /// The rest image of `p` (see the module documentation), its carrier and place; `None`
    /// where no carrier is found (the image is not within a cell of the rest field's exact
    /// shell, or `p` is farther than `reach` \[m\] from the surface) or a carrier is
    /// degenerate.
    fn locate(&self, p: Vec3, hint: Option<u32>, reach: f32) -> Option<(Vec3, u32, OnTriangle)> {
        let field = self.field();
        let reach = reach.min(field.exact_reach());
        let first = || match field.nearby_triangle(self.fitted_back(p)) {
            Some(carrier) => Some(carrier),
            // Where the deformation strays from the fit, the fitted-back point may miss the
            // exact shell: the closest triangle within the reach is found in the tree, unless
            // the certified bound puts the point beyond it already.
            None if self.bound(p).0 > reach => None,
            None => self.body.closest_local_triangle_within(p, reach),
        };
        let mut hinted = hint.filter(|&t| (t as usize) < self.current.len());
        let mut carrier = match hinted {
            Some(t) => t,
            None => first()?,
        };
        let (mut image, mut place) = self.image(carrier, p)?;
        for _ in 0..3 {
            match field.nearby_triangle(image) {
                Some(next) if next != carrier => {
                    carrier = next;
                    (image, place) = self.image(carrier, p)?;
                }
                Some(_) => break,
                // The hint led off the exact shell: start afresh, once.
                None if hinted.take().is_some() => {
                    carrier = first()?;
                    (image, place) = self.image(carrier, p)?;
                }
                None => break,
            }
        }
        Some((image, carrier, place))
    }

    /// The field's distance and gradient at `p` \[m\] (current body frame), with the carrier
    /// (see the module documentation for the error); `None` where the rest field has no exact
    /// cell at the image (farther than about [`DistanceField::exact_reach`] from the surface)
    /// or no carrier is found. `hint` is a carrier to start from (a nearby point's, say), and
    /// becomes this point's carrier where one is found: a hint only saves lookups where it is
    /// near, and the carrier found is checked against the field either way.
    pub(crate) fn sample(&self, p: Vec3, hint: &mut Option<u32>) -> Option<MovedSample> {
        let sample = self.sample_unturned(p, hint, f32::INFINITY)?;
        Some(MovedSample {
            gradient: self.turned(sample.triangle, sample.gradient)?,
            ..sample
        })
    }

    /// `rest_gradient` (the rest field's, at the image through carrier `triangle`) turned from
    /// the rest triangle's frame to the current one's; `None` where either triangle is
    /// degenerate (no frame to turn through).
    pub(crate) fn turned(&self, triangle: u32, rest_gradient: Vec3) -> Option<Vec3> {
        let t = triangle as usize;
        let rest = triangle_frame(self.rest().triangles().get(t)?.vertices)?;
        let current = triangle_frame(self.current.get(t)?.vertices)?;
        Some(current * (rest.transpose() * rest_gradient))
    }

    /// [`MovedField::sample`] with the gradient left in the rest triangle's frame
    /// ([`MovedField::turned`] turns it): most samples only need their distance. Only a point
    /// that may lie within `reach` \[m\] of the surface is searched for in the triangle tree
    /// where the lookups find no carrier: `None` then also stands for a point farther than that.
    pub(crate) fn sample_unturned(
        &self,
        p: Vec3,
        hint: &mut Option<u32>,
        reach: f32,
    ) -> Option<MovedSample> {
        let (image, carrier, place) = self.locate(p, *hint, reach)?;
        *hint = Some(carrier);
        // (A degenerate carrier gives no place on it: `image` found none.)
        let (distance, gradient) = self.field().sample(image)?;
        let (u, v) = (place.u.clamp(0.0, 1.0), place.v.clamp(0.0, 1.0));
        let (u, v) = if u + v > 1.0 {
            (u / (u + v), v / (u + v))
        } else {
            (u, v)
        };
        Some(MovedSample {
            distance,
            gradient,
            triangle: carrier,
            weights: Vec3::new(1.0 - u - v, u, v),
        })
    }

    /// A certified bound at `p` \[m\] (current body frame), as [`DistanceField::bound`]:
    /// `(bound, sign)`, the rest field's at the fitted-back point scaled by the map's least
    /// stretch, less its deviation
    /// (see the module documentation).
    pub(crate) fn bound(&self, p: Vec3) -> (f32, f32) {
        let (bound, sign) = self.field().bound(self.fitted_back(p));
        let bound = self.deformation.map.bound(bound);
        if bound > 0.0 {
            (bound, sign)
        } else {
            (0.0, 0.0)
        }
    }

    /// Whether `p` is certified outside by more than `margin` \[m\], as
    /// [`DistanceField::outside_clearance`].
    pub(crate) fn outside_clearance(&self, p: Vec3, margin: f32) -> Option<f32> {
        let (bound, sign) = self.bound(p);
        (sign > 0.0 && bound > margin).then_some(bound)
    }

    /// See [`DistanceField::exact_reach`].
    pub(crate) fn exact_reach(&self) -> f32 {
        self.field().exact_reach()
    }
}

impl CollisionBody {
    /// This deforming body read through `rest`'s field: its contacts
    /// ([`crate::query_body_field`]) and the projection's certified clear nodes then come from
    /// the rest mesh's distance field moved with the body (see `moving_field.rs`), and every
    /// later instant made by [`CollisionBody::deformed`] keeps reading it. Errors where the
    /// body's triangles are not the rest mesh's (count and vertex indices).
    pub fn reading_rest_field(&self, rest: &RestField) -> Result<Self> {
        if !rest.matches(&self.shape.indices) {
            return Err(CollideError::InvalidParameter {
                name: "rest field",
                value: format!(
                    "a mesh of {} triangles, read by a body of {}",
                    rest.indices().len(),
                    self.shape.indices.len()
                ),
                allowed: "the body's own mesh at rest (the same triangles over the same vertices)",
            });
        }
        let shape = &self.shape;
        let positions = positions_of(
            &shape.indices,
            &shape.triangles,
            shape.pseudonormals.vertex_count,
        );
        let deformation = Deformation::of(rest, &positions);
        Ok(self.with_shape(Arc::new(self.shape.with_deformation(Some(deformation)))))
    }

    /// The moving field of this instant, where the body reads a rest field.
    pub(crate) fn moved_field(&self) -> Option<MovedField<'_>> {
        let deformation = self.shape.deformation.as_ref()?;
        Some(MovedField::new(deformation, self))
    }

    /// How far \[m\] the body's vertices stray from the rigid transform fitted to its
    /// deformation from the rest field's mesh; `None` where it reads none
    /// ([`CollisionBody::reading_rest_field`]).
    pub fn deviation_from_rest(&self) -> Option<f32> {
        Some(self.shape.deformation.as_ref()?.deviation())
    }

    /// The rigid transform fitted to the body's deformation from the rest field's mesh (body
    /// frame: current ≈ `rotation` · rest + `translation` \[m\]) and how far \[m\] any
    /// vertex strays from it ([`CollisionBody::deviation_from_rest`]); `None` where it reads no
    /// rest field.
    pub fn rigid_fit(&self) -> Option<(Mat3, Vec3, f32)> {
        let fit = &self.shape.deformation.as_ref()?.fit;
        Some((fit.rotation, fit.translation, fit.deviation))
    }

    /// Whether `local` \[m\] (body frame) is certified outside by more than `margin` \[m\]:
    /// through the body's distance field for a rigid body, its moving field for a deforming
    /// one that reads a rest field, nothing otherwise (building no field for a deforming
    /// instant).
    pub(crate) fn field_clearance(&self, local: Vec3, margin: f32) -> Option<f32> {
        if self.is_deforming() {
            self.moved_field()?.outside_clearance(local, margin)
        } else {
            self.distance_field().outside_clearance(local, margin)
        }
    }
}

impl CollisionBody {
    /// The signed distance \[m\] (positive outside) and its gradient that this body's field
    /// contacts read at `local` \[m\] (body frame): its distance field's
    /// ([`DistanceField::sample`]) for a rigid body, its rest field's read through the
    /// deformation for a deforming one that reads a rest field (see `moving_field.rs` for the
    /// error); `None` where the field is not exact there, or a deforming body reads none.
    pub fn local_field_sample(&self, local: Vec3) -> Option<(f32, Vec3)> {
        if self.is_deforming() {
            let sample = self.moved_field()?.sample(local, &mut None)?;
            Some((sample.distance, sample.gradient))
        } else {
            self.distance_field().sample(local)
        }
    }

    /// A certified bound at `local` \[m\] (body frame), as [`DistanceField::bound`]: the
    /// distance field's for a rigid body, the rest field's read through the fitted map for a
    /// deforming one that reads a rest field (`(0, 0)`, nothing certified, for one that reads
    /// none).
    pub fn local_field_bound(&self, local: Vec3) -> (f32, f32) {
        if self.is_deforming() {
            self.moved_field()
                .map_or((0.0, 0.0), |field| field.bound(local))
        } else {
            self.distance_field().bound(local)
        }
    }
}

/// Boxes inside a rest mesh (the level selection's occluder boxes, head space \[m\]) prepared
/// to follow its deformation ([`CollisionBody::carried_occluders`]): per box and triangle, how
/// far the triangle lies from the box at rest, at least.
#[derive(Debug, Clone)]
pub struct RestBoxes {
    boxes: Vec<(Vec3, Vec3)>,
    /// Per box, per triangle: the distance \[m\] from the triangle's bounding box to the box
    /// (every point of the triangle is at least this far from the box).
    apart: Vec<Vec<f32>>,
}

impl RestField {
    /// `boxes` (`(low, high)` corners, inside the rest mesh) prepared to follow the
    /// deformation.
    pub fn boxes(&self, boxes: &[(Vec3, Vec3)]) -> RestBoxes {
        let apart = boxes
            .iter()
            .map(|&(low, high)| {
                self.triangles()
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.vertices;
                        let (t_low, t_high) = (a.min(b).min(c), a.max(b).max(c));
                        // The gap between two boxes, axis by axis.
                        (low - t_high).max(t_low - high).max(Vec3::ZERO).length()
                    })
                    .collect()
            })
            .collect();
        RestBoxes {
            boxes: boxes.to_vec(),
            apart,
        }
    }
}

impl CollisionBody {
    /// Writes into `out` the boxes of `rest` carried to this instant, each inside the deformed
    /// body: a box is moved by a rigid transform (the deformation's fit,
    /// [`CollisionBody::rigid_fit`], or none) and shrunk by the most that a triangle strays
    /// from its rest place so moved beyond its distance from the box. Every point of the
    /// carried box is then inside (the surface, morphing from the moved rest mesh, never
    /// crosses it: each triangle point moves less than its distance from the point). Of the two
    /// transforms each box takes the one that keeps more of it; a box shrunk away is left out
    /// ([`hair_core::lod::carried_boxes`]). Returns `false`, writing nothing, where the body
    /// reads no rest field or `rest` was prepared on another mesh.
    pub fn carried_occluders(&self, rest: &RestBoxes, out: &mut Vec<(Vec3, Vec3)>) -> bool {
        let Some(deformation) = self.shape.deformation.as_ref() else {
            return false;
        };
        let current = &self.shape.triangles;
        if rest.apart.iter().any(|apart| apart.len() != current.len()) {
            return false;
        }
        let fit = &deformation.fit;
        let rest_triangles = deformation.rest.triangles();
        let transforms = [
            (fit.rotation, fit.translation),
            (Mat3::IDENTITY, Vec3::ZERO),
        ];
        // Per transform and box, the shrink: one pass over the triangles, each straying from
        // its rest place so moved by its farthest vertex.
        let mut shrinks = vec![[0.0f32; 2]; rest.boxes.len()];
        for (t, (now, then)) in current.iter().zip(rest_triangles).enumerate() {
            let mut strays = [0.0f32; 2];
            for (x, r) in now.vertices.iter().zip(then.vertices) {
                strays[0] = strays[0].max(x.distance(fit.rotation * r + fit.translation));
                strays[1] = strays[1].max(x.distance(r));
            }
            for (shrink, apart) in shrinks.iter_mut().zip(&rest.apart) {
                for (s, stray) in shrink.iter_mut().zip(strays) {
                    *s = s.max(stray - apart[t]);
                }
            }
        }
        let mut best: Vec<Option<(f32, (Vec3, Vec3))>> = vec![None; rest.boxes.len()];
        let mut carried = Vec::new();
        for (k, (rotation, translation)) in transforms.into_iter().enumerate() {
            for (i, shrink) in shrinks.iter().enumerate() {
                // A hair's breadth more: a box touching the bound would touch the surface.
                let one = [rest.boxes[i]];
                hair_core::lod::carried_boxes(
                    &one,
                    rotation,
                    translation,
                    &[shrink[k] + 1e-6],
                    &mut carried,
                );
                if let Some(&(low, high)) = carried.first() {
                    let volume = (high - low).element_product();
                    if best[i].is_none_or(|(kept, _)| volume > kept) {
                        best[i] = Some((volume, (low, high)));
                    }
                }
            }
        }
        out.clear();
        out.extend(best.into_iter().flatten().map(|(_, b)| b));
        true
    }
}
