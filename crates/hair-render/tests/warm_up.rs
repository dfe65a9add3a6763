//! `Renderer::warm_up` draws every level once and leaves nothing behind that changes a frame:
//! a warmed-up renderer draws the same image as a cold one.

mod common;

use common::single_sample_renderer;
use glam::Vec3;
use hair_core::{Level, Scene};
use hair_render::{ActiveSkeletons, Camera, FrameSettings};

#[test]
fn warmed_up_renderer_draws_the_same_frames() {
    let scene = Scene::preset("curly").unwrap();
    let groom = &scene.groom;
    let mut cold = single_sample_renderer(None);
    let mut warm = single_sample_renderer(None);
    for renderer in [&mut cold, &mut warm] {
        renderer.upload_groom(groom).unwrap();
        renderer.set_head_mesh(Some(&scene.head.mesh)).unwrap();
    }
    // Three levels, each shaded, colour-coded and fading.
    assert_eq!(warm.warm_up(groom).unwrap(), 9);
    let camera = Camera::orbit(
        Vec3::new(0.0, -0.01, 0.0),
        1.2,
        150f32.to_radians(),
        8f32.to_radians(),
        35f32.to_radians(),
    );
    let settings = FrameSettings::new(240, 135, camera);
    let mut active = ActiveSkeletons::new();
    for level in [Level::Cluster, Level::Patch] {
        active.gather_rest_pose(groom, level).unwrap();
        let a = cold.render(&active.frame(), &settings).unwrap();
        let b = warm.render(&active.frame(), &settings).unwrap();
        assert_eq!(a.dimensions(), (240, 135));
        let differing = a
            .pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 1))
            .count();
        assert_eq!(differing, 0, "{level:?}: {differing} pixels differ");
        // The frame shows hair and head, so the comparison compared something.
        let background = *a.get_pixel(0, 0);
        let drawn = a.pixels().filter(|p| **p != background).count();
        assert!(drawn > 500, "{level:?}: only {drawn} pixels drawn");
    }
}
