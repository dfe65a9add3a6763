//! The pieces of USD text the writers share: identifiers, floats that read back to the same
//! bits, arrays of vectors, and the `InvalidInput` error.

use std::fmt::Write as _;
use std::io;

use glam::Vec3;

/// An `InvalidInput` error with `message`.
pub(crate) fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// Refuses a name that is not a USD identifier (a letter or `_`, then letters, digits or `_`).
pub(crate) fn check_identifier(name: &str) -> io::Result<()> {
    let mut chars = name.chars();
    let valid = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
    if valid {
        Ok(())
    } else {
        Err(invalid_input(format!(
            "prim name {name:?} is not a USD identifier"
        )))
    }
}

/// Appends `x` (finite) in its shortest form that reads back to the same bits.
pub(crate) fn push_float(out: &mut String, x: f32) {
    let magnitude = x.abs();
    let _ = if x == 0.0 {
        // `-0` could be read as the integer 0; `-0.0` keeps the sign.
        write!(out, "{}", if x.is_sign_negative() { "-0.0" } else { "0" })
    } else if (1e-5..1e16).contains(&magnitude) {
        write!(out, "{x}")
    } else {
        write!(out, "{x:e}")
    };
}

/// Appends `[(x, y, z), …]`.
pub(crate) fn vec3_array(out: &mut String, values: &[Vec3]) {
    out.push('[');
    for (i, v) in values.iter().enumerate() {
        out.push_str(if i > 0 { ", (" } else { "(" });
        push_float(out, v.x);
        out.push_str(", ");
        push_float(out, v.y);
        out.push_str(", ");
        push_float(out, v.z);
        out.push(')');
    }
    out.push(']');
}
