//! The procedural head-and-neck: an analytic star-shaped surface, its mesh, scalp, part line and roots.
//!
//! The head is generated in code (no external file). It is the default collision body and the
//! default scene's head, and hair roots are placed on its scalp. Frame: metres, right-handed, +Y up,
//! the face looking along +Z, the origin at the head's centre (about eye level, between the ears).
//!
//! - [`shape`]: the analytic surface `radius(direction)` (cranium, jaw, nose and neck, smoothly
//!   united), exact points and normals.
//! - [`tessellation`]: the closed latitude-longitude mesh.
//! - [`scalp`]: hairline, crown, part line and the comb-direction field.
//! - [`roots`]: section roots spread evenly over the scalp.

pub mod params;
pub mod roots;
pub mod scalp;
pub mod shape;
pub mod tessellation;

#[cfg(test)]
mod root_tests;
#[cfg(test)]
mod tests;

use glam::{DVec3, Vec3};

pub use params::HeadParams;
pub use roots::{MAX_ROOT_COUNT, ScalpRoot};

use crate::error::{HairError, Result};
use crate::mesh::TriangleMesh;

/// Fraction of the largest box inscribed in the cranium ellipsoid that [`Head::inner_box`] keeps.
const INNER_BOX_SCALE: f64 = 0.95;

/// The body hair grows on and collides with: the procedural head (its mesh and the analytic
/// surface the mesh was tessellated from, [`Head::procedural`]) or a mesh read from a file
/// ([`Head::from_mesh`]).
///
/// The scalp queries ([`Head::surface_point`], [`Head::is_scalp`], [`Head::part_distance`],
/// [`Head::crown`], [`Head::part_line`], [`Head::hairline`], [`Head::scalp_roots`]) describe the
/// procedural surface; they generate the preset grooms and mean nothing for a mesh from a file
/// ([`Head::is_procedural`] tells which). [`Head::mesh`] and [`Head::occluder_boxes`], what the
/// pipeline draws, collides with and occludes by, are the body's own either way.
#[derive(Debug, Clone)]
pub struct Head {
    /// The closed mesh [m]: counter-clockwise triangles seen from outside, exact unit vertex normals;
    /// `longitude_bands · (latitude_bands - 1) + 2` vertices (a single vertex at each pole, joined by
    /// triangle fans) and `2 · longitude_bands · (latitude_bands - 1)` triangles.
    pub mesh: TriangleMesh,
    /// The parameters the head was built with (the scalp, part and hairline queries read them;
    /// change them only through [`Head::procedural`]).
    pub params: HeadParams,
    /// The crown [m], where the part line ends and hair whorls.
    crown: Vec3,
    /// The part line [m], points from the front hairline to the crown.
    part_line: Vec<Vec3>,
    /// The hairline loop [m], by azimuth from the face towards +X.
    hairline: Vec<Vec3>,
    /// The hairline in front of the ears [m], one polyline from the right temple to the left.
    front_hairline: Vec<Vec3>,
    /// For a mesh from a file: its occluder boxes `(min, max)` [m] (`None`: the procedural head).
    loaded_occluders: Option<Vec<(Vec3, Vec3)>>,
}

impl Head {
    /// Builds the head: validates `params`, tessellates the surface and traces hairline and part.
    pub fn procedural(params: &HeadParams) -> Result<Head> {
        params.validate()?;
        let mesh = tessellation::tessellate(params.latitude_bands, params.longitude_bands);
        let hairline = scalp::hairline(params);
        let front_hairline = scalp::front_hairline(&hairline);
        Ok(Head {
            mesh,
            params: params.clone(),
            crown: scalp::crown(params).as_vec3(),
            part_line: scalp::part_line(params),
            hairline,
            front_hairline,
            loaded_occluders: None,
        })
    }

    /// A body from a mesh (a file's, in the scene's frame [m]: see hair-formats'
    /// `read_mesh_file`) with `occluder_boxes`
    /// `(min, max)` [m] that lie inside it (none is allowed: nothing is then hidden by the body).
    /// The mesh is drawn and collided with in place of the procedural head. Fails on a mesh that
    /// fails [`TriangleMesh::validate_surface`], and on a box that is not finite or
    /// whose `min` exceeds its `max`.
    pub fn from_mesh(mesh: TriangleMesh, occluder_boxes: Vec<(Vec3, Vec3)>) -> Result<Head> {
        mesh.validate_surface().map_err(|error| {
            HairError::invalid(
                "body mesh",
                error,
                "a valid mesh with a triangle of some area",
            )
        })?;
        if let Some((min, max)) = occluder_boxes
            .iter()
            .find(|(min, max)| !(min.is_finite() && max.is_finite() && min.cmple(*max).all()))
        {
            return Err(HairError::invalid(
                "occluder box",
                format!("{min}..{max}"),
                "finite corners with min <= max",
            ));
        }
        let mut head = Head::procedural(&HeadParams::default())?;
        head.mesh = mesh;
        head.loaded_occluders = Some(occluder_boxes);
        Ok(head)
    }

    /// Whether this is the procedural head (its scalp queries describe it), not a mesh from a
    /// file.
    pub fn is_procedural(&self) -> bool {
        self.loaded_occluders.is_none()
    }

    /// The point of the analytic surface along `direction` from the head's centre [m], and the unit
    /// outward normal there. Exact (to f32 rounding): the mesh's vertices are such points. A zero or
    /// non-finite direction is read as +Y (the top of the head).
    pub fn surface_point(&self, direction: Vec3) -> (Vec3, Vec3) {
        let direction = direction.as_dvec3();
        let direction = if direction.is_finite() {
            direction
        } else {
            DVec3::Y
        };
        let (point, normal) = shape::surface_point(direction);
        (point.as_vec3(), normal.as_vec3())
    }

    /// Whether hair grows at `point` [m]: the point is projected radially onto the surface (along
    /// the direction from the head's centre) and tested against the hairline height at its azimuth.
    /// False for the centre itself and for non-finite points.
    pub fn is_scalp(&self, point: Vec3) -> bool {
        let point = point.as_dvec3();
        if !point.is_finite() || point.length_squared() < 1e-12 {
            return false;
        }
        let surface = shape::surface_point(point).0;
        scalp::height_above_hairline(&self.params, surface) >= 0.0
    }

    /// Distance [m] from `point` to the part line: the straight-line distance in 3-D to the nearest
    /// point of the part line (a polyline of 97 surface points from the front hairline to the crown,
    /// in the plane `x = part_offset`). For a point on the scalp within a few centimetres of the part
    /// this is within about 1 % of the distance along the surface.
    pub fn part_distance(&self, point: Vec3) -> f32 {
        scalp::distance_to_polyline(point, &self.part_line)
    }

    /// The crown [m]: the back end of the part line, where hair whorls (behind the top of the head).
    pub fn crown(&self) -> Vec3 {
        self.crown
    }

    /// The part line [m]: surface points in the plane `x = part_offset`, from the front hairline to
    /// the crown.
    pub fn part_line(&self) -> &[Vec3] {
        &self.part_line
    }

    /// The hairline [m]: a closed loop of surface points by azimuth from the face towards +X (the
    /// last point joins the first).
    pub fn hairline(&self) -> &[Vec3] {
        &self.hairline
    }

    /// Height of the hairline [m] at azimuth `azimuth` [rad] (`atan2(x, z)`: 0 at the face, π/2
    /// above the left ear, ±π at the nape).
    pub fn hairline_height(&self, azimuth: f32) -> f32 {
        scalp::hairline_height(&self.params, f64::from(azimuth)) as f32
    }

    /// An axis-aligned box `(min, max)` [m] inside the head, for the paper's conservative occlusion
    /// test (§7.1: hair whose rays from the camera both cross this box is hidden by the head).
    ///
    /// It is the largest axis-aligned box inscribed in the cranium ellipsoid (half-extents equal to
    /// the semi-axes divided by √3, corners on the ellipsoid), shrunk about its centre to 95 %. The
    /// head's surface encloses the cranium, so every point of the box is inside the head.
    ///
    /// For a mesh from a file: the largest of its occluder boxes (a point at the mesh's first
    /// vertex when it has none, which hides nothing).
    pub fn inner_box(&self) -> (Vec3, Vec3) {
        if let Some(boxes) = &self.loaded_occluders {
            let volume = |(min, max): &(Vec3, Vec3)| (*max - *min).element_product();
            return boxes
                .iter()
                .copied()
                .max_by(|a, b| volume(a).total_cmp(&volume(b)))
                .unwrap_or((self.mesh.positions[0], self.mesh.positions[0]));
        }
        let half = shape::CRANIUM_SEMI_AXES * (INNER_BOX_SCALE / 3f64.sqrt());
        (
            (shape::CRANIUM_CENTRE - half).as_vec3(),
            (shape::CRANIUM_CENTRE + half).as_vec3(),
        )
    }

    /// Axis-aligned boxes `(min, max)` [m] inside the head whose union blocks more of the view
    /// than [`Head::inner_box`] alone, for the occlusion test: that box; three boxes stretched along
    /// x, y and z inside the cranium ellipsoid (half-extents `0.9, 0.3, 0.3` of the semi-axes in
    /// some order, so `0.81 + 0.09 + 0.09 < 1` puts their corners inside it), shrunk to 95 %; and
    /// the square inscribed in the neck's cross-section (half side `r/√2`, 95 %) from near its
    /// bottom to the cranium. Every point of every box is inside the head.
    ///
    /// For a mesh from a file: the boxes it was given ([`Head::from_mesh`]).
    pub fn occluder_boxes(&self) -> Vec<(Vec3, Vec3)> {
        if let Some(boxes) = &self.loaded_occluders {
            return boxes.clone();
        }
        let mut boxes = vec![self.inner_box()];
        for stretched in [
            DVec3::new(0.9, 0.3, 0.3),
            DVec3::new(0.3, 0.9, 0.3),
            DVec3::new(0.3, 0.3, 0.9),
        ] {
            let half = shape::CRANIUM_SEMI_AXES * stretched * INNER_BOX_SCALE;
            boxes.push((
                (shape::CRANIUM_CENTRE - half).as_vec3(),
                (shape::CRANIUM_CENTRE + half).as_vec3(),
            ));
        }
        let side = shape::NECK_RADIUS / 2f64.sqrt() * INNER_BOX_SCALE;
        let neck_low = DVec3::new(
            -side,
            shape::NECK_BOTTOM_Y + 0.02,
            shape::NECK_AXIS_Z - side,
        );
        let neck_high = DVec3::new(side, shape::CRANIUM_CENTRE.y, shape::NECK_AXIS_Z + side);
        boxes.push((neck_low.as_vec3(), neck_high.as_vec3()));
        boxes
    }
}
