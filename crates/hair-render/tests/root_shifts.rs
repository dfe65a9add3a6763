//! Strand root shifts (`Renderer::set_strand_root_shifts`): a shifted strand is drawn, whole,
//! where its shift puts it and no longer where its skeleton alone would; an empty set of shifts
//! puts it back, and so does a new upload; a wrong count or a non-finite shift is refused with
//! the shifts before kept.

mod common;

use common::*;
use glam::{Vec2, Vec3};
use hair_render::{Renderer, StrandSet};

/// Whether each of `points` is drawn by `renderer` (one strand on a vertical chain from y = 0.1
/// to y = −0.1 at x = 0).
fn drawn(renderer: &mut Renderer, points: &[Vec3]) -> Vec<bool> {
    lit_at(renderer, &vertical_chain(0.1, 9).frame(), points)
}

/// Uploads two strands on chain 0: one offset 0.04 m along +X (the binormal), one along −X.
fn upload_two(renderer: &mut Renderer) {
    renderer
        .upload_strands(&StrandSet {
            strand_chain: &[0, 0],
            strand_root_offsets: &[Vec2::new(0.0, 0.04), Vec2::new(0.0, -0.04)],
            strand_shades: &[0.5, 0.5],
        })
        .unwrap();
}

#[test]
fn a_shifted_strand_is_drawn_where_its_shift_puts_it() {
    let mut renderer = single_sample_renderer(None);
    upload_two(&mut renderer);
    // Points near the root, halfway and near the tip of each strand's unshifted line
    // (x = ±0.04), and of the first strand's line moved 0.04 m further along +X (x = 0.08).
    let along = [0.08f32, 0.0, -0.08];
    let at = |x: f32| along.iter().map(move |&y| Vec3::new(x, y, 0.0));
    let points: Vec<Vec3> = at(0.04).chain(at(-0.04)).chain(at(0.08)).collect();
    let unshifted = [true, true, true, true, true, true, false, false, false];
    assert!(!renderer.strands_shifted());
    assert_eq!(drawn(&mut renderer, &points), unshifted);
    // Only the first strand moves, all of it, by 0.04 m along +X.
    renderer
        .set_strand_root_shifts(&[Vec3::new(0.04, 0.0, 0.0), Vec3::ZERO])
        .unwrap();
    assert!(renderer.strands_shifted());
    assert_eq!(
        drawn(&mut renderer, &points),
        [false, false, false, true, true, true, true, true, true]
    );
    // Refused: one shift for two strands, a NaN; the shifts set before stay.
    let error = renderer
        .set_strand_root_shifts(&[Vec3::X])
        .unwrap_err()
        .to_string();
    assert!(error.contains("1 strand root shifts for 2"), "{error}");
    let error = renderer
        .set_strand_root_shifts(&[Vec3::ZERO, Vec3::new(0.0, f32::NAN, 0.0)])
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("strand 1") && error.contains("not finite"),
        "{error}"
    );
    assert_eq!(drawn(&mut renderer, &points)[6..], [true, true, true]);
    // No shifts: back where the skeleton draws it.
    renderer.set_strand_root_shifts(&[]).unwrap();
    assert!(!renderer.strands_shifted());
    assert_eq!(drawn(&mut renderer, &points), unshifted);
    // A new upload draws unshifted too.
    renderer
        .set_strand_root_shifts(&[Vec3::new(0.04, 0.0, 0.0), Vec3::ZERO])
        .unwrap();
    upload_two(&mut renderer);
    assert!(!renderer.strands_shifted());
    assert_eq!(drawn(&mut renderer, &points), unshifted);
}
