//! Wavefront OBJ writing (meshes and polylines); [`write_file_atomically`] (from hair-core) is
//! re-exported here, where it always was.
//!
//! Coordinates are written as f32 in their shortest decimal form that reads back to the same f32
//! (Rust's `Display` for `f32`: `0.1`, `-0.0123`, never exponents), so a file round-trips exactly.
//! Vertex indices are 1-based and global across objects, as OBJ requires; normals are indexed
//! separately (`f a//na b//nb c//nc`). The output opens in Blender and any OBJ reader.

use std::io::{self, Write};

use glam::Vec3;
use hair_core::mesh::TriangleMesh;

pub use hair_core::atomic_file::write_file_atomically;

/// Writes OBJ elements to `W`, numbering vertices and normals across everything written.
///
/// Writes go straight to `W`: give it a buffered writer (`BufWriter`, `Vec<u8>`) for speed. Every
/// element is checked before any of it is written, so an error (a non-finite coordinate, an index
/// out of range) leaves the output as it was before that call.
#[derive(Debug)]
pub struct ObjWriter<W: Write> {
    writer: W,
    /// Number of `v` lines written so far.
    vertex_count: usize,
    /// Number of `vn` lines written so far.
    normal_count: usize,
}

fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// Checks that every coordinate of `points` is finite (OBJ has no NaN or infinity).
fn require_finite(what: &str, points: &[Vec3]) -> io::Result<()> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(invalid_input(format!(
            "{what} {index} is not finite: {}",
            points[index]
        ))),
        None => Ok(()),
    }
}

impl<W: Write> ObjWriter<W> {
    /// A writer that has written nothing yet.
    pub fn new(writer: W) -> Self {
        ObjWriter {
            writer,
            vertex_count: 0,
            normal_count: 0,
        }
    }

    /// Number of vertices (`v` lines) written so far; the next vertex has OBJ index this + 1.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Writes a comment line `# text` (line breaks in `text` become spaces).
    pub fn comment(&mut self, text: &str) -> io::Result<()> {
        let text: String = text
            .chars()
            .map(|c| if c == '\n' || c == '\r' { ' ' } else { c })
            .collect();
        writeln!(self.writer, "# {text}")
    }

    /// Starts a new object: an `o name` line. Whitespace and control characters in `name` become
    /// `_` (OBJ names are one word); an empty name becomes `object`.
    pub fn object(&mut self, name: &str) -> io::Result<()> {
        let name: String = name
            .chars()
            .map(|c| {
                if c.is_whitespace() || c.is_control() {
                    '_'
                } else {
                    c
                }
            })
            .collect();
        let name = if name.is_empty() { "object" } else { &name };
        writeln!(self.writer, "o {name}")
    }

    fn vertices(&mut self, points: &[Vec3]) -> io::Result<()> {
        for p in points {
            writeln!(self.writer, "v {} {} {}", p.x, p.y, p.z)?;
        }
        self.vertex_count += points.len();
        Ok(())
    }

    /// Writes a triangle mesh [m]: its vertices (`v`), its normals (`vn`) when it has one per vertex,
    /// and one `f` line per triangle (`f a//a b//b c//c` with normals, `f a b c` without), keeping
    /// the triangles' winding. Errors (writing nothing) on a mesh that fails
    /// [`TriangleMesh::validate`]: normals present but not one per vertex, a triangle index out of
    /// range, a coordinate not finite.
    pub fn mesh(&mut self, mesh: &TriangleMesh) -> io::Result<()> {
        mesh.validate()
            .map_err(|error| invalid_input(error.to_string()))?;
        let with_normals = !mesh.normals.is_empty();
        let vertex_base = self.vertex_count + 1;
        let normal_base = self.normal_count + 1;
        self.vertices(&mesh.positions)?;
        if with_normals {
            for n in &mesh.normals {
                writeln!(self.writer, "vn {} {} {}", n.x, n.y, n.z)?;
            }
            self.normal_count += mesh.normals.len();
        }
        for triangle in &mesh.triangles {
            let [a, b, c] = triangle.map(|i| i as usize);
            if with_normals {
                let (va, vb, vc) = (vertex_base + a, vertex_base + b, vertex_base + c);
                let (na, nb, nc) = (normal_base + a, normal_base + b, normal_base + c);
                writeln!(self.writer, "f {va}//{na} {vb}//{nb} {vc}//{nc}")?;
            } else {
                let (va, vb, vc) = (vertex_base + a, vertex_base + b, vertex_base + c);
                writeln!(self.writer, "f {va} {vb} {vc}")?;
            }
        }
        Ok(())
    }

    /// Writes one polyline [m]: its points as `v` lines, then one `l i j k ...` line joining them in
    /// order. A polyline of fewer than two points writes its vertices but no `l` line (OBJ lines need
    /// two). Errors (writing nothing) when a coordinate is not finite.
    pub fn polyline(&mut self, points: &[Vec3]) -> io::Result<()> {
        require_finite("polyline point", points)?;
        self.polyline_unchecked(points)
    }

    fn polyline_unchecked(&mut self, points: &[Vec3]) -> io::Result<()> {
        let first = self.vertex_count + 1;
        self.vertices(points)?;
        if points.len() >= 2 {
            self.writer.write_all(b"l")?;
            for index in first..first + points.len() {
                write!(self.writer, " {index}")?;
            }
            self.writer.write_all(b"\n")?;
        }
        Ok(())
    }

    /// Writes many polylines stored flat [m]: curve `c` owns `points[offsets[c]..offsets[c + 1]]`,
    /// so `offsets` has one entry more than there are curves, starts at 0, never decreases and ends
    /// at `points.len()` (an empty `offsets` means no curves and needs no points). Each curve is
    /// written as by [`ObjWriter::polyline`]. Errors (writing nothing) on bad offsets or a
    /// non-finite coordinate.
    pub fn polylines_flat(&mut self, points: &[Vec3], offsets: &[u32]) -> io::Result<()> {
        let valid = match offsets {
            [] => points.is_empty(),
            [first, ..] => {
                *first == 0
                    && offsets.windows(2).all(|w| w[0] <= w[1])
                    && offsets[offsets.len() - 1] as usize == points.len()
            }
        };
        if !valid {
            return Err(invalid_input(format!(
                "curve offsets must start at 0, never decrease and end at the {} points",
                points.len()
            )));
        }
        require_finite("curve point", points)?;
        for curve in offsets.windows(2) {
            self.polyline_unchecked(&points[curve[0] as usize..curve[1] as usize])?;
        }
        Ok(())
    }

    /// Flushes and returns the underlying writer.
    pub fn finish(mut self) -> io::Result<W> {
        self.writer.flush()?;
        Ok(self.writer)
    }
}

#[cfg(test)]
mod tests;
