//! Wavefront OBJ polylines: every `l` record is one curve through the `v` vertices it names
//! (1-based, or negative counting back from the last vertex defined; `l 1/1 2/2` texture indices
//! are ignored). Faces, normals and everything else are left aside. What
//! [`ObjWriter::polyline`](crate::obj::ObjWriter::polyline) writes reads back equal.

use std::path::Path;

use glam::Vec3;

use super::curves::{Curves, CurvesBuilder};
use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::read_file;
use super::text::{lines, parse, shorten};

/// Reads the polylines (`l` records) of an OBJ file from its bytes, coordinates in metres before
/// `options.axes`. Errors name the line; the data is called [`FormatError::IN_MEMORY`].
pub fn read_obj_curves(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the polylines of an OBJ file; errors name the file. See [`read_obj_curves`].
pub fn read_obj_curves_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

/// An `l` record: its line and its vertex indices, 0-based, not yet checked against the
/// vertices (a record may name vertices defined after it).
struct Record {
    line: usize,
    indices: std::ops::Range<usize>,
}

fn read(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut vertex_lines: Vec<usize> = Vec::new();
    let mut indices: Vec<i64> = Vec::new();
    let mut records: Vec<Record> = Vec::new();
    for line in lines(bytes) {
        let (line, text) = line?;
        let mut tokens = text.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let x = parse(tokens.next(), line, "vertex x")?;
                let y = parse(tokens.next(), line, "vertex y")?;
                let z = parse(tokens.next(), line, "vertex z")?;
                vertices.push(Vec3::new(x, y, z));
                vertex_lines.push(line);
            }
            Some("l") => {
                let first = indices.len();
                for token in tokens {
                    let vertex = token.split('/').next().unwrap_or_default();
                    let index: i64 = parse(Some(vertex), line, "vertex index")?;
                    let resolved = match index {
                        1.. => index - 1,
                        ..0 => vertices.len() as i64 + index,
                        0 => -1,
                    };
                    if resolved < 0 {
                        return Err(FormatErrorKind::Syntax {
                            line,
                            message: format!(
                                "vertex index {} names no vertex ({} defined so far)",
                                shorten(vertex),
                                vertices.len()
                            ),
                        });
                    }
                    indices.push(resolved);
                }
                if indices.len() == first {
                    return Err(FormatErrorKind::Syntax {
                        line,
                        message: "an `l` record without vertex indices".into(),
                    });
                }
                records.push(Record {
                    line,
                    indices: first..indices.len(),
                });
            }
            _ => {}
        }
    }
    let mut builder = CurvesBuilder::new(options, 0, false, false);
    let mut points = Vec::new();
    let mut point_lines = Vec::new();
    for record in &records {
        points.clear();
        point_lines.clear();
        for &index in &indices[record.indices.clone()] {
            let Some(&p) = vertices.get(index as usize) else {
                return Err(FormatErrorKind::Syntax {
                    line: record.line,
                    message: format!(
                        "vertex index {} names no vertex (the file has {})",
                        index + 1,
                        vertices.len()
                    ),
                });
            };
            points.push(p);
            point_lines.push(vertex_lines[index as usize]);
        }
        builder.push(&points, &[], &[], |_, j| {
            Location::Line(point_lines.get(j).copied().unwrap_or(record.line))
        })?;
    }
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_records_become_curves() {
        let text = "# two curves\nv 0 0 0\nv 0 1 0\nv 0 2 0.5\nl 1 2 3\nv 1 0 0\nv 1 -1 0\n\
                    l -2/1 -1/2\nf 1 2 3\n";
        let curves = read_obj_curves(text.as_bytes(), &ImportOptions::default()).unwrap();
        assert_eq!(curves.offsets, [0, 3, 5]);
        assert_eq!(curves.curve(1), [Vec3::X, Vec3::new(1.0, -1.0, 0.0)]);
    }

    #[test]
    fn a_missing_vertex_names_the_line() {
        let error =
            read_obj_curves(b"v 0 0 0\nv 1 0 0\nl 1 2 9\n", &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: line 3: vertex index 9 names no vertex (the file has 2)"
        );
        let error = read_obj_curves(b"v 0 0 0\nl 0 1\n", &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: line 2: vertex index 0 names no vertex (1 defined so far)"
        );
    }

    #[test]
    fn a_nan_vertex_names_its_line() {
        let error =
            read_obj_curves(b"v 0 0 0\nv 0 nan 0\nl 1 2\n", &ImportOptions::default()).unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: curve 0, point 1 at line 2: position [0, NaN, 0] is not finite"
        );
    }

    #[test]
    fn a_file_without_polylines_is_an_empty_groom() {
        let error = read_obj_curves(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &Default::default())
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "<memory>: no usable curve: the file has 0 curves, 0 of them skipped"
        );
    }
}
