//! An Alembic `Xform`'s matrix from its operations (`.ops`) and their values (`.vals`), composed
//! as Alembic's `XformSample::getMatrix` does, for the `.abc` reader.

use glam::{DMat4, DVec3};

/// Composes an Alembic transform from its operations (`.ops`, one byte each: type << 4 | hint)
/// and their values (`.vals`), as Alembic's `XformSample::getMatrix` does, in column-vector form.
pub(crate) fn compose(ops: &[u8], vals: &[f64]) -> Result<DMat4, String> {
    let mut matrix = DMat4::IDENTITY;
    let mut next = 0;
    for (i, &op) in ops.iter().enumerate() {
        let kind = op >> 4;
        let channels = match kind {
            0 | 1 => 3,
            2 => 4,
            3 => 16,
            4..=6 => 1,
            _ => return Err(format!("operation {i} has unknown type {kind}")),
        };
        let v = vals.get(next..next + channels).ok_or_else(|| {
            format!(
                "the {} operations need more than the {} values of .vals",
                ops.len(),
                vals.len()
            )
        })?;
        next += channels;
        let op_matrix = match kind {
            0 => DMat4::from_scale(DVec3::new(v[0], v[1], v[2])),
            1 => DMat4::from_translation(DVec3::new(v[0], v[1], v[2])),
            2 => {
                let axis = DVec3::new(v[0], v[1], v[2])
                    .try_normalize()
                    .ok_or_else(|| format!("rotation {i} has a zero axis"))?;
                DMat4::from_axis_angle(axis, v[3].to_radians())
            }
            // Imath's row-major rows are glam's columns: the transpose, as column vectors need.
            3 => DMat4::from_cols_slice(v),
            4 => DMat4::from_rotation_x(v[0].to_radians()),
            5 => DMat4::from_rotation_y(v[0].to_radians()),
            _ => DMat4::from_rotation_z(v[0].to_radians()),
        };
        // Alembic: `ret = m * ret` with row vectors, so `ret = ret * m` with column vectors.
        matrix *= op_matrix;
    }
    if !matrix.is_finite() {
        return Err(format!("the transform is not finite: {matrix}"));
    }
    Ok(matrix)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PyAlembic's `XformSample` with `setTranslation((1, 2, 3))`, `setRotation((0, 0, 1), 90)`,
    /// `setXRotation(90)`, `setScale((1, 2, 3))` has the op encodings 16, 32, 64, 0 and maps
    /// (1, 1, 1) to (4, 3, 5) by its `getMatrix()`.
    #[test]
    fn transforms_compose_as_alembic_does() {
        let ops = [16, 32, 64, 0];
        let vals = [1.0, 2.0, 3.0, 0.0, 0.0, 1.0, 90.0, 90.0, 1.0, 2.0, 3.0];
        let matrix = compose(&ops, &vals).unwrap();
        let p = matrix.transform_point3(DVec3::ONE);
        assert!((p - DVec3::new(4.0, 3.0, 5.0)).length() < 1e-12, "{p}");
        // The same transform as one matrix op: `getMatrix()`'s rows, as PyAlembic prints them.
        let rows = [
            0.0, 1.0, 0.0, 0.0, //
            0.0, 0.0, 2.0, 0.0, //
            3.0, 0.0, 0.0, 0.0, //
            1.0, 2.0, 3.0, 1.0,
        ];
        let p = compose(&[48], &rows).unwrap().transform_point3(DVec3::ONE);
        assert_eq!(p, DVec3::new(4.0, 3.0, 5.0));
    }

    #[test]
    fn bad_transforms_are_errors() {
        assert_eq!(
            compose(&[16], &[1.0]).unwrap_err(),
            "the 1 operations need more than the 1 values of .vals"
        );
        assert_eq!(
            compose(&[0x70], &[]).unwrap_err(),
            "operation 0 has unknown type 7"
        );
        assert_eq!(
            compose(&[32], &[0.0, 0.0, 0.0, 90.0]).unwrap_err(),
            "rotation 0 has a zero axis"
        );
        assert!(compose(&[16], &[f64::NAN, 0.0, 0.0]).is_err());
    }
}
