//! A triangle mesh written beside curves in a USD text file ([`UsdMeshTrack`]): one `Mesh` root
//! prim with `faceVertexCounts` (all 3), `faceVertexIndices`, `subdivisionScheme = "none"`, and
//! `points` and `extent`, time-sampled where the mesh has more than one sample or the file is an
//! animation. The body a run's hair grows on is written this way beside the hair, at its own
//! time codes, so that a USD viewer plays both together.

use std::fmt::Write as _;
use std::io::{self, Write};

use glam::Vec3;

use super::curves::vector_text;
use super::usda_text::{check_identifier, invalid_input, vec3_array};

/// A mesh [m] and its samples: one set of triangles, positions per time code.
#[derive(Debug, Clone, PartialEq)]
pub struct UsdMeshTrack {
    /// The prim's name, a USD identifier.
    pub name: String,
    /// Triangles as three indices into each sample's positions, counter-clockwise seen from the
    /// front (USD's `rightHanded` orientation).
    pub triangles: Vec<[u32; 3]>,
    /// `(time code, positions [m])`, the codes increasing; every sample has the same number of
    /// positions.
    pub samples: Vec<(f64, Vec<Vec3>)>,
}

impl UsdMeshTrack {
    /// Checks the track: a USD identifier as its name, at least one triangle and one sample,
    /// codes finite and increasing, every sample the first's size and finite, every index
    /// inside it. `InvalidInput` names the first problem.
    pub fn check(&self) -> io::Result<()> {
        check_identifier(&self.name)?;
        if self.triangles.is_empty() {
            return Err(invalid_input(format!(
                "mesh {:?} has no triangles",
                self.name
            )));
        }
        let Some((_, first)) = self.samples.first() else {
            return Err(invalid_input(format!(
                "mesh {:?} has no samples",
                self.name
            )));
        };
        let count = first.len();
        if let Some(bad) = self
            .triangles
            .iter()
            .flatten()
            .find(|&&v| v as usize >= count)
        {
            return Err(invalid_input(format!(
                "mesh {:?}: vertex index {bad} is out of its {count} points",
                self.name
            )));
        }
        for (i, (code, points)) in self.samples.iter().enumerate() {
            if !code.is_finite() || (i > 0 && *code <= self.samples[i - 1].0) {
                return Err(invalid_input(format!(
                    "mesh {:?}: sample {i}'s time code {code} is not finite or not after the \
                     sample before",
                    self.name
                )));
            }
            if points.len() != count {
                return Err(invalid_input(format!(
                    "mesh {:?}: sample {i} (time code {code}) has {} points; the first has \
                     {count}",
                    self.name,
                    points.len()
                )));
            }
            if let Some(p) = points.iter().find(|p| !p.is_finite()) {
                return Err(invalid_input(format!(
                    "mesh {:?}: sample {i} (time code {code}) has a point that is not finite: \
                     {}",
                    self.name,
                    vector_text(*p)
                )));
            }
        }
        Ok(())
    }

    /// Writes the prim (checked before by [`UsdCurvesWriter::with_mesh`]
    /// (super::UsdCurvesWriter::with_mesh)): `points` and `extent` as time samples where
    /// `time_sampled`, else the first sample's as default values.
    pub(crate) fn write_to<W: Write>(&self, writer: &mut W, time_sampled: bool) -> io::Result<()> {
        let mut out = String::with_capacity(64 * 1024);
        let _ = writeln!(out, "\ndef Mesh \"{}\"\n{{", self.name);
        let extent = |points: &[Vec3]| {
            let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
            [lo, hi]
        };
        if time_sampled {
            out.push_str("    float3[] extent.timeSamples = {\n");
            for (code, points) in &self.samples {
                let _ = write!(out, "        {code}: ");
                vec3_array(&mut out, &extent(points));
                out.push_str(",\n");
            }
            out.push_str("    }\n");
        } else {
            out.push_str("    float3[] extent = ");
            vec3_array(&mut out, &extent(&self.samples[0].1));
            out.push('\n');
        }
        out.push_str("    int[] faceVertexCounts = [");
        for i in 0..self.triangles.len() {
            out.push_str(if i > 0 { ", 3" } else { "3" });
        }
        out.push_str("]\n    int[] faceVertexIndices = [");
        for (i, v) in self.triangles.iter().flatten().enumerate() {
            let _ = write!(out, "{}{v}", if i > 0 { ", " } else { "" });
        }
        out.push_str("]\n");
        if time_sampled {
            out.push_str("    point3f[] points.timeSamples = {\n");
            writer.write_all(out.as_bytes())?;
            out.clear();
            for (code, points) in &self.samples {
                let _ = write!(out, "        {code}: ");
                vec3_array(&mut out, points);
                out.push_str(",\n");
                writer.write_all(out.as_bytes())?;
                out.clear();
            }
            out.push_str("    }\n");
        } else {
            out.push_str("    point3f[] points = ");
            vec3_array(&mut out, &self.samples[0].1);
            out.push('\n');
        }
        out.push_str("    uniform token subdivisionScheme = \"none\"\n}\n");
        writer.write_all(out.as_bytes())
    }
}
