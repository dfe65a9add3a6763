//! The TressFX test data: where it is, and its groom and collision mesh read through
//! `hair_formats` (shared by `tests/ratboy_collision.rs` and `benches/ratboy.rs`).

use glam::Vec3;
use std::path::{Path, PathBuf};

/// The samples' `tressfx/` folder ([`hair_core::samples`]: `HAIRLOD_DATA`, or `../shared/data`
/// beside the workspace), or the error naming the file that is missing. The tests that read it are
/// ignored by default, `.ci/run` runs them, and they fail with this error without the data.
pub fn data_dir() -> Result<PathBuf, hair_core::samples::MissingSample> {
    hair_core::samples::tressfx_dir()
}

/// Strands of a TressFX 4.x file: `(vertices_per_strand, positions)`, strand after strand
/// (through `hair_formats`).
pub fn read_tfx4(path: &Path) -> Result<(usize, Vec<Vec3>), String> {
    let curves = hair_formats::read_tfx_file(path, &Default::default())
        .map_err(|error| error.to_string())?;
    let vertices_per_strand = curves.range(0).len();
    Ok((vertices_per_strand, curves.points))
}

/// The triangle mesh of a `.tfxmesh` file (positions and normals from the file, through
/// `hair_formats`).
pub fn read_tfxmesh(path: &Path) -> Result<hair_core::TriangleMesh, String> {
    hair_formats::read_tfxmesh_file(path, &Default::default()).map_err(|error| error.to_string())
}
