//! The real TressFX grooms and body mesh in `shared/data/tressfx` (AMD samples, MIT): counts,
//! finiteness, plausible extents in metres, and the mohawk's roots on the body.

use std::path::PathBuf;
use std::time::Instant;

use glam::Vec3;

use crate::{Curves, ImportAxes, ImportOptions, read_curves_file, read_mesh_file, read_tfx_file};

/// The TressFX 3 samples (ponytail, testhair1) are in centimetres: strands 5 to 92 units long on a
/// head whose roots span 43 units.
pub(crate) fn centimetres() -> ImportOptions {
    ImportOptions {
        axes: ImportAxes {
            scale_to_metres: 0.01,
            ..ImportAxes::default()
        },
        strict: true,
        ..ImportOptions::default()
    }
}

/// Mean length of the curves [m].
fn mean_length(curves: &Curves) -> f32 {
    curves
        .iter()
        .map(|c| c.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>())
        .sum::<f32>()
        / curves.curve_count() as f32
}

/// A file of the TressFX samples (`tressfx/<name>` in [`hair_core::samples::data_dir`]). Panics,
/// naming the path looked for, when it is missing: the tests that call it are ignored by default
/// and `.ci/run` runs them with the data.
pub(crate) fn data_file(name: &str) -> PathBuf {
    hair_core::samples::tressfx_file(name).unwrap_or_else(|error| panic!("{error}"))
}

/// Checks `curves` has `count` curves of `points` points each, nothing skipped, all finite.
fn assert_uniform(curves: &Curves, count: usize, points: usize) {
    assert_eq!(curves.curve_count(), count);
    assert_eq!(curves.point_count(), count * points);
    assert!(curves.iter().all(|c| c.len() == points));
    assert!(curves.skipped.is_empty(), "{:?}", &curves.skipped[..1]);
    assert!(curves.points.iter().all(|p| p.is_finite()));
    assert_eq!(curves.check_layout(), Ok(()));
}

/// Checks the bounds are those of hair on a head or body, in metres: between 5 cm and 2.5 m
/// across, within 5 m of the origin.
fn assert_plausible_extent(curves: &Curves) -> Vec3 {
    let (lo, hi) = curves.bounds().unwrap();
    let size = hi - lo;
    assert!(
        size.max_element() > 0.05 && size.max_element() < 2.5,
        "{lo} {hi}"
    );
    assert!(
        lo.abs().max_element() < 5.0 && hi.abs().max_element() < 5.0,
        "{lo} {hi}"
    );
    size
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_mohawk_has_2228_strands_of_32_vertices() {
    // The best of five reads, file reading included.
    let mut best = f64::INFINITY;
    let mut curves = Curves::default();
    for _ in 0..5 {
        let start = Instant::now();
        curves = read_tfx_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::strict()).unwrap();
        best = best.min(start.elapsed().as_secs_f64());
    }
    eprintln!("ratboy_mohawk.tfx read in {:.2} ms", best * 1e3);
    assert_uniform(&curves, 2228, 32);
    let size = assert_plausible_extent(&curves);
    eprintln!("mohawk bounds {:?}, size {size}", curves.bounds().unwrap());
    // Strands a few centimetres long, not millimetres or metres.
    let mean_length = mean_length(&curves);
    eprintln!("mohawk mean strand length {mean_length} m");
    assert!(mean_length > 0.01 && mean_length < 0.5, "{mean_length}");
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_ponytail_parts_have_their_counts() {
    for (name, count) in [
        ("ponytail_back.tfx", 517),
        ("ponytail_front_top.tfx", 876),
        ("ponytail_side.tfx", 3066),
        ("ponytail_tail.tfx", 474),
    ] {
        let curves =
            read_curves_file(data_file(name), &centimetres()).unwrap_or_else(|e| panic!("{e}"));
        assert_uniform(&curves, count, 16);
        assert_plausible_extent(&curves);
        let length = mean_length(&curves);
        assert!(
            length > 0.1 && length < 0.8,
            "{name}: mean length {length} m"
        );
    }
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn testhair1_has_10027_strands_of_4_vertices() {
    let curves = read_curves_file(data_file("testhair1.tfx"), &centimetres()).unwrap();
    assert_uniform(&curves, 10_027, 4);
    assert_plausible_extent(&curves);
    // A synthetic groom: every strand 11 cm long.
    for curve in curves.iter() {
        let length: f32 = curve.windows(2).map(|w| w[0].distance(w[1])).sum();
        assert!((length - 0.11).abs() < 1e-5, "{length}");
    }
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn the_body_mesh_holds_the_mohawk_roots() {
    let start = Instant::now();
    let body = read_mesh_file(data_file("ratboy_body.tfxmesh"), &ImportOptions::default()).unwrap();
    eprintln!(
        "ratboy_body.tfxmesh read in {:.2} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!(body.vertex_count(), 12_909);
    assert_eq!(body.triangle_count(), 25_814);
    assert_eq!(body.validate_surface(), Ok(()));
    assert!(body.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    let mohawk = read_tfx_file(data_file("ratboy_mohawk.tfx"), &ImportOptions::default()).unwrap();
    let mut distances: Vec<f32> = mohawk
        .roots()
        .map(|root| {
            body.positions
                .iter()
                .map(|v| v.distance_squared(root))
                .fold(f32::INFINITY, f32::min)
                .sqrt()
        })
        .collect();
    distances.sort_by(f32::total_cmp);
    let median = distances[distances.len() / 2];
    eprintln!(
        "mohawk roots to the nearest body vertex: median {:.2} mm, max {:.2} mm",
        median * 1e3,
        distances[distances.len() - 1] * 1e3
    );
    assert!(median < 0.02, "median root distance {median} m");
}
