//! USD text (`.usda`) `BasisCurves`, written: one `linear` `BasisCurves` prim with
//! `curveVertexCounts`, `points`, `extent`, and `widths` and `primvars:displayColor` (interpolation
//! `vertex`) where the curves have them; the stage says `upAxis = "Y"` and `metersPerUnit = 1`.
//! An animation ([`UsdCurvesWriter`] with several frames) writes `points.timeSamples` and
//! `extent.timeSamples` at time codes 0, 1, 2, … (or the codes given with
//! [`UsdCurvesWriter::push_frame_at`]) with `startTimeCode`, `endTimeCode` and
//! `timeCodesPerSecond`; the topology, widths and colours do not change over frames. A mesh
//! written beside the curves ([`UsdCurvesWriter::with_mesh`], the body the hair grows on) is a
//! second root prim with its own time samples ([`UsdMeshTrack`]).
//!
//! Every `f32` is written in its shortest form that reads back to the same bits (`-0.0` kept), in
//! an exponent form (`1e-7`, `3.4e38`) outside `1e-5 ≤ |x| < 1e16`, which USD's parser accepts:
//! [`read_usda`](super::read_usda) and Pixar's `Usd.Stage` read the same values bit for bit.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use glam::Vec3;

use super::curves::{Curves, vector_text};
use super::usda_text::{check_identifier, invalid_input, push_float, vec3_array};
use super::usda_write_mesh::UsdMeshTrack;
use crate::obj::write_file_atomically;

/// Writes curves (fixed topology) and one or more frames of their points as a USD text file.
///
/// ```no_run
/// # use hair_formats::UsdCurvesWriter;
/// # use glam::Vec3;
/// // Two curves of 2 and 3 points, moving up 1 cm a frame.
/// let offsets = [0, 2, 5];
/// let mut writer = UsdCurvesWriter::new(&offsets, None, None)?;
/// for frame in 0..3 {
///     let points: Vec<Vec3> =
///         (0..5).map(|i| Vec3::new(i as f32 * 0.01, frame as f32 * 0.01, 0.0)).collect();
///     writer.push_frame(&points)?;
/// }
/// writer.write("hair.usda")?;
/// # Ok::<(), std::io::Error>(())
/// ```
///
/// Frames are kept in memory (12 bytes per point and frame) until [`UsdCurvesWriter::write`]
/// writes the file whole, atomically.
#[derive(Debug, Clone)]
pub struct UsdCurvesWriter {
    offsets: Vec<u32>,
    widths: Option<Vec<f32>>,
    colors: Option<Vec<Vec3>>,
    /// The points of every frame, one after the other.
    frames: Vec<Vec3>,
    /// The time code of every frame, increasing.
    time_codes: Vec<f64>,
    time_codes_per_second: f64,
    prim_name: String,
    /// A mesh written beside the curves.
    mesh: Option<UsdMeshTrack>,
}

impl UsdCurvesWriter {
    /// A writer for curves laid out by `offsets` (curve `i` owns points
    /// `offsets[i]..offsets[i + 1]`, as in [`Curves::offsets`]), with a width [m] and a linear
    /// RGB colour per point where given. Offsets must start at 0 and give every curve at least
    /// two points; widths and colours need one finite value per point (widths >= 0);
    /// `InvalidInput` otherwise.
    pub fn new(
        offsets: &[u32],
        widths: Option<&[f32]>,
        colors: Option<&[Vec3]>,
    ) -> io::Result<Self> {
        let points = offsets.last().copied().unwrap_or(0) as usize;
        if offsets.first().is_some_and(|&o| o != 0) {
            return Err(invalid_input("curve offsets must start at 0".into()));
        }
        if let Some(curve) = offsets
            .windows(2)
            .position(|w| w[1] < w[0].saturating_add(2))
        {
            return Err(invalid_input(format!(
                "curve {curve} has {} points; a linear BasisCurves curve needs at least 2",
                i64::from(offsets[curve + 1]) - i64::from(offsets[curve])
            )));
        }
        if let Some(widths) = widths {
            if widths.len() != points {
                return Err(invalid_input(format!(
                    "{} widths for {points} points",
                    widths.len()
                )));
            }
            if let Some(i) = widths.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
                return Err(invalid_input(format!(
                    "width {i} is {}; a finite width >= 0 is needed",
                    widths[i]
                )));
            }
        }
        if let Some(colors) = colors {
            if colors.len() != points {
                return Err(invalid_input(format!(
                    "{} colours for {points} points",
                    colors.len()
                )));
            }
            if let Some(i) = colors.iter().position(|c| !c.is_finite()) {
                return Err(invalid_input(format!(
                    "colour {i} is not finite: {}",
                    vector_text(colors[i])
                )));
            }
        }
        Ok(UsdCurvesWriter {
            offsets: offsets.to_vec(),
            widths: widths.map(<[f32]>::to_vec),
            colors: colors.map(<[Vec3]>::to_vec),
            frames: Vec::new(),
            time_codes: Vec::new(),
            time_codes_per_second: 24.0,
            prim_name: "hair".to_owned(),
            mesh: None,
        })
    }

    /// A writer for the topology, widths and colours of `curves`, with their points as frame 0.
    pub fn from_curves(curves: &Curves) -> io::Result<Self> {
        let mut writer = UsdCurvesWriter::new(
            &curves.offsets,
            curves.widths.as_deref(),
            curves.colors.as_deref(),
        )?;
        writer.push_frame(&curves.points)?;
        Ok(writer)
    }

    /// Sets the time codes (frames) per second of an animation (24 by default); a finite
    /// number > 0.
    pub fn with_time_codes_per_second(mut self, rate: f64) -> io::Result<Self> {
        if !(rate.is_finite() && rate > 0.0) {
            return Err(invalid_input(format!(
                "time codes per second {rate}: a finite number > 0 is needed"
            )));
        }
        self.time_codes_per_second = rate;
        Ok(self)
    }

    /// Names the prim (`hair` by default): a USD identifier (a letter or `_`, then letters,
    /// digits or `_`), not the mesh's.
    pub fn with_prim_name(mut self, name: &str) -> io::Result<Self> {
        check_identifier(name)?;
        if self.mesh.as_ref().is_some_and(|mesh| mesh.name == name) {
            return Err(invalid_input(format!(
                "prim name {name:?} is the mesh's; the curves need their own"
            )));
        }
        self.prim_name = name.to_owned();
        Ok(self)
    }

    /// Writes `mesh` beside the curves, as a second root prim (checked: see
    /// [`UsdMeshTrack::check`]; its name must differ from the curves').
    pub fn with_mesh(mut self, mesh: UsdMeshTrack) -> io::Result<Self> {
        self.set_mesh(Some(mesh))?;
        Ok(self)
    }

    /// Sets the mesh written beside the curves (`None`: none), as
    /// [`with_mesh`](Self::with_mesh) does; on an error the mesh is left as it was.
    pub fn set_mesh(&mut self, mesh: Option<UsdMeshTrack>) -> io::Result<()> {
        if let Some(mesh) = &mesh {
            mesh.check()?;
            if mesh.name == self.prim_name {
                return Err(invalid_input(format!(
                    "mesh prim name {:?} is the curves'; the mesh needs its own",
                    mesh.name
                )));
            }
        }
        self.mesh = mesh;
        Ok(())
    }

    /// Number of points of each frame.
    pub fn point_count(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0) as usize
    }

    /// Number of frames pushed so far.
    pub fn frame_count(&self) -> usize {
        self.frames
            .len()
            .checked_div(self.point_count())
            .unwrap_or(0)
    }

    /// Adds the next frame, at the time code after the last frame's (0 for the first): one
    /// point [m] per point of the topology, all finite (`InvalidInput` otherwise, and nothing is
    /// added).
    pub fn push_frame(&mut self, points: &[Vec3]) -> io::Result<()> {
        let code = self.time_codes.last().map_or(0.0, |last| last + 1.0);
        self.push_frame_at(code, points)
    }

    /// Adds a frame at time code `code` (finite, after the last frame's): one point [m] per
    /// point of the topology, all finite (`InvalidInput` otherwise, and nothing is added).
    pub fn push_frame_at(&mut self, code: f64, points: &[Vec3]) -> io::Result<()> {
        if !code.is_finite() || self.time_codes.last().is_some_and(|&last| code <= last) {
            return Err(invalid_input(format!(
                "time code {code} of frame {}: a finite code after the last frame's ({:?}) is \
                 needed",
                self.frame_count(),
                self.time_codes.last()
            )));
        }
        if self.point_count() == 0 {
            return Err(invalid_input("no curves to write".into()));
        }
        let frame = self.frame_count();
        if points.len() != self.point_count() {
            return Err(invalid_input(format!(
                "frame {frame} has {} points; the curves have {}",
                points.len(),
                self.point_count()
            )));
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(invalid_input(format!(
                "frame {frame}, point {i} is not finite: {}",
                vector_text(points[i])
            )));
        }
        self.frames.extend_from_slice(points);
        self.time_codes.push(code);
        Ok(())
    }

    /// Writes the USD text to `writer`: `points` with one frame, `points.timeSamples` with more.
    /// No frame is an `InvalidInput` error, before anything is written.
    pub fn write_to<W: Write>(&self, writer: &mut W) -> io::Result<()> {
        let frames = self.frame_count();
        if frames == 0 {
            return Err(invalid_input("no frame of points to write".into()));
        }
        let mut out = String::with_capacity(64 * 1024);
        // Time samples where the curves have more than one frame or the mesh moves.
        let animated = frames > 1 || self.mesh.as_ref().is_some_and(|m| m.samples.len() > 1);
        out.push_str("#usda 1.0\n(\n");
        let _ = writeln!(out, "    defaultPrim = \"{}\"", self.prim_name);
        out.push_str("    doc = \"hairlod BasisCurves export (metres, +Y up)\"\n");
        let (first, last) = (self.time_codes[0], self.time_codes[frames - 1]);
        if animated {
            let _ = writeln!(out, "    endTimeCode = {last}");
        }
        out.push_str("    metersPerUnit = 1\n");
        if animated {
            let _ = writeln!(out, "    startTimeCode = {first}");
            let _ = writeln!(
                out,
                "    timeCodesPerSecond = {}",
                self.time_codes_per_second
            );
        }
        out.push_str("    upAxis = \"Y\"\n)\n\n");
        let _ = writeln!(out, "def BasisCurves \"{}\"\n{{", self.prim_name);
        out.push_str("    int[] curveVertexCounts = [");
        for (i, w) in self.offsets.windows(2).enumerate() {
            let _ = write!(out, "{}{}", if i > 0 { ", " } else { "" }, w[1] - w[0]);
        }
        out.push_str("]\n");
        let n = self.point_count();
        let half_width = self.widths.iter().flatten().fold(0f32, |m, &w| m.max(w)) * 0.5;
        let frame = |f: usize| &self.frames[f * n..(f + 1) * n];
        let extent = |points: &[Vec3]| {
            let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
            [lo - half_width, hi + half_width]
        };
        if !animated {
            out.push_str("    float3[] extent = ");
            vec3_array(&mut out, &extent(frame(0)));
            out.push_str("\n    point3f[] points = ");
            vec3_array(&mut out, frame(0));
            out.push('\n');
        } else {
            out.push_str("    float3[] extent.timeSamples = {\n");
            for f in 0..frames {
                let _ = write!(out, "        {}: ", self.time_codes[f]);
                vec3_array(&mut out, &extent(frame(f)));
                out.push_str(",\n");
            }
            out.push_str("    }\n    point3f[] points.timeSamples = {\n");
            writer.write_all(out.as_bytes())?;
            out.clear();
            for f in 0..frames {
                let _ = write!(out, "        {}: ", self.time_codes[f]);
                vec3_array(&mut out, frame(f));
                out.push_str(",\n");
                writer.write_all(out.as_bytes())?;
                out.clear();
            }
            out.push_str("    }\n");
        }
        if let Some(colors) = &self.colors {
            out.push_str("    color3f[] primvars:displayColor = ");
            vec3_array(&mut out, colors);
            out.push_str(" (\n        interpolation = \"vertex\"\n    )\n");
        }
        out.push_str("    uniform token type = \"linear\"\n");
        if let Some(widths) = &self.widths {
            out.push_str("    float[] widths = [");
            for (i, &w) in widths.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                push_float(&mut out, w);
            }
            out.push_str("] (\n        interpolation = \"vertex\"\n    )\n");
        }
        out.push_str("}\n");
        writer.write_all(out.as_bytes())?;
        if let Some(mesh) = &self.mesh {
            mesh.write_to(writer, animated)?;
        }
        Ok(())
    }

    /// The USD text as a string (see [`write_to`](Self::write_to)).
    pub fn to_usda_string(&self) -> io::Result<String> {
        let mut bytes = Vec::new();
        self.write_to(&mut bytes)?;
        String::from_utf8(bytes).map_err(|e| invalid_input(e.to_string()))
    }

    /// Writes the USD text file at `path` ([`write_to`](Self::write_to)), atomically: the file is
    /// either replaced whole or left as it was. Errors name the path.
    pub fn write(&self, path: impl AsRef<Path>) -> io::Result<()> {
        let path = path.as_ref();
        if self.frame_count() == 0 {
            return Err(invalid_input(format!(
                "writing {}: no frame of points to write",
                path.display()
            )));
        }
        write_file_atomically(path, |writer| self.write_to(writer))
    }
}

/// Writes `curves` [m] (points, widths and colours where they have them) as the USD text file at
/// `path`, one frame, atomically. Invalid curves (a bad layout, a non-finite value, a curve of
/// fewer than two points) are an `InvalidInput` error and nothing is written.
pub fn write_usda_curves(path: impl AsRef<Path>, curves: &Curves) -> io::Result<()> {
    let path = path.as_ref();
    UsdCurvesWriter::from_curves(curves)
        .map_err(|e| io::Error::new(e.kind(), format!("writing {}: {e}", path.display())))?
        .write(path)
}

/// [`write_usda_curves`] into a string.
pub fn write_usda_curves_string(curves: &Curves) -> io::Result<String> {
    UsdCurvesWriter::from_curves(curves)?.to_usda_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_short_and_exact() {
        let mut out = String::new();
        for x in [
            0.1f32,
            -0.0,
            0.0,
            1e-7,
            3.4e38,
            1.0,
            -2.5,
            1e-5,
            123_456_790.0,
        ] {
            push_float(&mut out, x);
            out.push(' ');
        }
        assert_eq!(out, "0.1 -0.0 0 1e-7 3.4e38 1 -2.5 0.00001 123456790 ");
        for x in out.split_whitespace() {
            let _: f32 = x.parse().unwrap();
        }
        for bits in (0..u32::MAX).step_by(65_521) {
            let x = f32::from_bits(bits);
            if x.is_finite() {
                let mut text = String::new();
                push_float(&mut text, x);
                assert_eq!(text.parse::<f32>().unwrap().to_bits(), bits, "{text}");
            }
        }
    }

    #[test]
    fn the_text_has_the_basis_curves_layout() {
        let curves = Curves {
            points: vec![Vec3::ZERO, Vec3::Y, Vec3::X, Vec3::new(1.0, 0.5, 0.0)],
            offsets: vec![0, 2, 4],
            widths: Some(vec![0.002, 0.001, 0.002, 0.001]),
            colors: None,
            skipped: Vec::new(),
        };
        let text = write_usda_curves_string(&curves).unwrap();
        assert_eq!(
            text,
            "#usda 1.0\n(\n    defaultPrim = \"hair\"\n    doc = \"hairlod BasisCurves export \
             (metres, +Y up)\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\n\
             def BasisCurves \"hair\"\n{\n    int[] curveVertexCounts = [2, 2]\n    \
             float3[] extent = [(-0.001, -0.001, -0.001), (1.001, 1.001, 0.001)]\n    \
             point3f[] points = [(0, 0, 0), (0, 1, 0), (1, 0, 0), (1, 0.5, 0)]\n    \
             uniform token type = \"linear\"\n    float[] widths = [0.002, 0.001, 0.002, 0.001] \
             (\n        interpolation = \"vertex\"\n    )\n}\n"
        );
    }
}
