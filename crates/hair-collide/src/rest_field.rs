//! The rest mesh that a deforming body reads its distance field from ([`RestField`]), and each
//! instant's fits to it ([`Deformation`]: the rigid one, and the map the field is read through,
//! `field_map.rs`); `moving_field.rs` reads the field through them.

use std::sync::Arc;

use glam::{DMat3, Mat3, Vec3};

use crate::distance_field::DistanceField;
use crate::field_map::FieldMap;
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
    /// `(Σ X̃ X̃ᵀ)⁻¹` of the centred rest vertices `X̃` \[1/m²\] (the affine fit's second
    /// factor, `field_map.rs`); `None` for a flat mesh.
    spread_inverse: Option<Mat3>,
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
    /// What the moving field reads the rest field through: the affine fit where it keeps the
    /// vertices closer than the rigid one, else the rigid one.
    pub(crate) map: FieldMap,
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
        let centred: Vec<Vec3> = vertices.iter().map(|v| at(v) - centroid).collect();
        let spread = centred.iter().fold(DMat3::ZERO, |sum, x| {
            let x = x.as_dvec3();
            sum + DMat3::from_cols(x * x.x, x * x.y, x * x.z)
        });
        let spread_inverse = (spread.determinant().abs() > 1e-30)
            .then(|| spread.inverse().as_mat3())
            .filter(|m| m.is_finite());
        RestField {
            rest: Arc::new(RestBody {
                indices,
                triangles,
                field,
                vertices,
                centred,
                centroid,
                spread_inverse,
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
    /// documentation), and the map its field is read through (`field_map.rs`).
    fn fit(&self, positions: &[Vec3]) -> (RigidFit, FieldMap) {
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
        let affine = rest.spread_inverse.map(|inverse| covariance * inverse);
        // Each vertex against its rest place moved by either fit: `M X̃ + x̄` (the fits carry
        // the rest centroid onto the current one).
        let (rigid_squared, affine_squared) = rest.vertices.iter().zip(&rest.centred).fold(
            (0.0f32, 0.0f32),
            |(rigid, affine_far), (vertex, rest_offset)| {
                let x = at(vertex) - centroid;
                let by_affine = affine.map_or(0.0, |a| x.distance_squared(a * *rest_offset));
                (
                    rigid.max(x.distance_squared(rotation * *rest_offset)),
                    affine_far.max(by_affine),
                )
            },
        );
        let rigid = RigidFit {
            rotation,
            translation: centroid - rotation * rest.centroid,
            deviation: rigid_squared.sqrt(),
        };
        let map = affine
            .and_then(|a| FieldMap::affine(a, centroid - a * rest.centroid, affine_squared.sqrt()))
            .filter(|map| map.deviation < rigid.deviation)
            .unwrap_or(FieldMap::rigid(
                rigid.rotation,
                rigid.translation,
                rigid.deviation,
            ));
        (rigid, map)
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
        let (fit, map) = rest.fit(positions);
        Deformation {
            rest: rest.clone(),
            fit,
            map,
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
