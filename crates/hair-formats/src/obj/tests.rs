//! Tests of the OBJ writer: read back strictly and with `tobj`, bad input, atomic file writes.

use super::*;

fn tetrahedron() -> TriangleMesh {
    let mut mesh = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.1, -0.25, 1.5e-7)],
        normals: Vec::new(),
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    };
    mesh.compute_vertex_normals();
    mesh
}

/// A strict reader for what the writer emits: vertices, normals, faces `a//a` and lines, every
/// index 1-based and in range at the point it appears.
#[derive(Default)]
struct Parsed {
    vertices: Vec<Vec3>,
    normals: usize,
    faces: Vec<[usize; 3]>,
    lines: Vec<Vec<usize>>,
    objects: Vec<String>,
}

fn parse(text: &str) -> Parsed {
    let mut parsed = Parsed::default();
    for line in text.lines() {
        let mut words = line.split(' ');
        let keyword = words.next().unwrap();
        let rest: Vec<&str> = words.collect();
        match keyword {
            "v" | "vn" => {
                assert_eq!(rest.len(), 3, "{line}");
                let v: Vec<f32> = rest.iter().map(|w| w.parse().unwrap()).collect();
                if keyword == "v" {
                    parsed.vertices.push(Vec3::new(v[0], v[1], v[2]));
                } else {
                    parsed.normals += 1;
                }
            }
            "f" => {
                assert_eq!(rest.len(), 3, "{line}");
                let face: Vec<usize> = rest
                    .iter()
                    .map(|w| {
                        let (v, n) = w.split_once("//").unwrap();
                        assert_eq!(v, n, "vertex and normal numbered alike here");
                        v.parse().unwrap()
                    })
                    .collect();
                parsed.faces.push([face[0], face[1], face[2]]);
            }
            "l" => parsed
                .lines
                .push(rest.iter().map(|w| w.parse().unwrap()).collect()),
            "o" => parsed.objects.push(rest.join(" ")),
            "#" => {}
            _ => panic!("unexpected line {line}"),
        }
        for index in parsed
            .faces
            .iter()
            .flatten()
            .chain(parsed.lines.iter().flatten())
        {
            assert!((1..=parsed.vertices.len()).contains(index), "{line}");
        }
    }
    parsed
}

fn sample_file() -> Vec<u8> {
    let mut writer = ObjWriter::new(Vec::new());
    writer.comment("hairlod\ntest").unwrap();
    writer.object("head mesh").unwrap();
    writer.mesh(&tetrahedron()).unwrap();
    writer.object("part").unwrap();
    writer.polyline(&[Vec3::ZERO, Vec3::Y, Vec3::ONE]).unwrap();
    writer.object("strands").unwrap();
    let points = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::NEG_X, Vec3::NEG_Y];
    writer.polylines_flat(&points, &[0, 2, 2, 5]).unwrap();
    assert_eq!(writer.vertex_count(), 4 + 3 + 5);
    writer.finish().unwrap()
}

#[test]
fn strict_reader_reads_back_vertices_faces_and_lines() {
    let text = String::from_utf8(sample_file()).unwrap();
    let parsed = parse(&text);
    let mesh = tetrahedron();
    assert_eq!(parsed.objects, ["head_mesh", "part", "strands"]);
    // Shortest round-trip formatting: coordinates come back bit for bit.
    assert_eq!(parsed.vertices[..4], mesh.positions[..]);
    assert_eq!(parsed.normals, 4);
    let expected: Vec<[usize; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| i as usize + 1))
        .collect();
    assert_eq!(parsed.faces, expected);
    // Global numbering: the polyline follows the mesh's 4 vertices; the empty curve (offsets
    // 2..2) writes nothing.
    assert_eq!(
        parsed.lines,
        vec![vec![5, 6, 7], vec![8, 9], vec![10, 11, 12]]
    );
}

#[test]
fn tobj_reads_back_the_objects() {
    let bytes = sample_file();
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
    };
    let (models, _) = tobj::load_obj_buf(&mut &bytes[..], &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .unwrap();
    let names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["head_mesh", "part", "strands"]);
    let head = &models[0].mesh;
    assert_eq!(head.positions.len(), 4 * 3);
    assert_eq!(head.normals.len(), 4 * 3);
    // tobj renumbers vertices in order of first use: compare the corners' coordinates.
    let mesh = tetrahedron();
    let corner = |i: u32| {
        let p = &head.positions[3 * i as usize..3 * i as usize + 3];
        Vec3::new(p[0], p[1], p[2])
    };
    let read: Vec<Vec3> = head.indices.iter().map(|&i| corner(i)).collect();
    let written: Vec<Vec3> = mesh
        .triangles
        .iter()
        .flatten()
        .map(|&i| mesh.positions[i as usize])
        .collect();
    assert_eq!(read, written);
    // tobj reads an `l` element as a face of that many vertices (and reports no arities when
    // every face has three).
    assert_eq!(models[1].mesh.indices, [0, 1, 2]);
    assert_eq!(models[2].mesh.face_arities, [2, 3]);
    assert_eq!(models[2].mesh.indices.len(), 5);
}

#[test]
fn bad_input_is_an_error_and_writes_nothing() {
    let mut writer = ObjWriter::new(Vec::new());
    let mut mesh = tetrahedron();
    mesh.triangles.push([0, 1, 4]);
    let error = writer.mesh(&mesh).unwrap_err();
    assert!(error.to_string().contains("refers to vertex 4"), "{error}");
    mesh.triangles.pop();
    mesh.normals.pop();
    let error = writer.mesh(&mesh).unwrap_err();
    assert!(
        error.to_string().contains("3 normals for 4 vertices"),
        "{error}"
    );
    let mut mesh = tetrahedron();
    mesh.positions[1].z = f32::NAN;
    let error = writer.mesh(&mesh).unwrap_err();
    assert!(
        error.to_string().contains("vertex 1 is not finite"),
        "{error}"
    );
    let mut mesh = tetrahedron();
    mesh.normals[0].x = f32::INFINITY;
    let error = writer.mesh(&mesh).unwrap_err();
    assert!(
        error.to_string().contains("normal 0 is not finite"),
        "{error}"
    );
    assert!(writer.polyline(&[Vec3::ZERO, Vec3::NAN]).is_err());
    assert!(writer.polylines_flat(&[Vec3::ZERO], &[0, 2]).is_err());
    assert!(writer.polylines_flat(&[Vec3::ZERO], &[1, 1]).is_err());
    assert!(writer.polylines_flat(&[Vec3::ZERO], &[]).is_err());
    assert!(writer.polylines_flat(&[], &[]).is_ok());
    assert_eq!(writer.vertex_count(), 0);
    assert!(writer.finish().unwrap().is_empty());
}

fn scratch_directory(name: &str) -> std::path::PathBuf {
    let directory = std::env::temp_dir().join(format!("hairlod-obj-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    directory
}

#[test]
fn atomic_writer_leaves_only_the_finished_file() {
    let directory = scratch_directory("ok");
    let path = directory.join("head.obj");
    write_file_atomically(&path, |file| {
        let mut writer = ObjWriter::new(file);
        writer.mesh(&tetrahedron())?;
        writer.finish().map(|_| ())
    })
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(parse(&text).faces.len(), 4);
    let entries: Vec<_> = std::fs::read_dir(&directory).unwrap().collect();
    assert_eq!(entries.len(), 1, "no temporary file is left behind");
    std::fs::remove_dir_all(&directory).unwrap();
}

#[test]
fn failed_write_leaves_no_file_and_names_the_path() {
    let directory = scratch_directory("fail");
    let path = directory.join("broken.obj");
    let error = write_file_atomically(&path, |file| {
        file.write_all(b"v 0 0 0\n")?;
        Err(io::Error::other("interrupted"))
    })
    .unwrap_err();
    assert!(error.to_string().contains("broken.obj"), "{error}");
    assert!(error.to_string().contains("interrupted"), "{error}");
    assert_eq!(std::fs::read_dir(&directory).unwrap().count(), 0);
    // An existing file survives a failed rewrite untouched.
    std::fs::write(&path, "old").unwrap();
    let _ = write_file_atomically(&path, |_| Err(io::Error::other("no")));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    assert_eq!(std::fs::read_dir(&directory).unwrap().count(), 1);
    // A directory that does not exist is an error naming the path.
    let missing = directory.join("missing").join("x.obj");
    let error = write_file_atomically(&missing, |_| Ok(())).unwrap_err();
    assert!(error.to_string().contains("missing"), "{error}");
    std::fs::remove_dir_all(&directory).unwrap();
}
