//! The paper-curly groom's strands exported through every writable format (cyHair `.hair`, USD
//! `.usda`, OBJ polylines) and read back: the same points bit for bit, and so the same fitted
//! hierarchy (counts and errors) as the strands themselves.

use std::path::PathBuf;

use hairlod::core::fit::{FitSettings, SectionCount, fit_hierarchy};
use hairlod::core::representation::geometry::strand_polylines;
use hairlod::formats::obj::{ObjWriter, write_file_atomically};
use hairlod::formats::{Curves, read_curves_file, write_hair, write_usda_curves};
use hairlod::{RigidTransform, Scene};

/// A fresh folder under the target's temporary directory.
fn folder() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("groom_round_trip");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every strand of the paper-curly groom at rest, at its skeletons' resolution.
fn paper_curly_strands() -> Curves {
    let scene = Scene::preset("paper-curly").unwrap();
    let skeletons = &scene.groom.skeletons;
    let head = RigidTransform::IDENTITY;
    let (positions, frames) = skeletons.rest_pose(&head);
    let lines = strand_polylines(&scene.groom, &positions, &frames, 1).unwrap();
    Curves {
        points: lines.points,
        offsets: lines.offsets,
        ..Curves::default()
    }
}

#[test]
fn paper_curly_round_trips_through_every_format_and_fits_back_the_same() {
    let strands = paper_curly_strands();
    assert_eq!(strands.curve_count(), 37_765);
    let dir = folder();
    let hair = dir.join("paper-curly.hair");
    let usda = dir.join("paper-curly.usda");
    let obj = dir.join("paper-curly.obj");
    write_hair(&hair, &strands).unwrap();
    write_usda_curves(&usda, &strands).unwrap();
    write_file_atomically(&obj, |writer| {
        ObjWriter::new(writer).polylines_flat(&strands.points, &strands.offsets)
    })
    .unwrap();
    // The paper's 91 sections (§8.2).
    let settings = FitSettings {
        sections: SectionCount::Fixed(91),
        ..FitSettings::default()
    };
    let fitted = fit_hierarchy(&strands, &settings).unwrap();
    for path in [hair, usda, obj] {
        let read =
            read_curves_file(&path, &Default::default()).unwrap_or_else(|error| panic!("{error}"));
        assert_eq!(read.offsets, strands.offsets, "{}", path.display());
        assert_eq!(read.points, strands.points, "{}", path.display());
        let again = fit_hierarchy(&read, &settings).unwrap();
        assert_eq!(again.report, fitted.report, "{}", path.display());
    }
    assert_eq!(fitted.report.sections, 91);
    eprintln!("{}", fitted.report);
}
