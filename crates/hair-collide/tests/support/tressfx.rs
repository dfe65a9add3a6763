//! Readers for the TressFX 4.0 `.tfx` groom and the `.tfxmesh` collision mesh (test data only).

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

/// Strands of a TressFX 4.x file: `(vertices_per_strand, positions)`, strand after strand.
pub fn read_tfx4(path: &Path) -> Result<(usize, Vec<Vec3>), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let word = |k: usize| -> Result<[u8; 4], String> {
        bytes
            .get(4 * k..4 * k + 4)
            .map(|b| [b[0], b[1], b[2], b[3]])
            .ok_or("truncated header".to_string())
    };
    let version = f32::from_le_bytes(word(0)?);
    if !(4.0..5.0).contains(&version) {
        return Err(format!("version {version}, expected 4.x"));
    }
    let strand_count = u32::from_le_bytes(word(1)?) as usize;
    let vertices_per_strand = u32::from_le_bytes(word(2)?) as usize;
    let offset = u32::from_le_bytes(word(3)?) as usize;
    let count = strand_count * vertices_per_strand;
    let data = bytes
        .get(offset..offset + count * 16)
        .ok_or("positions past the end of the file")?;
    let positions = data
        .chunks_exact(16)
        .map(|c| {
            let f =
                |k: usize| f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
            Vec3::new(f(0), f(1), f(2))
        })
        .collect();
    Ok((vertices_per_strand, positions))
}

/// The triangle mesh of a `.tfxmesh` file (positions and normals from the file).
pub fn read_tfxmesh(path: &Path) -> Result<hair_core::TriangleMesh, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty());
    let mut mesh = hair_core::TriangleMesh::default();
    while let Some(line) = lines.next() {
        let mut fields = line.split_whitespace();
        let key = fields.next().unwrap_or("");
        let count: usize = fields.next().and_then(|n| n.parse().ok()).unwrap_or(0);
        let mut rows = Vec::with_capacity(count);
        for _ in 0..count {
            let row: Vec<&str> = lines
                .next()
                .ok_or(format!("{key}: missing rows"))?
                .split_whitespace()
                .collect();
            rows.push(row);
        }
        let float = |s: &str| s.parse::<f32>().map_err(|e| format!("{key}: {s}: {e}"));
        match key {
            "numOfVertices" => {
                for row in rows {
                    mesh.positions
                        .push(Vec3::new(float(row[1])?, float(row[2])?, float(row[3])?));
                    mesh.normals
                        .push(Vec3::new(float(row[4])?, float(row[5])?, float(row[6])?));
                }
            }
            "numOfTriangles" => {
                for row in rows {
                    let index = |s: &str| s.parse::<u32>().map_err(|e| format!("{key}: {s}: {e}"));
                    mesh.triangles
                        .push([index(row[1])?, index(row[2])?, index(row[3])?]);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}
