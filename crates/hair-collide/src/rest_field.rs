//! The rest mesh that a deforming body reads its distance field from ([`RestField`]), and each
//! instant's fits to it ([`Deformation`]: the rigid one, and the map the field is read through,
//! `field_map.rs`); `moving_field.rs` reads the field through them.

use std::sync::Arc;

use glam::{DMat3, DMat4, Mat3, Vec3};

use crate::deviation_blocks::{Blocks, NearDeviations};
use crate::distance_field::DistanceField;
use crate::field_map::FieldMap;
use crate::geometry::Triangle;
use crate::robust_fit::{BlockMoments, bulk_fit};

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
    /// The vertices that triangles use, sorted by block of `blocks` (ascending within one).
    vertices: Vec<u32>,
    /// Those vertices at rest \[m\] (body frame), centred on `centroid`.
    centred: Vec<Vec3>,
    /// The mean of those vertices at rest \[m\].
    centroid: Vec3,
    /// `Σ X̃ X̃ᵀ` of the centred rest vertices `X̃` \[m²\].
    spread: DMat3,
    /// Its inverse \[1/m²\] (the affine fit's second factor, `field_map.rs`); `None` for a
    /// flat mesh.
    spread_inverse: Option<DMat3>,
    /// The vertices in blocks, for the deviations per region (`deviation_blocks.rs`).
    blocks: Blocks,
    /// Per occupied block, `Σ h hᵀ` with `h = (X̃, 1)` over its vertices (`robust_fit.rs`).
    block_spreads: Vec<DMat4>,
}

/// What an instant's fit writes besides its result, kept to be lent to a later instant.
#[derive(Debug, Clone, Default)]
pub(crate) struct FitScratch {
    moments: Vec<BlockMoments>,
    deviations: Vec<f32>,
    errors: Vec<f64>,
    ranks: Vec<(f64, f64)>,
    kept: Vec<bool>,
}

/// A rigid transform fitted to a deformation: current ≈ `rotation` · rest + `translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RigidFit {
    pub(crate) rotation: Mat3,
    pub(crate) translation: Vec3,
}

/// A deforming body's instant read through its rest field.
#[derive(Debug, Clone)]
pub(crate) struct Deformation {
    pub(crate) rest: RestField,
    pub(crate) fit: RigidFit,
    /// What the moving field reads the rest field through: the affine fit to the bulk of the
    /// mesh (`robust_fit.rs`), else the affine fit to all of it, else the rigid one.
    pub(crate) map: FieldMap,
    /// How far the mesh strays from `map` around each block (`deviation_blocks.rs`).
    pub(crate) near: NearDeviations,
    scratch: FitScratch,
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
        let used: Vec<u32> = (0..vertex_count as u32)
            .filter(|&v| used[v as usize])
            .collect();
        let at = |&v: &u32| positions[v as usize];
        let longest_edge = triangles
            .iter()
            .flat_map(|t| {
                let [a, b, c] = t.vertices;
                [a.distance(b), b.distance(c), c.distance(a)]
            })
            .filter(|e| e.is_finite())
            .fold(0.0, f32::max);
        let rest: Vec<Vec3> = used.iter().map(at).collect();
        let (blocks, order) = Blocks::of(&rest, longest_edge);
        let vertices: Vec<u32> = order.iter().map(|&i| used[i as usize]).collect();
        let centroid = vertices.iter().map(at).sum::<Vec3>() / (vertices.len().max(1) as f32);
        let centred: Vec<Vec3> = vertices.iter().map(|v| at(v) - centroid).collect();
        let block_spreads: Vec<DMat4> = (0..blocks.occupied())
            .map(|block| {
                centred[blocks.vertices(block)]
                    .iter()
                    .fold(DMat4::ZERO, |sum, x| {
                        let h = x.as_dvec3().extend(1.0);
                        sum + DMat4::from_cols(h * h.x, h * h.y, h * h.z, h)
                    })
            })
            .collect();
        let spread = block_spreads.iter().fold(DMat3::ZERO, |sum, s| {
            sum + DMat3::from_cols(
                s.x_axis.truncate(),
                s.y_axis.truncate(),
                s.z_axis.truncate(),
            )
        });
        let spread_inverse = (spread.determinant().abs() > 1e-30)
            .then(|| spread.inverse())
            .filter(|m| m.is_finite());
        RestField {
            rest: Arc::new(RestBody {
                indices,
                triangles,
                field,
                vertices,
                centred,
                centroid,
                spread,
                spread_inverse,
                blocks,
                block_spreads,
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

    /// The instant whose vertices are at `positions` \[m\] read through this rest field:
    /// its rigid fit (see the module documentation), the map its field is read through
    /// (`field_map.rs`) and the deviations from it per region (`deviation_blocks.rs`), in the
    /// memory of `near` and `scratch`.
    fn fit(
        &self,
        positions: &[Vec3],
        near: &mut NearDeviations,
        scratch: &mut FitScratch,
    ) -> (RigidFit, FieldMap) {
        let rest = &self.rest;
        let at = |v: u32| positions[v as usize];
        let blocks = &rest.blocks;
        let count = rest.vertices.len().max(1) as f64;
        // Each block's moments of the displacements `d = x − X` (`robust_fit.rs`), summed in
        // single precision within a block (tens of vertices) and double across.
        scratch.moments.clear();
        scratch.moments.extend((0..blocks.occupied()).map(|block| {
            let range = blocks.vertices(block);
            let (mut sum, mut cross, mut square) = (Vec3::ZERO, Mat3::ZERO, 0.0f32);
            for (&vertex, &offset) in rest.vertices[range.clone()]
                .iter()
                .zip(&rest.centred[range])
            {
                let d = at(vertex) - (offset + rest.centroid);
                sum += d;
                cross += Mat3::from_cols(d * offset.x, d * offset.y, d * offset.z);
                square += d.length_squared();
            }
            let cross = cross.as_dmat3();
            BlockMoments {
                cross: DMat4::from_cols(
                    cross.x_axis.extend(0.0),
                    cross.y_axis.extend(0.0),
                    cross.z_axis.extend(0.0),
                    sum.as_dvec3().extend(0.0),
                ),
                square: square as f64,
            }
        }));
        let whole = scratch
            .moments
            .iter()
            .fold(DMat4::ZERO, |total, m| total + m.cross);
        let mean_displacement = whole.w_axis.truncate() / count;
        let displaced = DMat3::from_cols(
            whole.x_axis.truncate(),
            whole.y_axis.truncate(),
            whole.z_axis.truncate(),
        );
        // The cross-covariance Σ x X̃ᵀ = Σ d X̃ᵀ + Σ X X̃ᵀ, the second the rest spread (the
        // rest offsets sum to zero).
        let covariance = (displaced + rest.spread).as_mat3();
        let centroid = rest.centroid + mean_displacement.as_vec3();
        let rotation = polar_rotation(covariance).unwrap_or(Mat3::IDENTITY);
        // The affine fits, as `x ≈ A X̃ + k`: of the whole mesh, then of its bulk.
        let whole_fit = rest.spread_inverse.map(|inverse| {
            let g = displaced * inverse;
            DMat4::from_cols(
                g.x_axis.extend(0.0),
                g.y_axis.extend(0.0),
                g.z_axis.extend(0.0),
                mean_displacement.extend(0.0),
            )
        });
        let affine = |fit: DMat4| {
            let map = (DMat3::IDENTITY
                + DMat3::from_cols(
                    fit.x_axis.truncate(),
                    fit.y_axis.truncate(),
                    fit.z_axis.truncate(),
                ))
            .as_mat3();
            let at_centroid = rest.centroid + fit.w_axis.truncate().as_vec3();
            FieldMap::affine(map, at_centroid - map * rest.centroid, 0.0)
                .map(|field_map| (field_map, at_centroid))
        };
        let chosen = whole_fit.and_then(|start| {
            let bulk = bulk_fit(
                &rest.block_spreads,
                &scratch.moments,
                start,
                &mut scratch.errors,
                &mut scratch.ranks,
                &mut scratch.kept,
            );
            affine(bulk).or_else(|| affine(start))
        });
        let (mut map, linear, at_centroid) = match chosen {
            Some((map, at_centroid)) => (map, map.map, at_centroid),
            None => (
                FieldMap::rigid(rotation, centroid - rotation * rest.centroid, 0.0),
                rotation,
                centroid,
            ),
        };
        // Each vertex against its rest place moved by the chosen map (`A X̃ + k`), block by
        // block.
        scratch.deviations.clear();
        scratch
            .deviations
            .extend((0..blocks.occupied()).map(|block| {
                let range = blocks.vertices(block);
                let mut mapped = 0.0f32;
                for (&vertex, &offset) in rest.vertices[range.clone()]
                    .iter()
                    .zip(&rest.centred[range])
                {
                    mapped = mapped.max(at(vertex).distance_squared(linear * offset + at_centroid));
                }
                // The mapped points' rounding at a head's scale.
                mapped.sqrt() + 1e-6
            }));
        map.deviation = scratch.deviations.iter().copied().fold(0.0, f32::max);
        near.fill(blocks, &scratch.deviations, map.deviation, map.shrink);
        let rigid = RigidFit {
            rotation,
            translation: centroid - rotation * rest.centroid,
        };
        (rigid, map)
    }

    /// The blocks the deviations per region are kept in.
    pub(crate) fn blocks(&self) -> &Blocks {
        &self.rest.blocks
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
        Self::of_reusing(rest, positions, None)
    }

    /// [`Deformation::of`] in the memory of `spare`, an instant no longer needed.
    fn of_reusing(rest: &RestField, positions: &[Vec3], spare: Option<Deformation>) -> Self {
        let (mut near, mut scratch) = spare
            .map(|spare| (spare.near, spare.scratch))
            .unwrap_or_default();
        let (fit, map) = rest.fit(positions, &mut near, &mut scratch);
        Deformation {
            rest: rest.clone(),
            fit,
            map,
            near,
            scratch,
        }
    }

    /// The same rest field at the instant whose vertices are at `positions` \[m\], in the
    /// memory of `spare` where one is given.
    pub(crate) fn at(&self, positions: &[Vec3], spare: Option<Deformation>) -> Self {
        Self::of_reusing(&self.rest, positions, spare)
    }

    /// How far \[m\] any vertex, at `positions` \[m\] (this instant's), strays from the
    /// fitted rigid transform.
    pub(crate) fn deviation(&self, positions: &[Vec3]) -> f32 {
        let rest = &self.rest.rest;
        let (rotation, translation) = (self.fit.rotation, self.fit.translation);
        rest.vertices
            .iter()
            .zip(&rest.centred)
            .map(|(&v, &offset)| {
                let x = positions[v as usize];
                x.distance_squared(rotation * (offset + rest.centroid) + translation)
            })
            .fold(0.0, f32::max)
            .sqrt()
    }

    /// The certified distance \[m\] at a current point whose rest image through the map is
    /// `rest_point`, where the rest field certifies `rest_bound` \[m\]: the whole mesh's
    /// bound, or the one from the deviations around the point where it is larger
    /// (`deviation_blocks.rs`); not positive where nothing is certified.
    #[inline]
    pub(crate) fn bound(&self, rest_point: Vec3, rest_bound: f32) -> f32 {
        let whole = self.map.bound(rest_bound);
        if rest_bound <= 0.0 {
            return whole;
        }
        self.near
            .bound(self.rest.blocks(), rest_point, rest_bound, self.map.shrink)
            .map_or(whole, |near| near.max(whole))
    }
}
