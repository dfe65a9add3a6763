//! USD `Mesh` prims over time, text `.usda` and binary `.usdc`, read as one [`MeshSequence`]: a
//! body that moves and deforms. Every `def Mesh` of the layer is joined as the still reader
//! (`usd_mesh.rs`) joins them, with the same triangulation, orientation and unit handling (its
//! code), after each prim's points go through its transform and its ancestors' (`usd_xform.rs`).
//!
//! Time: the sequence has one sample per time code at which anything that is read varies (the
//! union of the time samples of every mesh's `points`, `faceVertexCounts`, `faceVertexIndices`
//! and of every transform op above it); at each, every attribute takes USD's value (linear
//! between its own samples, held outside them, its default when it has none). Seconds are
//! time codes divided by the layer's `timeCodesPerSecond` (else its `framesPerSecond`, else 24,
//! as in USD). A layer with no time samples gives one sample at time 0. The topology (the
//! face counts and indices, the number of points) must be the same at every sample: a change
//! is an error naming the prim and the time code.
//!
//! The two encodings are read by `usd_tracks.rs` into the same `MeshTrack`s; composition arcs
//! are not followed.

use std::path::Path;

use glam::{DMat4, Vec3};

use hair_core::MeshSequence;
use hair_core::mesh::TriangleMesh;

use super::error::{FormatError, FormatErrorKind, Location};
use super::options::ImportOptions;
use super::read_file;
use super::usd_layer::{Encoding, sniff};
use super::usd_mesh::add_prim;
use super::usd_tracks::{MeshTrack, Tracks, crate_tracks, text_tracks};
use super::usd_xform::{OpStack, world};
use super::usda_mesh::MeshValues;
use super::usda_values::{Array, Sample};

/// Reads the `Mesh` prims of a USD file of either encoding (text `#usda` or binary `PXR-USDC`,
/// by its first bytes) over time [m, +Y up, s]: every mesh joined, through its transforms, at
/// every time code where something varies; see the module documentation. The data is called
/// [`FormatError::IN_MEMORY`].
pub fn read_usd_mesh_sequence(
    bytes: &[u8],
    options: &ImportOptions,
) -> Result<MeshSequence, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads the `Mesh` prims of a USD file (`.usda`, `.usdc` or `.usd`) over time; errors name the
/// file. See [`read_usd_mesh_sequence`].
pub fn read_usd_mesh_sequence_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<MeshSequence, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

fn read(bytes: &[u8], options: &ImportOptions) -> Result<MeshSequence, FormatErrorKind> {
    options.axes.validate()?;
    let tracks = match sniff(bytes)? {
        Encoding::Text => text_tracks(bytes)?,
        Encoding::Crate => crate_tracks(bytes)?,
    };
    build(&tracks, options)
}

/// An error about a prim.
fn prim_error(track: &MeshTrack, message: String) -> FormatErrorKind {
    FormatErrorKind::Usd {
        element: track.path.clone(),
        message,
        location: track.line.map_or(Location::Unknown, Location::Line),
    }
}

/// The time codes of the sequence: every sample of what is read, sorted; `[0]` when none.
fn time_codes(meshes: &[MeshTrack]) -> Vec<f64> {
    let mut codes: Vec<f64> = meshes
        .iter()
        .flat_map(|m| {
            m.points
                .codes()
                .chain(m.counts.codes())
                .chain(m.indices.codes())
                .chain(m.stacks.iter().flat_map(OpStack::codes))
        })
        .collect();
    codes.sort_by(f64::total_cmp);
    codes.dedup();
    if codes.is_empty() {
        codes.push(0.0);
    }
    codes
}

/// A mesh's topology at the first time code: its face counts, indices and number of points.
struct Topology {
    counts: Vec<i64>,
    indices: Vec<i64>,
    points: usize,
}

/// Joins every mesh at every time code into the sequence.
fn build(tracks: &Tracks, options: &ImportOptions) -> Result<MeshSequence, FormatErrorKind> {
    options.sequence.validate()?;
    let axes = &options.axes;
    if tracks.meshes.is_empty() {
        return Err(FormatErrorKind::Usd {
            element: "layer".into(),
            message: "has no Mesh prim (`def Mesh`)".into(),
            location: Location::Unknown,
        });
    }
    let mut codes = time_codes(&tracks.meshes);
    options
        .sequence
        .window(&mut codes, tracks.time_codes_per_second);
    let mut first: Vec<Topology> = Vec::with_capacity(tracks.meshes.len());
    let mut mirrored = Vec::with_capacity(tracks.meshes.len());
    let mut triangles = Vec::new();
    let mut samples = Vec::with_capacity(codes.len());
    for (s, &code) in codes.iter().enumerate() {
        let mut mesh = TriangleMesh::default();
        for (m, track) in tracks.meshes.iter().enumerate() {
            let missing =
                |name: &str| prim_error(track, format!("has no {name} value at time code {code}"));
            let points = track
                .points
                .at(code, Sample::lerp)
                .ok_or_else(|| missing("points"))?;
            let counts = track
                .counts
                .at(code, Sample::lerp)
                .ok_or_else(|| missing("faceVertexCounts"))?;
            let indices = track
                .indices
                .at(code, Sample::lerp)
                .ok_or_else(|| missing("faceVertexIndices"))?;
            let world =
                world(&track.stacks, Some(code)).map_err(|(attribute, message, line)| {
                    FormatErrorKind::Usd {
                        element: attribute,
                        message: format!("at time code {code}: {message}"),
                        location: line.map_or(Location::Unknown, Location::Line),
                    }
                })?;
            if s == 0 {
                first.push(Topology {
                    counts: counts.values.clone(),
                    indices: indices.values.clone(),
                    points: points.len(),
                });
                mirrored.push(world.determinant() < 0.0);
            } else {
                check_topology(track, &first[m], codes[0], code, &points, &counts, &indices)?;
            }
            let points = transformed(points, world);
            let values = MeshValues {
                path: track.path.clone(),
                line: track.line,
                points,
                counts,
                indices,
                orientation: track.orientation.clone(),
            };
            add_prim(&mut mesh, &tracks.units, axes, values, mirrored[m])
                .map_err(|error| at_time_code(error, code))?;
        }
        if s == 0 {
            if mesh.triangles.is_empty() {
                return Err(FormatErrorKind::NoTriangles);
            }
            triangles = mesh.triangles;
            options.sequence.check(codes.len(), mesh.positions.len())?;
        }
        samples.push(mesh.positions);
    }
    let times = codes
        .iter()
        .map(|code| code / tracks.time_codes_per_second)
        .collect();
    MeshSequence::new(triangles, times, samples)
        .and_then(|sequence| {
            sequence.with_time_codes_per_second(Some(tracks.time_codes_per_second))
        })
        .map_err(|error| FormatErrorKind::Usd {
            element: "layer".into(),
            message: format!("the meshes joined over time codes {codes:?}: {error}"),
            location: Location::Unknown,
        })
}

/// Refuses a topology that differs from the first time code's.
fn check_topology(
    track: &MeshTrack,
    first: &Topology,
    first_code: f64,
    code: f64,
    points: &Array<Vec3>,
    counts: &Array<i64>,
    indices: &Array<i64>,
) -> Result<(), FormatErrorKind> {
    if counts.values != first.counts || indices.values != first.indices {
        return Err(prim_error(
            track,
            format!(
                "the topology changes between samples: faceVertexCounts or faceVertexIndices \
                 at time code {code} differ from those at time code {first_code} ({} faces, {} \
                 indices, where there were {} and {})",
                counts.len(),
                indices.len(),
                first.counts.len(),
                first.indices.len()
            ),
        ));
    }
    if points.len() != first.points {
        return Err(prim_error(
            track,
            format!(
                "has {} points at time code {code}, but {} at time code {first_code}: the \
                 topology changes between samples",
                points.len(),
                first.points
            ),
        ));
    }
    Ok(())
}

/// Points through a transform, in f64 (unchanged, bit for bit, by the identity).
fn transformed(mut points: Array<Vec3>, world: DMat4) -> Array<Vec3> {
    if world != DMat4::IDENTITY {
        for p in &mut points.values {
            *p = world.transform_point3(p.as_dvec3()).as_vec3();
        }
    }
    points
}

/// Adds the time code to an error about a sample.
fn at_time_code(error: FormatErrorKind, code: f64) -> FormatErrorKind {
    match error {
        FormatErrorKind::Usd {
            element,
            message,
            location,
        } => FormatErrorKind::Usd {
            element,
            message: format!("at time code {code}: {message}"),
            location,
        },
        other => other.renaming_element(|element| format!("{element} at time code {code}")),
    }
}
