//! Ranges of the scene-file values that place things in the world (camera distances and
//! positions, head translations, directions), derived from what `f32` coordinates, the camera's
//! clipping planes and its `Depth32Float` depth buffer can hold. Every error names the field, the
//! value as given and the range.

use glam::Vec3;

use super::SceneFileError;

type Result<T> = std::result::Result<T, SceneFileError>;

/// The closest a camera may be to the point it looks at [m]: ten times the 0.1 mm floor of its
/// near plane ([`Camera::orbit`](hair_core::Camera::orbit) puts it at `d/100`,
/// [`Camera::looking_at`](hair_core::Camera::looking_at) at `d/1000`, neither under 0.1 mm), so
/// the target is never clipped, and far above the 1 µm below which the camera has no view
/// direction.
pub const MIN_CAMERA_DISTANCE: f32 = 1e-3;

/// The farthest a camera may be from the point it looks at [m], and the largest camera position
/// or target coordinate [m]. At 10 km `f32` coordinates are 2⁻¹⁰ m ≈ 1 mm apart (8192..16384 m),
/// coarser than a strand's detail, and the depth buffer (an `f32` in 0..1 with the near plane at
/// `d/100`) tells apart only points about `6·10⁻⁶·d` = 6 cm apart in depth at the target; a head
/// there is under a tenth of a pixel in a 720-line image. Beyond it the camera maths overflow
/// (from about 10¹⁹ m, where `d²` is no longer a finite `f32`).
pub const MAX_CAMERA_DISTANCE: f32 = 1e4;

/// The largest coordinate of a head's position [m] (a head keyframe's `translation`, a
/// character's `position`). At 1 km `f32` coordinates are 2⁻¹⁴ m ≈ 61 µm apart (512..1024 m),
/// about a hair's width: farther, the simulated strands lose the shape they are drawn in (the
/// file's curves are kept to 0.1 mm) and, far enough, collapse onto a few representable points.
pub const MAX_HEAD_COORDINATE: f32 = 1e3;

/// `value` [m], finite and within `MIN_CAMERA_DISTANCE..=MAX_CAMERA_DISTANCE`, else an error
/// naming `field`.
pub(super) fn camera_distance(field: &str, value: f32) -> Result<f32> {
    if value.is_finite() && (MIN_CAMERA_DISTANCE..=MAX_CAMERA_DISTANCE).contains(&value) {
        Ok(value)
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {}: expected a distance in {MIN_CAMERA_DISTANCE}..={MAX_CAMERA_DISTANCE} m \
             ({})",
            format_number(value),
            camera_range_reason()
        )))
    }
}

/// A camera position or target [m], each coordinate finite and within `±MAX_CAMERA_DISTANCE`.
pub(super) fn camera_point(field: &str, value: [f32; 3]) -> Result<Vec3> {
    bounded_point(field, value, MAX_CAMERA_DISTANCE, camera_range_reason())
}

/// A head's position [m] (a keyframe's translation, a character's place), each coordinate finite
/// and within `±MAX_HEAD_COORDINATE`.
pub(super) fn head_point(field: &str, value: [f32; 3]) -> Result<Vec3> {
    bounded_point(
        field,
        value,
        MAX_HEAD_COORDINATE,
        "f32 coordinates there are 61 µm apart, a hair's width; farther, the simulated strands \
         lose their shape",
    )
}

/// A unit direction from `value`, any finite vector but zero: scaled by its largest component
/// before it is normalised, so that no length overflows (`[1e38, 1e38, 0]` is the diagonal).
/// Errors name `field` and the value as given.
pub(super) fn direction(field: &str, value: [f32; 3]) -> Result<Vec3> {
    let vector = Vec3::from_array(value);
    let largest = vector.abs().max_element();
    let unit = if vector.is_finite() && largest > 0.0 {
        (vector / largest).try_normalize()
    } else {
        None
    };
    unit.ok_or_else(|| {
        SceneFileError::new(format!(
            "{field} = {}: expected a direction, three finite numbers not all zero",
            format_point(value)
        ))
    })
}

/// Why camera values are bounded, for the messages.
fn camera_range_reason() -> &'static str {
    "the near plane is at least 0.1 mm, so a closer target is clipped; at 10 km f32 coordinates \
     are 1 mm apart and the depth buffer resolves only 6 cm at the target"
}

fn bounded_point(field: &str, value: [f32; 3], limit: f32, why: &str) -> Result<Vec3> {
    if value.iter().all(|c| c.is_finite() && c.abs() <= limit) {
        Ok(Vec3::from_array(value))
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {}: expected three finite coordinates in -{limit}..={limit} m ({why})",
            format_point(value)
        )))
    }
}

/// `value` as one would write it: `1e38` and `1e-30`, not forty digits.
pub(super) fn format_number(value: f32) -> String {
    if value.is_finite() && value != 0.0 && !(1e-4..1e6).contains(&value.abs()) {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

/// `[x, y, z]`, each number as [`format_number`] writes it.
pub(super) fn format_point(value: [f32; 3]) -> String {
    let [x, y, z] = value.map(format_number);
    format!("[{x}, {y}, {z}]")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_file::SceneFile;

    fn error_of(text: &str) -> String {
        SceneFile::parse(text).unwrap_err().to_string()
    }

    #[test]
    fn camera_distances_outside_what_the_camera_holds_name_the_field_and_range() {
        for (text, field) in [
            ("[camera]\ndistance = 1e30", "camera.distance = 1e30"),
            ("[camera]\ndistance = 1e-30", "camera.distance = 1e-30"),
            (
                "[camera]\npath = \"zoom-out\"\nend_distance = 2e4",
                "camera.end_distance = 20000",
            ),
        ] {
            let error = error_of(text);
            assert!(error.contains(field), "{error}");
            assert!(error.contains("0.001..=10000 m"), "{error}");
            assert!(error.contains("depth buffer"), "{error}");
        }
        SceneFile::parse("[camera]\ndistance = 9000.0").unwrap();
    }

    #[test]
    fn camera_positions_and_targets_are_bounded() {
        let error = error_of(
            "[camera]\npath = \"keyframes\"\n[[camera.keyframes]]\ntime = 0.0\n\
             position = [1e38, 0.0, 1.0]\n",
        );
        assert!(
            error.contains("camera.keyframes[0].position = [1e38, 0, 1]"),
            "{error}"
        );
        assert!(error.contains("-10000..=10000 m"), "{error}");
        let error = error_of(
            "[camera]\npath = \"keyframes\"\n[[camera.keyframes]]\ntime = 0.0\n\
             position = [0.0, 0.0, 1e-4]\n",
        );
        assert!(error.contains("camera.keyframes[0]"), "{error}");
        assert!(error.contains("0.001..=10000 m"), "{error}");
        let error = error_of("[camera]\ntarget = [0.0, -2e4, 0.0]");
        assert!(error.contains("camera.target = [0, -20000, 0]"), "{error}");
    }

    #[test]
    fn head_translations_are_bounded() {
        let error = error_of(
            "[motion]\nkind = \"keyframes\"\n[[motion.keyframes]]\ntime = 0.0\n\
             translation = [0.0, 1e38, 0.0]\n",
        );
        assert!(
            error.contains("motion.keyframes[0].translation = [0, 1e38, 0]"),
            "{error}"
        );
        assert!(error.contains("-1000..=1000 m"), "{error}");
        let error = error_of("[[character]]\nposition = [2000.0, 0.0, 0.0]\n");
        assert!(
            error.contains("character[0].position = [2000, 0, 0]"),
            "{error}"
        );
    }

    #[test]
    fn a_huge_wind_direction_is_normalised_and_a_zero_one_reported_as_given() {
        let shot = SceneFile::parse("[wind]\nspeed = 2.0\ndirection = [1e38, 1e38, 0.0]")
            .unwrap()
            .resolve()
            .unwrap();
        let hair_core::dynamics::WindField::Constant(wind) = shot.environment.wind else {
            panic!("a steady wind: {:?}", shot.environment.wind);
        };
        let diagonal = Vec3::new(1.0, 1.0, 0.0).normalize() * 2.0;
        assert!((wind - diagonal).length() < 1e-5, "{wind}");
        let error = error_of("[wind]\ndirection = [0.0, 0.0, 0.0]");
        assert!(error.contains("wind.direction = [0, 0, 0]"), "{error}");
        assert!(error.contains("not all zero"), "{error}");
    }

    /// The ends of the ranges are cameras the camera maths hold: valid, finite clipping planes,
    /// the target in front of the near plane and projected into the picture.
    #[test]
    fn cameras_at_the_ends_of_the_ranges_are_valid() {
        for text in [
            "[camera]\ndistance = 0.001",
            "[camera]\ndistance = 10000.0\ntarget = [10000.0, -10000.0, 10000.0]",
            "[camera]\npath = \"zoom-out\"\ndistance = 0.001\nend_distance = 10000.0",
            "[camera]\npath = \"keyframes\"\n[[camera.keyframes]]\ntime = 0.0\n\
             position = [10000.0, 10000.0, 10000.0]\ntarget = [10000.0, 10000.0, 0.0]\n\
             [[camera.keyframes]]\ntime = 0.1\nposition = [0.0, 0.0, 0.001]\n",
        ] {
            let shot = SceneFile::parse(text).unwrap().resolve().unwrap();
            for frame in 0..shot.frames {
                let camera = shot.camera(frame);
                camera
                    .validate()
                    .unwrap_or_else(|e| panic!("{text}: frame {frame}: {e}"));
                let depth = camera.position.distance(camera.target);
                assert!(
                    camera.near < depth && depth < camera.far,
                    "{text}: {camera:?}"
                );
                let pixel = camera.project_to_pixel(camera.target, shot.width, shot.height);
                assert!(pixel.is_some_and(|p| p.is_finite()), "{text}: {camera:?}");
            }
        }
    }
}
