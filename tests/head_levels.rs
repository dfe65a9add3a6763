//! The head drawn at the tessellation its size on screen allows ([`HeadLevels::select`]): its
//! silhouette moves by at most the half pixel the choice allows, so the head's area on screen
//! changes by at most half a pixel times its perimeter.

use glam::Vec3;
use hairlod::core::{Camera, Head, HeadParams, RigidTransform};
use hairlod::head_levels::{HEAD_PIXEL_TOLERANCE, HeadLevels};
use hairlod::render::{ActiveSkeletons, FrameSettings, Renderer, RendererOptions};

/// Pixels of `image` that differ from its corner (the background) by more than a quarter of the
/// way to full contrast in some channel: the head's pixels, an edge pixel counted when the head
/// covers enough of it.
fn head_mask(image: &image::RgbaImage) -> Vec<bool> {
    let background = image.get_pixel(0, 0).0;
    image
        .pixels()
        .map(|p| (0..3).any(|c| (i32::from(p.0[c]) - i32::from(background[c])).abs() > 64))
        .collect()
}

/// Mask pixels with a 4-neighbour outside the mask: the silhouette's length [pixels].
fn perimeter(mask: &[bool], width: usize) -> usize {
    let height = mask.len() / width;
    let inside = |x: isize, y: isize| {
        x >= 0
            && y >= 0
            && (x as usize) < width
            && (y as usize) < height
            && mask[y as usize * width + x as usize]
    };
    (0..height as isize)
        .flat_map(|y| (0..width as isize).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            inside(x, y)
                && [(1, 0), (-1, 0), (0, 1), (0, -1)]
                    .iter()
                    .any(|(dx, dy)| !inside(x + dx, y + dy))
        })
        .count()
}

#[test]
fn a_coarser_head_moves_its_silhouette_by_at_most_the_tolerance() {
    let head = Head::procedural(&HeadParams::default()).unwrap();
    let levels = HeadLevels::new(&head);
    let mut renderer = Renderer::new(&RendererOptions::from_env().unwrap()).unwrap();
    let (width, height) = (960u32, 540u32);
    let mut coarser_seen = 0;
    for distance in [1.5f32, 8.0, 16.0, 30.0] {
        let camera = Camera::looking_at(Vec3::new(0.3, 0.1, distance), Vec3::ZERO, 0.6);
        let chosen = levels.select(
            &camera,
            height,
            &RigidTransform::IDENTITY,
            HEAD_PIXEL_TOLERANCE,
        );
        let mut draw = |level: usize| {
            renderer
                .set_head_mesh(Some(&levels.levels()[level].mesh))
                .unwrap();
            let image = renderer
                .render(
                    &ActiveSkeletons::new().frame(),
                    &FrameSettings::new(width, height, camera),
                )
                .unwrap();
            head_mask(&image)
        };
        let fine = draw(0);
        let coarse = draw(chosen);
        let area = |mask: &[bool]| mask.iter().filter(|&&m| m).count() as f32;
        let edge = perimeter(&fine, width as usize) as f32;
        assert!(
            area(&fine) > 20.0,
            "the head is in the picture at {distance} m"
        );
        // Every point of the drawn mesh lies within the tolerance of the finest (projected at
        // the head's nearest point), so the silhouette moves by at most that many pixels and
        // the area by at most that times the silhouette's length.
        let change = (area(&coarse) - area(&fine)).abs();
        assert!(
            change <= HEAD_PIXEL_TOLERANCE * edge,
            "{distance} m: level {chosen}, area {} against {} px, silhouette {edge} px",
            area(&coarse),
            area(&fine)
        );
        if chosen > 0 {
            coarser_seen += 1;
        }
        if distance < 2.0 {
            // The measure sees a tessellation too coarse for the distance: the coarsest head
            // up close (a centimetre off, about 8 px here) changes the area by more.
            let coarsest = draw(levels.levels().len() - 1);
            assert!(
                (area(&coarsest) - area(&fine)).abs() > HEAD_PIXEL_TOLERANCE * edge,
                "{} against {} px",
                area(&coarsest),
                area(&fine)
            );
        }
    }
    assert!(
        coarser_seen >= 3,
        "heads 8 m to 30 m away are drawn coarser"
    );
}
