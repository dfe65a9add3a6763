//! The TressFX test data: where it is, and its groom and collision mesh read through
//! `hair_core::formats`.

use glam::Vec3;
use std::path::{Path, PathBuf};

/// `../shared/data/tressfx` seen from the workspace root. Panics, naming the path, when it is
/// absent: the data is not part of this repository, but CI always has it.
pub fn data_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/tressfx");
    assert!(
        dir.is_dir(),
        "the TressFX Ratboy data is missing: expected the folder {} (`../shared/data/tressfx` \
         beside the workspace)",
        dir.display()
    );
    dir
}

/// Strands of a TressFX 4.x file: `(vertices_per_strand, positions)`, strand after strand
/// (through `hair_core::formats`).
pub fn read_tfx4(path: &Path) -> Result<(usize, Vec<Vec3>), String> {
    let curves = hair_core::formats::read_tfx_file(path, &Default::default())
        .map_err(|error| error.to_string())?;
    let vertices_per_strand = curves.range(0).len();
    Ok((vertices_per_strand, curves.points))
}

/// The triangle mesh of a `.tfxmesh` file (positions and normals from the file, through
/// `hair_core::formats`).
pub fn read_tfxmesh(path: &Path) -> Result<hair_core::TriangleMesh, String> {
    hair_core::formats::read_tfxmesh_file(path, &Default::default())
        .map_err(|error| error.to_string())
}
