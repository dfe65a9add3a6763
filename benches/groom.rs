//! Criterion benches of the model: building the paper-curly groom, every strand as drawn once
//! (37,765 strands), and importing those strands from a cyHair file and fitting the
//! paper's hierarchy to them (the real-groom issue's import-speed measure): reading alone,
//! reading and fitting, and the whole import a scene's `[groom] file` goes through
//! ([`load_scene`]: read, fit, build the groom; with the head's mesh as the body file, roots
//! attached and occluders found too). The sag-free rest pose is not part of it (`hang_groom`,
//! measured in `tests/rest_pose.rs`).

use criterion::{Criterion, criterion_group, criterion_main};
use hairlod::core::representation::geometry::strand_polylines;
use hairlod::loaded::{BodyFile, GroomFile, load_scene};
use hairlod::{Groom, GroomParams, Head, HeadParams, RigidTransform, Scene};
use std::hint::black_box;
use std::io::Write;

fn build_groom(c: &mut Criterion) {
    let head = Head::procedural(&HeadParams::default()).expect("default head");
    let params = GroomParams::paper_curly();
    c.bench_function("build paper-curly groom", |b| {
        b.iter(|| Groom::generate(black_box(&params), &head).expect("groom"))
    });
}

fn evaluate_all_strands(c: &mut Criterion) {
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let groom = &scene.groom;
    let head = RigidTransform::IDENTITY;
    let (positions, mut frames) = groom.skeletons.rest_pose(&head);
    let samples_per_segment = 4;
    let mut group = c.benchmark_group("paper-curly strands");
    group.sample_size(30);
    group.bench_function("node frames + all strands as drawn", |b| {
        b.iter(|| {
            groom
                .skeletons
                .node_frames_into(&head, &positions, &mut frames);
            black_box(
                strand_polylines(groom, &positions, &frames, samples_per_segment).expect("strands"),
            );
        })
    });
    group.bench_function("all strands as drawn", |b| {
        b.iter(|| {
            black_box(
                strand_polylines(groom, &positions, &frames, samples_per_segment).expect("strands"),
            );
        })
    });
    group.finish();
}

fn import_and_fit(c: &mut Criterion) {
    use hairlod::core::fit::{FitSettings, SectionCount, fit_hierarchy};
    use hairlod::formats::{Curves, read_hair_file, write_hair};
    let scene = Scene::preset("paper-curly").expect("paper-curly");
    let skeletons = &scene.groom.skeletons;
    let head = RigidTransform::IDENTITY;
    let (positions, frames) = skeletons.rest_pose(&head);
    let lines = strand_polylines(&scene.groom, &positions, &frames, 1).expect("strands");
    let strands = Curves {
        points: lines.points,
        offsets: lines.offsets,
        ..Curves::default()
    };
    let path = std::env::temp_dir().join("hairlod-bench-paper-curly.hair");
    write_hair(&path, &strands).expect("a writable temporary file");
    let settings = FitSettings {
        sections: SectionCount::Fixed(91),
        ..FitSettings::default()
    };
    let mut group = c.benchmark_group("import 37765-strand paper-curly .hair");
    group.sample_size(10);
    group.bench_function("read", |b| {
        b.iter(|| read_hair_file(black_box(&path), &Default::default()).expect("readable"))
    });
    group.bench_function("read + fit the hierarchy (91 sections)", |b| {
        b.iter(|| {
            let curves = read_hair_file(black_box(&path), &Default::default()).expect("readable");
            fit_hierarchy(&curves, &settings).expect("a fit")
        })
    });
    // The whole import of a scene's groom file, with the groom's own head as the body file.
    let body_path = std::env::temp_dir().join("hairlod-bench-procedural-head.obj");
    write_mesh_obj(&body_path, &scene.head.mesh);
    let groom_file = GroomFile {
        sections: SectionCount::Fixed(91),
        ..GroomFile::new(vec![path.clone()])
    };
    let body = BodyFile {
        path: body_path,
        axes: Default::default(),
        seconds: None,
    };
    let params = GroomParams::paper_curly();
    group.bench_function(
        "read + fit + build the groom (load_scene, 91 sections)",
        |b| b.iter(|| load_scene(black_box(&groom_file), None, &params).expect("loads")),
    );
    group.bench_function(
        "read + fit + build the groom on a body file (roots attached, occluders)",
        |b| b.iter(|| load_scene(black_box(&groom_file), Some(&body), &params).expect("loads")),
    );
    group.finish();
}

/// Writes `mesh` as an OBJ triangle mesh (`v` and `f` records) to `path`.
fn write_mesh_obj(path: &std::path::Path, mesh: &hairlod::core::mesh::TriangleMesh) {
    let mut file = std::io::BufWriter::new(std::fs::File::create(path).expect("a writable file"));
    for p in &mesh.positions {
        writeln!(file, "v {} {} {}", p.x, p.y, p.z).expect("written");
    }
    for [a, b, c] in &mesh.triangles {
        writeln!(file, "f {} {} {}", a + 1, b + 1, c + 1).expect("written");
    }
    file.flush().expect("written");
}

criterion_group!(benches, build_groom, evaluate_all_strands, import_and_fit);
criterion_main!(benches);
