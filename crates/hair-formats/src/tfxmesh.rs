//! TressFX collision meshes (`.tfxmesh`, text): `numOfBones N` and N bone lines, `numOfVertices
//! N` and N lines `index x y z nx ny nz j0..j3 w0..w3`, `numOfTriangles N` and N lines `index v0
//! v1 v2`; `#` starts a comment. Positions and normals are read (metres); bones and skinning
//! weights are left aside.

use std::path::Path;

use glam::Vec3;

use super::curves::vector_text;
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::text::{lines, parse, shorten};
use super::{finish_mesh, read_file};
use hair_core::mesh::TriangleMesh;

/// Reads a TressFX `.tfxmesh` collision mesh from its bytes (metres before `options.axes`). The
/// mesh passes [`TriangleMesh::validate`], has triangles and unit normals (the file's). Errors name
/// the line; the data is called [`FormatError::IN_MEMORY`].
pub fn read_tfxmesh(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads a TressFX `.tfxmesh` file; errors name the file. See [`read_tfxmesh`].
pub fn read_tfxmesh_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<TriangleMesh, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

/// The non-comment lines of the file, read in order.
struct Lines<'a> {
    lines: Vec<(usize, &'a str)>,
    next: usize,
}

impl<'a> Lines<'a> {
    /// The line after the last one (for errors at the end of the file).
    fn end_line(&self) -> usize {
        self.lines.last().map_or(1, |&(line, _)| line + 1)
    }

    fn next(&mut self, expected: &str) -> Result<(usize, &'a str), FormatErrorKind> {
        let line = self.lines.get(self.next).copied();
        self.next += 1;
        line.ok_or_else(|| FormatErrorKind::Syntax {
            line: self.end_line(),
            message: format!("the file ends where {expected} was expected"),
        })
    }

    fn peek_keyword(&self) -> Option<&'a str> {
        let (_, text) = self.lines.get(self.next)?;
        text.split_whitespace().next()
    }

    /// Reads `keyword N` and checks that N lines follow.
    fn count(&mut self, keyword: &str) -> Result<usize, FormatErrorKind> {
        let (line, text) = self.next(&format!("`{keyword} N`"))?;
        let mut tokens = text.split_whitespace();
        let found = tokens.next().unwrap_or_default();
        if found != keyword {
            return Err(FormatErrorKind::Syntax {
                line,
                message: format!("expected `{keyword} N`, found `{}`", shorten(text)),
            });
        }
        let count: usize = parse(tokens.next(), line, &format!("count of {keyword}"))?;
        let remaining = self.lines.len() - self.next;
        if count > remaining {
            return Err(FormatErrorKind::Syntax {
                line,
                message: format!("{keyword} {count}, but only {remaining} lines follow"),
            });
        }
        Ok(count)
    }
}

/// Reads the leading `index` of an element line and checks that it is `expected`.
fn element_index<'t>(
    tokens: &mut impl Iterator<Item = &'t str>,
    line: usize,
    what: &str,
    expected: usize,
) -> Result<(), FormatErrorKind> {
    let index: usize = parse(tokens.next(), line, &format!("{what} index"))?;
    if index != expected {
        return Err(FormatErrorKind::Syntax {
            line,
            message: format!("{what} index {index}, expected {expected} (elements in order)"),
        });
    }
    Ok(())
}

fn read(bytes: &[u8], options: &ImportOptions) -> Result<TriangleMesh, FormatErrorKind> {
    options.axes.validate()?;
    let axes = &options.axes;
    let mut file = Lines {
        lines: lines(bytes).collect::<Result<_, _>>()?,
        next: 0,
    };
    if file.peek_keyword() == Some("numOfBones") {
        let bones = file.count("numOfBones")?;
        file.next += bones;
    }
    let vertex_count = file.count("numOfVertices")?;
    let mut mesh = TriangleMesh {
        positions: Vec::with_capacity(vertex_count),
        normals: Vec::with_capacity(vertex_count),
        triangles: Vec::new(),
    };
    for vertex in 0..vertex_count {
        let (line, text) = file.next("a vertex")?;
        let mut tokens = text.split_whitespace();
        element_index(&mut tokens, line, "vertex", vertex)?;
        let mut read_vec3 = |what: &str| -> Result<Vec3, FormatErrorKind> {
            let x = parse(tokens.next(), line, &format!("{what} x"))?;
            let y = parse(tokens.next(), line, &format!("{what} y"))?;
            let z = parse(tokens.next(), line, &format!("{what} z"))?;
            Ok(Vec3::new(x, y, z))
        };
        let position = read_vec3("position")?;
        let normal = read_vec3("normal")?;
        for (what, value) in [("position", position), ("normal", normal)] {
            if !value.is_finite() {
                return Err(FormatErrorKind::NonFinite {
                    element: format!("vertex {vertex}"),
                    what,
                    value: vector_text(value),
                    location: Location::Line(line),
                });
            }
        }
        let scaled = axes.point(position);
        if !scaled.is_finite() {
            return Err(FormatErrorKind::NonFinite {
                element: format!("vertex {vertex}"),
                what: "position",
                value: format!("{} (after scaling to metres)", vector_text(scaled)),
                location: Location::Line(line),
            });
        }
        mesh.positions.push(scaled);
        mesh.normals.push(axes.direction(normal));
    }
    let triangle_count = file.count("numOfTriangles")?;
    mesh.triangles.reserve(triangle_count);
    for triangle in 0..triangle_count {
        let (line, text) = file.next("a triangle")?;
        let mut tokens = text.split_whitespace();
        element_index(&mut tokens, line, "triangle", triangle)?;
        let mut corners = [0u32; 3];
        for corner in &mut corners {
            let index: u32 = parse(tokens.next(), line, "vertex index")?;
            if index as usize >= vertex_count {
                return Err(FormatErrorKind::Syntax {
                    line,
                    message: format!(
                        "triangle {triangle} names vertex {index}, but the mesh has \
                         {vertex_count} vertices"
                    ),
                });
            }
            *corner = index;
        }
        if axes.reverses_winding() {
            corners.swap(1, 2);
        }
        mesh.triangles.push(corners);
    }
    if let Some(&(line, text)) = file.lines.get(file.next) {
        return Err(FormatErrorKind::Syntax {
            line,
            message: format!("unexpected `{}` after the triangles", shorten(text)),
        });
    }
    finish_mesh(mesh)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) const TETRAHEDRON: &str = "# TressFX collision mesh\nnumOfBones 1\n0 root\n\
        numOfVertices 4\n# vertex index, x y z, nx ny nz, joints, weights\n\
        0 0 0 0 -1 -1 -1 0 0 0 0 1 0 0 0\n1 1 0 0 1 0 0 0 0 0 0 1 0 0 0\n\
        2 0 1 0 0 1 0 0 0 0 0 1 0 0 0\n3 0 0 1 0 0 2 0 0 0 0 1 0 0 0\n\
        numOfTriangles 4\n0 0 2 1\n1 0 1 3\n2 0 3 2\n3 1 2 3\n";

    #[test]
    fn a_tetrahedron_reads_with_unit_normals() {
        let mesh = read_tfxmesh(TETRAHEDRON.as_bytes(), &ImportOptions::default()).unwrap();
        assert_eq!(mesh.vertex_count(), 4);
        assert_eq!(mesh.triangles, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
        assert_eq!(mesh.normals[3], Vec3::Z);
        assert!((mesh.normals[0].length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_mirror_keeps_the_triangles_facing_out() {
        let options = ImportOptions::with_axes(crate::ImportAxes {
            mirror_x: true,
            ..Default::default()
        });
        let mesh = read_tfxmesh(TETRAHEDRON.as_bytes(), &options).unwrap();
        assert_eq!(mesh.positions[1], -Vec3::X);
        let centre = mesh.positions.iter().copied().sum::<Vec3>() / 4.0;
        for t in 0..mesh.triangle_count() {
            let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
            assert!(mesh.triangle_normal(t).dot((a + b + c) / 3.0 - centre) > 0.0);
        }
    }

    #[test]
    fn a_count_beyond_the_lines_names_its_line() {
        let text = TETRAHEDRON.replace("numOfTriangles 4", "numOfTriangles 4000000000");
        let error = read_tfxmesh(text.as_bytes(), &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: line 10: numOfTriangles 4000000000, but only 4 lines follow"
        );
    }

    #[test]
    fn a_triangle_past_the_vertices_names_its_line() {
        let text = TETRAHEDRON.replace("3 1 2 3\n", "3 1 2 4\n");
        let error = read_tfxmesh(text.as_bytes(), &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: line 14: triangle 3 names vertex 4, but the mesh has 4 vertices"
        );
    }

    #[test]
    fn a_nan_vertex_names_its_line() {
        let text = TETRAHEDRON.replace("2 0 1 0 0 1 0", "2 0 NaN 0 0 1 0");
        let error = read_tfxmesh(text.as_bytes(), &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: vertex 2 at line 8: position [0, NaN, 0] is not finite"
        );
    }

    #[test]
    fn a_missing_coordinate_names_its_line() {
        let text = TETRAHEDRON.replace("1 1 0 0 1 0 0 0 0 0 0 1 0 0 0", "1 1 0");
        let error = read_tfxmesh(text.as_bytes(), &ImportOptions::default()).unwrap_err();
        assert_eq!(error.to_string(), "<memory>: line 7: missing position z");
    }
}
