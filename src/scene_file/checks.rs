//! The checks every scene-file value goes through: a number within its range, a count, a finite
//! vector, an image size; each error names the field and the allowed range.

use glam::Vec3;

use super::SceneFileError;

type Result<T> = std::result::Result<T, SceneFileError>;

/// `value` checked to be finite and within `range` (inclusive), else an error naming `field`.
pub(super) fn within(field: &str, value: f32, low: f32, high: f32, range: &str) -> Result<f32> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {value}: expected {range}"
        )))
    }
}

/// `value` checked to be finite and > 0.
pub(super) fn positive(field: &str, value: f32) -> Result<f32> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {value}: expected a finite number > 0"
        )))
    }
}

/// A count checked to be within `low..=high`.
pub(super) fn count(field: &str, value: usize, low: usize, high: usize) -> Result<usize> {
    if (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {value}: expected a whole number in {low}..={high}"
        )))
    }
}

/// A vector of finite components.
pub(super) fn vector(field: &str, value: [f32; 3]) -> Result<Vec3> {
    if value.iter().all(|c| c.is_finite()) {
        Ok(Vec3::from_array(value))
    } else {
        Err(SceneFileError::new(format!(
            "{field} = {value:?}: expected three finite numbers"
        )))
    }
}

/// Parses `WIDTHxHEIGHT`, each 16..=8192 pixels; an error names `field` (a scene-file path or a
/// command-line flag).
pub fn parse_size(field: &str, text: &str) -> Result<(u32, u32)> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (16..=8192).contains(&w) && (16..=8192).contains(&h) => Ok((w, h)),
        _ => Err(SceneFileError::new(format!(
            "{field} = {text:?}: expected WIDTHxHEIGHT in pixels, each 16..=8192, e.g. 1280x720"
        ))),
    }
}
