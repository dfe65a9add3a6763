//! How a file's coordinates become the scene's (metres, +Y up, right-handed) and how strictly
//! degenerate curves are treated: [`ImportAxes`] and [`ImportOptions`].

use glam::Vec3;

use super::error::FormatErrorKind;
pub use super::sequence_limits::SequenceLimits;

hair_core::named_enum! {
    /// Which axis points up in the file.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum UpAxis {
        /// +Y up (Maya, Houdini, TressFX): kept as is.
        #[default]
        Y = "y",
        /// +Z up (Blender, 3ds Max): rotated to +Y up by −90° about X, `(x, y, z) → (x, z, −y)`.
        Z = "z",
    }
}

/// The change from a file's axes and units to the scene's (metres, +Y up, right-handed), applied
/// after reading, in this order: scale, up axis, mirror. The default is the identity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImportAxes {
    /// Metres per file unit (0.01 for centimetres); a finite number > 0. Widths scale too.
    pub scale_to_metres: f32,
    /// The file's up axis.
    pub up: UpAxis,
    /// Negate x (a file from a left-handed tool); triangle windings are reversed to stay
    /// counter-clockwise seen from outside.
    pub mirror_x: bool,
}

impl Default for ImportAxes {
    fn default() -> Self {
        ImportAxes {
            scale_to_metres: 1.0,
            up: UpAxis::Y,
            mirror_x: false,
        }
    }
}

impl ImportAxes {
    /// Checks that `scale_to_metres` is a finite number > 0.
    pub fn validate(&self) -> Result<(), FormatErrorKind> {
        let scale = self.scale_to_metres;
        if scale.is_finite() && scale > 0.0 {
            Ok(())
        } else {
            Err(FormatErrorKind::InvalidOption {
                name: "scale_to_metres",
                value: scale.to_string(),
                allowed: "a finite number > 0 (metres per file unit)",
            })
        }
    }

    /// Whether this is the identity (nothing to do).
    pub fn is_identity(&self) -> bool {
        *self == ImportAxes::default()
    }

    /// A point [file units] in scene coordinates [m].
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.direction(p * self.scale_to_metres)
    }

    /// A direction (a normal) in scene coordinates: rotated and mirrored, not scaled.
    pub fn direction(&self, d: Vec3) -> Vec3 {
        let d = match self.up {
            UpAxis::Y => d,
            UpAxis::Z => Vec3::new(d.x, d.z, -d.y),
        };
        if self.mirror_x {
            Vec3::new(-d.x, d.y, d.z)
        } else {
            d
        }
    }

    /// A length [file units] in metres.
    pub fn length(&self, l: f32) -> f32 {
        l * self.scale_to_metres
    }

    /// Whether triangle windings must be reversed (a mirror changes handedness).
    pub fn reverses_winding(&self) -> bool {
        self.mirror_x
    }
}

/// Options of every reader.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImportOptions {
    /// From the file's axes and units to the scene's.
    pub axes: ImportAxes,
    /// Degenerate curves (fewer than two points, a zero-length segment) are errors instead of
    /// being skipped and reported in [`Curves::skipped`](super::Curves::skipped). Empty roots of
    /// USC-HairSalon files are skipped even then (the format's way to say "no strand here").
    pub strict: bool,
    /// How much of a mesh sequence (a body's animation) to keep; the default keeps all.
    pub sequence: SequenceLimits,
}

impl ImportOptions {
    /// Default options with strict reading.
    pub fn strict() -> Self {
        ImportOptions {
            strict: true,
            ..ImportOptions::default()
        }
    }

    /// Default options with these axes.
    pub fn with_axes(axes: ImportAxes) -> Self {
        ImportOptions {
            axes,
            ..ImportOptions::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_up_turns_into_y_up_right_handed() {
        let axes = ImportAxes {
            up: UpAxis::Z,
            ..ImportAxes::default()
        };
        // File +Z (up) becomes +Y; file +Y (forward in Blender) becomes −Z; x stays.
        assert_eq!(axes.point(Vec3::Z), Vec3::Y);
        assert_eq!(axes.point(Vec3::Y), -Vec3::Z);
        assert_eq!(axes.point(Vec3::X), Vec3::X);
        // A rotation keeps handedness: X × Y = Z before and after.
        let (x, y, z) = (
            axes.point(Vec3::X),
            axes.point(Vec3::Y),
            axes.point(Vec3::Z),
        );
        assert_eq!(x.cross(y), z);
        assert!(!axes.reverses_winding());
    }

    #[test]
    fn scale_and_mirror_apply_after_reading() {
        let axes = ImportAxes {
            scale_to_metres: 0.01,
            up: UpAxis::Y,
            mirror_x: true,
        };
        assert_eq!(
            axes.point(Vec3::new(100.0, 200.0, 300.0)),
            Vec3::new(-1.0, 2.0, 3.0)
        );
        assert_eq!(axes.direction(Vec3::X), -Vec3::X);
        assert_eq!(axes.length(250.0), 2.5);
        assert!(axes.reverses_winding());
        assert!(ImportAxes::default().is_identity());
        assert!(!axes.is_identity());
    }

    #[test]
    fn a_scale_must_be_positive_and_finite() {
        for scale in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            let axes = ImportAxes {
                scale_to_metres: scale,
                ..ImportAxes::default()
            };
            let error = axes.validate().unwrap_err();
            assert!(
                error
                    .to_string()
                    .starts_with("invalid import option scale_to_metres"),
                "{error}"
            );
        }
        assert_eq!(ImportAxes::default().validate(), Ok(()));
    }
}
