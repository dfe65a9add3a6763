//! Alembic `.abc` polygon meshes over time (Ogawa archives, through the `ogawa-rs` crate behind
//! the checks and the panic guard of `alembic.rs`), read as one [`MeshSequence`].
//!
//! Read: every `PolyMesh` object (schema `AbcGeom_PolyMesh_v1`), at any depth, in the order of
//! the object tree, joined: its positions `P`, `.faceCounts` and `.faceIndices` at every sample,
//! its points through its parent `Xform` chain (`.ops` and `.vals`, composed as the curves
//! reader does, `alembic_xform.rs`) at every sample of each transform. Each polygon becomes a
//! fan of triangles from its first corner, as USD meshes do (`usd_mesh.rs`, whose code this
//! is); Alembic's faces are wound clockwise seen from their front (as Maya's exporter writes
//! them), so the windings are reversed into the counter-clockwise of [`MeshSequence`]; a
//! transform with a negative determinant reverses them again.
//!
//! Time: one sample per time at which anything read has a sample (the union over every mesh's
//! `P`, face arrays and transforms), each property taken at that time linearly between its own
//! samples (positions and transform values; face arrays are held) and held outside them. A
//! sample's time comes from its property's time sampling as Alembic stores it [s]: uniform or
//! cyclic `start + cycle · time_per_cycle` (the cycle's times listed once), acyclic the listed
//! times. The topology must not change between samples: a change is an error naming the object
//! and the time. Positions are taken as metres before the [`ImportAxes`](super::ImportAxes)
//! conversion (Alembic has no unit).
//!
//! Every sample of a property is read by `alembic_samples.rs`, which works around a fault of
//! `ogawa-rs` 0.4.0 in locating them.

use std::path::Path;

use glam::{DMat4, Vec3};
use ogawa_rs::{F32X3_TYPE, I32_TYPE, ObjectReader, PodArray};

use hair_core::MeshSequence;
use hair_core::mesh::TriangleMesh;

use super::alembic::{Kind, Memory, Reading, check_archive, crate_error, guarded};
use super::alembic_samples::{samples, timed};
use super::alembic_xform::compose;
use super::error::{FormatError, FormatErrorKind, Location};
use super::ogawa::structure;
use super::options::{ImportOptions, UpAxis};
use super::read_file;
use super::usd_attrs::Units;
use super::usd_mesh::add_prim;
use super::usd_xform::Timed;
use super::usda_mesh::MeshValues;
use super::usda_values::Array;

/// Reads the `PolyMesh` objects of an Alembic (Ogawa) archive over time [m before
/// `options.axes`, s]: every mesh joined, through its transforms, at every time where something
/// has a sample; see the module documentation. The data is called [`FormatError::IN_MEMORY`].
pub fn read_alembic_mesh_sequence(
    bytes: &[u8],
    options: &ImportOptions,
) -> Result<MeshSequence, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the `PolyMesh` objects of an Alembic `.abc` archive over time; errors name the file.
/// See [`read_alembic_mesh_sequence`].
pub fn read_alembic_mesh_sequence_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<MeshSequence, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

/// One transform of a mesh's chain: its ops (constant) and its values at each sample.
#[derive(Clone)]
struct XformTrack {
    path: String,
    ops: Vec<u8>,
    vals: Timed<Vec<f64>>,
    at: u64,
}

/// One PolyMesh object over time.
struct MeshTrack {
    path: String,
    points: Timed<Vec<Vec3>>,
    counts: Timed<Vec<i32>>,
    indices: Timed<Vec<i32>>,
    /// Its parent transforms, outermost first.
    xforms: Vec<XformTrack>,
    at: u64,
}

fn read(data: &[u8], options: &ImportOptions) -> Result<MeshSequence, FormatErrorKind> {
    options.axes.validate()?;
    check_archive(data)?;
    let meshes = guarded(|| collect(data))?;
    build(&meshes, options)
}

/// Reads every PolyMesh object of the archive.
fn collect(data: &[u8]) -> Result<Vec<MeshTrack>, FormatErrorKind> {
    let mut reader = Memory(std::io::Cursor::new(data));
    let archive = ogawa_rs::Archive::new(&mut reader).map_err(crate_error("archive", 0))?;
    let root = archive
        .load_root_object(&mut reader)
        .map_err(crate_error("/", 0))?;
    let mut reading = Reading {
        reader,
        archive,
        objects: Vec::new(),
    };
    let mut meshes = Vec::new();
    walk(&mut reading, &root, "", &mut Vec::new(), &mut meshes)?;
    Ok(meshes)
}

/// Reads the meshes under `object` (at `path`, under the transforms `xforms`).
fn walk(
    reading: &mut Reading,
    object: &ObjectReader,
    path: &str,
    xforms: &mut Vec<XformTrack>,
    meshes: &mut Vec<MeshTrack>,
) -> Result<(), FormatErrorKind> {
    for index in 0..object.children.len() {
        let child_path = format!("{path}/{}", object.children[index].name);
        let child = object
            .load_child(
                index,
                &mut reading.reader,
                &reading.archive.indexed_meta_data,
                &reading.archive.time_samplings,
            )
            .map_err(crate_error(&child_path, object.group.position))?;
        let mut pushed = false;
        match reading.kind(&child, &child_path)? {
            Kind::PolyMesh => meshes.push(mesh(reading, &child, &child_path, xforms)?),
            Kind::Xform => {
                if let Some(xform) = xform(reading, &child, &child_path)? {
                    xforms.push(xform);
                    pushed = true;
                }
            }
            Kind::Curves | Kind::Other => {}
        }
        walk(reading, &child, &child_path, xforms, meshes)?;
        if pushed {
            xforms.pop();
        }
    }
    Ok(())
}

/// An Xform object's ops and values over time; `None` when it has no `.ops`.
fn xform(
    reading: &mut Reading,
    object: &ObjectReader,
    path: &str,
) -> Result<Option<XformTrack>, FormatErrorKind> {
    let at = object.group.position;
    let Some(compound) = reading.compound(object, ".xform", path)? else {
        return Ok(None);
    };
    let element = format!("{path} .xform");
    let ops = match samples(reading, &compound, ".ops", &element, None)? {
        None => return Ok(None),
        Some(ops) => ops,
    };
    let mut first_ops = None;
    for (time, values, ops_at) in ops {
        let PodArray::U8(values) = values else {
            return Err(structure(element, ".ops is not uint8".into(), at));
        };
        match &first_ops {
            None => first_ops = Some(values),
            Some(first) if *first != values => {
                let message = format!(
                    "the transform's operations change at {time} s (operations that change over \
                     time are not read)"
                );
                return Err(structure(element, message, ops_at));
            }
            Some(_) => {}
        }
    }
    let vals = match samples(reading, &compound, ".vals", &element, None)? {
        None => Timed::new(Some(Vec::new()), Vec::new()),
        Some(vals) => timed(vals, |values| match values {
            PodArray::F64(v) => Some(v),
            PodArray::U8(empty) if empty.is_empty() => Some(Vec::new()),
            _ => None,
        })
        .ok_or_else(|| structure(&element, ".vals is not float64".into(), at))?,
    };
    Ok(Some(XformTrack {
        path: path.to_owned(),
        ops: first_ops.unwrap_or_default(),
        vals,
        at,
    }))
}

/// A PolyMesh object's samples.
fn mesh(
    reading: &mut Reading,
    object: &ObjectReader,
    path: &str,
    xforms: &[XformTrack],
) -> Result<MeshTrack, FormatErrorKind> {
    let at = object.group.position;
    let Some(geom) = reading.compound(object, ".geom", path)? else {
        return Err(structure(
            path,
            "a PolyMesh object without .geom".into(),
            at,
        ));
    };
    let element = format!("{path} .geom");
    let missing = |name: &str| structure(&element, format!("no {name} property"), at);
    let wrong = |name: &str| structure(&element, format!("{name} is not of its type"), at);
    let points =
        samples(reading, &geom, "P", &element, Some(&F32X3_TYPE))?.ok_or_else(|| missing("P"))?;
    let points = timed(points, |values| match values {
        PodArray::F32(p) => Some(
            p.chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect(),
        ),
        PodArray::U8(empty) if empty.is_empty() => Some(Vec::new()),
        _ => None,
    })
    .ok_or_else(|| wrong("P"))?;
    let mut ints = |name: &str| -> Result<Timed<Vec<i32>>, FormatErrorKind> {
        let values = samples(reading, &geom, name, &element, Some(&I32_TYPE))?
            .ok_or_else(|| missing(name))?;
        timed(values, |values| match values {
            PodArray::I32(v) => Some(v),
            PodArray::U8(empty) if empty.is_empty() => Some(Vec::new()),
            _ => None,
        })
        .ok_or_else(|| wrong(name))
    };
    let counts = ints(".faceCounts")?;
    let indices = ints(".faceIndices")?;
    Ok(MeshTrack {
        path: path.to_owned(),
        points,
        counts,
        indices,
        xforms: xforms.to_vec(),
        at,
    })
}

/// A Usd-worded error of the shared join, as an Alembic error; a value's element names the
/// sample's time.
fn as_alembic(error: FormatErrorKind, time: f64) -> FormatErrorKind {
    match error {
        FormatErrorKind::Usd {
            element, message, ..
        } => FormatErrorKind::Alembic {
            element,
            message: format!("at {time} s: {message}"),
            location: Location::Unknown,
        },
        other => other.renaming_element(|element| format!("{element} at {time} s")),
    }
}

/// The world matrix of a mesh at `time` [s].
fn world(track: &MeshTrack, time: f64) -> Result<DMat4, FormatErrorKind> {
    let mut matrix = DMat4::IDENTITY;
    for xform in &track.xforms {
        let vals = xform
            .vals
            .at(time, |a, b, w| {
                if a.len() == b.len() {
                    a.iter().zip(b).map(|(x, y)| x + (y - x) * w).collect()
                } else {
                    a.clone()
                }
            })
            .unwrap_or_default();
        let local = compose(&xform.ops, &vals).map_err(|message| {
            structure(
                format!("{} .xform", xform.path),
                format!("at {time} s: {message}"),
                xform.at,
            )
        })?;
        matrix *= local;
    }
    Ok(matrix)
}

/// The times of the sequence: those of every property with more than one sample (a property
/// with one is constant, whatever its time sampling says), sorted; when nothing is animated, the
/// earliest sample's time.
fn sequence_times(meshes: &[MeshTrack]) -> Vec<f64> {
    let properties = || {
        meshes.iter().flat_map(|m| {
            [
                m.points.codes().collect::<Vec<_>>(),
                m.counts.codes().collect(),
                m.indices.codes().collect(),
            ]
            .into_iter()
            .chain(m.xforms.iter().map(|x| x.vals.codes().collect()))
        })
    };
    let mut times: Vec<f64> = properties()
        .filter(|codes| codes.len() > 1)
        .flatten()
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    if times.is_empty() {
        let earliest = properties().flatten().min_by(f64::total_cmp);
        times.push(earliest.unwrap_or(0.0));
    }
    times
}

/// Joins every mesh at every time.
fn build(meshes: &[MeshTrack], options: &ImportOptions) -> Result<MeshSequence, FormatErrorKind> {
    if meshes.is_empty() {
        return Err(structure(
            "archive",
            "no PolyMesh object (schema AbcGeom_PolyMesh_v1)".into(),
            0,
        ));
    }
    options.sequence.validate()?;
    let mut times = sequence_times(meshes);
    options.sequence.window(&mut times, 1.0);
    let units = Units::new(UpAxis::Y, 1.0);
    let held = |a: &Vec<i32>, _: &Vec<i32>, _| a.clone();
    let lerp = |a: &Vec<Vec3>, b: &Vec<Vec3>, w: f64| {
        if a.len() == b.len() {
            a.iter().zip(b).map(|(p, q)| p.lerp(*q, w as f32)).collect()
        } else {
            a.clone()
        }
    };
    let mut first = Vec::with_capacity(meshes.len());
    let mut triangles = Vec::new();
    let mut samples = Vec::with_capacity(times.len());
    for (s, &time) in times.iter().enumerate() {
        let mut joined = TriangleMesh::default();
        for (m, track) in meshes.iter().enumerate() {
            // Every property has a sample (checked when read), so each has a value.
            let points = track.points.at(time, lerp).unwrap_or_default();
            let counts = track.counts.at(time, held).unwrap_or_default();
            let indices = track.indices.at(time, held).unwrap_or_default();
            let world = world(track, time)?;
            if s == 0 {
                first.push((
                    counts.clone(),
                    indices.clone(),
                    points.len(),
                    world.determinant(),
                ));
            } else {
                let (c0, i0, n0, _) = &first[m];
                let problem = if *c0 != counts || *i0 != indices {
                    Some("its .faceCounts or .faceIndices differ from the first sample's".into())
                } else if *n0 != points.len() {
                    Some(format!(
                        "P has {} points where the first sample has {n0}",
                        points.len()
                    ))
                } else {
                    None
                };
                if let Some(problem) = problem {
                    return Err(structure(
                        &track.path,
                        format!(
                            "the topology changes between samples: at {time} s (sample {s} of \
                             the sequence), {problem}"
                        ),
                        track.at,
                    ));
                }
            }
            let points = points
                .iter()
                .map(|p| world.transform_point3(p.as_dvec3()).as_vec3())
                .collect();
            let values = MeshValues {
                path: track.path.clone(),
                line: None,
                points: Array::from_values(points),
                counts: Array::from_values(counts.iter().map(|&c| i64::from(c)).collect()),
                indices: Array::from_values(indices.iter().map(|&i| i64::from(i)).collect()),
                // Alembic's clockwise faces.
                orientation: ("leftHanded".into(), None),
            };
            add_prim(&mut joined, &units, &options.axes, values, first[m].3 < 0.0)
                .map_err(|error| as_alembic(error, time))?;
        }
        if s == 0 {
            if joined.triangles.is_empty() {
                return Err(FormatErrorKind::NoTriangles);
            }
            triangles = joined.triangles;
            options
                .sequence
                .check(times.len(), joined.positions.len())?;
        }
        samples.push(joined.positions);
    }
    MeshSequence::new(triangles, times, samples).map_err(|error| FormatErrorKind::Alembic {
        element: "archive".into(),
        message: format!("the meshes joined over time: {error}"),
        location: Location::Unknown,
    })
}
