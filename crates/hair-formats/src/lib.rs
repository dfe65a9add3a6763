//! `hair-formats`: hairlod's groom and body files in and out. The model they fill ([`Curves`],
//! [`TriangleMesh`]) is hair-core's; this crate only reads and writes it: TressFX `.tfx` (4.x
//! and 3.x) and `.tfxmesh`, cyHair `.hair` (read and written), USD `BasisCurves` and `Mesh`
//! (text `.usda` read by the project's parser, and curves written with time samples; binary
//! `.usdc` read through the `openusd` crate; `.usd` is either, by its first bytes), USC-HairSalon
//! `.data`, OBJ polylines and triangle meshes, and Alembic `.abc` linear `Curves` (read through
//! the `ogawa-rs` crate, after checking the Ogawa container); OBJ written ([`obj`]) and a scene
//! exported as OBJ ([`export`]). Bodies that move and deform are read as a [`MeshSequence`] from
//! USD `Mesh` prims and Alembic `PolyMesh` objects at every time sample, through their transforms
//! ([`read_mesh_sequence_file`]).
//!
//! File formats are adapters at the edge: the readers produce plain polylines ([`Curves`]: points
//! per curve, optional widths and colours) and meshes ([`TriangleMesh`]) in metres, +Y up, after
//! the file's axes and units are converted ([`ImportAxes`]). Everything after that is the same code
//! as for procedural grooms.
//!
//! Every reader is a pure function of the file's bytes (`read_tfx(&bytes, &options)`) with a
//! `read_*_file(path, ..)` wrapper; [`read_curves_file`] and [`read_mesh_file`] pick the reader by
//! the file's extension. Readers check every count against the file's length before allocating,
//! never panic, and return either everything or a [`FormatError`] that names the file, the
//! element and the byte offset or line. Degenerate curves (fewer than two points, a zero-length
//! segment) are skipped and listed in [`Curves::skipped`], or refused with
//! [`ImportOptions::strict`]; a file without a usable curve is always an error.

pub mod export;
pub mod obj;

mod alembic;
mod alembic_curves;
mod alembic_layout;
mod alembic_mesh;
mod alembic_samples;
mod alembic_xform;
mod binary;
mod curves;
mod cyhair;
mod error;
mod obj_curves;
mod obj_mesh;
mod ogawa;
mod options;
mod sequence_limits;
mod text;
mod tfx;
mod tfxmesh;
mod usc;
mod usd_attrs;
mod usd_crate;
mod usd_layer;
mod usd_mesh;
mod usd_sequence;
mod usd_tracks;
mod usd_xform;
mod usda_lex;
mod usda_mesh;
mod usda_parse;
mod usda_prims;
mod usda_read;
mod usda_text;
mod usda_values;
mod usda_write;
mod usda_write_mesh;
mod usdc_check;

#[cfg(test)]
pub(crate) mod tests;

use std::path::Path;

pub use alembic::{read_alembic, read_alembic_file};
pub use alembic_mesh::{read_alembic_mesh_sequence, read_alembic_mesh_sequence_file};
pub use curves::{Curves, SkipReason, SkippedCurve};
pub use cyhair::{
    HAIR_HEADER_LEN, read_hair, read_hair_file, write_hair, write_hair_bytes, write_hair_to,
};
pub use error::{FormatError, FormatErrorKind, Location};
pub use obj_curves::{read_obj_curves, read_obj_curves_file};
pub use obj_mesh::{read_obj_mesh, read_obj_mesh_file};
pub use options::{ImportAxes, ImportOptions, SequenceLimits, UpAxis};
pub use tfx::{TFX3_HEADER_LEN, TFX4_HEADER_LEN, read_tfx, read_tfx_file};
pub use tfxmesh::{read_tfxmesh, read_tfxmesh_file};
pub use usc::{read_usc_data, read_usc_data_file};
pub use usd_crate::{read_usd_curves, read_usd_curves_file, read_usdc, read_usdc_file};
pub use usd_mesh::{read_usd_mesh, read_usd_mesh_file};
pub use usd_sequence::{read_usd_mesh_sequence, read_usd_mesh_sequence_file};
pub use usda_read::{read_usda, read_usda_at, read_usda_file, read_usda_file_at};
pub use usda_write::{UsdCurvesWriter, write_usda_curves, write_usda_curves_string};
pub use usda_write_mesh::UsdMeshTrack;

use hair_core::MeshSequence;
use hair_core::MeshSequenceError;
use hair_core::mesh::TriangleMesh;

/// A groom (curves) file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CurveFormat {
    /// TressFX `.tfx`, 4.x or 3.x.
    Tfx,
    /// cyHair `.hair`.
    CyHair,
    /// USC-HairSalon `.data`.
    UscData,
    /// Wavefront OBJ polylines (`l` records), `.obj`.
    ObjCurves,
    /// USD text `BasisCurves`, `.usda`.
    UsdText,
    /// USD binary crate `BasisCurves`, `.usdc`.
    UsdCrate,
    /// USD `BasisCurves` of either encoding, `.usd`: text or binary by the first bytes.
    Usd,
    /// Alembic (Ogawa) `Curves` objects, `.abc`.
    Alembic,
}

/// The curve file extensions [`CurveFormat::from_path`] knows.
pub const CURVE_EXTENSIONS: &str = ".tfx, .hair, .data, .obj, .usda, .usdc, .usd, .abc";
/// The mesh file extensions [`read_mesh_file`] knows.
pub const MESH_EXTENSIONS: &str = ".tfxmesh, .obj, .usda, .usdc, .usd";

/// The lower-case extension of `path` (empty when none).
fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

impl CurveFormat {
    /// The format named by the extension of `path` (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, FormatError> {
        match extension(path).as_str() {
            "tfx" => Ok(CurveFormat::Tfx),
            "hair" => Ok(CurveFormat::CyHair),
            "data" => Ok(CurveFormat::UscData),
            "obj" => Ok(CurveFormat::ObjCurves),
            "usda" => Ok(CurveFormat::UsdText),
            "usdc" => Ok(CurveFormat::UsdCrate),
            "usd" => Ok(CurveFormat::Usd),
            "abc" => Ok(CurveFormat::Alembic),
            other => Err(FormatError::from(FormatErrorKind::UnknownExtension {
                extension: other.to_owned(),
                known: CURVE_EXTENSIONS,
            })
            .in_file(path)),
        }
    }
}

/// Reads curves in `format` from the file's bytes (see the format's own reader).
pub fn read_curves(
    bytes: &[u8],
    format: CurveFormat,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    match format {
        CurveFormat::Tfx => read_tfx(bytes, options),
        CurveFormat::CyHair => read_hair(bytes, options),
        CurveFormat::UscData => read_usc_data(bytes, options),
        CurveFormat::ObjCurves => read_obj_curves(bytes, options),
        CurveFormat::UsdText => read_usda(bytes, options),
        CurveFormat::UsdCrate => read_usdc(bytes, options),
        CurveFormat::Usd => read_usd_curves(bytes, options),
        CurveFormat::Alembic => read_alembic(bytes, options),
    }
}

/// Reads a groom file, choosing the reader by extension: `.tfx` (TressFX 4.x or 3.x), `.hair`
/// (cyHair), `.data` (USC-HairSalon), `.obj` (polylines), `.usda` (USD text `BasisCurves`),
/// `.usdc` (USD binary `BasisCurves`, through the `openusd` crate) or `.usd` (either, by the first
/// bytes), USD at the default time, or `.abc` (Alembic `Curves` at the first time sample). Errors
/// name the file.
pub fn read_curves_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    let path = path.as_ref();
    match CurveFormat::from_path(path)? {
        CurveFormat::Tfx => read_tfx_file(path, options),
        CurveFormat::CyHair => read_hair_file(path, options),
        CurveFormat::UscData => read_usc_data_file(path, options),
        CurveFormat::ObjCurves => read_obj_curves_file(path, options),
        CurveFormat::UsdText => read_usda_file(path, options),
        CurveFormat::UsdCrate => read_usdc_file(path, options),
        CurveFormat::Usd => read_usd_curves_file(path, options),
        CurveFormat::Alembic => read_alembic_file(path, options),
    }
}

/// Reads a body mesh file, choosing the reader by extension: `.tfxmesh` (TressFX collision mesh),
/// `.obj` (triangulated) or `.usda`, `.usdc`, `.usd` (USD `Mesh` prims, text or binary by the
/// first bytes; triangulated). The mesh passes [`TriangleMesh::validate`], has at least one
/// triangle and has unit vertex normals. Errors name the file.
pub fn read_mesh_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<TriangleMesh, FormatError> {
    let path = path.as_ref();
    match extension(path).as_str() {
        "tfxmesh" => read_tfxmesh_file(path, options),
        "obj" => read_obj_mesh_file(path, options),
        "usda" | "usdc" | "usd" => read_usd_mesh_file(path, options),
        other => Err(FormatError::from(FormatErrorKind::UnknownExtension {
            extension: other.to_owned(),
            known: MESH_EXTENSIONS,
        })
        .in_file(path)),
    }
}

/// The mesh sequence file extensions [`read_mesh_sequence_file`] knows.
pub const MESH_SEQUENCE_EXTENSIONS: &str = ".tfxmesh, .obj, .usda, .usdc, .usd, .abc";

/// Reads a body file as a mesh over time [m, s], choosing the reader by extension: `.usda`,
/// `.usdc`, `.usd` ([`read_usd_mesh_sequence_file`]: every `Mesh` prim through its transforms at
/// every time code where something varies), `.abc` ([`read_alembic_mesh_sequence_file`]: every
/// `PolyMesh` object at every sample); formats without animation (`.tfxmesh`, `.obj`) give one
/// sample at time 0 ([`MeshSequence::still`]). Errors name the file.
pub fn read_mesh_sequence_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<MeshSequence, FormatError> {
    let path = path.as_ref();
    let still = |mesh: TriangleMesh| {
        MeshSequence::still(&mesh).map_err(|error| {
            let kind = match error {
                MeshSequenceError::Mesh { source, .. } => FormatErrorKind::Mesh(source),
                // Not reached: a mesh the readers checked is one valid sample.
                other => FormatErrorKind::Io {
                    message: other.to_string(),
                },
            };
            FormatError::from(kind).in_file(path)
        })
    };
    match extension(path).as_str() {
        "tfxmesh" => still(read_tfxmesh_file(path, options)?),
        "obj" => still(read_obj_mesh_file(path, options)?),
        "usda" | "usdc" | "usd" => read_usd_mesh_sequence_file(path, options),
        "abc" => read_alembic_mesh_sequence_file(path, options),
        other => Err(FormatError::from(FormatErrorKind::UnknownExtension {
            extension: other.to_owned(),
            known: MESH_SEQUENCE_EXTENSIONS,
        })
        .in_file(path)),
    }
}

/// Reads the file at `path` whole and parses it; every error names the file.
fn read_file<T>(
    path: &Path,
    parse: impl FnOnce(&[u8]) -> Result<T, FormatErrorKind>,
) -> Result<T, FormatError> {
    let bytes = std::fs::read(path).map_err(|error| {
        FormatError::from(FormatErrorKind::Io {
            message: error.to_string(),
        })
        .in_file(path)
    })?;
    parse(&bytes).map_err(|kind| FormatError::from(kind).in_file(path))
}

/// Checks a mesh a reader built, then gives it unit normals: the file's where it has them (made
/// unit length), computed from the triangles where it has none or where one is zero.
fn finish_mesh(mut mesh: TriangleMesh) -> Result<TriangleMesh, FormatErrorKind> {
    mesh.validate().map_err(FormatErrorKind::Mesh)?;
    if mesh.triangles.is_empty() {
        return Err(FormatErrorKind::NoTriangles);
    }
    let mut recompute = mesh.normals.is_empty();
    for normal in &mut mesh.normals {
        *normal = normal.normalize_or_zero();
        recompute |= *normal == glam::Vec3::ZERO;
    }
    if recompute {
        mesh.compute_vertex_normals();
    }
    Ok(mesh)
}
