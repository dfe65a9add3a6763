//! Integration tests of grooms on the procedural head: the paper's counts, control-point counts,
//! determinism, and OBJ export parsed back by an independent OBJ reader (`tobj`).

use hairlod::core::representation::drawn::strand_last_point;
use hairlod::core::representation::geometry::{
    cluster_control_grid, patch_control_grid, strand_polylines,
};
use hairlod::formats::export::{ExportOptions, export_obj};
use hairlod::{Level, RigidTransform, Scene};

#[test]
fn paper_curly_has_the_papers_counts() {
    // §8.2: 455 strand groups holding 37,765 strands, represented by 91 patches or 273 clusters.
    let scene = Scene::preset("paper-curly").unwrap();
    let counts = scene.groom.counts();
    assert_eq!(counts.sections, 91);
    assert_eq!(counts.patches, 91);
    assert_eq!(counts.clusters, 273);
    assert_eq!(counts.strand_groups, 455);
    assert_eq!(counts.strands, 37_765);
    let n = counts.nodes_per_skeleton;
    assert_eq!(counts.skeleton_nodes, (91 + 273 + 455) * n);
    assert_eq!(scene.groom.skeletons.chain_count(), 91 + 273 + 455);
}

#[test]
fn control_point_counts_are_2n_and_4n() {
    let scene = Scene::preset("curly").unwrap();
    let groom = &scene.groom;
    let positions = groom.skeletons.rest_positions(&RigidTransform::IDENTITY);
    let mut frames = vec![hairlod::Frame::default(); positions.len()];
    groom
        .skeletons
        .node_frames_into(&RigidTransform::IDENTITY, &positions, &mut frames);
    let patch = groom.level_chains(Level::Patch).start;
    let cluster = groom.level_chains(Level::Cluster).start;
    let n = groom.skeletons.chain_node_count(patch);
    assert_eq!(
        patch_control_grid(groom, &positions, &frames, patch).len(),
        2 * n
    );
    assert_eq!(
        cluster_control_grid(groom, &positions, &frames, cluster).len(),
        4 * n
    );
    let polylines = strand_polylines(groom, &positions, &frames, 3).unwrap();
    assert_eq!(polylines.offsets.len(), groom.strands.strand_count() + 1);
    // Each strand takes the 3(n − 1) tessellation steps up to its length and its exact end.
    let segments = 3 * (n - 1);
    let expected: usize = (0..groom.strands.strand_count())
        .map(|s| strand_last_point(groom.strands.length(s), segments) + 1)
        .sum();
    assert_eq!(polylines.points.len(), expected);
    assert!(expected < groom.strands.strand_count() * (segments + 1));
}

#[test]
fn grooms_are_deterministic() {
    let a = Scene::preset("wavy").unwrap();
    let b = Scene::preset("wavy").unwrap();
    assert_eq!(a.groom, b.groom);
}

#[test]
fn exported_obj_of_each_level_parses_back() {
    let scene = Scene::preset("curly").unwrap();
    let counts = scene.groom.counts();
    let directory = std::env::temp_dir().join(format!("hairlod-obj-{}", std::process::id()));
    std::fs::create_dir_all(&directory).unwrap();
    for level in Level::ALL {
        let path = directory.join(format!("{}.obj", level.name()));
        let options = ExportOptions {
            level,
            samples_per_segment: 2,
            ..ExportOptions::default()
        };
        let summary = export_obj(&path, &scene, &options).unwrap();
        let load = tobj::LoadOptions {
            ignore_points: true,
            ignore_lines: false,
            ..tobj::LoadOptions::default()
        };
        let (models, _) = tobj::load_obj(&path, &load).unwrap();
        // One model for the head and one for the hair.
        assert_eq!(models.len(), 2, "{level}");
        let head = &models[0].mesh;
        assert_eq!(head.indices.len(), 3 * scene.head.mesh.triangle_count());
        let hair = &models[1].mesh;
        let vertex_count = hair.positions.len() / 3;
        assert_eq!(
            vertex_count,
            summary.vertices - scene.head.mesh.vertex_count()
        );
        assert!(hair.indices.iter().all(|&i| (i as usize) < vertex_count));
        match level {
            Level::StrandGroup => {
                assert_eq!(summary.polylines, counts.strands);
                // tobj reads long `l` records as polygons, so count the records ourselves too:
                // one `l` line per strand, each index within the vertices written so far.
                let text = std::fs::read_to_string(&path).unwrap();
                let mut vertices = 0usize;
                let mut lines = 0usize;
                for record in text.lines() {
                    if record.starts_with("v ") {
                        vertices += 1;
                    } else if let Some(rest) = record.strip_prefix("l ") {
                        lines += 1;
                        for index in rest.split_whitespace() {
                            let index: usize = index.parse().unwrap();
                            assert!((1..=vertices).contains(&index), "{record}");
                        }
                    }
                }
                assert_eq!(lines, counts.strands);
                assert_eq!(vertices, summary.vertices);
            }
            Level::Cluster => {
                assert_eq!(summary.items, counts.clusters);
                assert!(summary.triangles > 0 && hair.indices.len() % 3 == 0);
            }
            Level::Patch => assert_eq!(summary.items, counts.patches),
        }
    }
    std::fs::remove_dir_all(&directory).unwrap();
}
