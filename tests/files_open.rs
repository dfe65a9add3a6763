//! A character from files opens as a user expects: a groom of guides only grows children by
//! default (and `children_per_strand = 0` turns that off), and a scene that names files but no
//! camera frames the body and groom (and a given target or distance is kept). The groom is
//! written here: guides on the procedural head, so nothing outside the repository is needed.

use glam::Vec3;
use hairlod::core::{Curves, Head, HeadParams};
use hairlod::framing::scene_bounds;
use hairlod::loaded::{CHILD_TARGET_STRANDS_PER_M2, SPARSE_STRANDS_PER_M2, root_density};
use hairlod::{SceneFile, Shot};

/// `count` guides on the procedural head's scalp (a golden-angle spiral over the upper
/// hemisphere, the scalp's points kept), each 12 points, 2 cm apart, along the scalp's normal.
fn guides(count: usize) -> Curves {
    let head = Head::procedural(&HeadParams::default()).unwrap();
    let mut curves = Curves {
        offsets: vec![0],
        ..Curves::default()
    };
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let mut k = 0;
    while curves.curve_count() < count {
        k += 1;
        let y = 1.0 - (k as f32 + 0.5) / 1500.0;
        assert!(y > -0.2, "the scalp holds fewer than {count} spiral points");
        let r = (1.0 - y * y).sqrt();
        let direction = Vec3::new(
            r * (golden * k as f32).cos(),
            y,
            r * (golden * k as f32).sin(),
        );
        let (root, normal) = head.surface_point(direction);
        if !head.is_scalp(root) {
            continue;
        }
        for i in 0..12 {
            curves.points.push(root + normal * (0.02 * i as f32));
        }
        curves.offsets.push(curves.points.len() as u32);
    }
    curves
}

/// The shot of a scene reading `file` (a groom of guides) with `extra` scene text.
fn shot_of(file: &std::path::Path, extra: &str) -> Shot {
    let text = format!(
        "[groom]\nfile = \"{}\"\nstrands_per_section = 5\n{extra}\n[frames]\ncount = 2\nsize = \"320x180\"\n",
        file.display()
    );
    SceneFile::parse(&text).unwrap().resolve().unwrap()
}

#[test]
fn guides_grow_children_by_default_and_the_camera_frames_them() {
    let dir = std::env::temp_dir().join(format!("hairlod-files-open-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("guides.hair");
    let curves = guides(150);
    hairlod::formats::write_hair(&file, &curves).unwrap();
    let roots: Vec<Vec3> = curves.offsets[..150]
        .iter()
        .map(|&o| curves.points[o as usize])
        .collect();
    let density = root_density(&roots).unwrap();
    // 150 guides on a few hundred cm² of scalp: well under 2 per cm².
    assert!(density < SPARSE_STRANDS_PER_M2, "{density}");

    let mut shot = shot_of(&file, "");
    assert!(shot.camera.frame_all.is_some());
    let (scene, loaded, framing) = shot.build_framed_scene().unwrap();
    let grown = loaded
        .unwrap()
        .report
        .grown_children
        .expect("children grown");
    assert_eq!(grown.root_density, density);
    // Enough children to reach the target density, and no more.
    let per = grown.per_strand;
    assert!((per + 1) as f32 * density >= CHILD_TARGET_STRANDS_PER_M2);
    assert!((per as f32) * density < CHILD_TARGET_STRANDS_PER_M2);
    assert_eq!(scene.groom.strands.strand_count(), 150 * (per + 1));

    // Framed: every corner of the body's and groom's bounds is in the first frame's view.
    let framing = framing.expect("framed");
    let (min, max) = scene_bounds(&scene).unwrap();
    assert_eq!((framing.min, framing.max), (min, max));
    assert_eq!(shot.camera.target, 0.5 * (min + max));
    let camera = shot.camera(0);
    let aspect = 320.0 / 180.0;
    for corner in 0..8 {
        let pick = |bit: usize, lo: f32, hi: f32| if corner & bit == 0 { lo } else { hi };
        let p = Vec3::new(
            pick(1, min.x, max.x),
            pick(2, min.y, max.y),
            pick(4, min.z, max.z),
        );
        assert!(camera.sphere_in_frustum(p, 0.0, aspect), "corner {p}");
    }

    // children_per_strand = 0: the guides alone. A target given: the camera as given.
    let mut plain = shot_of(
        &file,
        "children_per_strand = 0\n[camera]\ntarget = [0.0, 0.1, 0.0]",
    );
    assert!(plain.camera.frame_all.is_none());
    let (scene, loaded, framing) = plain.build_framed_scene().unwrap();
    assert!(loaded.unwrap().report.grown_children.is_none());
    assert_eq!(scene.groom.strands.strand_count(), 150);
    assert!(framing.is_none());
    assert_eq!(plain.camera.target, Vec3::new(0.0, 0.1, 0.0));
    std::fs::remove_dir_all(&dir).unwrap();
}
