//! The rest mesh that a deforming body reads its distance field from ([`RestField`]), and each
//! instant's rigid fit to it ([`Deformation`]); `moving_field.rs` reads the field through them.

use std::sync::Arc;

use glam::{Mat3, Vec3};

use crate::distance_field::DistanceField;
use crate::geometry::Triangle;

/// The rest mesh that a deforming body's instants read their field from
/// ([`CollisionBody::reading_rest_field`](crate::CollisionBody::reading_rest_field)): its triangles, its distance field (built once, by
/// [`RestField::of`]) and its vertices. Cloning shares it.
#[derive(Debug, Clone)]
pub struct RestField {
    rest: Arc<RestBody>,
}

/// What [`RestField`] shares.
#[derive(Debug)]
struct RestBody {
    /// Per triangle, its vertex indices.
    indices: Arc<[[u32; 3]]>,
    /// The triangles at rest (body frame).
    triangles: Vec<Triangle>,
    /// The rest mesh's distance field, exact within [`MOVING_REACH`] of the surface.
    field: DistanceField,
    /// The vertices that triangles use, ascending.
    vertices: Vec<u32>,
    /// Those vertices at rest \[m\] (body frame), centred on `centroid`.
    centred: Vec<Vec3>,
    /// The mean of those vertices at rest \[m\].
    centroid: Vec3,
}

/// A rigid transform fitted to a deformation: current ≈ `rotation` · rest + `translation`, with
/// every vertex within `deviation` \[m\] of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RigidFit {
    pub(crate) rotation: Mat3,
    pub(crate) translation: Vec3,
    pub(crate) deviation: f32,
}

/// A deforming body's instant read through its rest field.
#[derive(Debug, Clone)]
pub(crate) struct Deformation {
    pub(crate) rest: RestField,
    pub(crate) fit: RigidFit,
}

/// How far from the surface \[m\] a rest field samples exactly: the presets' widest segment
/// volumes (strand groups about 10 mm in radius) decide from the samples, where a rigid body's
/// field (exact within [`EXACT_REACH`](crate::distance_field::EXACT_REACH)) would leave them to
/// its certified bound, which a deformation loosens by the fit's deviation.
pub const MOVING_REACH: f32 = 0.016;

impl RestField {
    /// The rest field of a mesh of `triangles` (each with its `indices` into `vertex_count`
    /// vertices) whose distance field is `field`.
    pub(crate) fn from_parts(
        indices: Arc<[[u32; 3]]>,
        triangles: Vec<Triangle>,
        vertex_count: usize,
        field: DistanceField,
    ) -> Self {
        let positions = positions_of(&indices, &triangles, vertex_count);
        let mut used = vec![false; vertex_count];
        for &v in indices.iter().flatten() {
            used[v as usize] = true;
        }
        let vertices: Vec<u32> = (0..vertex_count as u32)
            .filter(|&v| used[v as usize])
            .collect();
        let at = |&v: &u32| positions[v as usize];
        let centroid = vertices.iter().map(at).sum::<Vec3>() / (vertices.len().max(1) as f32);
        let centred = vertices.iter().map(|v| at(v) - centroid).collect();
        RestField {
            rest: Arc::new(RestBody {
                indices,
                triangles,
                field,
                vertices,
                centred,
                centroid,
            }),
        }
    }

    /// The rest mesh's triangles (body frame).
    pub(crate) fn triangles(&self) -> &[Triangle] {
        &self.rest.triangles
    }

    /// Its triangles' vertex indices.
    pub(crate) fn indices(&self) -> &[[u32; 3]] {
        &self.rest.indices
    }

    /// The rest distance field.
    pub fn field(&self) -> &DistanceField {
        &self.rest.field
    }

    /// Whether `triangles` (an instant's) are this rest mesh's, in the same order.
    pub(crate) fn matches(&self, indices: &[[u32; 3]]) -> bool {
        *self.rest.indices == *indices
    }

    /// The rigid fit of the instant whose vertices are at `positions` (see the module
    /// documentation).
    fn fit(&self, positions: &[Vec3]) -> RigidFit {
        let rest = &self.rest;
        let at = |&v: &u32| positions[v as usize];
        let count = rest.vertices.len().max(1) as f32;
        // The centroid and the cross-covariance Σ (x − x̄)(X − X̄)ᵀ = Σ x (X − X̄)ᵀ (the rest
        // offsets sum to zero), column by column, in one pass.
        let mut sum = Vec3::ZERO;
        let mut covariance = Mat3::ZERO;
        for (vertex, rest_offset) in rest.vertices.iter().zip(&rest.centred) {
            let x = at(vertex);
            sum += x;
            covariance += Mat3::from_cols(x * rest_offset.x, x * rest_offset.y, x * rest_offset.z);
        }
        let centroid = sum / count;
        let rotation = polar_rotation(covariance).unwrap_or(Mat3::IDENTITY);
        let translation = centroid - rotation * rest.centroid;
        let deviation = rest
            .vertices
            .iter()
            .zip(&rest.centred)
            .map(|(vertex, rest_offset)| {
                at(vertex).distance_squared(rotation * (*rest_offset + rest.centroid) + translation)
            })
            .fold(0.0f32, f32::max)
            .sqrt();
        RigidFit {
            rotation,
            translation,
            deviation,
        }
    }
}

/// The mesh's vertex positions \[m\] from its `triangles` (each with its `indices` into
/// `vertex_count` vertices); a vertex no triangle uses is left at the origin.
pub(crate) fn positions_of(
    indices: &[[u32; 3]],
    triangles: &[Triangle],
    vertex_count: usize,
) -> Vec<Vec3> {
    let mut positions = vec![Vec3::ZERO; vertex_count];
    for (corners, triangle) in indices.iter().zip(triangles) {
        for (&v, &p) in corners.iter().zip(&triangle.vertices) {
            positions[v as usize] = p;
        }
    }
    positions
}

/// The rotation nearest `m` (its polar factor) by Higham's iteration; `None` where `m` is
/// singular or a reflection (a mesh too flat or turned inside out to fit).
fn polar_rotation(m: Mat3) -> Option<Mat3> {
    let scale = m
        .to_cols_array()
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f32::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut r = m / scale;
    if r.determinant() <= 1e-6 {
        return None;
    }
    for _ in 0..40 {
        let next = (r + r.inverse().transpose()) * 0.5;
        let change = (next - r)
            .to_cols_array()
            .iter()
            .map(|x| x.abs())
            .sum::<f32>();
        r = next;
        if change < 1e-6 {
            break;
        }
    }
    r.is_finite().then_some(r)
}

impl Deformation {
    /// `rest` read at the instant whose vertices are at `positions` \[m\] (body frame).
    pub(crate) fn of(rest: &RestField, positions: &[Vec3]) -> Self {
        Deformation {
            rest: rest.clone(),
            fit: rest.fit(positions),
        }
    }

    /// The same rest field at the instant whose vertices are at `positions` \[m\].
    pub(crate) fn at(&self, positions: &[Vec3]) -> Self {
        Self::of(&self.rest, positions)
    }

    /// How far \[m\] any vertex strays from the fitted rigid transform.
    pub(crate) fn deviation(&self) -> f32 {
        self.fit.deviation
    }
}
