//! The Ratboy mohawk's roots attached to its body (the TressFX samples, `hair_core::samples`;
//! ignored by default, run by `.ci/run`): every root's
//! attachment is at most as far as its nearest body vertex (the closest surface point can only be
//! nearer), the roots lie on the body's surface (the data's README: median 6 mm from a vertex),
//! and the attachment points ride the body when it moves.

mod support;

use glam::{Quat, Vec3};
use hair_collide::{CollisionBody, attach_roots};
use support::tressfx::{data_dir, read_tfx4, read_tfxmesh};

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_roots_attach_to_the_ratboy_body() {
    let dir = data_dir().unwrap_or_else(|error| panic!("{error}"));
    let mesh = read_tfxmesh(&dir.join("ratboy_body.tfxmesh")).unwrap();
    let (vertices_per_strand, positions) = read_tfx4(&dir.join("ratboy_mohawk.tfx")).unwrap();
    let roots: Vec<Vec3> = positions
        .iter()
        .step_by(vertices_per_strand)
        .copied()
        .collect();
    assert_eq!(roots.len(), 2228);
    let body = CollisionBody::from_mesh(&mesh).unwrap();
    let (attachments, report) = attach_roots(&body, &roots).unwrap();
    // Brute force: the distance from each root to its nearest vertex bounds its attachment's.
    let mut nearest_vertex: Vec<f32> = roots
        .iter()
        .map(|root| {
            mesh.positions
                .iter()
                .map(|v| v.distance(*root))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    for ((root, attachment), bound) in roots.iter().zip(&attachments).zip(&nearest_vertex) {
        let distance = attachment.point_on(&mesh).distance(*root);
        assert!(distance <= bound + 1e-6, "{root}: {distance} > {bound}");
        assert!((distance - attachment.signed_distance.abs()).abs() < 1e-5);
    }
    nearest_vertex.sort_by(f32::total_cmp);
    let vertex_median = nearest_vertex[nearest_vertex.len() / 2];
    eprintln!(
        "mohawk roots to the body: {report:?}; to the nearest vertex: median {vertex_median} m"
    );
    assert!(report.median <= vertex_median);
    // The roots were placed on the body's surface (measured: median 0.2 µm, largest 0.7 mm),
    // not merely near its vertices (median 5.9 mm): every one within a millimetre.
    assert!(report.median < 1e-4 && report.max < 1e-3, "{report:?}");

    // Move the body rigidly: the attachment points move with it.
    let (rotation, shift) = (Quat::from_rotation_x(0.4), Vec3::new(0.0, 0.1, -0.05));
    let mut moved = mesh.clone();
    for p in &mut moved.positions {
        *p = rotation * *p + shift;
    }
    for attachment in &attachments {
        let expected = rotation * attachment.point_on(&mesh) + shift;
        assert!(attachment.point_on(&moved).distance(expected) < 1e-5);
    }
}
