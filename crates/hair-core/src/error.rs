//! The error type of `hair-core`: every invalid parameter names itself and its allowed range.

use thiserror::Error;

/// Errors from building or evaluating hair models.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HairError {
    /// A parameter is outside its allowed range (or not finite).
    #[error("invalid {name}: {value} (allowed: {allowed})")]
    InvalidParameter {
        /// Name of the parameter, as the user would write it (`hair_length`, `curl_factor`).
        name: &'static str,
        /// The offending value, formatted.
        value: String,
        /// The allowed range or set, in words (`a finite number > 0 m`).
        allowed: &'static str,
    },
    /// Two arrays that must agree in size do not.
    #[error("size mismatch: {what} has {actual} entries, expected {expected}")]
    SizeMismatch {
        /// What was being sized.
        what: &'static str,
        /// The size that was given.
        actual: usize,
        /// The size that was required.
        expected: usize,
    },
    /// A name (preset, level, style) that is not known.
    #[error("unknown {kind} `{name}` (known: {known})")]
    UnknownName {
        /// What kind of name (`preset`, `level`).
        kind: &'static str,
        /// The name that was given.
        name: String,
        /// The known names, comma separated.
        known: String,
    },
    /// Reading or writing a file failed.
    #[error("{action} {path}: {message}")]
    Io {
        /// What was being done (`writing`, `reading`).
        action: &'static str,
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
}

/// Result alias for `hair-core`.
pub type Result<T, E = HairError> = std::result::Result<T, E>;

impl HairError {
    /// Shorthand for [`HairError::InvalidParameter`].
    pub fn invalid(
        name: &'static str,
        value: impl std::fmt::Display,
        allowed: &'static str,
    ) -> Self {
        HairError::InvalidParameter {
            name,
            value: value.to_string(),
            allowed,
        }
    }
}

impl HairError {
    /// An [`HairError::Io`] for `path`. An `error` whose message names the action and the path
    /// already (as [`write_file_atomically`](crate::atomic_file::write_file_atomically)'s do: `writing
    /// PATH: why`) keeps only the why, so that the message says `writing PATH:` once.
    pub fn io(action: &'static str, path: &std::path::Path, error: &std::io::Error) -> Self {
        let path = path.display().to_string();
        let message = error.to_string();
        let prefix = format!("{action} {path}: ");
        let message = match message.strip_prefix(&prefix) {
            Some(why) => why.to_string(),
            None => message,
        };
        HairError::Io {
            action,
            path,
            message,
        }
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn require_positive(name: &'static str, value: f32) -> Result<f32> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(HairError::invalid(name, value, "a finite number > 0"))
    }
}

/// Checks that `value` is finite and not negative.
pub fn require_non_negative(name: &'static str, value: f32) -> Result<f32> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(HairError::invalid(name, value, "a finite number >= 0"))
    }
}

/// Checks that `value` is finite and lies in `[low, high]`; `allowed` describes the range in words.
pub fn require_in_range(
    name: &'static str,
    value: f32,
    low: f32,
    high: f32,
    allowed: &'static str,
) -> Result<f32> {
    if value.is_finite() && value >= low && value <= high {
        Ok(value)
    } else {
        Err(HairError::invalid(name, value, allowed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_name_the_parameter_and_range() {
        let error = require_positive("hair_length", -0.5).unwrap_err();
        assert_eq!(
            error.to_string(),
            "invalid hair_length: -0.5 (allowed: a finite number > 0)"
        );
        assert!(require_positive("hair_length", f32::NAN).is_err());
        assert!(require_non_negative("radius", 0.0).is_ok());
        assert!(require_in_range("curl_factor", 91.0, 0.0, 90.0, "0..=90 degrees").is_err());
    }

    /// A failed atomic write names its path once, not `writing X: writing X: …`.
    #[test]
    fn a_failed_write_names_its_path_once() {
        let path = std::env::temp_dir()
            .join(format!("hairlod-no-such-folder-{}", std::process::id()))
            .join("groom.obj");
        let io = crate::atomic_file::write_file_atomically(&path, |_| Ok(())).unwrap_err();
        let error = HairError::io("writing", &path, &io).to_string();
        let named = format!("writing {}", path.display());
        assert!(error.starts_with(&format!("{named}: ")), "{error}");
        assert_eq!(error.matches(&named).count(), 1, "{error}");
        // A message that does not name the path keeps all of it.
        let plain = std::io::Error::other("disk full");
        let error = HairError::io("writing", &path, &plain).to_string();
        assert_eq!(error, format!("{named}: disk full"));
    }
}
