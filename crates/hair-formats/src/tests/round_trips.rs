//! Round trips: cyHair written by [`write_hair`] and OBJ polylines written by [`ObjWriter`] read
//! back bit for bit; every extension reaches its reader through [`read_curves_file`].

use glam::Vec3;

use super::real_data::data_file;
use super::scratch_dir;
use crate::cyhair::tests::sample_curves;
use crate::obj::ObjWriter;
use crate::tfx::tests::{tfx4_bytes, two_strands};
use crate::usc::tests::{strands_with_empty_roots, usc_bytes};
use crate::{
    Curves, ImportAxes, ImportOptions, UpAxis, read_curves_file, read_hair_file, read_obj_curves,
    read_tfx_file, write_hair,
};

/// The bits of every value of some curves (`-0.0 != 0.0`, unlike `==` on floats).
#[derive(Debug, PartialEq)]
pub(crate) struct Bits {
    points: Vec<[u32; 3]>,
    offsets: Vec<u32>,
    widths: Option<Vec<u32>>,
    colors: Option<Vec<[u32; 3]>>,
}

/// The bits of every value of `curves`, to compare bit for bit.
pub(crate) fn bits(curves: &Curves) -> Bits {
    let vec_bits = |v: &Vec3| v.to_array().map(f32::to_bits);
    Bits {
        points: curves.points.iter().map(vec_bits).collect(),
        offsets: curves.offsets.clone(),
        widths: curves
            .widths
            .as_ref()
            .map(|w| w.iter().map(|x| x.to_bits()).collect()),
        colors: curves
            .colors
            .as_ref()
            .map(|c| c.iter().map(vec_bits).collect()),
    }
}

/// Writes `curves` as cyHair into `dir`, reads them back strictly and through the dispatcher:
/// every bit the same.
fn cyhair_round_trip(dir: &std::path::Path, name: &str, curves: &Curves) {
    let path = dir.join(name);
    write_hair(&path, curves).unwrap();
    let read = read_hair_file(&path, &ImportOptions::strict()).unwrap();
    assert_eq!(bits(&read), bits(curves), "{name}");
    assert!(read.skipped.is_empty());
    let dispatched = read_curves_file(&path, &ImportOptions::default()).unwrap();
    assert_eq!(bits(&dispatched), bits(curves));
}

#[test]
fn cyhair_files_round_trip_bit_for_bit() {
    let dir = scratch_dir("hair-round-trip");
    let mut with_everything = sample_curves();
    with_everything.points[1].x = -0.0;
    with_everything.points[2] = Vec3::new(1e-30, -3.4e38, 7.123_456_7);
    cyhair_round_trip(&dir, "sample.hair", &with_everything);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_round_trips_through_cyhair_bit_for_bit() {
    let dir = scratch_dir("hair-round-trip-mohawk");
    let mohawk = read_tfx_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::default()).unwrap();
    cyhair_round_trip(&dir, "mohawk.hair", &mohawk);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Writes `curves` as OBJ polylines and reads them back strictly: every bit the same.
fn obj_round_trip(curves: &Curves) {
    let mut writer = ObjWriter::new(Vec::new());
    writer.comment("round trip").unwrap();
    writer.object("hair").unwrap();
    writer
        .polylines_flat(&curves.points, &curves.offsets)
        .unwrap();
    let bytes = writer.finish().unwrap();
    let read = read_obj_curves(&bytes, &ImportOptions::strict()).unwrap();
    assert_eq!(bits(&read), bits(curves));
}

#[test]
fn obj_polylines_round_trip_bit_for_bit() {
    let mut sample = sample_curves();
    sample.widths = None;
    sample.colors = None;
    sample.points[1].x = -0.0;
    obj_round_trip(&sample);
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_round_trips_through_obj_bit_for_bit() {
    let mohawk = read_tfx_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::default()).unwrap();
    obj_round_trip(&mohawk);
}

#[test]
fn every_extension_reaches_its_reader() {
    let dir = scratch_dir("dispatch");
    let tfx = dir.join("groom.tfx");
    std::fs::write(&tfx, tfx4_bytes(&two_strands())).unwrap();
    let data = dir.join("groom.DATA");
    std::fs::write(&data, usc_bytes(&strands_with_empty_roots())).unwrap();
    let obj = dir.join("groom.obj");
    std::fs::write(&obj, "v 0 0 0\nv 0 1 0\nl 1 2\n").unwrap();
    let options = ImportOptions::default();
    assert_eq!(read_curves_file(&tfx, &options).unwrap().curve_count(), 2);
    let usc = read_curves_file(&data, &options).unwrap();
    assert_eq!((usc.curve_count(), usc.skipped.len()), (2, 2));
    assert_eq!(read_curves_file(&obj, &options).unwrap().point_count(), 2);
    let abc = dir.join("groom.Abc");
    std::fs::write(&abc, super::alembic::fixture()).unwrap();
    assert_eq!(read_curves_file(&abc, &options).unwrap().curve_count(), 4);
    let mesh_path = dir.join("body.tfxmesh");
    std::fs::write(&mesh_path, crate::tfxmesh::tests::TETRAHEDRON).unwrap();
    let mesh = crate::read_mesh_file(&mesh_path, &options).unwrap();
    assert_eq!(mesh.triangle_count(), 4);
    let obj_mesh = dir.join("body.obj");
    std::fs::write(&obj_mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let mesh = crate::read_mesh_file(&obj_mesh, &options).unwrap();
    assert_eq!(mesh.normals, [Vec3::Z; 3]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn axes_convert_a_z_up_centimetre_file() {
    let dir = scratch_dir("axes");
    let path = dir.join("z-up-cm.hair");
    let curves = sample_curves();
    write_hair(&path, &curves).unwrap();
    let axes = ImportAxes {
        scale_to_metres: 0.01,
        up: UpAxis::Z,
        mirror_x: false,
    };
    let read = read_hair_file(&path, &ImportOptions::with_axes(axes)).unwrap();
    for (p, q) in curves.points.iter().zip(&read.points) {
        assert_eq!(*q, Vec3::new(p.x, p.z, -p.y) * 0.01);
    }
    for (w, v) in curves
        .widths
        .iter()
        .flatten()
        .zip(read.widths.iter().flatten())
    {
        assert_eq!(*v, w * 0.01);
    }
    assert_eq!(read.colors, curves.colors, "colours are not scaled");
    std::fs::remove_dir_all(&dir).unwrap();
}
