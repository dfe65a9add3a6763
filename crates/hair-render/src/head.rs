//! The head mesh on the GPU: validated, normals filled in, interleaved position + normal vertices.

use hair_core::TriangleMesh;
use wgpu::util::DeviceExt;

use crate::error::{Result, invalid};

/// A head mesh uploaded for drawing.
#[derive(Debug)]
pub(crate) struct GpuMesh {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

/// Checks that `mesh` is drawable: [`TriangleMesh::validate`] (finite positions and normals,
/// indices in range, one normal per vertex or none, in which case they are computed), and an
/// index count that fits one `u32` draw. A mesh without triangles is drawable (as nothing).
pub(crate) fn validate_mesh(mesh: &TriangleMesh) -> Result<()> {
    mesh.validate()?;
    if u32::try_from(mesh.triangles.len() * 3).is_err() {
        return Err(invalid("head mesh exceeds the u32 index range"));
    }
    Ok(())
}

/// Uploads a validated mesh; `None` when it has no triangles.
pub(crate) fn upload_mesh(device: &wgpu::Device, mesh: &TriangleMesh) -> Option<GpuMesh> {
    if mesh.triangles.is_empty() {
        return None;
    }
    let computed;
    let normals = if mesh.normals.len() == mesh.positions.len() {
        &mesh.normals
    } else {
        let mut copy = mesh.clone();
        copy.compute_vertex_normals();
        computed = copy.normals;
        &computed
    };
    let vertex_data: Vec<[f32; 6]> = mesh
        .positions
        .iter()
        .zip(normals)
        .map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z])
        .collect();
    let index_data: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hair-render head vertices"),
        contents: bytemuck::cast_slice(&vertex_data),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hair-render head indices"),
        contents: bytemuck::cast_slice(&index_data),
        usage: wgpu::BufferUsages::INDEX,
    });
    Some(GpuMesh {
        vertices,
        indices,
        index_count: index_data.len() as u32,
    })
}
